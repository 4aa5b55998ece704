/* @brief Physically possible gaze: the one set of rules that every trace reader (drivers/trace), the gaze pipeline
 * and the evaluation truth of `fovea gaze eval` apply to a sample, so no reader passes on, and no truth scores, a ray
 * no eye can make. A gaze direction is possible when it is finite, non-zero and points into the forward half-space
 * of the head (head frame: -z forward; a direction with z >= 0 points sideways or backwards: 90 deg or more from
 * straight ahead, beyond any eye's rotation, about 50 deg). Two eyes are possible together when their horizontal
 * vergence (left yaw - right yaw, positive converging) is within [-FV_GAZE_MAX_DIVERGENCE_DEG,
 * FV_GAZE_MAX_CONVERGENCE_DEG] and their vertical misalignment is at most FV_GAZE_MAX_VERTICAL_VERGENCE_DEG
 * (bounds and their physiology: docs/gaze.md, "Physically impossible gaze"). What breaks a rule is marked invalid,
 * never passed on; a format whose documentation says how to repair a fault does so in its reader and counts it as
 * repaired (Pupil Core's gaze point behind the head). */
#ifndef FV_GAZE_VALIDITY_H
#define FV_GAZE_VALIDITY_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "fovea/fv_gaze_sample.h"

/* Horizontal fusional divergence reaches about 4 deg (7 prism dioptres at distance); the rest of the 10 deg is two
 * trackers' per-eye errors of up to 3 deg each. Convergence of 60 deg fixates 5.5 cm in front of 63-mm-apart eyes,
 * nearer than the near point of convergence of any healthy adult (< 10 cm: about 35 deg). Vertical fusional range is
 * about 2 deg (3-4 prism dioptres); 10 deg leaves the same allowance for the trackers' errors as divergence. */
#define FV_GAZE_MAX_DIVERGENCE_DEG 10.0
#define FV_GAZE_MAX_CONVERGENCE_DEG 60.0
#define FV_GAZE_MAX_VERTICAL_VERGENCE_DEG 10.0

/* Kinds of impossible gaze, counted apart. */
typedef enum fv_gaze_fault {
    FV_GAZE_FAULT_POINT_BEHIND = 0, /* the combined gaze point lies behind the head (Pupil Core: gaze_point_3d_z < 0) */
    FV_GAZE_FAULT_BACKWARD = 1,     /* a direction (an eye's or the combined ray) pointing sideways or backwards */
    FV_GAZE_FAULT_DIVERGENT = 2,    /* the eyes diverge more than FV_GAZE_MAX_DIVERGENCE_DEG */
    FV_GAZE_FAULT_CONVERGENT = 3,   /* the eyes converge more than FV_GAZE_MAX_CONVERGENCE_DEG */
    FV_GAZE_FAULT_VERTICAL = 4,     /* the eyes are misaligned vertically by more than the bound */
    FV_GAZE_FAULTS = 5
} fv_gaze_fault;

/** Short description of a fault ("gaze point behind the head", ...); never NULL. */
const char *fv_gaze_fault_str(fv_gaze_fault f);

/** Samples repaired and samples whose gaze (or part of it) was dropped, per kind. */
typedef struct fv_gaze_validity_counts {
    uint64_t repaired[FV_GAZE_FAULTS];
    uint64_t dropped[FV_GAZE_FAULTS];
} fv_gaze_validity_counts;

/** A direction no eye can make is false: non-finite, (near) zero, or not pointing forward (z >= 0, head frame). */
bool fv_gaze_direction_possible(fv_vec3 d);
/** An eye's direction is usable: flagged valid, not a blink, and possible. */
bool fv_gaze_eye_usable(const fv_eye_sample *e);
/** The fault of a pair of eye directions (head frame), or -1 when the pair is possible (or either is not). */
int fv_gaze_vergence_fault(fv_vec3 left, fv_vec3 right);
/** Apply the rules to a sample in place: an impossible direction of an eye or of the combined ray is cleared (NaN,
 *  flag clear); a pair of eyes no human can make clears both eyes and the combined ray (which the device computes
 *  from them). Returns the faults found as bits (1u << fv_gaze_fault); 0 = nothing dropped. */
uint32_t fv_gaze_sample_enforce(fv_gaze_sample *s);
/** The sample's gaze under the same rules (on a copy): the combined ray, else the normalised mean of the usable
 *  eyes. false when there is none. */
bool fv_gaze_sample_direction(const fv_gaze_sample *s, fv_vec3 *out);
/** Count one sample's faults (bits as above). */
void fv_gaze_validity_count(fv_gaze_validity_counts *c, uint32_t repaired_bits, uint32_t dropped_bits);
uint64_t fv_gaze_validity_total(const fv_gaze_validity_counts *c, bool repaired);
/** One line without a newline: "N repaired (why: n, ...), M dropped (why: n, ...)", or "none" when both are 0. */
void fv_gaze_validity_describe(const fv_gaze_validity_counts *c, char *buf, size_t cap);

#endif
