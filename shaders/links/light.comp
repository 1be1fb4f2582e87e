#version 460
// Vertex links, a lighting frame: pixel i (row-major) is element i. Each sample is one
// next-event estimate of the direct irradiance at the element, E_d = integral of L cos, through
// the path tracer's light sampling (every light kind: punctual, emissive triangles, the
// environment), so the frame's average is E_d. It also leaves the element's diffuse albedo
// (at normal incidence, from the material at one of its corners) for the gather.
//
// With LINKS_FAN_LIGHT each sample is taken at a point of the element's fan (the triangles
// around it) drawn with the density of the element's interpolation weight there (a triangle by
// area, then barycentrics from Dirichlet(2, 1, 1), the element's corner weighing 2), so the
// frame's average is the fan's hat-weighted mean of E_d: the continuous form of the paper's
// light-link oversampling, which keeps light that peaks within a triangle from being missed
// or overweighted by its corners.

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

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

#ifdef LINKS_FAN_LIGHT
// A point of the element's fan with the density of its interpolation weight (the hat), and the
// surface's shading normal there on the element's side; `o` is lifted off the surface.
void fan_point(ElementRay e, inout Rng rng, out vec3 o, out vec3 n) {
    float u = rng_next(rng);
    uint k = e.fan.x, last = e.fan.x + max(e.fan.y, 1u) - 1u;
    while (k < last && uintBitsToFloat(LINKS_FANS.v[k].z) < u) ++k;
    uvec4 entry = LINKS_FANS.v[k];
    // Dirichlet(2, 1, 1) by normalised gamma variates (1 - u: never log 0).
    float g0 = -log((1.0 - rng_next(rng)) * (1.0 - rng_next(rng)));
    float g1 = -log(1.0 - rng_next(rng));
    float g2 = -log(1.0 - rng_next(rng));
    vec3 b;
    if (entry.y == 0u) b = vec3(g0, g1, g2);
    else if (entry.y == 1u) b = vec3(g1, g0, g2);
    else b = vec3(g1, g2, g0);
    b /= b.x + b.y + b.z;
    Surface s = surface_at(Hit(0.0, b.y, b.z, e.corner.x, entry.x));
    vec3 ng = dot(s.ng, e.normal.xyz) >= 0.0 ? s.ng : -s.ng;
    n = dot(s.ns, ng) >= 0.0 ? s.ns : -s.ns;
    o = offset_ray(s.position, ng, s.magnitude);
}
#endif

void main() {
    load_frame_constants();
    uvec2 pixel;
    uint index;
    if (!band_pixel(pixel, index) || index >= links_elements()) return;
    ElementRay e = LINKS_ELEMENTS.v[index];
    vec3 sum = pc.g.accum.v[index].xyz;
    uint rays = 0u, rejected = 0u;
    for (uint si = pc.sample_begin; si != pc.sample_end; ++si) {
        Rng rng = rng_init(pixel, si, frame_index(), render_seed());
        vec3 n = e.normal.xyz;
        vec3 o = e.origin.xyz;
#ifdef LINKS_FAN_LIGHT
        fan_point(e, rng, o, n);
#endif
        LightSample ls;
        vec3 c = vec3(0.0);
        if (sample_light(o, rng, ls)) {
            float cos_theta = dot(n, ls.wi);
            if (cos_theta > 0.0 && ls.pdf > 0.0) {
                Hit blocker;
                rays++;
                Ray shadow = ls.infinite ? Ray(o, ls.wi, INF) : Ray(o, ls.target - o, 1.0);
                if (!trace(shadow, true, blocker)) c = ls.radiance * (cos_theta / ls.pdf);
            }
        }
        if (any(isnan(c)) || any(isinf(c))) rejected++;
        else sum += c;
    }
    pc.g.accum.v[index] = vec4(sum, 0.0);
    // The albedo at the element's corner, as the camera paths' diffuse lobe weighs light.
    uvec4 k = e.corner;
    Hit at = Hit(0.0, k.z == 1u ? 1.0 : 0.0, k.z == 2u ? 1.0 : 0.0, k.x, k.y);
    Surface s = surface_at(at);
    Bsdf bsdf = make_bsdf(s, vec3(0.0, 0.0, 1.0));
    LINKS_OUTPUT.v[index] = vec4(diffuse_reflectance(bsdf, layer_fresnel(bsdf, 1.0)) * sheen_view_scale(bsdf), 0.0);
    if (rejected > 0u) atomicAdd(pc.g.stats.v[0], rejected);
    atomicAdd(pc.g.stats.v[4u + pixel.y], rays);
}
