/* @brief `fovea devices [--json]`: what each driver of this build sees, hardware first, then recordings and the
 * simulated eye; says plainly when no eye tracker is attached. */
#include <cjson/cJSON.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "fv_registry.h"
#include "fv_app_drivers.h"

static const char *g_usage = "usage: fovea devices [--json]\n"
                             "  Probe every driver (hid, usb, then trace and sim) and list what each one sees.\n"
                             "  --json   machine-readable output\n";

static cJSON *listing_json(const fv_registry_listing *l)
{
    cJSON *root = cJSON_CreateObject();
    cJSON *drivers = cJSON_AddArrayToObject(root, "drivers");
    for (size_t i = 0; i < l->driver_count; i++) {
        const fv_registry_driver_listing *d = &l->drivers[i];
        cJSON *o = cJSON_CreateObject();
        fv_cli_json_add_string(o, "scheme", d->driver->scheme);
        fv_cli_json_add_string(o, "summary", d->driver->summary ? d->driver->summary : "");
        cJSON_AddBoolToObject(o, "hardware", !fv_registry_is_virtual(d->driver));
        fv_cli_json_add_string(o, "result", fv_result_str(d->result));
        cJSON_AddBoolToObject(o, "truncated", d->truncated);
        cJSON *devs = cJSON_AddArrayToObject(o, "devices");
        for (size_t k = 0; k < d->count; k++) {
            cJSON *x = cJSON_CreateObject();
            fv_cli_json_add_string(x, "uri", d->devices[k].uri);
            fv_cli_json_add_string(x, "name", d->devices[k].name);
            fv_cli_json_add_string(x, "driver", d->devices[k].driver);
            fv_cli_json_add_string(x, "detail", d->devices[k].detail);
            cJSON_AddItemToArray(devs, x);
        }
        cJSON_AddItemToArray(drivers, o);
    }
    cJSON_AddNumberToObject(root, "eye_trackers", (double)l->hardware_devices);
    cJSON_AddBoolToObject(root, "eye_trackers_attached", l->hardware_devices > 0);
    return root;
}

static void print_text(const fv_registry_listing *l)
{
    for (size_t i = 0; i < l->driver_count; i++) {
        const fv_registry_driver_listing *d = &l->drivers[i];
        printf("%-6s %s\n", d->driver->scheme, d->driver->summary ? d->driver->summary : "");
        if (FV_FAILED(d->result)) {
            printf("       could not look (%s)\n", fv_result_str(d->result));
            continue;
        }
        if (d->count == 0) {
            if (strcmp(d->driver->scheme, "trace") == 0)
                printf("       nothing to discover: open a recording with trace:FILE\n");
            else
                printf("       nothing found\n");
        }
        for (size_t k = 0; k < d->count; k++) {
            const fv_device_info *x = &d->devices[k];
            printf("       %-28s %s%s%s\n", x->uri, x->name, x->detail[0] ? " — " : "", x->detail);
        }
        if (d->truncated) printf("       (more devices than listed)\n");
    }
    printf("\n");
    if (l->hardware_devices == 0)
        printf("no eye trackers attached (recordings and the simulated eye are still available: "
               "--gaze trace:FILE or --gaze sim:seed=1)\n");
    else
        printf("%zu eye tracker%s attached\n", l->hardware_devices, l->hardware_devices == 1 ? "" : "s");
}

int fv_cmd_devices(int argc, char **argv)
{
    bool json = false;
    for (int i = 1; i < argc; i++) {
        if (fv_cli_is_help(argv[i])) {
            fputs(g_usage, stdout);
            return FV_EXIT_OK;
        } else if (strcmp(argv[i], "--json") == 0) {
            json = true;
        } else {
            return fv_cli_usage_error("devices", g_usage, "unknown argument '%s'", argv[i]);
        }
    }
    fv_registry reg;
    if (FV_FAILED(fv_registry_init(&reg, fv_app_drivers()))) return FV_EXIT_FAIL; /* logged */
    fv_registry_listing listing;
    fv_result r = fv_registry_probe(&reg, &listing);
    if (FV_FAILED(r)) {
        fprintf(stderr, "fovea devices: probing failed (%s)\n", fv_result_str(r));
        fv_registry_listing_fini(&listing);
        return FV_EXIT_FAIL;
    }
    int rc = FV_EXIT_OK;
    if (json) {
        cJSON *root = listing_json(&listing);
        if (fv_cli_json_print(root, true) != FV_EXIT_OK) rc = FV_EXIT_FAIL;
        cJSON_Delete(root);
    } else {
        print_text(&listing);
    }
    fv_registry_listing_fini(&listing);
    return rc;
}
