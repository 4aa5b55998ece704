/* @brief `fovea material` as a user runs it: a measured preset and given coefficients, text and JSON, the closed
 * form against the numeric integral in the output (1e-6 relative), sigma_a = 0 reflecting everything, and bad
 * input refused with exit 2 and a line naming the option and the reason. */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>

#include "fv_test.h"

static const char *g_fovea;

static fv_test_cmd *run(const char *args)
{
    static fv_test_cmd res;
    fv_test_run_cmd(&res, NULL, g_fovea, args);
    return &res;
}

static void triple(const cJSON *root, const char *key, double out[3])
{
    const cJSON *a = cJSON_GetObjectItemCaseSensitive(root, key);
    if (!cJSON_IsArray(a) || cJSON_GetArraySize(a) != 3) fail_msg("'%s' is not an array of 3", key);
    for (int k = 0; k < 3; k++) {
        const cJSON *v = cJSON_GetArrayItem(a, k);
        assert_true(cJSON_IsNumber(v));
        out[k] = v->valuedouble;
        assert_true(isfinite(out[k]));
    }
}

static void marble_in_json_has_every_quantity_and_closed_equals_numeric(void **state)
{
    (void)state;
    fv_test_cmd *r = run("material MARBLE --json");
    if (r->exit_code != 0) fail_msg("exit %d: %s", r->exit_code, r->err);
    cJSON *root = cJSON_Parse(r->out);
    assert_non_null(root);
    assert_string_equal(cJSON_GetObjectItemCaseSensitive(root, "material")->valuestring, "Marble");
    assert_true(cJSON_GetObjectItemCaseSensitive(root, "eta")->valuedouble == 1.5);
    const char *keys[] = {"sigma_a_per_mm", "sigma_s_prime_per_mm", "sigma_t_prime_per_mm", "alpha_prime",
                          "sigma_tr_per_mm", "zr_mm", "zv_mm", "rd_total_closed", "rd_total_numeric"};
    double v[9][3];
    for (int i = 0; i < 9; i++) triple(root, keys[i], v[i]);
    double fdr = cJSON_GetObjectItemCaseSensitive(root, "fdr")->valuedouble;
    double a = cJSON_GetObjectItemCaseSensitive(root, "a")->valuedouble;
    /* Fdr(1.5) of Jensen et al. 2001's fit, and A from it. */
    assert_true(fabs(fdr - (-1.440 / 2.25 + 0.710 / 1.5 + 0.668 + 0.0636 * 1.5)) < 1e-12);
    assert_true(fabs(a - (1 + fdr) / (1 - fdr)) < 1e-12);
    for (int k = 0; k < 3; k++) {
        assert_true(fabs(v[2][k] - (v[0][k] + v[1][k])) < 1e-12);          /* sigma_t' */
        assert_true(fabs(v[5][k] - 1.0 / v[2][k]) < 1e-12);                /* zr */
        assert_true(fabs(v[6][k] - v[5][k] * (1.0 + 4.0 * a / 3.0)) < 1e-9); /* zv */
        if (fabs(v[7][k] - v[8][k]) > 1e-6 * v[7][k]) fail_msg("channel %d: closed %.12g numeric %.12g", k, v[7][k], v[8][k]);
        assert_true(v[7][k] > 0.7 && v[7][k] < 1.0);
    }
    cJSON_Delete(root);
    r = run("material skin1");
    if (r->exit_code != 0) fail_msg("exit %d: %s", r->exit_code, r->err);
    fv_assert_contains(r->out, "Skin1");
    fv_assert_contains(r->out, "rd_total_closed");
    fv_assert_contains(r->out, "rd_total_numeric");
}

