/* @brief The dipole diffusion approximation of subsurface scattering (Jensen, Marschner, Levoy, Hanrahan 2001, "A
 * Practical Model for Subsurface Light Transport"; ../shared/papers/README.md section 4, with the corrected eq. 4 of
 * Ki & Oh) as pure functions in double: one colour channel's derived quantities, the diffuse reflectance profile
 * Rd(r), its integral over a disk and over the whole plane (closed form and numeric), the footprint kernels the
 * renderer sums samples with, and Schlick's Fresnel transmittance. Lengths are in any one unit: the coefficients
 * per unit, r and z in units (the renderer uses metres, `fovea material` millimetres). No allocation, no I/O; every
 * output is finite for any input (negative or non-finite coefficients count as 0, eta outside (0, 1e3] as 1). The
 * GPU's copy of these formulas is render/include/fv_sss_gather.glsl. */
#ifndef FV_DIPOLE_H
#define FV_DIPOLE_H

#include <stdbool.h>

/** One channel of a material, derived (Jensen et al. 2001, section 2.4). */
typedef struct fv_dipole {
    double sigma_a, sigma_s_prime; /* absorption, reduced scattering (per unit), as sanitised */
    double eta;                    /* relative index of refraction, as sanitised */
    double sigma_t_prime;          /* sigma_t' = sigma_a + sigma_s' */
    double alpha_prime;            /* reduced albedo alpha' = sigma_s' / sigma_t' (0 when sigma_t' = 0) */
    double sigma_tr;               /* effective transport coefficient sqrt(3 sigma_a sigma_t') */
    double fdr;                    /* diffuse Fresnel reflectance Fdr(eta) */
    double a;                      /* A = (1 + Fdr) / (1 - Fdr) */
    double zr, zv;                 /* depth of the real source 1/sigma_t' and height of the virtual one zr(1 + 4A/3)
                                    * (units; 0 when sigma_t' = 0: no scattering, Rd = 0) */
} fv_dipole;

/** Derive one channel. sigma_a >= 0, sigma_s_prime >= 0 (per unit), eta > 0. */
fv_dipole fv_dipole_make(double sigma_a, double sigma_s_prime, double eta);

/** Diffuse Fresnel reflectance: -1.440/eta^2 + 0.710/eta + 0.668 + 0.0636 eta for eta >= 1 (Jensen et al. 2001,
 *  eq. 5; Egan and Hilgeman's fit), -0.4399 + 0.7099/eta - 0.3319/eta^2 + 0.0636/eta^3 for eta < 1; clamped to
 *  [0, 0.999] so A stays finite. */
double fv_dipole_fdr(double eta);

/** Rd(r) = alpha'/(4 pi) [zr (sigma_tr + 1/dr) e^(-sigma_tr dr) / dr^2 + zv (sigma_tr + 1/dv) e^(-sigma_tr dv) / dv^2],
 *  dr = sqrt(r^2 + zr^2), dv = sqrt(r^2 + zv^2): outgoing radiant exitance per unit incident flux at distance r
 *  (per unit^2). Finite (at most DBL_MAX) for any r >= 0; 0 for r < 0 or NaN. */
double fv_dipole_rd(const fv_dipole *d, double r);

/** The integral of Rd over the disk of radius `radius` around the point of incidence, in closed form:
 *  alpha'/2 [e^(-sigma_tr zr) - zr e^(-sigma_tr dr(R)) / dr(R) + e^(-sigma_tr zv) - zv e^(-sigma_tr dv(R)) / dv(R)]
 *  (d/dr of e^(-s d)/d is -r (s + 1/d) e^(-s d) / d^2). In [0, 1]. */
double fv_dipole_rd_disk(const fv_dipole *d, double radius);

/** Total diffuse reflectance, closed form: alpha'/2 (1 + e^(-(4/3) A sqrt(3(1 - alpha')))) e^(-sqrt(3(1 - alpha')))
 *  (Jensen et al. 2001, eq. 6 integrated; the limit of fv_dipole_rd_disk). */
double fv_dipole_rd_total(const fv_dipole *d);

/** The part of a point source's total diffuse reflectance that leaves the surface farther than `radius` from it:
 *  alpha'/2 [zr e^(-sigma_tr dr(R)) / dr(R) + zv e^(-sigma_tr dv(R)) / dv(R)] (the disk integral's complement, in
 *  closed form without cancellation). In [0, 1]; 0 for an infinite radius. */
double fv_dipole_rd_tail(const fv_dipole *d, double radius);

