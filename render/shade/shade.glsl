// @brief The body of the shading pass's compute shader (shade.comp, shade_atomic.comp: the same shading, counting
// the GI gather's work per subgroup or per pixel; the file that includes this one sets #version, the extensions and
// FV_GI_STATS). Full-resolution and listed-pixel shading: the shared shading function (fv_shade_surface) on the
// decoded G-buffer, into linear RGBA32F per eye layer. Either every pixel (tiles interleaved over the dispatch) or a
// list. Every invocation reaches the end of main (fv_gi_stats_flush: subgroup operations over whole subgroups).
#include "fv_gpu.h"
#include "fv_scene_set.h"
#include "fv_shade_inputs_interface.h"
#include "fv_common.glsl"
#include "shade_interface.h"

layout(local_size_x = FV_SHADE_GROUP_X, local_size_y = FV_SHADE_GROUP_Y, local_size_z = 1) in;

FV_SCENE_SET_DECLARE
FV_SHADE_INPUTS_DECLARE
#define FV_GBUFFER_SET FV_SHADE_SET
#define FV_GBUFFER_BINDING_DEPTH FV_SHADE_BINDING_DEPTH
#define FV_GBUFFER_BINDING_NORMAL FV_SHADE_BINDING_NORMAL
#define FV_GBUFFER_BINDING_ALBEDO FV_SHADE_BINDING_ALBEDO
#define FV_GBUFFER_BINDING_MATERIAL FV_SHADE_BINDING_MATERIAL
#include "fv_gbuffer_decode.glsl"
layout(set = FV_SHADE_SET, binding = FV_SHADE_BINDING_COLOR, rgba32f) uniform writeonly image2DArray out_color;
layout(std430, set = FV_SHADE_SET, binding = FV_SHADE_BINDING_PIXELS) readonly buffer Pixels {
    uint count;
    uint pad0, pad1, pad2;
    uint pixels[];
} list;
layout(push_constant) uniform Push { fv_shade_push pc; };

#include "fv_shade_common.glsl"

void shade_pixel(uvec3 p)
{
    if (p.x >= frame.counts.y || p.y >= frame.counts.z || p.z > 1u) return;
    imageStore(out_color, ivec3(p), vec4(fv_shade_surface(fv_gbuffer_surface(p)), 1.0));
}

// This invocation's pixel, or false when it has none (past the list, or a padding tile).
bool pixel_of_invocation(out uvec3 p)
{
    p = uvec3(0u);
    // pc.mode is uniform over the dispatch: one pipeline for both modes, the shading function compiled once
    uint groups_x = pc.mode == FV_SHADE_MODE_LIST ? FV_GPU_LIST_GROUPS_X : pc.groups_x;
    uint group = gl_WorkGroupID.x + gl_WorkGroupID.y * groups_x;
    if (pc.mode == FV_SHADE_MODE_LIST) {
        uint i = group * FV_SHADE_GROUP_SIZE + gl_LocalInvocationIndex;
        if (i >= list.count || i >= uint(list.pixels.length())) return false;
        p = fv_pixel_unpack(list.pixels[i]);
        return true;
    }
    uint stripe = group % FV_SHADE_STRIPES;
    uint tile = stripe * pc.tiles_per_stripe + group / FV_SHADE_STRIPES;
    if (group / FV_SHADE_STRIPES >= pc.tiles_per_stripe || tile >= pc.tile_count) return false;
    uint per_eye = pc.tiles_x * pc.tiles_y;
    uint layer = tile / per_eye;
    uint t = tile % per_eye;
    uvec2 origin = uvec2(t % pc.tiles_x, t / pc.tiles_x) * uvec2(FV_SHADE_GROUP_X, FV_SHADE_GROUP_Y);
    p = uvec3(origin + gl_LocalInvocationID.xy, layer);
    return true;
}

void main()
{
    uvec3 p;
    if (pixel_of_invocation(p)) shade_pixel(p);
    fv_gi_stats_flush();
}
