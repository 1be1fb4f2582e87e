#version 460
// IGI, gather pass: the VPLs [vpl_first(), vpl_end()) of the pixel's subset lighting the
// vertex the camera pass recorded, as rho / pi * I * cos * cos / d^2 * V summed into the pixel's
// radiance, or with IGI_FILTERED as irradiance into its texel (the filters after assembly apply
// the albedo). With IGI_BOUNDED the 1/d^2 is bounded near the VPLs (the paper's clamp); with
// IGI_DOWNSAMPLED only the grid's pixels have a vertex; with IGI_INTERLEAVED a pixel gathers one
// of igi_tile().x * igi_tile().y subsets, scaled up by their number.

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

#include "common/scene.glsl"
#include "igi/igi.glsl"
#include "common/rng.glsl"
#include "common/sampling.glsl"
#include "common/textures.glsl"
#include "common/intersect.glsl"
#include "igi/visibility.glsl"
#include "common/trace.glsl"
#include "common/surface.glsl"
#include "common/environment.glsl"
#include "common/bsdf.glsl"
#include "common/lights.glsl"
#include "path/path.glsl"
#include "igi/pixel.glsl"

float bounded_inv_square(float d2) {
#ifdef IGI_BOUNDED
    // Marques and Santos: blended from 1/d_min^2 into 1/d^2 between 0.8 and 1.2 d_min.
    float dmin = vpl_min_distance();
    return mix(1.0 / (dmin * dmin), 1.0 / d2, smoothstep(0.8 * dmin, 1.2 * dmin, sqrt(d2)));
#else
    return 1.0 / d2;
#endif
}

void main() {
    load_frame_constants();
    uvec2 pixel;
    uint index;
    if (!band_pixel(pixel, index)) return;
    IgiVertex x = IGI_VERTICES.v[index];
    if (x.ng.w == 0.0) return;
    vec3 n = x.ns.xyz, ng = x.ng.xyz, wo = x.wo.xyz;
    uint step = igi_subsets();
    // The first VPL of the chunk in the pixel's subset.
    uint first = vpl_first() + (igi_subset(pixel) + step - vpl_first() % step) % step;
    vec3 origin = offset_ray(x.position.xyz, ng, x.position.w);
    vec3 sum = vec3(0.0);
    uint rays = 0u;
    for (uint j = first; j < vpl_end(); j += step) {
        Vpl v = IGI_VPLS.v[j];
        if (v.power.w == 0.0) continue;
        vec3 d = v.position.xyz - x.position.xyz;
        float d2 = dot(d, d);
        if (!(d2 > 0.0)) continue;
        vec3 wi = d * inversesqrt(d2);
        // The VPL's geometric normal: its radiance leaves a patch of the surface.
        float cos_y = -dot(wi, v.normal.xyz);
        float cos_x = dot(wi, n);
        // Both in front: of the VPL, and of the shading and geometric normals on the path's side.
        if (cos_y <= 0.0 || cos_x <= 0.0 || dot(wi, ng) <= 0.0) continue;
#ifdef IGI_FILTERED
        vec3 f = vec3(cos_x);
#else
        // bsdf_diffuse in world space: the specular layer's Fresnel at the half vector.
        vec3 fr = schlick(x.f0.xyz, dot(wo, normalize(wo + wi)));
        vec3 f = x.albedo.xyz * (1.0 - x.ns.w * max3(fr)) * INV_PI * cos_x;
#endif
        vec3 c = f * v.power.rgb * (cos_y * bounded_inv_square(d2));
        if (!any(greaterThan(c, vec3(0.0)))) continue;
        rays++;
        Hit h;
        if (!trace(Ray(origin, v.position.xyz - origin, 1.0), true, h)) sum += c;
    }
    sum *= float(step);
#ifdef IGI_FILTERED
    IGI_TEXELS.v[3u * index] += vec4(sum, 0.0);
#else
    pc.g.accum.v[index] += vec4(sum, 0.0);
#endif
    atomicAdd(pc.g.stats.v[4u + pixel.y], rays);
}