/** The radius beyond which at most `fraction` (in (0, 1)) of a point source's diffuse reflectance leaves:
 *  the smallest R with fv_dipole_rd_tail(R) <= fraction * (fv_dipole_rd_tail(0)), to 1e-9 relative by bisection
 *  in log R. Light entering farther than R from a receiver is dropped by the hierarchy's cutoff: on a uniformly lit
 *  plane that drops exactly `fraction` of the subsurface light. 0 when there is no scattering (alpha' = 0) or the
 *  fraction is out of range; at most FV_DIPOLE_CUTOFF_MAX units. */
#define FV_DIPOLE_CUTOFF_MAX 1e30
double fv_dipole_cutoff_radius(const fv_dipole *d, double fraction);

/** The same, by integrating 2 pi r Rd(r) dr over [0, inf) numerically: adaptive Gauss-Kronrod (7-15) in
 *  t = r / (r + zr), to a relative tolerance of 1e-12. */
double fv_dipole_rd_total_numeric(const fv_dipole *d);

/** Beyond FV_DIPOLE_KERNEL_NEAR footprint radii a footprint's mean is taken to second order,
 *  Rd + (1/2) tr(M Hessian(Rd)) with M the footprint's second moment (the mean over a region of f is
 *  f + (1/2) tr(M H) + O(size^4)); it meets the quadrature there within 1%. */
#define FV_DIPOLE_KERNEL_NEAR 4.0
/** ... and only while the footprint is small against the diffusion length: sigma_tr x radius <= this (larger
 *  footprints feel the exponential, and the quadrature is kept). */
#define FV_DIPOLE_KERNEL_SMOOTH 0.25

/** The isotropic kernel: the mean of Rd over the disk of area `area` (radius s = sqrt(area / pi)) centred `dist` from
 *  the receiver, so a sample contributes E * area * kernel. The disk is integrated in polar coordinates around the
 *  receiver: along each direction it spans radii [r1, r2] and Rd integrates in closed form (fv_dipole_rd_disk's
 *  antiderivative, differenced without cancellation); 4 Gauss-Legendre directions over the half disk. Beyond
 *  FV_DIPOLE_KERNEL_NEAR radii the second-order mean Rd + (s^2/8) Laplacian(Rd), which tends to Rd(dist) far away.
 *  The GPU uses it for a quad-tree cluster with no footprint (render/include/fv_sss_gather.glsl). area <= 0:
 *  Rd(dist). Per unit^2, finite. */
double fv_dipole_kernel(const fv_dipole *d, double dist, double area);

/** The footprint kernel: the mean of Rd over a sample's footprint, the parallelogram c +- a/2 +- b/2 (a, b: its
 *  edges, in the plane of the surface; fv_sss_texel_footprint) as seen from the receiver x, so a sample contributes
 *  E * |a x b| * kernel. The footprints of a light-view map's texels tile the surface, so on a uniformly lit plane
 *  the samples sum to the plane's total diffuse reflectance whatever the texel against the mean free path, with no
 *  ripple from where the receiver lies among them (a point or disk per sample leaves rings: issue 28).
 *  Integrated exactly in the radius: the receiver's foot on the footprint's plane (height h) sees each edge as a
 *  triangle; along direction phi the triangle spans [0, rho(phi)] and Rd(sqrt(rho^2 + h^2)) integrates in closed
 *  form; 4 Gauss-Legendre directions per edge. An edge shared by two footprints is evaluated at the same directions
 *  from both sides, so the quadrature's error cancels between neighbours and the tiling stays exact. The radial
 *  integral is taken relative to the footprint's centre distance (no cancellation far away). Beyond
 *  FV_DIPOLE_KERNEL_NEAR half-diagonals the second-order mean with M = (a a^T + b b^T) / 12 (while sigma_tr x
 *  half-diagonal <= FV_DIPOLE_KERNEL_SMOOTH; beyond, the disk of its area, as fv_dipole_kernel's quadrature). A degenerate footprint (|a x b| = 0): Rd(|c - x|). Per unit^2, finite. */
double fv_dipole_tile_kernel(const fv_dipole *d, const double c[3], const double a[3], const double b[3],
                             const double x[3]);

/** Schlick's Fresnel transmittance 1 - F, F = F0 + (1 - F0)(1 - cos)^5, F0 = ((eta - 1)/(eta + 1))^2, for the cosine
 *  between the direction and the normal (clamped to [0, 1]). In [0, 1]. */
double fv_fresnel_transmittance(double eta, double cos_theta);

#endif
