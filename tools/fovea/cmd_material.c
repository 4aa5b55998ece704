/* @brief `fovea material`: the dipole diffusion quantities of a translucent material (Jensen et al. 2001; the
 * corrected profile of ../shared/papers/README.md section 4) per RGB channel, from a measured preset or given
 * coefficients: sigma_t', alpha', sigma_tr, zr, zv, Fdr, A, and the total diffuse reflectance in closed form and
 * integrated numerically from the profile the renderer uses (render/sss/fv_dipole.h). */
#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "cli.h"
#include "fv_dipole.h"
#include "fv_scene.h"

static const char *const USAGE =
    "usage: fovea material NAME [--json]\n"
    "       fovea material --sigma-a R,G,B --sigma-s R,G,B --eta E [--json]\n"
    "\n"
    "The dipole diffusion approximation of a translucent material, per RGB channel: sigma_t' = sigma_a + sigma_s',\n"
    "alpha' = sigma_s' / sigma_t', sigma_tr = sqrt(3 sigma_a sigma_t'), zr = 1 / sigma_t', zv = zr (1 + 4A/3),\n"
    "Fdr(eta), A = (1 + Fdr) / (1 - Fdr), and the total diffuse reflectance: rd_total_closed (closed form) and\n"
    "rd_total_numeric (Rd(r) 2 pi r integrated over the plane, the profile the renderer uses).\n"
    "  NAME        a measured material of Jensen et al. 2001 (case-insensitive): apple, chicken1, chicken2, cream,\n"
    "              ketchup, marble, potato, skimmilk, skin1, skin2, spectralon, wholemilk\n"
    "  --sigma-a   absorption coefficient per channel, mm^-1 (0 or 1e-6..1e6)\n"
    "  --sigma-s   reduced scattering coefficient sigma_s' per channel, mm^-1 (0 or 1e-6..1e6)\n"
    "  --eta       relative index of refraction (0.01..100)\n"
    "  --json      one JSON object on stdout (lengths in mm, coefficients in mm^-1)\n";

/* "R,G,B": three coefficients, each 0 or in FV_SCENE_SIGMA_MIN_PER_MM..FV_SCENE_SIGMA_MAX_PER_MM (the scene file's
 * range, fv_translucency_coefficient_problem). NULL when they are, else why not (in why, one phrase). A value below
 * the double range (a denormal such as 1e-310) is read as the tiny number it is, not refused as "not a number". */
static const char *parse_rgb(const char *s, double out[3], char *why, size_t why_size)
{
    char buf[192];
    if (!s || strlen(s) >= sizeof buf) return "need R,G,B, three numbers";
    memcpy(buf, s, strlen(s) + 1);
    char *parts[3];
    char *p = buf;
    for (int k = 0; k < 3; k++) {
        parts[k] = p;
        char *comma = strchr(p, ',');
        if (k < 2) {
            if (!comma) return "need R,G,B, three numbers";
            *comma = '\0';
            p = comma + 1;
        } else if (comma) {
            return "need R,G,B, three numbers";
        }
    }
    for (int k = 0; k < 3; k++) {
        char *end = NULL;
        double v = strtod(parts[k], &end);
        if (!*parts[k] || isspace((unsigned char)parts[k][0]) || *end != '\0')
            return "need R,G,B, three numbers";
        const char *bad = fv_translucency_coefficient_problem(v);
        if (bad) {
            snprintf(why, why_size, "%s %s", parts[k], bad);
            return why;
        }
        out[k] = v;
    }
    return NULL;
}

static cJSON *triple(const double v[3])
{
    cJSON *a = cJSON_CreateArray();
    for (int k = 0; k < 3; k++) cJSON_AddItemToArray(a, cJSON_CreateNumber(v[k]));
    return a;
}

