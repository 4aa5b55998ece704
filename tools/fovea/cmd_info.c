/* @brief `fovea info`: the Vulkan devices, the one fovea picks and why, and the features fovea uses. */
#include <stdio.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "cli.h"
#include "fv_vk.h"

#define MAX_DEVICES 16

static const char *const USAGE =
    "usage: fovea info [--json] [--device INDEX|NAME]\n"
    "\n"
    "List the Vulkan devices, mark the one fovea would use and why, and show the features it relies on:\n"
    "multiview (both eyes in one pass), timestamps (per-pass GPU time), subgroup size, descriptor indexing.\n"
    "  --json          one JSON object on stdout\n"
    "  --device SEL    pick by index or name substring (default: $FOVEA_DEVICE, else prefer a discrete GPU)\n";

static void version_str(uint32_t v, char *out, size_t n)
{
    snprintf(out, n, "%u.%u.%u", VK_API_VERSION_MAJOR(v), VK_API_VERSION_MINOR(v), VK_API_VERSION_PATCH(v));
}

static void print_text(const fv_vk_device_info *d, uint32_t n, int chosen, const char *why)
{
    printf("Vulkan devices: %u\n", n);
    for (uint32_t i = 0; i < n; i++) {
        char api[24];
        version_str(d[i].api_version, api, sizeof api);
        printf("%s %u: %s (%s, Vulkan %s", (int)i == chosen ? "*" : " ", d[i].index, d[i].name,
               fv_vk_device_type_str(d[i].type), api);
        if (d[i].driver_name[0]) printf(", %s %s", d[i].driver_name, d[i].driver_info);
        printf(")\n");
        if ((int)i == chosen) printf("    chosen: %s\n", why);
        if (!d[i].usable) {
            printf("    unusable: %s\n", d[i].why_not);
            continue;
        }
        char mv[96];
        bool trusted = fv_vk_multiview_trusted(&d[i], mv, sizeof mv);
        printf("    multiview: %s (max %u views); G-buffer: %s\n", d[i].multiview ? "yes" : "no",
               d[i].max_multiview_views, mv);
        (void)trusted;
        if (d[i].timestamps) printf("    timestamps: yes (period %.3g ns)\n", (double)d[i].timestamp_period_ns);
        else printf("    timestamps: no (per-pass GPU times unavailable)\n");
        printf("    subgroup size: %u; descriptor indexing: %s; storage write without format: %s\n",
               d[i].subgroup_size, d[i].descriptor_indexing ? "yes" : "no",
               d[i].storage_image_write_without_format ? "yes" : "no");
        printf("    device-local memory: %.1f MiB; max 2D image: %u px; max workgroup invocations: %u\n",
               (double)d[i].device_local_bytes / (1024.0 * 1024.0), d[i].max_image_dimension_2d,
               d[i].max_compute_workgroup_invocations);
    }
    if (chosen < 0) printf("no device chosen: %s\n", why);
}

static int print_json(const fv_vk_device_info *d, uint32_t n, int chosen, const char *why)
{
    cJSON *root = cJSON_CreateObject();
    cJSON *arr = cJSON_AddArrayToObject(root, "devices");
    for (uint32_t i = 0; i < n; i++) {
        cJSON *o = cJSON_CreateObject();
        char api[24];
        version_str(d[i].api_version, api, sizeof api);
        cJSON_AddNumberToObject(o, "index", d[i].index);
        fv_cli_json_add_string(o, "name", d[i].name);
        fv_cli_json_add_string(o, "type", fv_vk_device_type_str(d[i].type));
        fv_cli_json_add_string(o, "api_version", api);
        fv_cli_json_add_string(o, "driver", d[i].driver_name);
        fv_cli_json_add_string(o, "driver_info", d[i].driver_info);
        cJSON_AddBoolToObject(o, "chosen", (int)i == chosen);
        cJSON_AddBoolToObject(o, "usable", d[i].usable);
        if (!d[i].usable) fv_cli_json_add_string(o, "why_not", d[i].why_not);
        cJSON *f = cJSON_AddObjectToObject(o, "features");
        char mv[96];
        bool trusted = fv_vk_multiview_trusted(&d[i], mv, sizeof mv);
        cJSON_AddBoolToObject(f, "multiview", d[i].multiview);
        cJSON_AddNumberToObject(f, "max_multiview_views", d[i].max_multiview_views);
        cJSON_AddBoolToObject(f, "gbuffer_multiview", trusted);
        fv_cli_json_add_string(f, "gbuffer_mode", mv);
        cJSON_AddBoolToObject(f, "timestamps", d[i].timestamps);
        cJSON_AddNumberToObject(f, "timestamp_period_ns", d[i].timestamp_period_ns);
        cJSON_AddNumberToObject(f, "subgroup_size", d[i].subgroup_size);
        cJSON_AddBoolToObject(f, "descriptor_indexing", d[i].descriptor_indexing);
        cJSON_AddBoolToObject(f, "storage_image_write_without_format", d[i].storage_image_write_without_format);
        cJSON_AddNumberToObject(f, "device_local_bytes", (double)d[i].device_local_bytes);
        cJSON_AddNumberToObject(f, "max_image_dimension_2d", d[i].max_image_dimension_2d);
        cJSON_AddItemToArray(arr, o);
    }
    if (chosen >= 0) cJSON_AddNumberToObject(root, "chosen", chosen);
    else cJSON_AddNullToObject(root, "chosen");
    fv_cli_json_add_string(root, "reason", why);
    int rc = fv_cli_json_print(root, true);
    cJSON_Delete(root);
    return rc;
}

int fv_cmd_info(int argc, char **argv)
{
    bool json = false;
    const char *selector = NULL;
    for (int i = 1; i < argc; i++) {
        const char *v = NULL;
        int o;
        if (fv_cli_is_help(argv[i])) {
            fputs(USAGE, stdout);
            return FV_EXIT_OK;
        } else if (strcmp(argv[i], "--json") == 0) {
            json = true;
        } else if ((o = fv_cli_option(argc, argv, &i, "--device", &v)) != 0) {
            if (o < 0 || !v || !*v) return fv_cli_usage_error("info", USAGE, "--device needs a value");
            selector = v;
        } else {
            return fv_cli_usage_error("info", USAGE, "unknown option '%s'", argv[i]);
        }
    }
    fv_vk_device_info devices[MAX_DEVICES];
    uint32_t n = 0;
    int chosen = -1;
    char why[160] = "";
    fv_result r = fv_vk_list_devices(selector, devices, MAX_DEVICES, &n, &chosen, why, sizeof why);
    if (r != FV_OK) {
        fprintf(stderr, "fovea info: cannot list Vulkan devices: %s\n", fv_result_str(r));
        return FV_EXIT_FAIL;
    }
    int rc = json ? print_json(devices, n, chosen, why) : (print_text(devices, n, chosen, why), FV_EXIT_OK);
    if (rc == FV_EXIT_OK && chosen < 0) {
        if (!json) fprintf(stderr, "fovea info: %s\n", why);
        return FV_EXIT_FAIL;
    }
    return rc;
}
