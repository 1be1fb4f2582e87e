// The AOV passes (frame::Output::Aov, crates/platoon-aov/src/aov.rs): one of albedo,
// normal, position, ids, one sample's ids or alpha per pixel, chosen by OUTPUT_AOV_*. Albedo
// and normal follow Cycles' denoising passes: the camera ray is followed through perfect
// specular vertices (mirrors, clear glass; their sampled lobe's weight tints the albedo) to the
// first vertex that is not, and the samples use the beauty's camera rays (the same random
// numbers), summed onto the buffer like the beauty's. Position and ids: the first hit of the
// ray through the pixel centre.

// Perfect specular vertices followed before a pixel's albedo or normal is given up (black).
const uint AOV_SPECULAR_CHAIN = 8u;

#if defined(OUTPUT_AOV_ALBEDO) || defined(OUTPUT_AOV_NORMAL)
vec3 aov_sample(uvec2 pixel, uint si, inout uint rays) {
    Rng rng = pixel_rng(pixel, si);
    Ray ray = camera_ray(pixel, rng);
    vec3 weight = vec3(1.0);
    float cone = cone_start();  // the beauty's ray cone, for its texture levels
    for (uint vertex = 0u; vertex <= AOV_SPECULAR_CHAIN; vertex++) {
        Hit hit;
        rays++;
        if (!trace(ray, false, hit)) return vec3(0.0);
        cone += cone_spread() * hit.t;
        Surface s = surface_at(hit, ray.dir, cone);
        vec3 t, b;
        make_frame(s.ns, t, b);
        vec3 wo = to_local(-ray.dir, t, b, s.ns);
        Bsdf bsdf = make_bsdf(s, wo);
        bool stop = !bsdf_all_delta(bsdf);
#ifdef HAS_UNLIT
        stop = stop || s.unlit;
#endif
        if (stop) {
#ifdef OUTPUT_AOV_ALBEDO
            return weight * s.base_color;
#else
            return dot(s.ns, ray.dir) > 0.0 ? -s.ns : s.ns;
#endif
        }
        BsdfSample bs;
        if (!bsdf_sample(bsdf, wo, rng, bs)) return vec3(0.0);
        weight *= bs.weight;
        vec3 wi = to_world(bs.wi, t, b, s.ns);
        vec3 ng_wo = dot(s.ng, ray.dir) < 0.0 ? s.ng : -s.ng;
        ray = Ray(offset_ray(s.position, dot(wi, ng_wo) > 0.0 ? ng_wo : -ng_wo, s.magnitude), wi, INF);
    }
    return vec3(0.0);
}
#endif

// (instance + 1, material + 1, triangle + 1) of a hit.
vec3 hit_ids(Hit hit) {
    return vec3(float(hit.instance) + 1.0, float(surface_at(hit).material) + 1.0, float(hit.triangle) + 1.0);
}

// The first hit of sample `si`'s camera ray, the beauty's (its random numbers go on in `rng`
// for what the pass draws next); false when the ray sees no surface.
bool first_hit(uvec2 pixel, uint si, out Rng rng, out Ray ray, out Hit hit, inout uint rays) {
    rng = pixel_rng(pixel, si);
    ray = camera_ray(pixel, rng);
    rays++;
    return trace(ray, false, hit);
}

// The pass's samples of one pixel, added onto `sum` (position and ids: one sample, written).
vec3 aov_pixel(uvec2 pixel, vec3 sum, inout uint rays) {
#if defined(OUTPUT_AOV_ALBEDO) || defined(OUTPUT_AOV_NORMAL)
    for (uint si = pc.sample_begin; si != pc.sample_end; si++) sum += aov_sample(pixel, si, rays);
    return sum;
#elif defined(OUTPUT_AOV_AO)
    // Ambient occlusion at the first hit of each of the pass's camera rays (the beauty's): a
    // cosine-distributed ray about the shading normal toward the camera, unoccluded within
    // ao_distance() counts 1; a camera ray that sees no surface counts 1 (nothing occludes it).
    for (uint si = pc.sample_begin; si != pc.sample_end; si++) {
        Rng rng;
        Ray ray;
        Hit hit;
        if (!first_hit(pixel, si, rng, ray, hit, rays)) {
            sum += vec3(1.0);
            continue;
        }
        Surface s = surface_at(hit);
        vec3 n = dot(s.ns, ray.dir) > 0.0 ? -s.ns : s.ns;
        vec3 ng = dot(s.ng, ray.dir) > 0.0 ? -s.ng : s.ng;
        vec3 t, b;
        make_frame(n, t, b);
        vec3 wi = to_world(sample_cosine_hemisphere(rng_next2(rng)), t, b, n);
        // A direction the shading normal bends below the surface is occluded by it.
        if (dot(wi, ng) <= 0.0) continue;
        Hit blocker;
        rays++;
        if (!trace(Ray(offset_ray(s.position, ng, s.magnitude), wi, ao_distance()), true, blocker))
            sum += vec3(1.0);
    }
    return sum;
#elif defined(COLOR_PART)
    // A BSDF part's colour (Cycles' DiffCol, GlossCol, TransCol): at the first hit of each of
    // the pass's camera rays, the BSDF's sampled weight times the part's share of it, whose
    // mean is the part's directional albedo (a Lambertian surface's: its colour exactly).
    for (uint si = pc.sample_begin; si != pc.sample_end; si++) {
        Rng rng;
        Ray ray;
        Hit hit;
        if (!first_hit(pixel, si, rng, ray, hit, rays)) continue;
        Surface s = surface_at(hit);
        vec3 t, b;
        make_frame(s.ns, t, b);
        vec3 wo = to_local(-ray.dir, t, b, s.ns);
        BsdfSample bs;
        if (bsdf_sample(make_bsdf(s, wo), wo, rng, bs)) sum += bs.weight * share_of_part(COLOR_PART);
    }
    return sum;
#elif defined(OUTPUT_AOV_ALPHA)
    // How many of the pass's camera rays (the beauty's) find a surface: a transparent film's
    // alpha, over the samples.
    for (uint si = pc.sample_begin; si != pc.sample_end; si++) {
        Rng rng;
        Ray ray;
        Hit hit;
        if (first_hit(pixel, si, rng, ray, hit, rays)) sum += vec3(1.0);
    }
    return sum;
#elif defined(OUTPUT_AOV_SAMPLE_IDS)
    // The ids under one sample's camera ray (Cryptomatte's coverage, frame/cryptomatte.rs).
    Rng rng;
    Ray ray;
    Hit hit;
    return first_hit(pixel, pc.sample_begin, rng, ray, hit, rays) ? hit_ids(hit) : vec3(0.0);
#else
    vec2 ndc = pixel_ndc(pixel, vec2(0.5));
    vec3 dir = F.cam_forward.xyz + ndc.x * F.cam_right.w * F.cam_right.xyz + ndc.y * F.cam_up.w * F.cam_up.xyz;
    vec3 origin = F.cam_origin.xyz;
#ifdef HAS_ORTHOGRAPHIC
    origin += ndc.x * F.cam_right.w * F.cam_right.xyz + ndc.y * F.cam_up.w * F.cam_up.xyz;
    dir = F.cam_forward.xyz;
#endif
    Hit hit;
    rays++;
    if (!trace(Ray(origin, normalize(dir), INF), false, hit)) return vec3(0.0);
#ifdef OUTPUT_AOV_POSITION
    return surface_at(hit).position;
#else
    return hit_ids(hit);
#endif
#endif
}