int fv_cmd_material(int argc, char **argv)
{
    const char *name = NULL, *v = NULL;
    const char *sa_arg = NULL, *ss_arg = NULL, *eta_arg = NULL;
    bool json = false;
    int r;
    for (int i = 1; i < argc; i++) {
        if (fv_cli_is_help(argv[i])) {
            fputs(USAGE, stdout);
            return FV_EXIT_OK;
        }
        if (strcmp(argv[i], "--json") == 0) {
            json = true;
        } else if ((r = FV_CLI_OPT("material", USAGE, "--sigma-a")) != 0) {
            if (r < 0) return FV_EXIT_USAGE;
            sa_arg = v;
        } else if ((r = FV_CLI_OPT("material", USAGE, "--sigma-s")) != 0) {
            if (r < 0) return FV_EXIT_USAGE;
            ss_arg = v;
        } else if ((r = FV_CLI_OPT("material", USAGE, "--eta")) != 0) {
            if (r < 0) return FV_EXIT_USAGE;
            eta_arg = v;
        } else if (argv[i][0] == '-') {
            return fv_cli_usage_error("material", USAGE, "unknown option '%s'", argv[i]);
        } else if (name) {
            return fv_cli_usage_error("material", USAGE, "one material at a time ('%s' and '%s')", name, argv[i]);
        } else {
            name = argv[i];
        }
    }
    double sa[3], ss[3], eta;
    char label[40] = "";
    if (name) {
        if (sa_arg || ss_arg || eta_arg)
            return fv_cli_usage_error("material", USAGE, "give NAME or --sigma-a/--sigma-s/--eta, not both");
        fv_translucency t;
        if (fv_translucency_preset(name, &t) != FV_OK) {
            char known[256] = "";
            size_t at = 0;
            for (const char *const *n = fv_translucency_preset_names(); *n && at < sizeof known; n++) {
                int w = snprintf(known + at, sizeof known - at, "%s%s", at ? ", " : "", *n);
                if (w < 0) break;
                at += (size_t)w;
            }
            return fv_cli_usage_error("material", USAGE, "no measured material '%s' (known: %s)", name, known);
        }
        for (int k = 0; k < 3; k++) {
            sa[k] = t.sigma_a_per_mm[k];
            ss[k] = t.sigma_s_prime_per_mm[k];
        }
        eta = t.eta;
        snprintf(label, sizeof label, "%s", t.preset);
    } else {
        if (!sa_arg || !ss_arg || !eta_arg)
            return fv_cli_usage_error("material", USAGE, "give a material NAME, or all of --sigma-a, --sigma-s and --eta");
        char why[400];
        const char *bad = parse_rgb(sa_arg, sa, why, sizeof why);
        if (bad) return fv_cli_usage_error("material", USAGE, "--sigma-a '%s': %s", sa_arg, bad);
        if ((bad = parse_rgb(ss_arg, ss, why, sizeof why)))
            return fv_cli_usage_error("material", USAGE, "--sigma-s '%s': %s", ss_arg, bad);
        if (!fv_cli_parse_f64(eta_arg, 0.01, 100.0, &eta))
            return fv_cli_usage_error("material", USAGE, "--eta '%s': need a number in 0.01..100", eta_arg);
    }
    fv_dipole d[3];
    double st[3], ap[3], tr[3], zr[3], zv[3], closed[3], numeric[3];
    for (int k = 0; k < 3; k++) {
        d[k] = fv_dipole_make(sa[k], ss[k], eta);
        st[k] = d[k].sigma_t_prime;
        ap[k] = d[k].alpha_prime;
        tr[k] = d[k].sigma_tr;
        zr[k] = d[k].zr;
        zv[k] = d[k].zv;
        closed[k] = fv_dipole_rd_total(&d[k]);
        numeric[k] = fv_dipole_rd_total_numeric(&d[k]);
    }
    if (json) {
        cJSON *root = cJSON_CreateObject();
        if (label[0]) fv_cli_json_add_string(root, "material", label);
        else cJSON_AddNullToObject(root, "material");
        fv_cli_json_add_string(root, "length_unit", "mm");
        cJSON_AddNumberToObject(root, "eta", eta);
        cJSON_AddNumberToObject(root, "fdr", d[0].fdr);
        cJSON_AddNumberToObject(root, "a", d[0].a);
        cJSON_AddItemToObject(root, "sigma_a_per_mm", triple(sa));
        cJSON_AddItemToObject(root, "sigma_s_prime_per_mm", triple(ss));
        cJSON_AddItemToObject(root, "sigma_t_prime_per_mm", triple(st));
        cJSON_AddItemToObject(root, "alpha_prime", triple(ap));
        cJSON_AddItemToObject(root, "sigma_tr_per_mm", triple(tr));
        cJSON_AddItemToObject(root, "zr_mm", triple(zr));
        cJSON_AddItemToObject(root, "zv_mm", triple(zv));
        cJSON_AddItemToObject(root, "rd_total_closed", triple(closed));
        cJSON_AddItemToObject(root, "rd_total_numeric", triple(numeric));
        int rc = fv_cli_json_print(root, false);
        cJSON_Delete(root);
        return rc;
    }
    printf("material: %s   eta %.4g   Fdr %.6f   A %.6f   (lengths mm, coefficients mm^-1)\n",
           label[0] ? label : "(given coefficients)", eta, d[0].fdr, d[0].a);
    printf("%-22s %14s %14s %14s\n", "", "r", "g", "b");
    const struct {
        const char *name;
        const double *v;
    } rows[] = {{"sigma_a", sa},       {"sigma_s'", ss},       {"sigma_t'", st}, {"alpha'", ap},
                {"sigma_tr", tr},      {"zr", zr},             {"zv", zv},       {"rd_total_closed", closed},
                {"rd_total_numeric", numeric}};
    for (size_t i = 0; i < sizeof rows / sizeof rows[0]; i++)
        printf("%-22s %14.7g %14.7g %14.7g\n", rows[i].name, rows[i].v[0], rows[i].v[1], rows[i].v[2]);
    return FV_EXIT_OK;
}
