/* @brief The dipole diffusion approximation in double (see fv_dipole.h). */
#include "fv_dipole.h"

#include <float.h>
#include <math.h>

#define PI 3.14159265358979323846
#define COEFF_MAX 1e300 /* larger coefficients are clamped: every product below stays finite */

static double sane_coeff(double c) { return isfinite(c) && c > 0.0 ? fmin(c, COEFF_MAX) : (c > 0.0 ? COEFF_MAX : 0.0); }

double fv_dipole_fdr(double eta)
{
    if (!(isfinite(eta) && eta > 0.0 && eta <= 1e3)) eta = 1.0;
    double f = eta >= 1.0 ? -1.440 / (eta * eta) + 0.710 / eta + 0.668 + 0.0636 * eta
                          : -0.4399 + 0.7099 / eta - 0.3319 / (eta * eta) + 0.0636 / (eta * eta * eta);
    return fmin(fmax(f, 0.0), 0.999);
}

fv_dipole fv_dipole_make(double sigma_a, double sigma_s_prime, double eta)
{
    fv_dipole d = {0};
    d.sigma_a = sane_coeff(sigma_a);
    d.sigma_s_prime = sane_coeff(sigma_s_prime);
    d.eta = isfinite(eta) && eta > 0.0 && eta <= 1e3 ? eta : 1.0;
    d.sigma_t_prime = d.sigma_a + d.sigma_s_prime;
    d.fdr = fv_dipole_fdr(d.eta);
    d.a = (1.0 + d.fdr) / (1.0 - d.fdr);
    if (d.sigma_t_prime > 0.0) {
        d.alpha_prime = d.sigma_s_prime / d.sigma_t_prime;
        d.sigma_tr = sqrt(3.0) * sqrt(d.sigma_a) * sqrt(d.sigma_t_prime);
        d.zr = 1.0 / d.sigma_t_prime;
        d.zv = d.zr * (1.0 + 4.0 * d.a / 3.0);
    }
    return d;
}

/* z (s + 1/x) e^(-s x) / x^2 in log space, so that neither a tiny x nor a huge s overflows. */
static double source_term(double z, double s, double x)
{
    if (!(z > 0.0) || !(x > 0.0)) return 0.0;
    double lg = log(z) + log(s + 1.0 / x) - s * x - 2.0 * log(x);
    return exp(fmin(lg, 700.0));
}

double fv_dipole_rd(const fv_dipole *d, double r)
{
    if (!d || !(r >= 0.0) || !(d->alpha_prime > 0.0)) return 0.0;
    if (!isfinite(r)) return 0.0;
    double dr = hypot(r, d->zr), dv = hypot(r, d->zv);
    double v = d->alpha_prime / (4.0 * PI) * (source_term(d->zr, d->sigma_tr, dr) + source_term(d->zv, d->sigma_tr, dv));
    return isfinite(v) ? fmin(v, DBL_MAX) : DBL_MAX;
}

double fv_dipole_rd_disk(const fv_dipole *d, double radius)
{
    if (!d || !(d->alpha_prime > 0.0) || !(radius > 0.0)) return 0.0;
    double s = d->sigma_tr;
    double far_r = 0.0, far_v = 0.0;
    if (isfinite(radius)) {
        double dr = hypot(radius, d->zr), dv = hypot(radius, d->zv);
        far_r = d->zr / dr * exp(-s * dr);
        far_v = d->zv / dv * exp(-s * dv);
    }
    double v = 0.5 * d->alpha_prime * (exp(-s * d->zr) - far_r + exp(-s * d->zv) - far_v);
    return fmin(fmax(v, 0.0), 1.0);
}

double fv_dipole_rd_tail(const fv_dipole *d, double radius)
{
    if (!d || !(d->alpha_prime > 0.0) || !(radius >= 0.0) || !isfinite(radius)) return 0.0;
    double dr = hypot(radius, d->zr), dv = hypot(radius, d->zv);
    double v = 0.5 * d->alpha_prime * (d->zr / dr * exp(-d->sigma_tr * dr) + d->zv / dv * exp(-d->sigma_tr * dv));
    return isfinite(v) ? fmin(fmax(v, 0.0), 1.0) : 0.0;
}

