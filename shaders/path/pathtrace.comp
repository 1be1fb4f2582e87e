#version 460
#ifdef LAST_PATH_CUT
#extension GL_KHR_shader_subgroup_vote : require
#endif
// Unidirectional path tracing with next-event estimation and MIS (power heuristic), for the
// band of pixels (within lines [y0, y1)) and the samples [sample_begin, sample_end) of each pixel.
// Feature defines (HAS_*) and the estimator (SAMPLING_BSDF / SAMPLING_LIGHT, default MIS) are
// injected by the tracer; see crates/platoon-accel/src/features.rs.

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

#include "common/scene.glsl"
#include "common/rng.glsl"
#include "common/sampling.glsl"
#include "common/textures.glsl"
#include "common/intersect.glsl"
#include "common/trace.glsl"
#include "common/surface.glsl"
#include "common/environment.glsl"
#include "common/bsdf.glsl"
#include "common/lights.glsl"

#include "path/path.glsl"
#if defined(OUTPUT_BSDF_SAMPLE) || defined(OUTPUT_BSDF_VALUE)
#include "path/bsdf_probe.glsl"
#endif
#ifdef OUTPUT_AOV
#include "path/aov.glsl"
#endif

// llvmpipe ends every loop of a shader invocation (of a SIMD group) once they have run 65535
// iterations in all (Mesa's LP_MAX_TGSI_LOOP_ITERATIONS), silently: a megakernel pass of many
// long paths through a big scene runs past it and its traversals stop short. Past the limit
// each loop runs its body once and leaves, so a loop that must run twice tells (the bound is a
// push word, which the compiler cannot fold).
bool loop_limit_reached() {
    uint turns = 0u;
    while (turns < loop_canary()) turns++;
    return turns != loop_canary();
}

void main() {
    load_frame_constants();
    uvec2 pixel;
    uint index;
    if (!band_pixel(pixel, index)) return;
    vec3 sum = vec3(0.0);
    uint rays = 0u;
    uint rejected = 0u;
#ifdef OUTPUT_PRIMARY_HIT
    // The first hit through the pixel centre (frame::Output::PrimaryHit; one sample per pixel):
    // what the CPU ray queries are checked against.
    vec2 ndc = pixel_ndc(pixel, vec2(0.5));
    vec3 dir = normalize(F.cam_forward.xyz + ndc.x * F.cam_right.w * F.cam_right.xyz + ndc.y * F.cam_up.w * F.cam_up.xyz);
    Hit first;
    rays = 1u;
    if (trace(Ray(F.cam_origin.xyz, dir, INF), false, first))
        sum = vec3(first.t, float(first.instance), float(first.triangle));
    else
        sum = vec3(-1.0);
#elif defined(OUTPUT_BSDF_SAMPLE) || defined(OUTPUT_BSDF_VALUE)
    rays = 1u;
    sum = bsdf_probe(pixel);
#elif defined(OUTPUT_AOV)
    sum = aov_pixel(pixel, pc.g.accum.v[index].xyz, rays);
#else
    if (pc.g.accum.v[index].w == PIXEL_CONVERGED) return;
    sum = pixel_samples(pixel, pc.g.accum.v[index].xyz, rays, rejected);
    if (loop_limit_reached()) {
        // The pass's samples were cut short: the pixel keeps its sums, flagged (w = 1) for the
        // streaming kernels to render them (crates/platoon-tracer/src/method/path.rs).
        pc.g.accum.v[index] = vec4(pc.g.accum.v[index].xyz, PIXEL_CUT_SHORT);
        atomicAdd(pc.g.stats.v[STAT_CUT_SHORT], 1u);
        return;
    }
#endif
    pc.g.accum.v[index] = vec4(sum, 0.0);
    if (rejected > 0u) atomicAdd(pc.g.stats.v[0], rejected);
    atomicAdd(pc.g.stats.v[4u + pixel.y], rays);
}
