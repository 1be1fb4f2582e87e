// The path tracer's paths: one vertex at a time (path_step), the samples of a pixel with path
// regeneration (pixel_samples). Shared by pathtrace.comp and the methods that reuse the path loop
// (IGI's camera pass records its gathering vertex through the hooks).
//
// Hooks. A kernel that defines PATH_HOOKS defines, before including this file, the struct
// PathHook (what it carries along a path, Path::hook) and, after it, these functions:
//   void hook_path_start(inout PathHook h);
//       a new path;
//   bool hook_after_emission(inout Path p);
//       after a vertex added its emission, before the path goes on from it; false ends the path;
//   void hook_vertex(inout Path p, Hit hit, Surface s, Bsdf bsdf, vec3 wo, vec3 ng_wo);
//       at a vertex the path scatters from (at `hit`), before its next-event estimation;
//   void hook_bsdf_sampled(inout Path p, Bsdf bsdf, vec3 wo, BsdfSample bs);
//       after the vertex's BSDF sample weighed the throughput, before roulette.
// With PATH_TRACE_HOOK also (layered hit buffers' lookups):
//   bool hook_trace(inout Path p, inout Rng rng, out Hit hit);
//       the closest hit of the path's ray (without it: a traversal).
// And a macro a kernel may define before including this file:
//   PATH_NEE_ALONE(p): next-event estimation takes the whole of the direct light at the path's
//       vertices (its NEE weighs 1, light its BSDF rays find 0 where NEE could have sampled it).

#ifndef PATH_NEE_ALONE
#define PATH_NEE_ALONE(p) false
#endif

// The megakernel's push words (PathPasses::push_words in crates/platoon-tracer/src/method/path.rs):
// how many turns the loop-limit canary takes (2).
uint loop_canary() { return pc.method_words[0]; }
// stats[STAT_CUT_SHORT]: pixels whose pass the megakernel could not finish (scene.glsl's Stats).
const uint STAT_CUT_SHORT = 1u;
// A pixel's accumulation w: 0 rendering; PIXEL_CUT_SHORT its megakernel pass ran past the
// device's loop limit (the streaming kernels finish it); PIXEL_CONVERGED adaptive sampling's
// converged pixel (set by the tracer from FrameParams::converged), which takes no samples.
const float PIXEL_CUT_SHORT = 1.0;
const float PIXEL_CONVERGED = 2.0;

// Weight of emission found by a BSDF-sampled ray, against the NEE pdf of the same light.
float emission_weight(bool after_delta, float bsdf_pdf, float light_pdf) {
    if (after_delta) return 1.0;
#if defined(SAMPLING_BSDF)
    return 1.0;
#elif defined(SAMPLING_LIGHT) || (defined(LIGHT_SELECT_RIS) && !defined(RIS_MIS))
    // RIS alone: its pdf of a direction is not known in closed form, the light sample alone.
    return light_pdf > 0.0 ? 0.0 : 1.0;
#else
    return power_heuristic(bsdf_pdf, light_pdf);
#endif
}

// Adds light a path gathered. With CLAMP_INDIRECT what arrives after the first bounce is clamped
// to a largest component (biased: a firefly suppressor); direct light is never clamped.
vec3 clamped_light(vec3 c, uint depth) {
#ifdef CLAMP_INDIRECT
    float m = max3(c);
    if (depth >= 1u && m > clamp_indirect()) c *= clamp_indirect() / m;
#endif
    return c;
}

void add_light(inout vec3 L, vec3 c, uint depth) {
    L += clamped_light(c, depth);
}

#ifdef LIGHT_PASS
// A light pass's kernel (crates/platoon-aov/src/light_pass.rs) keeps its share of each
// light the path gathers, after the clamp, so that the passes sum to the beauty.
const uint LP_EMISSION = 6u;
const uint LP_ENVIRONMENT = 7u;
bool direct_pass() { return LIGHT_PASS < LP_EMISSION && LIGHT_PASS % 2u == 0u; }
bool indirect_pass() { return LIGHT_PASS < LP_EMISSION && LIGHT_PASS % 2u == 1u; }
// The pass's part of the BSDF's last evaluation or delta sample (bsdf.glsl's share_of_part).
float part_share() {
    if (LIGHT_PASS >= LP_EMISSION) return 0.0;
    // (min: the emission and environment passes returned above.)
    return share_of_part(int(min(LIGHT_PASS / 2u, 2u)));
}
#endif

