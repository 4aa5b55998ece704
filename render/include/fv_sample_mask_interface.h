/* @brief The frame's per-pixel sample mask ("fovea mask", uimage2DArray r32ui) and its block masks ("fovea blocks"),
 * as a contract between the passes that write and read them, shared by C and GLSL so that neither includes the
 * other: foveation (render/fovea: "fovea" writes shaded / unknown, "temporal" adds reused, "reconstruct" fills the
 * unknown pixels from all the others; the debug view draws them) and interpolation (render/interp: "interp_fill",
 * with a sample mask in the frame, marks the pixels it shaded and those it interpolated, so temporal reuse and
 * reconstruction keep them).
 *
 * A pixel's mask value is one of FV_SAMPLE_MASK_*; every value but UNKNOWN is a known colour (a seed for
 * reconstruction, never overwritten by it). The block masks: per eye an image of (blocks_x * words) x blocks_y
 * words, B = fovea.block px a block side, words = ceil(B * B / 32); pixel (x, y) is bit k % 32 of word
 * (x / B) * words + k / 32 in row y / B, with k = (y % B) * B + x % B. Every known pixel has its bit set. */
#ifndef FV_SAMPLE_MASK_INTERFACE_H
#define FV_SAMPLE_MASK_INTERFACE_H

#define FV_SAMPLE_MASK_UNKNOWN 0u      /* nothing known yet: reconstruction fills it */
#define FV_SAMPLE_MASK_SHADED 1u       /* shaded this frame by the shading function */
#define FV_SAMPLE_MASK_REUSED 2u       /* taken from the previous frames' history (temporal reuse) */
#define FV_SAMPLE_MASK_INTERPOLATED 3u /* interpolated from shaded pixels (interpolation's fill) */

#if defined(GL_core_profile) || defined(VULKAN) || defined(GL_SPIRV)
/* The block-mask word of pixel p (z: the eye) for blocks of B px and `words` words per block, and its bit. */
ivec3 fv_sample_block_word(uvec3 p, uint B, uint words)
{
    uint k = (p.y % B) * B + p.x % B;
    return ivec3(int((p.x / B) * words + k / 32u), int(p.y / B), int(p.z));
}
uint fv_sample_block_bit(uvec3 p, uint B) { return 1u << ((((p.y % B) * B + p.x % B)) % 32u); }
#endif

#endif
