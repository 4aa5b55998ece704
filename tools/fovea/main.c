/* @brief The `fovea` command: dispatches to subcommands (cmd_<name>.c). */
#include <stdio.h>
#include <string.h>

#include "cli.h"
#include "cli_interrupt.h"
#include "fovea_config.h"

typedef int (*cmd_fn)(int argc, char **argv);

typedef struct command {
    const char *name;
    const char *summary;
    cmd_fn fn;
    const char *ctrl_c; /* non-NULL: the command finishes its work on Ctrl-C and prints this first (cli_interrupt.h) */
} command;

int fv_cmd_run(int argc, char **argv);
int fv_cmd_info(int argc, char **argv);
int fv_cmd_devices(int argc, char **argv);
int fv_cmd_trace(int argc, char **argv);
int fv_cmd_hid(int argc, char **argv);
int fv_cmd_gaze(int argc, char **argv);
int fv_cmd_latency(int argc, char **argv);
int fv_cmd_compare(int argc, char **argv);
int fv_cmd_reference(int argc, char **argv);
int fv_cmd_knobs(int argc, char **argv);
int fv_cmd_bench(int argc, char **argv);
int fv_cmd_material(int argc, char **argv);
int fv_cmd_xr(int argc, char **argv);

/* Every command, in `fovea --help` order. */
static const command g_commands[] = {
    {"run", "render frames of a scene (headless by default) and report per-pass GPU time", fv_cmd_run,
     "fovea run: Ctrl-C: finishing the frame in flight, then the summary (Ctrl-C again ends it at once)"},
    {"info", "list Vulkan devices, the one fovea picks, and the features it uses", fv_cmd_info, NULL},
    {"devices", "list eye trackers each driver can see", fv_cmd_devices, NULL},
    {"trace", "inspect, convert and record gaze recordings", fv_cmd_trace, NULL},
    {"hid", "parse HID report descriptors and decode eye-tracker reports", fv_cmd_hid, NULL},
    {"gaze", "evaluate the gaze pipeline (filtering, saccades, prediction)", fv_cmd_gaze, NULL},
    {"latency", "simulate the frame loop and report gaze-to-photon latency", fv_cmd_latency, NULL},
    {"compare", "compare two images: PSNR, SSIM, mismatch, relative error, by eccentricity band", fv_cmd_compare, NULL},
    {"reference", "render a scene on the CPU: fovea's shading with exact shadows, or a path-traced ground truth",
     fv_cmd_reference, "fovea reference: Ctrl-C: stopping the render (Ctrl-C again ends it at once)"},
    {"knobs", "list the speed/accuracy knobs: ranges, units, their values under each preset", fv_cmd_knobs, NULL},
    {"bench", "sweep knobs: GPU time against error (vs exact and the CPU reference), Pareto plots", fv_cmd_bench,
     "fovea bench: Ctrl-C: finishing the frame in flight, then the report of the points done (Ctrl-C again ends it "
     "at once)"},
    {"material", "a translucent material's dipole quantities and total diffuse reflectance (closed form, numeric)",
     fv_cmd_material, NULL},
    {"xr", "fovea as an OpenXR runtime: 'fovea xr manifest' prints the runtime manifest's path", fv_cmd_xr, NULL},
    {NULL, NULL, NULL, NULL},
};

static void usage(FILE *f)
{
    fprintf(f, "usage: fovea [--version] [--help] COMMAND [ARGS]\n\n"
               "fovea is an eye-tracked VR display runtime. Commands:\n");
    for (size_t i = 0; g_commands[i].name; i++)
        fprintf(f, "  %-9s %s\n", g_commands[i].name, g_commands[i].summary);
    fprintf(f, "\n'fovea COMMAND --help' describes one command.\n"
               "Environment: FOVEA_DEVICE (Vulkan device index or name), FOVEA_VALIDATION=1 (Khronos validation),\n"
               "             FOVEA_LOG (e.g. 'hid=debug,*=info').\n");
}

/* The command named by argv[1], or NULL. */
static const command *find_command(int argc, char **argv)
{
    for (size_t i = 0; argc >= 2 && g_commands[i].name; i++)
        if (strcmp(argv[1], g_commands[i].name) == 0) return &g_commands[i];
    return NULL;
}

/* What the command prints when it catches Ctrl-C, or NULL (it dies by it); `trace record` catches it (the recording
 * is kept), `trace info` and `convert` do not. */
static const char *ctrl_c_message(const command *c, int argc, char **argv)
{
    if (c && !strcmp(c->name, "trace") && argc > 2 && !strcmp(argv[2], "record"))
        return "fovea trace: Ctrl-C: ending the recording (Ctrl-C again ends it at once)";
    return c ? c->ctrl_c : NULL;
}

int main(int argc, char **argv)
{
    const command *c = find_command(argc, argv);
    fv_cli_interrupt_install(ctrl_c_message(c, argc, argv)); /* first: before anything makes a thread */
    if (argc < 2) {
        usage(stderr);
        return FV_EXIT_USAGE;
    }
    const char *cmd = argv[1];
    if (fv_cli_is_help(cmd) || strcmp(cmd, "help") == 0) {
        usage(stdout);
        return FV_EXIT_OK;
    }
    if (strcmp(cmd, "--version") == 0 || strcmp(cmd, "version") == 0) {
        printf("fovea %s\n", FV_VERSION_STRING);
        return FV_EXIT_OK;
    }
    if (c) return c->fn(argc - 1, argv + 1);
    fprintf(stderr, "fovea: unknown command '%s'\n", cmd);
    usage(stderr);
    return FV_EXIT_USAGE;
}
