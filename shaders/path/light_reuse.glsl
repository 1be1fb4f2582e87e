// Light reuse (LIGHT_REUSE, with RIS_CONTRIBUTION; crates/platoon-core/src/method/path/light_reuse.rs):
// ReSTIR DI's temporal and spatial reuse (Bitterli et al. 2020) at the first vertex of a
// frame's first sample. The pixel's fresh candidates (path/resampled_light.glsl's) are combined
// with the previous frame's reservoir where the surface was then (its reprojection) and with a
// few of that frame's reservoirs around it; one sample is kept and shaded with one shadow ray,
// and its reservoir is left for the next frame. Every source is the previous frame's, which every
// device holds whole: the reuse never crosses a band border, and any split shows the same bits.
//
// A sample is (light, u): the light's index and the two numbers that placed a point on it
// (lights.glsl's light_sample_at), the same sample from every shading point. Its target at a
// point is the unshadowed luminance of f cos Le per unit of that measure (contribution_target
// times dω/du = pick / pdf), so resampling weights and the contribution weight W move between
// pixels without a Jacobian. Unbiased unless LIGHT_REUSE_BIASED: each source's resampling weight
// carries a balance-heuristic MIS weight (generalised RIS, Lin et al. 2022), M_i g_i(y) over the
// sum of M_j g_j(y) over all sources, where g_j is the light a Lambertian surface would take from
// y at source j's stored point and normals, 0 outside what that surface can see (the light's
// emitting side, the hemispheres its normals allow): the weights sum to one wherever a source
// could have drawn y, and a neighbour whose own target at its sample was small weighs as little.
// The biased setting weighs by M_i over the sum of M_j (Bitterli's 1/M: no g evaluated; darker
// where a neighbour cannot see a light the pixel sees).
// The reused sample takes the whole of the first vertex's direct light: the BSDF ray from there
// adds no light NEE could have sampled (path.glsl), as in RTXDI; MIS against BSDF sampling would
// weigh with the power's pdf, far below the reservoir's density.

layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer ReuseHistory {
    uvec4 size;       // the history's width and height (0: none), the frame's first sample, neighbours
    vec4 settings;    // the neighbours' radius in pixels, the cap on a source's M
    vec4 cam_origin;  // the previous frame's camera (light_reuse.rs's history_block)
    vec4 cam_right;   // w: tan of the half angle across (orthographic: the half width)
    vec4 cam_up;      // w: ... up (orthographic: the half height)
    vec4 cam_forward; // w: 1 for an orthographic camera
    vec4 records[];   // three a pixel (below)
};
layout(buffer_reference, std430, buffer_reference_align = 16) writeonly buffer ReuseRecords { vec4 v[]; };

// A pixel's reservoir (three vec4s): (position, (light + 1) x 2 + 1 where the surface
// transmits; light + 1 = 0: no sample), (u, W, M: 0 where the pixel has no such surface),
// (octahedral geometric normal, octahedral shading normal), the normals on the camera's side.
const uint REUSE_RECORD = 3u;

// The frame pixel whose samples the kernel is rendering (set before its paths start).
uint reuse_pixel;

ReuseHistory reuse_history() { return ReuseHistory(pc.g.method_buffer2); }

// The history's sizes and settings, read as whole vectors (a component and a swizzle of one
// member read through the buffer reference in one expression came back as the wrong component
// on llvmpipe, Mesa 22.3).
uvec4 reuse_size() { uvec4 v = reuse_history().size; return v; }
vec4 reuse_settings() { vec4 v = reuse_history().settings; return v; }

// Whether the path's vertex is the one that reuses: the first of the frame's first sample.
bool reuse_here(uint depth, uint sample_index) {
    return depth == 0u && sample_index == reuse_size().z;
}

vec2 oct_encode(vec3 n) {
    n /= abs(n.x) + abs(n.y) + abs(n.z);
    vec2 e = n.xy;
    if (n.z < 0.0) e = (1.0 - abs(n.yx)) * vec2(n.x >= 0.0 ? 1.0 : -1.0, n.y >= 0.0 ? 1.0 : -1.0);
    return e;
}

vec3 oct_decode(vec2 e) {
    vec3 n = vec3(e, 1.0 - abs(e.x) - abs(e.y));
    if (n.z < 0.0) n.xy = (1.0 - abs(n.yx)) * vec2(n.x >= 0.0 ? 1.0 : -1.0, n.y >= 0.0 ? 1.0 : -1.0);
    return normalize(n);
}

struct Reservoir {
    uint light;   // index + 1; 0: none
    vec2 u;
    float W;
    float M;
};

struct ReuseSurface {
    vec3 position;
    vec3 ng;      // geometric normal on the viewer's side
    vec3 ns;      // shading normal on the viewer's side
    bool transmits;
};