// Shading normals bend the hemispheres: a direction the shading frame calls reflection may cross
// the geometric surface (and the reverse). Such a direction must carry no light, or light leaks
// through closed smooth meshes (pbrt-v3's reflect/transmit test against the geometric normal).
// ng_wo: geometric normal on wo's side; shading_cos_product: wo.z * wi.z in the shading frame.
bool sides_agree(vec3 ng_wo, vec3 wi, float shading_cos_product) {
    return (dot(wi, ng_wo) > 0.0) == (shading_cos_product > 0.0);
}

#include "path/pixel_filter.glsl"
#ifdef RIS_CONTRIBUTION
#include "path/resampled_light.glsl"
#ifdef LIGHT_REUSE
#include "path/light_reuse.glsl"
#endif
#endif
#if defined(WORLD_CACHE) || defined(WORLD_CACHE_TRAIN)
#include "path/world_cache.glsl"
#endif

// The random numbers of a frame pixel's sample: the image pixel's (a border render's window
// draws what the whole image draws there).
Rng pixel_rng(uvec2 pixel, uint sample_index) {
    return rng_init(image_pixel(pixel), sample_index, frame_index(), render_seed());
}

// A frame pixel's point `offset` pixels from its top-left corner, in the normalised device
// coordinates of the image the camera frames.
vec2 pixel_ndc(uvec2 pixel, vec2 offset) {
    vec2 p = vec2(image_pixel(pixel));
    vec2 size = image_size();
    return vec2(2.0 * (p.x + offset.x) / size.x - 1.0, 1.0 - 2.0 * (p.y + offset.y) / size.y);
}

Ray camera_ray(uvec2 pixel, inout Rng rng) {
    vec2 jitter = pixel_position(rng_next2(rng));
    vec2 lens = rng_next2(rng);
    vec2 ndc = pixel_ndc(pixel, jitter);
    vec3 dir = F.cam_forward.xyz + ndc.x * F.cam_right.w * F.cam_right.xyz + ndc.y * F.cam_up.w * F.cam_up.xyz;
    vec3 origin = F.cam_origin.xyz;
#ifdef HAS_ORTHOGRAPHIC
    // Parallel rays from the image plane: cam_right.w and cam_up.w hold xmag and ymag.
    origin += ndc.x * F.cam_right.w * F.cam_right.xyz + ndc.y * F.cam_up.w * F.cam_up.xyz;
    dir = F.cam_forward.xyz;
#endif
#ifdef HAS_THIN_LENS
    // dir has unit forward component, so the focus plane point is origin + dir * focus.
    vec3 focus = origin + dir * F.cam_forward.w;
    vec2 d = sample_disk_concentric(lens) * F.cam_origin.w;
    origin += d.x * F.cam_right.xyz + d.y * F.cam_up.xyz;
    dir = focus - origin;
#endif
    return Ray(origin, normalize(dir), INF);
}

// The pixel's ray cone (texture level selection, TEXTURE_LOD): the angle a pixel spans at the
// camera, and the cone's width at the camera (a pixel's width for an orthographic camera, whose
// cone does not spread).
float cone_spread() {
#ifdef HAS_ORTHOGRAPHIC
    return 0.0;
#else
    return 2.0 * F.cam_up.w / image_size().y;
#endif
}
float cone_start() {
#ifdef HAS_ORTHOGRAPHIC
    return 2.0 * F.cam_up.w / image_size().y;
#else
    return 0.0;
#endif
}

// One path in flight: what the bounce loop carries from one vertex to the next.
struct Path {
    Ray ray;
    vec3 L;
    vec3 throughput;
    bool after_delta;  // the camera ray counts like a delta bounce
    float bsdf_pdf;
    uint depth;
    uint sample_index;  // the pixel's sample: what deterministic termination (DPT) reads
    uint diffuse;       // non-delta bounces so far (single diffuse bounce)
#ifdef HAS_VOLUME
    vec3 medium;        // the absorption of the medium the ray travels in (0: the outside)
#endif
#ifdef HAS_DISPERSION
    float wavelength;   // nm, from the first dispersive surface on (0: the path is RGB)
#endif
#ifdef LIGHT_PASS
    float pass_share;   // the light pass's part of the first vertex's BSDF sample
#endif
#ifdef TEXTURE_LOD
    // The pixel's cone's width at the ray's origin: widened along each segment at the camera's
    // spread, not by the bounces (curvature and roughness left out: it blurs less, never more).
    float cone;
#endif
#ifdef PATH_HOOKS
    PathHook hook;
#endif
#ifdef WORLD_CACHE_TRAIN
    // The second vertex's cell (0: the path did not go on from one), and the light and
    // throughput the path had there (after its emission): what it gathers after is the cell's.
    uint cache_key;
    vec3 cache_light;
    vec3 cache_throughput;
#endif
};

