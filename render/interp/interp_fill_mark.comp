#version 450
// @brief Hierarchical screen-space interpolation, after shading, with the frame's sample mask (foveation on): the
// fill or `--view interp` (interp_fill.glsl), then each pixel marked in the sample mask and its block bit set
// (fv_sample_mask_interface.h): SHADED where interpolation listed it (its corners too, which foveation alone would
// not have shaded), INTERPOLATED where it filled it; a pixel left to the mask's owner keeps its value (unknown).
// Temporal reuse and reconstruction, later, then take both as known and overwrite neither. Each pixel writes only
// itself in the mask; block bits are OR-ed in by atomics.
#extension GL_GOOGLE_include_directive : require
#include "interp_fill.glsl"
#include "fv_sample_mask_interface.h"

layout(set = FV_INTERP_FILL_SET, binding = FV_INTERP_FILL_BINDING_MASK, r32ui) uniform uimage2DArray mask_img;
layout(set = FV_INTERP_FILL_SET, binding = FV_INTERP_FILL_BINDING_BLOCKS, r32ui) uniform uimage2DArray blocks_img;

void main()
{
    uvec3 p = gl_GlobalInvocationID;
    uint code = interp_fill_pixel(p);
    if (code == FV_INTERP_FILL_OUTSIDE) return;
    uint m = (code & FV_INTERP_CODE_SHADED) != 0u   ? FV_SAMPLE_MASK_SHADED
             : (code & FV_INTERP_CODE_FILLED) != 0u ? FV_SAMPLE_MASK_INTERPOLATED
                                                    : FV_SAMPLE_MASK_UNKNOWN;
    if (m == FV_SAMPLE_MASK_UNKNOWN) return;
    imageStore(mask_img, ivec3(p), uvec4(m));
    imageAtomicOr(blocks_img, fv_sample_block_word(p, pc.block, pc.block_words), fv_sample_block_bit(p, pc.block));
}