void reuse_write(ReuseSurface s, Reservoir r) {
    ReuseRecords out_ = ReuseRecords(pc.g.method_buffer3);
    uint i = reuse_pixel * REUSE_RECORD;
    out_.v[i] = vec4(s.position, float(r.light * 2u + (s.transmits ? 1u : 0u)));
    out_.v[i + 1u] = vec4(r.u, r.W, r.M);
    out_.v[i + 2u] = vec4(oct_encode(s.ng), oct_encode(s.ns));
}

// No reservoir for the pixel (its camera ray found no surface that takes light samples).
void reuse_clear() {
    ReuseRecords out_ = ReuseRecords(pc.g.method_buffer3);
    uint i = reuse_pixel * REUSE_RECORD;
    out_.v[i] = vec4(0.0);
    out_.v[i + 1u] = vec4(0.0);
    out_.v[i + 2u] = vec4(0.0);
}

// The previous frame's reservoir of history pixel `h`.
void reuse_read(uint h, out ReuseSurface s, out Reservoir r) {
    ReuseHistory hist = reuse_history();
    vec4 a = hist.records[h * REUSE_RECORD];
    vec4 b = hist.records[h * REUSE_RECORD + 1u];
    vec4 c = hist.records[h * REUSE_RECORD + 2u];
    s.position = a.xyz;
    uint code = uint(a.w);
    s.transmits = (code & 1u) != 0u;
    s.ng = oct_decode(c.xy);
    s.ns = oct_decode(c.zw);
    r.light = code >> 1;
    r.u = b.xy;
    r.W = b.z;
    r.M = b.w;
}

// Where `x` was in the previous frame's image (its pixel coordinates), if inside it.
bool reuse_project(vec3 x, out vec2 at) {
    // Whole vectors first (reuse_size's reason).
    ReuseHistory h = reuse_history();
    vec4 origin = h.cam_origin;
    vec4 right = h.cam_right;
    vec4 up = h.cam_up;
    vec4 forward = h.cam_forward;
    vec3 d = x - origin.xyz;
    float z = dot(d, forward.xyz);
    bool orthographic = forward.w > 0.5;
    at = vec2(-1.0);
    if (!orthographic && z <= 0.0) return false;
    float scale = orthographic ? 1.0 : z;
    vec2 ndc = vec2(dot(d, right.xyz) / (scale * right.w), dot(d, up.xyz) / (scale * up.w));
    vec2 size = vec2(reuse_size().xy);
    at = vec2((ndc.x + 1.0) * 0.5 * size.x, (1.0 - ndc.y) * 0.5 * size.y);
    return all(greaterThanEqual(at, vec2(0.0))) && all(lessThan(at, size));
}

// The shading point the sources are resampled toward.
struct ReuseShading {
    ReuseSurface surface;
    Bsdf bsdf;
    vec3 wo, t, b, n;
    float distance;  // from the camera: the scale of the similarity test
};

// Sample (light + 1, u)'s light sample at q, and its target there (0 outside q's support).
float reuse_target(ReuseShading q, uint light, vec2 u, out LightSample ls) {
    ls.pdf = 0.0;
    if (light == 0u || light > light_count()) return 0.0;
    if (!light_sample_at(light - 1u, u, q.surface.position, ls) || !(ls.pdf > 0.0)) return 0.0;
    float target = contribution_target(q.bsdf, q.wo, q.t, q.b, q.n, q.surface.ng, ls);
    return target * ls.pick / ls.pdf;
}

// The light a Lambertian surface at source s would take from sample (light + 1, u), per unit
// of the samples' measure: the balance heuristic's stand-in for the source's target, 0 where
// that target is (the light's back, the hemispheres the normals leave out).
float reuse_proxy(ReuseSurface s, uint light, vec2 u) {
    LightSample ls;
    if (!light_sample_at(light - 1u, u, s.position, ls) || !(ls.pdf > 0.0)) return 0.0;
    float g = dot(ls.wi, s.ng);
    float n = dot(ls.wi, s.ns);
    bool seen = s.transmits ? (g > 0.0) == (n > 0.0) : (g > 0.0 && n > 0.0);
    return seen ? luminance(ls.radiance) * abs(n) * ls.pick / ls.pdf : 0.0;
}

// Whether a source's surface is close enough to q's to lend its sample (quality, not bias).
bool reuse_similar(ReuseShading q, ReuseSurface s) {
    return dot(q.surface.ng, s.ng) > 0.9
        && abs(dot(s.ng, q.surface.position - s.position)) < 0.05 * q.distance;
}

// The history pixel of coordinates `at`.
uint reuse_history_pixel(vec2 at) {
    uvec4 size = reuse_size();
    uvec2 p = min(uvec2(at), size.xy - 1u);
    return p.y * size.x + p.x;
}

// The pixel's own candidates and the previous frame's: where the surface was and around it.
const uint REUSE_MAX_SOURCES = 18u;