double fv_dipole_cutoff_radius(const fv_dipole *d, double fraction)
{
    if (!d || !(d->alpha_prime > 0.0) || !(fraction > 0.0 && fraction < 1.0)) return 0.0;
    double want = fraction * fv_dipole_rd_tail(d, 0.0);
    if (!(want > 0.0)) return 0.0;
    /* The tail falls monotonically from its value at 0; bracket the radius in powers of two of zr, then bisect. */
    double lo = 0.0, hi = d->zr > 0.0 ? d->zr : 1.0;
    while (fv_dipole_rd_tail(d, hi) > want) {
        lo = hi;
        hi *= 2.0;
        if (hi >= FV_DIPOLE_CUTOFF_MAX) return FV_DIPOLE_CUTOFF_MAX;
    }
    for (int k = 0; k < 200 && hi - lo > 1e-9 * hi; k++) {
        double mid = 0.5 * (lo + hi);
        if (fv_dipole_rd_tail(d, mid) > want) lo = mid;
        else hi = mid;
    }
    return hi;
}

double fv_dipole_rd_total(const fv_dipole *d)
{
    if (!d || !(d->alpha_prime > 0.0)) return 0.0;
    double q = sqrt(3.0 * fmax(1.0 - d->alpha_prime, 0.0));
    double v = 0.5 * d->alpha_prime * (1.0 + exp(-4.0 / 3.0 * d->a * q)) * exp(-q);
    return fmin(fmax(v, 0.0), 1.0);
}

/* ---- numeric integration: adaptive Gauss-Kronrod 7-15 (nodes and weights of QUADPACK's qk15) ---------------- */
static const double xgk[8] = {0.991455371120812639206854697526329, 0.949107912342758524526189684047851,
                              0.864864423359769072789712788640926, 0.741531185599394439863864773280788,
                              0.586087235467691130294144845693013, 0.405845151377397166906606412076961,
                              0.207784955007898467600689403773245, 0.0};
static const double wgk[8] = {0.022935322010529224963732008058970, 0.063092092629978553290700663189204,
                              0.104790010322250183839876322541518, 0.140653259715525918745189590510238,
                              0.169004726639267902826583426598550, 0.190350578064785409913256402421014,
                              0.204432940075298892414161999234649, 0.209482141084727828012999174891714};
static const double wg[4] = {0.129484966168869693270611432679082, 0.279705391489276667901467771423780,
                             0.381830050505118944950369775488975, 0.417959183673469387755102040816327};

/* 2 pi r Rd(r) dr/dt at r = zr t / (1 - t). */
static double integrand(const fv_dipole *d, double t)
{
    if (!(t > 0.0) || !(t < 1.0)) return 0.0;
    double u = 1.0 - t;
    double r = d->zr * t / u;
    return 2.0 * PI * r * fv_dipole_rd(d, r) * d->zr / (u * u);
}

static double gk15(const fv_dipole *d, double lo, double hi, double *out_err)
{
    double c = 0.5 * (lo + hi), h = 0.5 * (hi - lo);
    double fc = integrand(d, c);
    double k = fc * wgk[7], g = fc * wg[3];
    for (int j = 0; j < 7; j++) {
        double f = integrand(d, c - h * xgk[j]) + integrand(d, c + h * xgk[j]);
        k += wgk[j] * f;
        if (j % 2 == 1) g += wg[j / 2] * f;
    }
    *out_err = fabs((k - g) * h);
    return k * h;
}

/* Bisect until the Kronrod-Gauss difference is within tol; at most *budget panels in all. */
static double adapt(const fv_dipole *d, double lo, double hi, double tol, int depth, int *budget)
{
    double err;
    double v = gk15(d, lo, hi, &err);
    if (err <= tol || depth >= 40 || *budget <= 0) return v;
    *budget -= 2;
    double mid = 0.5 * (lo + hi);
    return adapt(d, lo, mid, 0.5 * tol, depth + 1, budget) + adapt(d, mid, hi, 0.5 * tol, depth + 1, budget);
}

