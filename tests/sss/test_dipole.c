/* @brief The dipole diffusion approximation (render/sss/fv_dipole.h) without a GPU: Rd(r) integrated numerically over
 * the plane equals the closed-form total diffuse reflectance for every measured material of Jensen et al. 2001
 * (../shared/data/materials/jensen2001.csv) and eta in {1.0, 1.3, 1.5}; sigma_a = 0 reflects everything; the disk
 * integral, the footprint kernels and the Fresnel transmittance at their limits; every extreme stays finite. */
#define _POSIX_C_SOURCE 200809L
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fv_dipole.h"
#include "fv_test.h"

#define PI 3.14159265358979323846

typedef struct row {
    char name[32];
    double sp[3], sa[3], eta;
} row;

/* The shared CSV: material, sigma_s' r g b, sigma_a r g b (mm^-1), eta, cross-checked. */
static int read_materials(row *out, int cap)
{
    size_t len = 0;
    char *text = fv_test_read_file(fv_test_data("materials/jensen2001.csv"), &len);
    int n = 0;
    char *save = NULL;
    char *line = strtok_r(text, "\n", &save); /* header */
    assert_non_null(line);
    assert_non_null(strstr(line, "sigma_s_prime_r_per_mm"));
    while ((line = strtok_r(NULL, "\n", &save)) && n < cap) {
        row *r = &out[n];
        char cross[8];
        int got = sscanf(line, "%31[^,],%lf,%lf,%lf,%lf,%lf,%lf,%lf,%7s", r->name, &r->sp[0], &r->sp[1], &r->sp[2],
                         &r->sa[0], &r->sa[1], &r->sa[2], &r->eta, cross);
        if (got != 9) fail_msg("jensen2001.csv: line '%s' has %d of 9 fields", line, got);
        n++;
    }
    free(text);
    return n;
}

static void rd_integrates_to_the_closed_form_for_every_jensen_material(void **state)
{
    (void)state;
    row rows[32];
    int n = read_materials(rows, 32);
    assert_int_equal(n, 12);
    const double etas[] = {1.0, 1.3, 1.5, -1.0 /* the table's own */};
    double worst = 0.0;
    for (int i = 0; i < n; i++)
        for (int e = 0; e < 4; e++)
            for (int c = 0; c < 3; c++) {
                double eta = etas[e] > 0 ? etas[e] : rows[i].eta;
                fv_dipole d = fv_dipole_make(rows[i].sa[c], rows[i].sp[c], eta);
                double closed = fv_dipole_rd_total(&d), numeric = fv_dipole_rd_total_numeric(&d);
                assert_true(closed > 0.0 && closed <= 1.0);
                double rel = fabs(numeric - closed) / closed;
                if (rel > worst) worst = rel;
                if (rel > 1e-6)
                    fail_msg("%s channel %d eta %.2f: numeric %.12g closed %.12g (rel %.3g)", rows[i].name, c, eta,
                             numeric, closed, rel);
                /* The disk integral grows to the same total. */
                double disk = fv_dipole_rd_disk(&d, 1e13 * d.zr);
                assert_true(fabs(disk - closed) <= 1e-9 * closed);
                /* The derived quantities follow their definitions. */
                assert_true(fabs(d.sigma_t_prime - (rows[i].sa[c] + rows[i].sp[c])) <= 1e-15 * d.sigma_t_prime);
                assert_true(fabs(d.zv - d.zr * (1.0 + 4.0 * d.a / 3.0)) <= 1e-15 * d.zv);
                assert_true(fabs(d.sigma_tr - sqrt(3.0 * d.sigma_a * d.sigma_t_prime)) <= 1e-12 * (d.sigma_tr + 1e-300));
            }
    print_message("worst relative difference numeric vs closed form: %.3g\n", worst);
    /* Marble (Jensen et al. 2001, fig. 5) reflects most light back: every channel's total exceeds 0.7. */
    for (int i = 0; i < n; i++) {
        if (strcmp(rows[i].name, "Marble")) continue;
        for (int c = 0; c < 3; c++) {
            fv_dipole d = fv_dipole_make(rows[i].sa[c], rows[i].sp[c], rows[i].eta);
            if (!(fv_dipole_rd_total(&d) > 0.7)) fail_msg("marble channel %d: total %g", c, fv_dipole_rd_total(&d));
        }
    }
}