#ifdef LIGHT_PASS
// The light pass's share of light the path's ray found (emission, the environment): the camera
// ray's finds are the emission and environment passes'; the first vertex's BSDF ray brings
// direct light, later rays indirect, in the part of the first vertex's sample.
float found_share(Path p, bool environment) {
    if (p.depth == 0u) return float(LIGHT_PASS == (environment ? LP_ENVIRONMENT : LP_EMISSION));
    return (p.depth == 1u ? direct_pass() : indirect_pass()) ? p.pass_share : 0.0;
}
// ... of next-event estimation's light at the path's vertex, the BSDF just evaluated toward it.
float nee_share(Path p) {
    if (p.depth == 0u) return direct_pass() ? part_share() : 0.0;
    return indirect_pass() ? p.pass_share : 0.0;
}
#define FOUND_LIGHT(L, c, depth, p, environment) L += clamped_light(c, depth) * found_share(p, environment)
#else
#define FOUND_LIGHT(L, c, depth, p, environment) add_light(L, c, depth)
#endif

// Weight of emission the path's ray found (light_pdf: NEE's pdf of the same light).
float path_emission_weight(Path p, float light_pdf) {
#ifdef LIGHT_REUSE
    // The reused light sample takes the whole of the first vertex's direct light: far better
    // than one drawn by power, it would lose to BSDF rays in an MIS weighed with the power's pdf.
    if (!p.after_delta && p.depth == 1u && reuse_here(0u, p.sample_index))
        return light_pdf > 0.0 ? 0.0 : 1.0;
#endif
#ifndef SAMPLING_BSDF
    if (PATH_NEE_ALONE(p) && !p.after_delta) return light_pdf > 0.0 ? 0.0 : 1.0;
#endif
    return emission_weight(p.after_delta, p.bsdf_pdf, light_pdf);
}

#ifdef PATH_HOOKS
void hook_path_start(inout PathHook h);
bool hook_after_emission(inout Path p);
void hook_vertex(inout Path p, Hit hit, Surface s, Bsdf bsdf, vec3 wo, vec3 ng_wo);
void hook_bsdf_sampled(inout Path p, Bsdf bsdf, vec3 wo, BsdfSample bs);
#endif
#ifdef PATH_TRACE_HOOK
bool hook_trace(inout Path p, inout Rng rng, out Hit hit);
#endif

Path path_start(Ray ray, uint sample_index) {
    Path p;
    p.ray = ray;
    p.L = vec3(0.0);
    p.throughput = vec3(1.0);
    p.after_delta = true;
    p.bsdf_pdf = 0.0;
    p.depth = 0u;
    p.sample_index = sample_index;
    p.diffuse = 0u;
#ifdef HAS_VOLUME
    p.medium = vec3(0.0);
#endif
#ifdef HAS_DISPERSION
    p.wavelength = 0.0;
#endif
#ifdef LIGHT_PASS
    p.pass_share = 0.0;
#endif
#ifdef TEXTURE_LOD
    p.cone = cone_start();
#endif
#ifdef PATH_HOOKS
    hook_path_start(p.hook);
#endif
#ifdef WORLD_CACHE_TRAIN
    p.cache_key = 0u;
    p.cache_light = vec3(0.0);
    p.cache_throughput = vec3(0.0);
#endif
    return p;
}


#ifdef HAS_VOLUME
// Beer-Lambert: what a medium of absorption `a` lets through over `d` (d = INF: an endless ray,
// which a medium that absorbs takes whole).
vec3 transmittance(vec3 a, float d) {
    return d < INF ? exp(-a * d) : vec3(equal(a, vec3(0.0)));
}

