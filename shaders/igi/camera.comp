#version 460
// IGI, camera pass (one sample per dispatch): the path tracer's camera paths (path.glsl), whose
// first diffuse vertex is recorded for the gather passes (IgiVertex, igi/igi.glsl) instead of being lit by
// indirect paths. Direct light and specular chains are the path tracer's, so only indirect
// diffuse light is approximated. With IGI_FILTERED it also adds the pixel's G-buffer sums for
// the filters after assembly. Defines: crates/platoon-accel/src/features.rs.
//
// The gather is deferred to passes of its own rather than run inline in the path because
// llvmpipe ends a shader invocation's loops after 65535 iterations in all (Mesa's
// LP_MAX_TGSI_LOOP_ITERATIONS, shared by every loop of the invocation): hundreds of VPLs, each a
// BVH traversal, over a pass of samples exceed it and the loops stop short, silently. Each
// gather pass takes a bounded chunk of the VPLs for one sample.

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

// The path loop's hooks (path/path.glsl): what a camera path carries for its gathering vertex.
#define PATH_HOOKS
struct PathHook {
    bool gathered;       // the first diffuse vertex has gathered the VPLs' light
    bool gathering;      // the current vertex is that vertex
    vec3 indirect_scale; // what of the throughput carries on past the next vertex's emission
};

#include "common/scene.glsl"
#include "igi/igi.glsl"
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
#include "igi/pixel.glsl"

uvec2 igi_pixel;
IgiVertex igi_vertex;

// Records the path's first diffuse vertex for the gather passes.
void igi_record(Path p, Surface s, Bsdf bsdf, vec3 wo, vec3 ng_wo) {
    vec3 n = wo.z >= 0.0 ? s.ns : -s.ns;
    vec3 w = -p.ray.dir;
    // The diffuse lobe's reflected share (not what diffuse transmission passes) under the
    // sheen's scaling at the view; the gather applies the specular layer's Fresnel.
    vec3 albedo = p.throughput * bsdf.w.x * bsdf.base_color * (diffuse_reflected(bsdf) * sheen_view_scale(bsdf));
#ifdef IGI_FILTERED
    // The G-buffer of the filters: IgiTexel in crates/platoon-core/src/igi/mod.rs. The albedo
    // with the specular layer's Fresnel at the viewing direction (the filters gather irradiance
    // and apply it after).
    uint a = 3u * (igi_pixel.y * F.dims.x + igi_pixel.x);
    vec3 reflectance = p.throughput * diffuse_reflectance(bsdf, layer_fresnel(bsdf, abs(wo.z))) * (sheen_view_scale(bsdf) * INV_PI);
    IGI_TEXELS.v[a] += vec4(0.0, 0.0, 0.0, 1.0);
    IGI_TEXELS.v[a + 1u] += vec4(reflectance, distance(F.cam_origin.xyz, s.position));
    IGI_TEXELS.v[a + 2u] += vec4(n, 0.0);
    if (!igi_gathers(igi_pixel)) return;
#endif
    igi_vertex = IgiVertex(vec4(s.position, s.magnitude), vec4(n, bsdf.specular), vec4(ng_wo, 1.0), vec4(w, 0.0), vec4(albedo, 0.0), vec4(bsdf.f0, 0.0));
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
    // Instant global illumination: the first vertex with a diffuse lobe takes its indirect
    // diffuse light from the VPLs (gathered by later passes); its direct light stays the path
    // tracer's (NEE, and the emission the BSDF ray finds next, both weighed by MIS).
    p.hook.gathering = !p.hook.gathered && bsdf.p.x > 0.0;
    if (p.hook.gathering) {
        p.hook.gathered = true;
        igi_record(p, s, bsdf, wo, ng_wo);
    }
}

void hook_bsdf_sampled(inout Path p, Bsdf bsdf, vec3 wo, BsdfSample bs) {
    // The emission at the next vertex is direct light (full BSDF); the light beyond it is
    // indirect, whose diffuse share the VPLs gave: the rest of the BSDF, (f - f_diffuse) / f.
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
    igi_pixel = pixel;
    igi_vertex = IgiVertex(vec4(0.0), vec4(0.0), vec4(0.0), vec4(0.0), vec4(0.0), vec4(0.0));
    uint rays = 0u;
    uint rejected = 0u;
    pc.g.accum.v[index] = vec4(pixel_samples(pixel, pc.g.accum.v[index].xyz, rays, rejected), 0.0);
    IGI_VERTICES.v[index] = igi_vertex;
    if (rejected > 0u) atomicAdd(pc.g.stats.v[0], rejected);
    atomicAdd(pc.g.stats.v[4u + pixel.y], rays);
}