static void no_absorption_reflects_everything(void **state)
{
    (void)state;
    const double etas[] = {1.0, 1.3, 1.5, 0.7, 2.5};
    const double sps[] = {1e-3, 1.0, 11.6, 1e3};
    for (int e = 0; e < 5; e++)
        for (int s = 0; s < 4; s++) {
            fv_dipole d = fv_dipole_make(0.0, sps[s], etas[e]);
            assert_true(d.sigma_tr == 0.0);
            assert_true(d.alpha_prime == 1.0);
            double closed = fv_dipole_rd_total(&d), numeric = fv_dipole_rd_total_numeric(&d);
            if (fabs(closed - 1.0) > 1e-12 || fabs(numeric - 1.0) > 1e-6)
                fail_msg("sigma_a 0, sigma_s' %g, eta %g: closed %.12g numeric %.12g", sps[s], etas[e], closed, numeric);
        }
}

static void extremes_stay_finite(void **state)
{
    (void)state;
    const double coeffs[] = {0.0, -1.0, NAN, INFINITY, -INFINITY, 1e-300, 1e-30, 1.0, 1e30, 1e300, DBL_MAX};
    const double etas[] = {1.0, 0.0, -1.0, NAN, INFINITY, 1e-9, 1e9, 1.3};
    const double rs[] = {0.0, -1.0, NAN, INFINITY, 1e-300, 1e-12, 1.0, 1e300};
    const size_t nc = sizeof coeffs / sizeof *coeffs, ne = sizeof etas / sizeof *etas, nr = sizeof rs / sizeof *rs;
    for (size_t a = 0; a < nc; a++)
        for (size_t s = 0; s < nc; s++)
            for (size_t e = 0; e < ne; e++) {
                fv_dipole d = fv_dipole_make(coeffs[a], coeffs[s], etas[e]);
                const double *f = &d.sigma_a;
                for (size_t k = 0; k < sizeof d / sizeof(double); k++)
                    if (!isfinite(f[k])) fail_msg("sigma_a %g sigma_s' %g eta %g: field %zu = %g", coeffs[a], coeffs[s],
                                                  etas[e], k, f[k]);
                double t = fv_dipole_rd_total(&d);
                assert_true(isfinite(t) && t >= 0.0 && t <= 1.0);
                for (size_t r = 0; r < nr; r++) {
                    double v = fv_dipole_rd(&d, rs[r]);
                    double k1 = fv_dipole_kernel(&d, rs[r], 1e-6), k2 = fv_dipole_kernel(&d, rs[r], rs[r]);
                    double disk = fv_dipole_rd_disk(&d, rs[r]);
                    if (!(isfinite(v) && v >= 0 && isfinite(k1) && k1 >= 0 && isfinite(k2) && k2 >= 0 && isfinite(disk)))
                        fail_msg("sigma_a %g sigma_s' %g eta %g r %g: Rd %g kernel %g %g disk %g", coeffs[a], coeffs[s],
                                 etas[e], rs[r], v, k1, k2, disk);
                }
            }
    /* sigma_s' = 0: nothing scatters back. */
    fv_dipole d = fv_dipole_make(0.5, 0.0, 1.3);
    assert_true(fv_dipole_rd(&d, 0.0) == 0.0 && fv_dipole_rd_total(&d) == 0.0 && fv_dipole_rd_total_numeric(&d) == 0.0);
    /* eta = 1: Fdr is the fit's small value, A about 1. */
    d = fv_dipole_make(0.01, 1.0, 1.0);
    assert_true(d.fdr >= 0.0 && d.fdr < 0.01 && fabs(d.a - 1.0) < 0.01);
    /* r = 0 is the profile's peak, finite, and Rd falls with r. */
    d = fv_dipole_make(0.0021, 2.19, 1.5);
    double prev = fv_dipole_rd(&d, 0.0);
    assert_true(isfinite(prev) && prev > 0.0);
    for (double r = 1e-3; r < 100.0; r *= 1.5) {
        double v = fv_dipole_rd(&d, r);
        assert_true(v <= prev);
        prev = v;
    }
    /* Huge coefficients: a point-like profile with a finite total. */
    d = fv_dipole_make(1e300, 1e300, 1.5);
    assert_true(isfinite(fv_dipole_rd(&d, 0.0)) && isfinite(fv_dipole_rd_total_numeric(&d)));
}

static void disk_integral_matches_numeric_integration(void **state)
{
    (void)state;
    fv_dipole d = fv_dipole_make(0.0021, 2.19, 1.5); /* marble, red, mm */
    const double radii[] = {0.01, 0.1, 0.5, 1.0, 3.0, 10.0, 50.0};
    for (int i = 0; i < 7; i++) {
        double R = radii[i];
        /* Composite Simpson in r on 200000 panels. */
        int n = 200000;
        double h = R / n, sum = 0.0;
        for (int k = 0; k <= n; k++) {
            double r = k * h;
            double w = (k == 0 || k == n) ? 1.0 : (k % 2 ? 4.0 : 2.0);
            sum += w * 2.0 * PI * r * fv_dipole_rd(&d, r);
        }
        sum *= h / 3.0;
        double disk = fv_dipole_rd_disk(&d, R);
        if (fabs(sum - disk) > 1e-7 * disk) fail_msg("R %g: Simpson %.12g closed %.12g", R, sum, disk);
    }
}

