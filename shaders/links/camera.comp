#version 460
// Vertex links, an image frame: the path tracer's camera paths (path/path.glsl), whose first
// vertex with a diffuse lobe adds the diffuse reflection of the indirect irradiance the links
// solved (interpolated from its triangle's elements by barycentrics) in place of its diffuse
// bounce. Direct light and specular chains are the path tracer's, so only indirect diffuse
// light is approximated, as in IGI (igi/camera.comp, whose hooks these follow).

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

#define PATH_HOOKS
struct PathHook {
    bool gathered;       // the first diffuse vertex has taken its indirect light
    bool gathering;      // the current vertex is that vertex
    vec3 indirect_scale; // what of the throughput carries on past the next vertex's emission
};

#include "common/scene.glsl"
#include "links/links.glsl"
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

// The indirect irradiance at a hit, from its triangle's corners' elements.
vec3 links_irradiance(Hit hit) {
    uint vertices = links_instances();
    if (hit.instance >= vertices) return vec3(0.0);
    uvec3 v = triangle_at(hit.triangle).v.xyz;
    uint base = LINKS_TABLE.v[hit.instance];
    vec3 b = vec3(1.0 - hit.b1 - hit.b2, hit.b1, hit.b2);
    vec3 e = vec3(0.0);
    for (int k = 0; k < 3; ++k) {
        if (vertices + v[k] >= links_table_length()) continue;
        uint local = LINKS_TABLE.v[vertices + v[k]];
        if (local != ~0u && base + local < links_irradiance_length())
            e += b[k] * LINKS_IRRADIANCE.v[base + local].xyz;
    }
    return e;
}

void hook_path_start(inout PathHook h) {
    h.gathered = false;
    h.gathering = false;
    h.indirect_scale = vec3(1.0);
}

bool hook_after_emission(inout Path p) {
    // Past the gathering vertex the path carries only what its other lobes reflect.
    p.throughput *= p.hook.indirect_scale;
    p.hook.indirect_scale = vec3(1.0);
    return any(greaterThan(p.throughput, vec3(0.0)));
}

void hook_vertex(inout Path p, Hit hit, Surface s, Bsdf bsdf, vec3 wo, vec3 ng_wo) {
    p.hook.gathering = !p.hook.gathered && bsdf.p.x > 0.0;
    if (!p.hook.gathering) return;
    p.hook.gathered = true;
    // The elements hold the light arriving on their normal's side (the front by winding).
    if (wo.z <= 0.0) return;
    vec3 reflectance = diffuse_reflectance(bsdf, layer_fresnel(bsdf, abs(wo.z))) * (sheen_view_scale(bsdf) * INV_PI);
    add_light(p.L, p.throughput * reflectance * links_irradiance(hit), p.depth + 1u);
}

void hook_bsdf_sampled(inout Path p, Bsdf bsdf, vec3 wo, BsdfSample bs) {
    // The emission at the next vertex is direct light (full BSDF); the light beyond it is
    // indirect, whose diffuse share the links gave: the rest of the BSDF, (f - f_diffuse) / f.
    if (p.hook.gathering && !bs.delta) {
        vec3 f = bs.weight * bs.pdf;
        vec3 rest = max(f - bsdf_diffuse(bsdf, wo, bs.wi), vec3(0.0));
        p.hook.indirect_scale = vec3(f.x > 0.0 ? rest.x / f.x : 0.0, f.y > 0.0 ? rest.y / f.y : 0.0, f.z > 0.0 ? rest.z / f.z : 0.0);
    }
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
}