// The light sample of the first vertex (surface s in frame t, b, s.ns; bsdf; wo; ng_wo), its
// pdf the reservoir's 1 / W in solid angle; leaves the pixel's reservoir for the next frame.
bool reuse_light(Surface s, vec3 t, vec3 b, Bsdf bsdf, vec3 wo, vec3 ng_wo, inout Rng rng,
                 out LightSample ls) {
    ReuseShading q;
    q.surface = ReuseSurface(s.position, ng_wo, wo.z < 0.0 ? -s.ns : s.ns, bsdf_transmits(bsdf));
    q.bsdf = bsdf;
    q.wo = wo;
    q.t = t;
    q.b = b;
    q.n = s.ns;
    q.distance = distance(s.position, F.cam_origin.xyz);

    // Source 0: the fresh candidates (path/resampled_light.glsl's), as a reservoir.
    uint m = ris_candidates();
    Reservoir sources[REUSE_MAX_SOURCES];
    ReuseSurface surfaces[REUSE_MAX_SOURCES];
    float fresh_target = 0.0;
    sources[0] = Reservoir(0u, vec2(0.0), 0.0, float(m));
    surfaces[0] = q.surface;
    LightSample fresh;
    float kept, wfresh;
    if (resample_candidates(s.position, bsdf, wo, t, b, s.ns, ng_wo, rng, fresh, kept, wfresh)) {
        sources[0].light = fresh.light + 1u;
        sources[0].u = fresh.u;
        fresh_target = kept * fresh.pick / fresh.pdf;
        sources[0].W = wfresh / (float(m) * fresh_target);
    }

    // The previous frame's reservoirs: where the surface was (when it was in view), then
    // around that point; only those of a surface like this one's.
    uint count = 1u;
    uvec4 size = reuse_size();
    vec4 settings = reuse_settings();
    float cap = settings.y;
    float mtotal = float(m);
    if (size.x > 0u) {
        vec2 at;
        bool seen = reuse_project(s.position, at);
        vec2 centre = seen ? at : vec2(image_pixel(uvec2(reuse_pixel % F.dims.x, reuse_pixel / F.dims.x))) + 0.5;
        uint neighbours = min(size.w, REUSE_MAX_SOURCES - 2u);
        for (uint k = 0u; k <= neighbours; k++) {
            vec2 p = centre;
            if (k > 0u) {
                vec2 u = rng_next2(rng);
                float radius = settings.x * sqrt(u.x);
                p += radius * vec2(cos(2.0 * PI * u.y), sin(2.0 * PI * u.y));
                if (any(lessThan(p, vec2(0.0))) || any(greaterThanEqual(p, vec2(size.xy)))) continue;
            } else if (!seen) {
                continue;
            }
            uint hp = reuse_history_pixel(p);
            ReuseSurface src;
            Reservoir sr;
            reuse_read(hp, src, sr);
            // A source whose candidates all missed still counts them.
            if (!(sr.M > 0.0) || !reuse_similar(q, src)) continue;
            sr.M = min(sr.M, cap);
            mtotal += sr.M;
            surfaces[count] = src;
            sources[count++] = sr;
        }
    }

    // Resampling: source i's sample weighs m_i(y_i) p̂(y_i) W_i, the MIS weight m_i from the
    // sources' stand-in targets (or their candidate counts when biased).
    float wsum = 0.0;
    float kept_target = 0.0;
    Reservoir r = Reservoir(0u, vec2(0.0), 0.0, min(mtotal, size.x > 0u ? cap : mtotal));
    for (uint i = 0u; i < count; i++) {
        Reservoir c = sources[i];
        if (c.light == 0u || !(c.W > 0.0) || isinf(c.W)) continue;
        LightSample cs;
        float target = i == 0u ? fresh_target : reuse_target(q, c.light, c.u, cs);
        if (!(target > 0.0)) continue;
#ifdef LIGHT_REUSE_BIASED
        float mis = c.M / mtotal;
#else
        float own = 0.0;
        float all_ = 0.0;
        for (uint j = 0u; j < count; j++) {
            float g = sources[j].M * reuse_proxy(surfaces[j], c.light, c.u);
            all_ += g;
            if (j == i) own = g;
        }
        float mis = all_ > 0.0 ? own / all_ : 0.0;
#endif
        float w = mis * target * c.W;
        if (!(w > 0.0)) continue;
        wsum += w;
        if (rng_next(rng) * wsum < w) {
            r.light = c.light;
            r.u = c.u;
            kept_target = target;
        }
    }
    if (r.light == 0u || !(wsum > 0.0) || !(kept_target > 0.0)) {
        r.light = 0u;
        reuse_write(q.surface, r);
        return false;
    }
    r.W = wsum / kept_target;
    reuse_write(q.surface, r);
    if (!(r.W > 0.0) || isinf(r.W)) return false;
    // The kept sample seen from here (the fresh one's too: one evaluation more, one register
    // set fewer than carrying it).
    if (reuse_target(q, r.light, r.u, ls) <= 0.0) return false;
    // f Le / pdf is the reservoir's estimate: pdf = (dω/du W)^-1 in solid angle; MIS weighs
    // with the pdf NEE's one draw had, which the BSDF side's weight uses too.
    ls.mis_pdf = ls.pdf;
    ls.pdf = ls.pdf / (ls.pick * r.W);
    return ls.pdf > 0.0;
}
