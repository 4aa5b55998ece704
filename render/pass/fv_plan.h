/* @brief The frame plan as data (no Vulkan): one entry per pass of the renderer's pass table, whether it runs this
 * frame and why, and the per-pass counters a frame reports. Shared by the renderer's public header and the passes. */
#ifndef FV_PLAN_H
#define FV_PLAN_H

#include <stdbool.h>
#include <stdint.h>

#define FV_MAX_PASSES 24
#define FV_PASS_ID_MAX 24
#define FV_PASS_REASON_MAX 160

/** One entry of the frame plan: a pass, whether it runs, why, and the parameters it was given. */
typedef struct fv_plan_entry {
    char pass[FV_PASS_ID_MAX];
    bool enabled;
    char reason[FV_PASS_REASON_MAX];
    uint32_t variant; /* a pass-defined choice made with the decision (e.g. a debug view), 0 by default */
} fv_plan_entry;

typedef struct fv_frame_plan {
    fv_plan_entry entries[FV_MAX_PASSES];
    uint32_t count;
} fv_frame_plan;

/** What a pass did in one frame (counted on the CPU when it recorded; 0 where it does not apply). */
typedef struct fv_pass_counters {
    uint64_t draws;         /* draw calls */
    uint64_t triangles;     /* triangles submitted (per view) x views */
    uint64_t pixels_shaded; /* pixels the shading function ran for */
    uint64_t dispatches;    /* compute dispatches (direct or indirect) */
    uint64_t gpu_lists;     /* pixel lists shaded whose size only the GPU knew (already added to pixels_shaded) */
} fv_pass_counters;

/** A named list of numbers a pass reports about its last frame (e.g. "light0.splits_m"), for --explain --json. */
#define FV_PASS_DETAIL_VALUES 9
typedef struct fv_pass_detail {
    char key[40];
    double value[FV_PASS_DETAIL_VALUES];
    uint32_t count;
} fv_pass_detail;

/** Append one named detail of up to three values (count <= 3) at out[n] when n < cap; returns the new count. */
uint32_t fv_pass_detail_add(fv_pass_detail *out, uint32_t n, uint32_t cap, const char *key, uint32_t count, double a,
                            double b, double c);

#endif
