#version 460
// Layered hit buffers, a probe (tests): pixel i answers query i of the tables
// (tables.rs: with_queries) by a lookup, as the image pass would answer a ray, and leaves the
// hit's point as its radiance (1e30 where the lookup found nothing).

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

#include "common/scene.glsl"
#include "common/rng.glsl"
#include "common/sampling.glsl"
#include "common/textures.glsl"
#include "common/intersect.glsl"
#include "common/surface.glsl"
#include "lhb/lhb.glsl"
#include "lhb/lookup.glsl"

void main() {
    load_frame_constants();
    uvec2 pixel;
    uint index;
    if (!band_pixel(pixel, index)) return;
    uint at = lhb_queries_at();
    vec3 answer = vec3(1e30);
    if (at != 0u && index < LHB_TABLES.v[at]) {
        uint q = at + 1u + 8u * index;
        float w[8];
        for (uint k = 0u; k < 8u; ++k) w[k] = uintBitsToFloat(LHB_TABLES.v[q + k]);
        Hit hit;
        if (lhb_lookup(vec3(w[0], w[1], w[2]), vec3(w[3], w[4], w[5]), vec2(w[6], w[7]), hit)) answer = lhb_point;
    }
    pc.g.accum.v[index] = vec4(answer, 0.0);
}