double fv_dipole_rd_total_numeric(const fv_dipole *in)
{
    if (!in || !(in->alpha_prime > 0.0) || !(in->zr > 0.0)) return 0.0;
    /* The total is scale-free: integrate the same material in units of its mean free path (sigma_t' = 1), so that
     * huge or tiny coefficients neither overflow nor underflow. */
    fv_dipole d = fv_dipole_make(in->sigma_a / in->sigma_t_prime, in->sigma_s_prime / in->sigma_t_prime, in->eta);
    /* A first estimate over 64 panels sets the absolute tolerance; each panel then refines on its own. */
    double est = 0.0, err;
    for (int i = 0; i < 64; i++) est += gk15(&d, i / 64.0, (i + 1) / 64.0, &err);
    double tol = 1e-13 * fmax(fabs(est), 1e-300);
    double sum = 0.0;
    int budget = 200000;
    for (int i = 0; i < 64; i++) sum += adapt(&d, i / 64.0, (i + 1) / 64.0, tol / 64.0, 0, &budget);
    return isfinite(sum) && sum > 0.0 ? fmin(sum, 1.0) : 0.0;
}

/* e^(-s x1)/x1 - e^(-s x2)/x2 with x2 = x1 + delta, without cancellation:
 * e^(-s x1)/x1 [-expm1(-s delta) + e^(-s delta) delta / x2]. */
static double source_diff(double s, double x1, double delta)
{
    if (!(x1 > 0.0)) return 0.0;
    double x2 = x1 + delta;
    double ed = exp(-s * delta);
    return exp(-s * x1) / x1 * (-expm1(-s * delta) + ed * delta / x2);
}

/* Gauss-Legendre, FV_DIPOLE_KERNEL_DIRECTIONS = 4 points on [-1, 1]. */
static const double gl_x[4] = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563, 0.8611363115940526};
static const double gl_w[4] = {0.3478548451374538, 0.6521451548625461, 0.6521451548625461, 0.3478548451374538};

/* rd_disk(r2) - rd_disk(r1) for r2 >= r1 >= 0, without cancellation (source_diff on each source's distances). */
static double disk_ring(const fv_dipole *d, double r1, double r2)
{
    double ring = (r2 - r1) * (r2 + r1);
    if (!(ring > 0.0)) return 0.0;
    double dr1 = hypot(r1, d->zr), dr2 = hypot(r2, d->zr), dv1 = hypot(r1, d->zv), dv2 = hypot(r2, d->zv);
    double v = 0.5 * d->alpha_prime * (d->zr * source_diff(d->sigma_tr, dr1, ring / (dr1 + dr2)) +
                                       d->zv * source_diff(d->sigma_tr, dv1, ring / (dv1 + dv2)));
    return v > 0.0 ? v : 0.0;
}

/* The mean of Rd over the disk of radius s centred dist from the receiver. */
static double disk_mean(const fv_dipole *d, double dist, double s)
{
    /* Polar coordinates around the receiver: along direction phi the disk spans radii [r1, r2], and the integral of
     * Rd over that wedge is (rd_disk(r2) - rd_disk(r1)) / (2 pi) per radian; by symmetry phi in [0, phi_max]. */
    double sum = 0.0, half;
    if (dist < s) { /* inside: r1 = 0, r2 = -dist cos phi + sqrt(s^2 - dist^2 sin^2 phi), phi in [0, pi] */
        half = 0.5 * PI;
        for (int k = 0; k < 4; k++) {
            double phi = half * (gl_x[k] + 1.0);
            double sn = sin(phi), c = cos(phi);
            double r2 = -dist * c + sqrt(fmax(s * s - dist * dist * sn * sn, 0.0));
            sum += gl_w[k] * disk_ring(d, 0.0, fmax(r2, 0.0));
        }
    } else { /* outside: r1,2 = dist cos phi -+ sqrt(s^2 - dist^2 sin^2 phi), phi in [0, asin(s / dist)] */
        half = 0.5 * asin(fmin(s / dist, 1.0));
        for (int k = 0; k < 4; k++) {
            double phi = half * (gl_x[k] + 1.0);
            double sn = sin(phi), c = cos(phi);
            double q = sqrt(fmax(s * s - dist * dist * sn * sn, 0.0));
            sum += gl_w[k] * disk_ring(d, fmax(dist * c - q, 0.0), dist * c + q);
        }
    }
    double v = sum * half / (PI * PI * s * s); /* (1/pi) int_0^phi_max ... dphi, over the disk's area */
    return isfinite(v) && v > 0.0 ? fmin(v, DBL_MAX) : 0.0;
}

