#version 460
// Layered hit buffers, an image pass: the path tracer's camera paths (path/path.glsl) up to and
// including their first vertex with a diffuse lobe; from there on every ray the path shoots is
// answered by a lookup in the buffers (lhb/lookup.glsl) instead of a traversal, for `bounces`
// lookups. Direct light stays exact: next-event estimation (traced shadow rays) takes the whole
// of it at the first diffuse vertex and beyond, and light a lookup finds counts only where NEE
// cannot sample it (after a delta bounce, or a source no light sample reaches).

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

#define PATH_HOOKS
struct PathHook {
    bool looking;  // past the first diffuse vertex: rays are lookups
    uint lookups;  // lookups this path made
};

#include "common/scene.glsl"
#include "common/rng.glsl"
#include "common/sampling.glsl"
#include "common/textures.glsl"
#include "common/intersect.glsl"
#include "common/trace.glsl"
#include "common/surface.glsl"
#include "lhb/lhb.glsl"
#include "common/environment.glsl"
#include "common/bsdf.glsl"
#include "common/lights.glsl"
#include "lhb/lookup.glsl"

// Push word 0 of an image pass: the lookup bounces (LhbPasses::push_words).
uint lhb_bounces() { return pc.method_words[0]; }

uint lhb_lookups = 0u;

#define PATH_TRACE_HOOK
#define PATH_NEE_ALONE(p) p.hook.looking

#include "path/path.glsl"

bool hook_trace(inout Path p, inout Rng rng, out Hit hit) {
    if (!p.hook.looking) return trace(p.ray, false, hit);
    p.hook.lookups++;
    lhb_lookups++;
    return lhb_lookup(p.ray.origin, p.ray.dir, rng_next2(rng), hit);
}

void hook_path_start(inout PathHook h) {
    h.looking = false;
    h.lookups = 0u;
}

bool hook_after_emission(inout Path p) {
    return true;
}

void hook_vertex(inout Path p, Hit hit, Surface s, Bsdf bsdf, vec3 wo, vec3 ng_wo) {
    if (bsdf.p.x > 0.0) p.hook.looking = true;
}

void hook_bsdf_sampled(inout Path p, Bsdf bsdf, vec3 wo, BsdfSample bs) {
    // The last lookup's vertex took its direct light; no ray leaves it.
    if (p.hook.looking && p.hook.lookups >= lhb_bounces()) p.throughput = vec3(0.0);
}

void main() {
    load_frame_constants();
    uvec2 pixel;
    uint index;
    if (!band_pixel(pixel, index)) return;
    uint rays = 0u;
    uint rejected = 0u;
    pc.g.accum.v[index] = vec4(pixel_samples(pixel, pc.g.accum.v[index].xyz, rays, rejected), 0.0);
    if (rejected > 0u) atomicAdd(pc.g.stats.v[0], rejected);
    atomicAdd(pc.g.stats.v[4u + pixel.y], rays);
    if (lhb_lookups > 0u) atomicAdd(pc.g.stats.v[STAT_LHB_QUEUED], lhb_lookups);
}