static void kernel_is_rd_far_away_and_the_disk_integral_on_top(void **state)
{
    (void)state;
    fv_dipole d = fv_dipole_make(0.0041, 2.62, 1.5); /* marble, green, mm */
    /* A small sample far from the receiver: the point value. */
    for (double dist = 0.5; dist < 40.0; dist *= 2.0) {
        double k = fv_dipole_kernel(&d, dist, 1e-8), rd = fv_dipole_rd(&d, dist);
        if (fabs(k - rd) > 1e-6 * rd) fail_msg("dist %g: kernel %.12g Rd %.12g", dist, k, rd);
    }
    /* The second-order mean takes over smoothly from the quadrature at FV_DIPOLE_KERNEL_NEAR radii. */
    for (double area = 0.01; area < 30.0; area *= 3.0) {
        double s = sqrt(area / PI), r = FV_DIPOLE_KERNEL_NEAR * s;
        double in = fv_dipole_kernel(&d, r * (1.0 - 1e-9), area), out = fv_dipole_kernel(&d, r * (1.0 + 1e-9), area);
        if (fabs(in - out) > 0.01 * in) fail_msg("area %g: kernel %.6g inside, %.6g outside the switch", area, in, out);
    }
    /* On top of the receiver: the disk integral over the disk of the sample's area, over that area. */
    const double areas[] = {1e-4, 0.01, 1.0, 25.0};
    for (int i = 0; i < 4; i++) {
        double s = sqrt(areas[i] / PI), want = fv_dipole_rd_disk(&d, s) / areas[i];
        double k = fv_dipole_kernel(&d, 0.0, areas[i]);
        if (fabs(k - want) > 1e-9 * want) fail_msg("area %g on top: kernel %.12g, disk integral %.12g", areas[i], k, want);
    }
    /* The footprint kernel of a square footprint far away is the isotropic kernel of its area (both tend to Rd),
     * and on top of its centre it lies between the disk integrals of its inscribed and circumscribed disks. */
    const double c[3] = {0, 0, 0}, a[3] = {1.0, 0, 0}, b[3] = {0, 1.0, 0};
    for (double dist = 5.0; dist < 40.0; dist *= 2.0) {
        const double x[3] = {dist * 0.6, dist * 0.8, 0.0};
        double kt = fv_dipole_tile_kernel(&d, c, a, b, x), ki = fv_dipole_kernel(&d, dist, 1.0);
        if (fabs(kt - ki) > 3e-3 * ki) fail_msg("dist %g: square footprint %.9g, disk of its area %.9g", dist, kt, ki);
    }
    const double x0[3] = {0, 0, 0};
    double top = fv_dipole_tile_kernel(&d, c, a, b, x0);
    assert_true(top < fv_dipole_rd_disk(&d, 0.5) / (PI * 0.25) && top > fv_dipole_rd_disk(&d, sqrt(0.5)) / (PI * 0.5));
}

static void fresnel_transmittance_at_its_limits(void **state)
{
    (void)state;
    for (double c = 0.0; c <= 1.0; c += 0.125) /* eta = 1: F0 = 0, Ft = 1 - (1 - c)^5 */
        assert_true(fabs(fv_fresnel_transmittance(1.0, c) - (1.0 - pow(1.0 - c, 5.0))) < 1e-15);
    assert_true(fv_fresnel_transmittance(1.0, 0.0) == 0.0); /* Schlick: F = F0 + (1 - F0) 1^5 = 1 at grazing */
    double f0 = pow((1.5 - 1.0) / 2.5, 2.0);
    assert_true(fabs(fv_fresnel_transmittance(1.5, 1.0) - (1.0 - f0)) < 1e-15);
    assert_true(fv_fresnel_transmittance(1.5, 0.0) == 0.0);
    assert_true(fv_fresnel_transmittance(1.3, -1.0) == 0.0);
    assert_true(fv_fresnel_transmittance(1.3, 2.0) == fv_fresnel_transmittance(1.3, 1.0));
    double prev = -1.0;
    for (double c = 0.0; c <= 1.0; c += 0.01) {
        double t = fv_fresnel_transmittance(1.5, c);
        assert_true(t >= prev && t >= 0.0 && t <= 1.0);
        prev = t;
    }
    assert_true(isfinite(fv_fresnel_transmittance(NAN, NAN)) && isfinite(fv_fresnel_transmittance(INFINITY, 0.5)));
}

/* The tail beyond R is the disk integral's complement; the cutoff radius drops exactly the fraction asked, for every
 * Jensen material and eta, and grows as the fraction shrinks; extremes give 0 or a finite radius, never NaN/Inf. */
