#version 460
// IGI, first pass: the frame's virtual point lights (Keller 1997). Invocation i shoots light path
// i: a light picked by power, a point and direction on it, then up to vpl_bounces() hits, each
// on a surface with a diffuse lobe leaving a VPL in slot i * bounces + hit (an empty slot, power
// w = 0, where the path ended early). The random numbers are a Halton sequence over the paths,
// rotated per (frame, seed): the set is a pure function of (scene, frame, seed), so every tracer
// builds the same one and a frame split between devices is the same bits. (A frame that
// continues a converging view's sums also keys it by its first sample: see halton.)

layout(local_size_x = 64, local_size_y = 1, local_size_z = 1) in;

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

// Bases of the Halton dimensions: light pick, point (2), direction (2), then lobe and direction
// (3) per bounce after the first (crates/platoon-core/src/igi: MAX_BOUNCES = 8).
const uint PRIMES[26] = uint[26](2u, 3u, 5u, 7u, 11u, 13u, 17u, 19u, 23u, 29u, 31u, 37u, 41u, 43u,
    47u, 53u, 59u, 61u, 67u, 71u, 73u, 79u, 83u, 89u, 97u, 101u);

float radical_inverse(uint base, uint i) {
    float inv = 1.0 / float(base);
    float f = inv;
    float r = 0.0;
    while (i > 0u) {
        r += f * float(i % base);
        i /= base;
        f *= inv;
    }
    return r;
}

// Dimension d of path i, Cranley-Patterson rotated by a hash of (seed, frame, d) and, for the
// frames that continue a converging view's sums (first sample past 0), of the first sample: each
// such frame gathers a VPL set of its own, and the film averages over sets.
float halton(uint i, uint d) {
    uint h = pcg_hash(pcg_hash(pcg_hash(render_seed() ^ 0x68bc21ebu) ^ frame_index()) ^ d);
    if (pc.sample_begin != 0u) h = pcg_hash(h ^ (pc.sample_begin * 0x9e3779b9u));
    float u = radical_inverse(PRIMES[d], i + 1u) + float(h >> 8) * (1.0 / 16777216.0);
    return min(fract(u), 0.99999994);
}

// A point on the disk of radius r about c facing along unit d.
vec3 disk_point(vec3 c, vec3 d, float r, vec2 u) {
    vec3 t, b;
    make_frame(d, t, b);
    vec2 p = sample_disk_concentric(u) * r;
    return c + p.x * t + p.y * b;
}

// The light a path starts from: origin, direction and the flux it carries (before dividing
// among the paths). False when the light gives nothing in that direction.
bool emit(uint path, out Ray ray, out vec3 power, out float range) {
    uint n = light_count();
    range = 0.0;
    if (n == 0u) return false;
    uint index = search_cdf(CDF_LIGHTS, 0u, n, halton(path, 0u));
    Light l = light_at(index);
    float pick = l.emission.w;
    if (!(pick > 0.0)) return false;
    vec2 u_pos = vec2(halton(path, 1u), halton(path, 2u));
    vec2 u_dir = vec2(halton(path, 3u), halton(path, 4u));
    uint kind = l.ids.x;
#ifdef HAS_EMISSIVE_TRIANGLES
    if (kind == LIGHT_TRIANGLE) {
        vec3 b = sample_triangle(u_pos);
        vec3 q = b.x * l.a.xyz + b.y * l.b.xyz + b.z * l.c.xyz;
        vec3 cr = cross(l.b.xyz - l.a.xyz, l.c.xyz - l.a.xyz);
        float area = 0.5 * length(cr);
        if (!(area > 0.0)) return false;
        vec3 nl = normalize(cr) * l.a.w;
        // Cosine-weighted about the front; a two-sided emitter picks its side with the first
        // direction number (reused, rescaled, for the direction).
        Material m = material_at(triangle_at(l.ids.z).material);
        float sides = 1.0;
        if ((m.textures1.w & MATERIAL_DOUBLE_SIDED) != 0) {
            sides = 2.0;
            if (u_dir.x < 0.5) { nl = -nl; u_dir.x *= 2.0; } else u_dir.x = u_dir.x * 2.0 - 1.0;
            u_dir.x = min(u_dir.x, 0.99999994);
        }
        vec3 t, bt;
        make_frame(nl, t, bt);
        vec3 dir = to_world(sample_cosine_hemisphere(u_dir), t, bt, nl);
        // The radiance leaving along dir is what a ray arriving along -dir sees.
        power = triangle_light_radiance(l, b, nl, -dir) * (PI * area * sides) / pick;
        ray = Ray(offset_ray(q, nl, coordinate_magnitude(l.a.xyz, l.b.xyz, l.c.xyz)), dir, INF);
        return any(greaterThan(power, vec3(0.0)));
    }
#endif
#ifdef HAS_PUNCTUAL_LIGHTS
    if (kind == LIGHT_POINT || kind == LIGHT_SPOT) {
        range = l.b.w;
        if (kind == LIGHT_POINT) {
            ray = Ray(l.a.xyz, sample_uniform_sphere(u_dir), INF);
            power = l.emission.rgb * (4.0 * PI) / pick;
            return true;
        }
        // Uniform in the cone of the outer angle, weighed by the falloff NEE applies.
        float cos_outer = clamp(l.c.x, -1.0, 1.0);
        float ct = 1.0 - u_dir.x * (1.0 - cos_outer);
        float st = sqrt(max(0.0, 1.0 - ct * ct));
        float phi = 2.0 * PI * u_dir.y;
        vec3 t, b;
        make_frame(l.b.xyz, t, b);
        vec3 dir = to_world(vec3(st * cos(phi), st * sin(phi), ct), t, b, l.b.xyz);
        float f = clamp((ct - l.c.x) * l.c.y, 0.0, 1.0);
        ray = Ray(l.a.xyz, dir, INF);
        power = l.emission.rgb * (f * f * 2.0 * PI * (1.0 - cos_outer)) / pick;
        return f > 0.0;
    }
    if (kind == LIGHT_DIRECTIONAL) {
        // The scene's bounding sphere, from just outside it.
        vec3 c = F.scene_sphere.xyz;
        float r = F.scene_sphere.w * 1.01;
        vec3 dir = l.b.xyz;
        ray = Ray(disk_point(c - dir * r, dir, r, u_pos), dir, INF);
        power = l.emission.rgb * (PI * r * r) / pick;
        return true;
    }
#endif
    if (kind == LIGHT_ENVIRONMENT) {
        // The scene's bounding sphere, from just outside it.
        vec3 c = F.scene_sphere.xyz;
        float r = F.scene_sphere.w * 1.01;
        float pdf;
        vec3 wi = env_sample(u_dir, pdf);
        if (!(pdf > 0.0)) return false;
        ray = Ray(disk_point(c + wi * r, -wi, r, u_pos), -wi, INF);
        power = env_radiance(wi) * (PI * r * r) / (pdf * pick);
        return true;
    }
    return false;
}