// The medium beyond surface `s` for a ray that crossed it (KHR_materials_volume, one medium at
// a time as the spec allows: the one of the last surface entered): the material's own entering
// from the front, the outside leaving from the back; a thin wall changes nothing.
vec3 medium_beyond(Surface s, vec3 medium, bool from_front) {
    if (!s.volume) return medium;
    return from_front ? s.absorption : vec3(0.0);
}
#endif

// Next-event estimation's shadow ray from a vertex, and the light it brings if nothing blocks
// it (weighed and clamped already): traced after the vertex's shading, by the megakernel's
// path_step or the streaming path tracer's connect kernel.
struct ShadowRay {
    Ray ray;
    vec3 light;
    bool valid;
};

// The path's vertex where its ray ended (`found`: at `hit`; else it left the scene): the light
// it finds there, next-event estimation's shadow ray (`shadow`, not traced) and the BSDF sample
// that carries the path on (p.ray). False once the path has ended; the shadow ray's light is
// still to be added then.
bool path_shade(inout Path p, bool found, Hit hit, inout Rng rng, out ShadowRay shadow) {
    shadow.valid = false;
#ifdef LIGHT_REUSE
    // Overwritten where the first vertex takes a light sample.
    if (reuse_here(p.depth, p.sample_index)) reuse_clear();
#endif
#ifdef HAS_VOLUME
    // What the medium absorbed along the segment just traced (before the light found at its end).
    p.throughput *= transmittance(p.medium, found ? hit.t : INF);
#endif
    if (!found) {
#ifdef FILM_TRANSPARENT
        // A transparent film leaves the environment the camera sees out (alpha 0 there).
        if (p.depth == 0u) return false;
#endif
        if (env_kind() != ENV_NONE)
            FOUND_LIGHT(p.L, p.throughput * env_radiance(p.ray.dir) * path_emission_weight(p, environment_light_pdf(p.ray.dir)), p.depth, p, true);
        return false;
    }
#ifdef TEXTURE_LOD
    p.cone += cone_spread() * hit.t;
    Surface s = surface_at(hit, p.ray.dir, p.cone);
#else
    Surface s = surface_at(hit);
#endif
#ifdef HAS_UNLIT
    // KHR_materials_unlit (the spec's advice to a path tracer): the base colour is radiance the
    // surface emits toward every viewer, and it reflects nothing. NEE never picks it, so a BSDF
    // ray that finds it takes it whole.
    if (s.unlit) {
        FOUND_LIGHT(p.L, p.throughput * s.base_color, p.depth, p, false);
        return false;
    }
#endif
#ifdef HAS_EMISSIVE_TRIANGLES
    vec3 le = triangle_emission(s, p.ray.dir);
    if (any(greaterThan(le, vec3(0.0))))
        FOUND_LIGHT(p.L, p.throughput * le * path_emission_weight(p, triangle_light_pdf(hit, s.ng, p.ray.dir)), p.depth, p, false);
#endif
#ifdef PATH_HOOKS
    if (!hook_after_emission(p)) return false;
#endif
    // depth + 1 segments so far; the next vertex would make depth + 2 (Mitsuba's max_depth).
    if (p.depth + 1u >= max_depth()) return false;
#if defined(WORLD_CACHE) || defined(WORLD_CACHE_TRAIN)
    // The second vertex, where a path would go on: the world cache's (path/world_cache.glsl).
    if (p.depth == 1u) {
        uint key = cache_key(s.position, dot(s.ng, p.ray.dir) < 0.0 ? s.ng : -s.ng);
#ifdef WORLD_CACHE
        vec3 cached;
        if (cache_lookup(key, cached)) {
            // Light reflected at the second vertex: indirect for the light passes.
            Path after = p;
            after.depth = 2u;
            FOUND_LIGHT(p.L, p.throughput * cached, 2u, after, false);
            return false;
        }
#else
        p.cache_key = key;
        p.cache_light = p.L;
        p.cache_throughput = p.throughput;
#endif
    }
#endif
#ifdef CAMERA_RAYS_ONLY
    // Max depth 1 compiles the bounce away: llvmpipe runs every instruction of a loop body under
    // a lane mask whichever way its branches go, so code skipped at run time still costs.
    return false;
#else

    vec3 t, b;
    make_frame(s.ns, t, b);
    vec3 wo = to_local(-p.ray.dir, t, b, s.ns);
#ifdef HAS_DISPERSION
    if (s.dispersion > 0.0 && s.transmission > 0.0) {
        // KHR_materials_dispersion: the path turns spectral at the first dispersive surface it
        // meets (one wavelength, its throughput weighed by the wavelength's colour) and every
        // dispersive surface then refracts at that wavelength's index; the rest stays RGB.
        if (p.wavelength == 0.0) {
            vec3 weight;
            p.wavelength = sample_wavelength(rng_next(rng), weight);
            p.throughput *= weight;
        }
        s.ior = dispersed_ior(s.ior, s.dispersion, p.wavelength);
    }
#endif
    Bsdf bsdf = make_bsdf(s, wo);
    // The geometric side the ray arrived on; new rays leave from the side they head to.
    vec3 ng_wo = dot(s.ng, p.ray.dir) < 0.0 ? s.ng : -s.ng;
    // With SINGLE_DIFFUSE_BOUNCE (Bikker's games) the path ends at its second non-delta vertex:
    // its NEE then takes the whole of the direct light, as no BSDF ray will follow for MIS.
    bool last_diffuse = false;
#ifdef SINGLE_DIFFUSE_BOUNCE
    last_diffuse = p.diffuse >= 1u;
#endif
#ifdef PATH_HOOKS
    hook_vertex(p, hit, s, bsdf, wo, ng_wo);
#endif

#ifndef SAMPLING_BSDF
    if (!bsdf_all_delta(bsdf)) {
        LightSample ls;
#if defined(LIGHT_REUSE)
        bool reused = reuse_here(p.depth, p.sample_index);
        if (reused ? reuse_light(s, t, b, bsdf, wo, ng_wo, rng, ls)
                   : sample_light_toward(s.position, bsdf, wo, t, b, s.ns, ng_wo, rng, ls)) {
#elif defined(RIS_CONTRIBUTION)
        if (sample_light_toward(s.position, bsdf, wo, t, b, s.ns, ng_wo, rng, ls)) {
#else
        if (sample_light(s.position, rng, ls)) {
#endif
            float pdf;
            vec3 wi_local = to_local(ls.wi, t, b, s.ns);
            vec3 f = bsdf_eval(bsdf, wo, wi_local, pdf);
            if (any(greaterThan(f, vec3(0.0))) && sides_agree(ng_wo, ls.wi, wi_local.z * wo.z)) {
                vec3 o = offset_ray(s.position, dot(ls.wi, ng_wo) > 0.0 ? ng_wo : -ng_wo, s.magnitude);
                shadow.ray = ls.infinite ? Ray(o, ls.wi, INF) : Ray(o, ls.target - o, 1.0);
#if defined(SAMPLING_LIGHT) || (defined(LIGHT_SELECT_RIS) && !defined(RIS_MIS))
                float w = 1.0;
#else
                bool alone = ls.delta || last_diffuse || PATH_NEE_ALONE(p);
#ifdef LIGHT_REUSE
                alone = alone || reused;
#endif
                float w = alone ? 1.0 : power_heuristic(ls.mis_pdf, pdf);
#endif
                vec3 through = vec3(1.0);
#ifdef HAS_VOLUME
                // The shadow ray's medium: the path's, or the one beyond if it crosses.
                vec3 m = dot(ls.wi, ng_wo) > 0.0 ? p.medium : medium_beyond(s, p.medium, dot(s.ng, p.ray.dir) < 0.0);
                through = transmittance(m, ls.infinite ? INF : distance(o, ls.target));
#endif
                shadow.light = clamped_light(p.throughput * through * f * ls.radiance * (w / ls.pdf), p.depth);
#ifdef LIGHT_PASS
                shadow.light *= nee_share(p);
#endif
                shadow.valid = true;
            }
        }
    }
#endif

    BsdfSample bs;
    if (!bsdf_sample(bsdf, wo, rng, bs)) return false;
#ifdef LIGHT_PASS
    if (p.depth == 0u) p.pass_share = part_share();
#endif
    vec3 wi = to_world(bs.wi, t, b, s.ns);
    if (!sides_agree(ng_wo, wi, bs.wi.z * wo.z)) return false;
#ifdef SINGLE_DIFFUSE_BOUNCE
    if (!bs.delta) {
        if (last_diffuse) return false;
        p.diffuse++;
    }
#endif
    p.throughput *= bs.weight;
#ifdef PATH_HOOKS
    hook_bsdf_sampled(p, bsdf, wo, bs);
#endif
    p.after_delta = bs.delta;
    p.bsdf_pdf = bs.pdf;
    if (!any(greaterThan(p.throughput, vec3(0.0)))) return false;
    if (p.depth >= rr_depth()) {
#ifdef RR_DETERMINISTIC
        // Bikker's deterministic path termination: the k-th test passes for the samples whose
        // index has bit k set, so of a pixel's N samples N/2 end at the first test, N/4 at the
        // second...; survivors weigh 2 per test. Paths cannot outlive log2(N) tests: biased.
        uint test = p.depth - rr_depth();
        if (test >= 32u || ((p.sample_index >> test) & 1u) == 0u) return false;
        p.throughput *= 2.0;
#else
#ifdef RR_FIXED
        float survive = rr_survival();
#else
        float survive = min(max3(p.throughput) * rr_survival(), 0.95);
#endif
        if (rng_next(rng) >= survive) return false;
        p.throughput /= survive;
#endif
    }
#ifdef HAS_VOLUME
    if (dot(wi, ng_wo) < 0.0) p.medium = medium_beyond(s, p.medium, dot(s.ng, p.ray.dir) < 0.0);
#endif
    p.ray = Ray(offset_ray(s.position, dot(wi, ng_wo) > 0.0 ? ng_wo : -ng_wo, s.magnitude), wi, INF);
    p.depth++;
    return true;
#endif
}

// Extends the path by one vertex; false once the path has ended (its radiance is in p.L).
bool path_step(inout Path p, inout Rng rng, inout uint rays) {
    Hit hit;
    rays++;
#ifdef PATH_TRACE_HOOK
    bool found = hook_trace(p, rng, hit);
#else
    bool found = trace(p.ray, false, hit);
#endif
    ShadowRay shadow;
    bool going = path_shade(p, found, hit, rng, shadow);
    if (shadow.valid) {
        Hit blocker;
        rays++;
        if (!trace(shadow.ray, true, blocker)) p.L += shadow.light;
    }
    return going;
}

// The pass's samples of one pixel, added onto `sum`.
vec3 pixel_samples(uvec2 pixel, vec3 sum, inout uint rays, inout uint rejected) {
    // Path regeneration (Bikker, ch. 6): samples and bounces share one loop, so a lane whose path
    // ends starts its next sample at once instead of idling until the longest path of its SIMD
    // group ends. Each sample still has its own random stream and is summed in sample order, so
    // the result is the same bits as one loop per sample. The sum continues the buffer's (earlier
    // passes, or earlier frames of a converging view) one sample at a time, so the bits do not
    // depend on how the samples were cut into passes or frames.
    uint si = pc.sample_begin;
#ifdef LIGHT_REUSE
    reuse_pixel = pixel.y * F.dims.x + pixel.x;
#endif
    Rng rng = pixel_rng(pixel, si);
    Path p = path_start(camera_ray(pixel, rng), si);
#ifdef LAST_PATH_CUT
    bool done = false;
#endif
    while (true) {
#ifdef LAST_PATH_CUT
        // Bikker's NOP (FrameParams::cut_last_paths): once every lane is on its last sample,
        // the group stops with the first lane to finish; the others' paths end here, their
        // light so far counting as the sample's (biased low).
        if (subgroupAll(done || si + 1u == pc.sample_end) && subgroupAny(done)) {
            if (!done) {
                if (any(isnan(p.L)) || any(isinf(p.L))) rejected++;
                else sum += p.L;
            }
            break;
        }
        if (done) continue;
#endif
        if (path_step(p, rng, rays)) continue;
        // NaN/Inf guard: such a sample contributes zero and is counted (pbrt-v4's policy).
        if (any(isnan(p.L)) || any(isinf(p.L))) rejected++;
        else sum += p.L;
        if (++si == pc.sample_end) {
#ifdef LAST_PATH_CUT
            done = true;
            continue;
#else
            break;
#endif
        }
        rng = pixel_rng(pixel, si);
        p = path_start(camera_ray(pixel, rng), si);
    }
    return sum;
}