static void given_coefficients_without_absorption_reflect_everything(void **state)
{
    (void)state;
    fv_test_cmd *r = run("material --sigma-a 0,0,0 --sigma-s 0.5,2,40 --eta 1.0 --json");
    if (r->exit_code != 0) fail_msg("exit %d: %s", r->exit_code, r->err);
    cJSON *root = cJSON_Parse(r->out);
    assert_non_null(root);
    assert_true(cJSON_IsNull(cJSON_GetObjectItemCaseSensitive(root, "material")));
    double c[3], n[3];
    triple(root, "rd_total_closed", c);
    triple(root, "rd_total_numeric", n);
    for (int k = 0; k < 3; k++) assert_true(fabs(c[k] - 1.0) < 1e-9 && fabs(n[k] - 1.0) < 1e-6);
    cJSON_Delete(root);
    /* No scattering at all: nothing comes back, and nothing is NaN. */
    r = run("material --sigma-a 1,1,1 --sigma-s 0,0,0 --eta 1.3 --json");
    if (r->exit_code != 0) fail_msg("exit %d: %s", r->exit_code, r->err);
    root = cJSON_Parse(r->out);
    assert_non_null(root);
    triple(root, "rd_total_numeric", n);
    for (int k = 0; k < 3; k++) assert_true(n[k] == 0.0);
    cJSON_Delete(root);
    /* the ends of the range, with the ends of eta: every quantity finite (triple checks), the closed form and the
     * integral agree (to 1e-4 there: at sigma_s'/sigma_a = 1e12 and eta 100 the quadrature is 4e-5 off) */
    const char *ends[] = {"material --sigma-a 1e-6,0,1e6 --sigma-s 1e-6,1e-6,1e6 --eta 0.01 --json",
                          "material --sigma-a 1e6,1e-6,0 --sigma-s 1e-6,1e6,1e6 --eta 100 --json"};
    for (int e = 0; e < 2; e++) {
        r = run(ends[e]);
        if (r->exit_code != 0) fail_msg("'%s': exit %d: %s", ends[e], r->exit_code, r->err);
        root = cJSON_Parse(r->out);
        assert_non_null(root);
        const char *keys[] = {"sigma_t_prime_per_mm", "alpha_prime", "sigma_tr_per_mm", "zr_mm", "zv_mm"};
        for (int i = 0; i < 5; i++) triple(root, keys[i], c);
        triple(root, "rd_total_closed", c);
        triple(root, "rd_total_numeric", n);
        for (int k = 0; k < 3; k++)
            if (!(c[k] >= 0 && c[k] <= 1 && fabs(c[k] - n[k]) <= 1e-4 * c[k] + 1e-15))
                fail_msg("'%s' channel %d: closed %.12g numeric %.12g", ends[e], k, c[k], n[k]);
        cJSON_Delete(root);
    }
}

static void bad_input_exits_2_naming_the_problem(void **state)
{
    (void)state;
    const struct {
        const char *args, *want;
    } cases[] = {
        {"material", "give a material NAME"},
        {"material jelly", "no measured material 'jelly' (known: Apple"},
        {"material --sigma-a 1,2 --sigma-s 1,1,1 --eta 1.3", "--sigma-a '1,2': need R,G,B"},
        {"material --sigma-a 1,2,3 --sigma-s 1,1,-1 --eta 1.3", "--sigma-s '1,1,-1'"},
        {"material --sigma-a 1,2,3 --sigma-s 1,1,1 --eta 0", "--eta '0': need a number in 0.01..100"},
        {"material --sigma-a 1,2,3 --sigma-s 1,1,nan --eta 1.3", "--sigma-s '1,1,nan'"},
        /* a denormal is a tiny positive number, below the smallest coefficient: said so, with the same range as
         * --help (it was "need R,G,B, three numbers in 0..1e6", which 1e-310 is) */
        {"material --sigma-a 1e-310,0.1,0.1 --sigma-s 1,1,1 --eta 1.3",
         "--sigma-a '1e-310,0.1,0.1': 1e-310 is below the smallest positive coefficient, 1e-06 mm^-1 (a coefficient "
         "is 0 or in 1e-06..1e+06 mm^-1"},
        {"material --sigma-a 1,1,1 --sigma-s 1e-40,1,1 --eta 1.3", "1e-40 is below the smallest positive coefficient"},
        {"material --sigma-a 1,1,1 --sigma-s 1,1,1.000001e6 --eta 1.3",
         "1.000001e6 is more than the largest coefficient, 1e+06 mm^-1"},
        {"material --sigma-a 1,2,3 --sigma-s 1,1,1", "all of --sigma-a, --sigma-s and --eta"},
        {"material marble --eta 1.3", "not both"},
        {"material marble skin1", "one material at a time"},
        {"material --sigma-a", "option --sigma-a needs a value"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        fv_test_cmd *r = run(cases[i].args);
        if (r->exit_code != 2) fail_msg("'%s': exit %d, want 2; stderr:\n%s", cases[i].args, r->exit_code, r->err);
        fv_assert_contains(r->err, cases[i].want);
    }
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: test_cli_material PATH_TO_FOVEA\n");
        return 2;
    }
    g_fovea = argv[1];
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(marble_in_json_has_every_quantity_and_closed_equals_numeric),
        cmocka_unit_test(given_coefficients_without_absorption_reflect_everything),
        cmocka_unit_test(bad_input_exits_2_naming_the_problem),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