/* One source's term of Rd at r and its radial derivatives: g(D) = z (s + 1/D) e^(-s D) / D^2 with D = sqrt(r^2 + z^2);
 * g' = -z e^(-sD)(s^2/D^2 + 3s/D^3 + 3/D^4), g'' = z e^(-sD)(s^3/D^2 + 5s^2/D^3 + 12s/D^4 + 12/D^5);
 * d^2/dr^2 g(D(r)) = g'' r^2/D^2 + g' z^2/D^3 and (1/r) d/dr g(D(r)) = g'/D. */
static void source_derivs(double z, double s, double r, double *out_g, double *out_frr, double *out_fr_r)
{
    double D = hypot(r, z);
    if (!(z > 0.0) || !(D > 0.0)) {
        *out_g = *out_frr = *out_fr_r = 0.0;
        return;
    }
    double e = z * exp(-s * D), i1 = 1.0 / D, i2 = i1 * i1, i3 = i2 * i1, i4 = i2 * i2, i5 = i4 * i1;
    double g1 = -e * (s * s * i2 + 3.0 * s * i3 + 3.0 * i4);
    double g2 = e * (s * s * s * i2 + 5.0 * s * s * i3 + 12.0 * s * i4 + 12.0 * i5);
    *out_g = e * (s + i1) * i2;
    *out_frr = g2 * r * r * i2 + g1 * z * z * i3;
    *out_fr_r = g1 * i1;
}

/* The mean of Rd over a region with second moment M about its centre, at distance r from the receiver, to second
 * order: Rd + (1/2) tr(M H), H = f_rr u u^T + (f_r / r)(I - u u^T) for the unit direction u; m_uu = u^T M u. */
static double rd_smoothed(const fv_dipole *d, double r, double m_uu, double m_trace)
{
    double v = 0.0;
    const double z[2] = {d->zr, d->zv};
    for (int k = 0; k < 2; k++) {
        double g, frr, fr_r;
        source_derivs(z[k], d->sigma_tr, r, &g, &frr, &fr_r);
        v += g + 0.5 * (frr * m_uu + fr_r * (m_trace - m_uu));
    }
    v *= d->alpha_prime / (4.0 * PI);
    return isfinite(v) && v > 0.0 ? fmin(v, DBL_MAX) : 0.0;
}

double fv_dipole_kernel(const fv_dipole *d, double dist, double area)
{
    if (!d || !(d->alpha_prime > 0.0)) return 0.0;
    if (!(dist >= 0.0) || !isfinite(dist)) return 0.0;
    if (!(area > 0.0) || !isfinite(area)) return fv_dipole_rd(d, dist);
    double s = sqrt(area / PI);
    if (!(s > 0.0)) return fv_dipole_rd(d, dist);
    if (dist > FV_DIPOLE_KERNEL_NEAR * s && d->sigma_tr * s <= FV_DIPOLE_KERNEL_SMOOTH)
        return rd_smoothed(d, dist, 0.25 * s * s, 0.5 * s * s); /* a disk: M = (s^2 / 4) I in its plane */
    return disk_mean(d, dist, s);
}