void store(uint slot, vec3 position, vec3 normal, vec3 power) {
    IGI_VPLS.v[slot] = Vpl(vec4(position, 0.0), vec4(normal, 0.0), vec4(power, 1.0));
}

void main() {
    load_frame_constants();
    uint path = gl_GlobalInvocationID.x;
    if (path >= vpl_paths()) return;
    uint bounces = vpl_bounces();
    uint base = path * bounces;
    for (uint k = 0u; k < bounces; ++k) IGI_VPLS.v[base + k] = Vpl(vec4(0.0), vec4(0.0), vec4(0.0));
    Ray ray;
    vec3 power;
    float range;
    if (!emit(path, ray, power, range)) return;
    power /= float(vpl_paths());
    // The lobe choice of transmission's Fresnel test is the one number not from the sequence.
    Rng rng = rng_init(uvec2(path, 0xffffffffu), 0u, frame_index(), render_seed());
    for (uint k = 0u; k < bounces; ++k) {
        Hit hit;
        if (!trace(ray, false, hit)) return;
        Surface s = surface_at(hit);
        if (k == 0u && range > 0.0) {
            // glTF's range window, as NEE applies it to the light arriving here.
            float r = hit.t * hit.t / (range * range);
            float w = clamp(1.0 - r * r, 0.0, 1.0);
            power *= w * w;
        }
        vec3 t, b;
        make_frame(s.ns, t, b);
        vec3 wo = to_local(-ray.dir, t, b, s.ns);
        Bsdf bsdf = make_bsdf(s, wo);
        vec3 ng_wo = dot(s.ng, ray.dir) < 0.0 ? s.ng : -s.ng;
        // Light arrives through the geometric surface but is reflected about the shading normal:
        // particles carry the adjoint's correction |wo.ns| / |wo.ng| (Veach 1997, 5.3), so that
        // the VPLs reflect what the path tracer's shading points do.
        float cos_ng_in = abs(dot(-ray.dir, s.ng));
        if (!(cos_ng_in > 0.0)) return;
        float shading_in = abs(wo.z) / cos_ng_in;
        if (bsdf.p.x > 0.0) {
            // Radiance x area of the diffuse reflection: flux x albedo / pi (Fresnel of the
            // specular layer taken at the incoming direction); it leaves through the geometric
            // surface, on the side the light arrived on.
            vec3 albedo = diffuse_reflectance(bsdf, layer_fresnel(bsdf, abs(wo.z))) * sheen_view_scale(bsdf);
            store(base + k, offset_ray(s.position, ng_wo, s.magnitude), ng_wo, power * albedo * (INV_PI * shading_in));
        }
        if (k + 1u == bounces) return;
        uint d = 5u + 3u * k;
        BsdfSample bs;
        if (!bsdf_sample_with(bsdf, wo, halton(path, d), vec2(halton(path, d + 1u), halton(path, d + 2u)), rng, bs)) return;
        vec3 wi = to_world(bs.wi, t, b, s.ns);
        if ((dot(wi, ng_wo) > 0.0) != (bs.wi.z * wo.z > 0.0)) return;
        float cos_ns_out = abs(bs.wi.z);
        power *= cos_ns_out > 0.0 ? bs.weight * (shading_in * abs(dot(wi, s.ng)) / cos_ns_out) : vec3(0.0);
        if (!any(greaterThan(power, vec3(0.0)))) return;
        ray = Ray(offset_ray(s.position, dot(wi, ng_wo) > 0.0 ? ng_wo : -ng_wo, s.magnitude), wi, INF);
    }
}