static void tail_and_cutoff_radius_drop_the_fraction_asked(void **state)
{
    (void)state;
    row rows[32];
    int n = read_materials(rows, 32);
    assert_int_equal(n, 12);
    const double etas[] = {1.0, 1.3, 1.5};
    const double fractions[] = {0.1, 0.01, 0.005, 0.001, 1e-6};
    double worst = 0.0;
    for (int i = 0; i < n; i++)
        for (int e = 0; e < 3; e++)
            for (int c = 0; c < 3; c++) {
                fv_dipole d = fv_dipole_make(rows[i].sa[c], rows[i].sp[c], etas[e]);
                double total = fv_dipole_rd_total(&d);
                if (fabs(fv_dipole_rd_tail(&d, 0.0) - total) > 1e-12 * total)
                    fail_msg("%s eta %g: tail(0) %.15g, total %.15g", rows[i].name, etas[e], fv_dipole_rd_tail(&d, 0.0),
                             total);
                for (double r = 0.01; r < 100.0; r *= 3.0)
                    if (fabs(fv_dipole_rd_tail(&d, r) + fv_dipole_rd_disk(&d, r) - total) > 1e-12)
                        fail_msg("%s: tail + disk at %g mm is not the total", rows[i].name, r);
                double prev = 0.0;
                for (int f = 0; f < 5; f++) {
                    double R = fv_dipole_cutoff_radius(&d, fractions[f]);
                    assert_true(isfinite(R) && R > prev);
                    double got = fv_dipole_rd_tail(&d, R) / total;
                    double rel = fabs(got - fractions[f]) / fractions[f];
                    if (rel > worst) worst = rel;
                    if (rel > 1e-6) fail_msg("%s eta %g ch %d: cutoff %.6g mm drops %.9g, not %g", rows[i].name,
                                             etas[e], c, R, got, fractions[f]);
                    prev = R;
                }
            }
    print_message("cutoff radius: worst relative error of the dropped fraction %.3g\n", worst);
    /* Marble (red, mm): 0.5% of the light leaves beyond a few diffusion lengths 1/sigma_tr = 8.5 mm. */
    fv_dipole m = fv_dipole_make(0.0021, 2.19, 1.5);
    double R = fv_dipole_cutoff_radius(&m, 0.005);
    print_message("marble red: 0.5%% beyond %.2f mm (1/sigma_tr = %.2f mm)\n", R, 1.0 / m.sigma_tr);
    assert_true(R > 1.0 / m.sigma_tr && R < 10.0 / m.sigma_tr);
    /* Extremes: no absorption (sigma_tr = 0: the tail falls as zr/R), huge coefficients, no scattering, bad
     * fractions. */
    fv_dipole z = fv_dipole_make(0.0, 1.0, 1.3);
    R = fv_dipole_cutoff_radius(&z, 0.01);
    assert_true(isfinite(R) && R > 0.0 && fabs(fv_dipole_rd_tail(&z, R) / fv_dipole_rd_total(&z) - 0.01) < 1e-6);
    fv_dipole h = fv_dipole_make(1e300, 1e300, 1.5);
    R = fv_dipole_cutoff_radius(&h, 0.01);
    assert_true(isfinite(R) && R >= 0.0);
    fv_dipole none = fv_dipole_make(1.0, 0.0, 1.5);
    assert_true(fv_dipole_cutoff_radius(&none, 0.01) == 0.0 && fv_dipole_rd_tail(&none, 1.0) == 0.0);
    const double bad[] = {0.0, 1.0, -0.5, 2.0, NAN, INFINITY};
    for (int k = 0; k < 6; k++) assert_true(fv_dipole_cutoff_radius(&m, bad[k]) == 0.0);
    assert_true(fv_dipole_rd_tail(&m, INFINITY) == 0.0 && fv_dipole_rd_tail(&m, NAN) == 0.0 &&
                fv_dipole_rd_tail(&m, -1.0) == 0.0 && fv_dipole_rd_tail(NULL, 1.0) == 0.0);
    assert_true(fv_dipole_cutoff_radius(NULL, 0.01) == 0.0);
    fv_dipole eta1 = fv_dipole_make(0.0021, 2.19, 1.0);
    assert_true(isfinite(fv_dipole_cutoff_radius(&eta1, 1e-12)));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(rd_integrates_to_the_closed_form_for_every_jensen_material),
        cmocka_unit_test(no_absorption_reflects_everything),
        cmocka_unit_test(extremes_stay_finite),
        cmocka_unit_test(disk_integral_matches_numeric_integration),
        cmocka_unit_test(kernel_is_rd_far_away_and_the_disk_integral_on_top),
        cmocka_unit_test(fresnel_transmittance_at_its_limits),
        cmocka_unit_test(tail_and_cutoff_radius_drop_the_fraction_asked),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