/* ---- the footprint kernel: a parallelogram ------------------------------------------------------------------ */
static double dot3(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static void cross3(const double *a, const double *b, double *o)
{
    o[0] = a[1] * b[2] - a[2] * b[1];
    o[1] = a[2] * b[0] - a[0] * b[2];
    o[2] = a[0] * b[1] - a[1] * b[0];
}

/* disk_ring(r1, r2) signed: negative when r2 < r1. */
static double ring_signed(const fv_dipole *d, double r1, double r2)
{
    return r2 >= r1 ? disk_ring(d, r1, r2) : -disk_ring(d, r2, r1);
}

/* The integral of Rd(sqrt(rho^2 + h^2)) over the parallelogram with corners q[0..3] (counter-clockwise, in the plane,
 * relative to the receiver's foot), as the sum over its edges of the triangle (foot, P, Q): along direction phi the
 * triangle spans [0, rho(phi)], rho = (P x E) / (w(phi) x E) for E = Q - P, and int_0^rho Rd(sqrt(t^2 + h^2)) t dt =
 * disk_ring(|h|, sqrt(rho^2 + h^2)) / (2 pi) = [ring_signed(R0, .) + disk_ring(|h|, R0)] / (2 pi); the constant
 * part sums to the winding angle times disk_ring(|h|, R0), zero outside the parallelogram. */
static double tile_integral(const fv_dipole *d, double q[4][2], double h)
{
    double hh = fabs(h);
    double c0 = 0.25 * (q[0][0] + q[1][0] + q[2][0] + q[3][0]), c1 = 0.25 * (q[0][1] + q[1][1] + q[2][1] + q[3][1]);
    double r0 = hypot(hypot(c0, c1), h);
    double tot = 0.0, wind = 0.0;
    for (int k = 0; k < 4; k++) {
        const double *P = q[k], *Q = q[(k + 1) & 3];
        double ex = Q[0] - P[0], ey = Q[1] - P[1];
        double cr = P[0] * ey - P[1] * ex;
        bool ends = (P[0] != 0.0 || P[1] != 0.0) && (Q[0] != 0.0 || Q[1] != 0.0);
        double dl = ends ? atan2(P[0] * Q[1] - P[1] * Q[0], P[0] * Q[0] + P[1] * Q[1]) : 0.0;
        double ph0 = ends ? atan2(P[1], P[0]) : 0.0;
        double sum = 0.0;
        for (int j = 0; j < 4; j++) {
            double ph = ph0 + 0.5 * dl * (gl_x[j] + 1.0);
            double den = cos(ph) * ey - sin(ph) * ex;
            double rho = den != 0.0 ? fmax(cr / den, 0.0) : 0.0;
            sum += gl_w[j] * ring_signed(d, r0, hypot(rho, h));
        }
        tot += 0.5 * dl * sum;
        wind += dl;
    }
    return (tot + wind * disk_ring(d, hh, r0)) / (2.0 * PI);
}

double fv_dipole_tile_kernel(const fv_dipole *d, const double c[3], const double a[3], const double b[3],
                             const double x[3])
{
    if (!d || !(d->alpha_prime > 0.0)) return 0.0;
    double off[3] = {c[0] - x[0], c[1] - x[1], c[2] - x[2]};
    double dist = sqrt(dot3(off, off));
    if (!isfinite(dist)) return 0.0;
    double n[3];
    cross3(a, b, n);
    double area = sqrt(dot3(n, n)), la = sqrt(dot3(a, a));
    if (!(area > 0.0) || !isfinite(area) || !(la > 0.0)) return fv_dipole_rd(d, dist);
    double apb[3] = {a[0] + b[0], a[1] + b[1], a[2] + b[2]}, amb[3] = {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
    double radius = 0.5 * sqrt(fmax(dot3(apb, apb), dot3(amb, amb)));
    if (dist > FV_DIPOLE_KERNEL_NEAR * radius) { /* far: the shape no longer matters to first order */
        if (d->sigma_tr * radius > FV_DIPOLE_KERNEL_SMOOTH) return disk_mean(d, dist, sqrt(area / PI));
        double ua = dot3(off, a) / dist, ub = dot3(off, b) / dist;
        return rd_smoothed(d, dist, (ua * ua + ub * ub) / 12.0, (dot3(a, a) + dot3(b, b)) / 12.0);
    }
    for (int k = 0; k < 3; k++) n[k] /= area;
    /* In-plane coordinates: e1 along a, e2 = n x e1 (so b has a positive e2 component: counter-clockwise). */
    double e1[3] = {a[0] / la, a[1] / la, a[2] / la}, e2[3];
    cross3(n, e1, e2);
    double h = dot3(off, n);
    double o0 = dot3(off, e1), o1 = dot3(off, e2); /* the centre, relative to the receiver's foot */
    double a0 = 0.5 * la, b0 = 0.5 * dot3(b, e1), b1 = 0.5 * dot3(b, e2);
    double q[4][2] = {{o0 - a0 - b0, o1 - b1}, {o0 + a0 - b0, o1 - b1}, {o0 + a0 + b0, o1 + b1}, {o0 - a0 + b0, o1 + b1}};
    double v = tile_integral(d, q, h) / area;
    return isfinite(v) && v > 0.0 ? fmin(v, DBL_MAX) : 0.0;
}

double fv_fresnel_transmittance(double eta, double cos_theta)
{
    if (!(isfinite(eta) && eta > 0.0)) eta = 1.0;
    double c = isfinite(cos_theta) ? fmin(fmax(cos_theta, 0.0), 1.0) : 0.0;
    double f0 = (eta - 1.0) / (eta + 1.0);
    f0 *= f0;
    double m = 1.0 - c, m2 = m * m;
    double f = f0 + (1.0 - f0) * m2 * m2 * m;
    return fmin(fmax(1.0 - f, 0.0), 1.0);
}
