/* @brief A pass of the test build (tests/render/stamp_pass): the proof that adding a pass is its folder and one line
 * of a pass table. It runs while foveation does, needs the fovea pass's "fovea mask", makes "test stamp" (R32UI, both
 * eyes) and clears it each frame to FV_STAMP_VALUE; test_render_pass_table draws with it. */
#ifndef FV_STAMP_PASS_H
#define FV_STAMP_PASS_H

#include "fv_pass.h"

#define FV_STAMP_VALUE 0x5eedu

/** The entry: declared images and all. */
extern const fv_pass fv_stamp_pass;
/** The same pass with a find it does not declare ("fovea prob"): its init must be refused. */
extern const fv_pass fv_stamp_sneak_pass;

#endif
