// Next-event estimation: one light entry picked from the power CDF, then a point or direction
// on it. Every pdf returned is in solid angle at the shading point and includes the pick.

struct LightSample {
    vec3 wi;        // unit direction to the light
    vec3 target;    // offset point on the light (finite lights)
    bool infinite;  // directional or environment: shadow ray to infinity
    vec3 radiance;  // incident radiance (or irradiance-like value for delta lights)
    float pdf;
    // The pdf MIS weighs the sample with: `pdf` itself, but for RIS, whose own density of a
    // direction has no closed form, the pdf of drawing the kept candidate (what the BSDF side's
    // weight uses too, so the two weights still sum to one: unbiased).
    float mis_pdf;
    bool delta;
    // The sample's light, the numbers that placed it there and the light's pick probability:
    // what names the sample from any shading point (light reuse).
    uint light;
    vec2 u;
    float pick;
};

// Probability of NEE picking light l: its share of the lights' power, or with
// LIGHT_SELECT_UNIFORM one in n (every light alike, Bikker's baseline).
float light_pick(Light l) {
#ifdef LIGHT_SELECT_UNIFORM
    return 1.0 / float(max(light_count(), 1u));
#else
    return l.emission.w;
#endif
}

// Emitted radiance of an emissive triangle towards -dir, 0 from the back of one-sided emitters.
vec3 triangle_emission(Surface s, vec3 dir) {
    if (!s.double_sided && dot(s.ng, dir) >= 0.0) return vec3(0.0);
    return s.emission;
}

#ifdef HAS_EMISSIVE_TRIANGLES
// Radiance of the emissive triangle of light l at barycentrics b (front normal nl), seen along
// dir: the point shaded as a surface, for textured and one-sided emission.
vec3 triangle_light_radiance(Light l, vec3 b, vec3 nl, vec3 dir) {
#if !defined(HAS_EMISSIVE_TEXTURES) && !defined(HAS_ALPHA_TEST)
    // No emitter is textured or partly transparent: each emits its factor all over, kept in
    // the light itself (b.w: double-sided), with no fetch of its triangle and material.
    if (l.b.w == 0.0 && dot(nl, dir) >= 0.0) return vec3(0.0);
    return l.emission.rgb;
#else
    Surface s;
    Triangle T = triangle_at(l.ids.z);
    Material m = material_at(T.material);
    s.attr = vertex_attributes(T, m, b);
    s.ng = nl;
    apply_material(s, m);
#ifdef HAS_ALPHA_TEST
    // An emitter that rays pass with probability 1 - alpha (BLEND), or always where it is cut
    // out (MASK), emits on average what a BSDF ray finds there: NEE's shadow ray ends at the
    // light and never tests its coverage, so the coverage scales its radiance.
    return material_coverage(m, s.attr) * triangle_emission(s, dir);
#else
    return triangle_emission(s, dir);
#endif
#endif
}

// Solid-angle pdf of NEE picking the emissive triangle hit at distance t along unit `dir`.
float triangle_light_pdf(Hit hit, vec3 ng_world, vec3 dir) {
    Instance inst = instance_at(hit.instance);
    uint local = tri_light_at(hit.triangle);
    if (inst.light_base == 0xffffffffu || local == 0xffffffffu) return 0.0;
    Light l = light_at(inst.light_base + local);
    float area = 0.5 * length(cross(l.b.xyz - l.a.xyz, l.c.xyz - l.a.xyz));
    float cos_l = abs(dot(ng_world, dir));
    if (area <= 0.0 || cos_l <= 0.0) return 0.0;
    return light_pick(l) * hit.t * hit.t / (cos_l * area);
}
#endif

float environment_light_pdf(vec3 dir) {
    uint n = light_count();
    if (n == 0u || env_kind() == ENV_NONE) return 0.0;
    // The environment is always the last entry.
    Light l = light_at(n - 1u);
    if (l.ids.x != LIGHT_ENVIRONMENT) return 0.0;
    return light_pick(l) * env_pdf(dir);
}

// The sample the numbers u place on light `index`, seen from p: a pure function of (index, u)
// and p, so that light reuse (path/light_reuse.glsl) can look at one sample from many points.
bool light_sample_at(uint index, vec2 u, vec3 p, out LightSample ls) {
    ls.pdf = 0.0;
    ls.delta = false;
    ls.infinite = false;
    ls.light = index;
    ls.u = u;
    Light l = light_at(index);
    float pmf = light_pick(l);
    ls.pick = pmf;
    uint kind = l.ids.x;
#ifdef HAS_EMISSIVE_TRIANGLES
    if (kind == LIGHT_TRIANGLE) {
        vec3 b = sample_triangle(u);
        vec3 q = b.x * l.a.xyz + b.y * l.b.xyz + b.z * l.c.xyz;
        vec3 cr = cross(l.b.xyz - l.a.xyz, l.c.xyz - l.a.xyz);
        float area = 0.5 * length(cr);
        if (area <= 0.0) return false;
        // a.w flips the world winding of mirrored instances back to the front face the hit
        // shader sees (glTF: a negative determinant makes the front face clockwise).
        vec3 nl = normalize(cr) * l.a.w;
        vec3 d = q - p;
        float dist2 = dot(d, d);
        if (dist2 <= 0.0) return false;
        ls.wi = d * inversesqrt(dist2);
        ls.radiance = triangle_light_radiance(l, b, nl, ls.wi);
        float cos_l = abs(dot(nl, ls.wi));
        if (cos_l <= 0.0 || all(equal(ls.radiance, vec3(0.0)))) return false;
        ls.pdf = pmf * dist2 / (cos_l * area);
        ls.target = offset_ray(q, dot(nl, ls.wi) < 0.0 ? nl : -nl, coordinate_magnitude(l.a.xyz, l.b.xyz, l.c.xyz));
        return true;
    }
#endif
#ifdef HAS_PUNCTUAL_LIGHTS
    if (kind == LIGHT_POINT || kind == LIGHT_SPOT) {
        vec3 d = l.a.xyz - p;
        float dist2 = dot(d, d);
        if (dist2 <= 0.0) return false;
        ls.wi = d * inversesqrt(dist2);
        float atten = 1.0 / dist2;
        float range = l.b.w;
        if (range > 0.0) {
            float r = dist2 / (range * range);
            atten *= clamp(1.0 - r * r, 0.0, 1.0) * clamp(1.0 - r * r, 0.0, 1.0);
        }
        if (kind == LIGHT_SPOT) {
            float cd = dot(-ls.wi, l.b.xyz);
            float f = clamp((cd - l.c.x) * l.c.y, 0.0, 1.0);
            atten *= f * f;
        }
        ls.radiance = l.emission.rgb * atten;
        ls.pdf = pmf;
        ls.delta = true;
        ls.target = l.a.xyz;
        return atten > 0.0;
    }
    if (kind == LIGHT_DIRECTIONAL) {
        ls.wi = -l.b.xyz;
        ls.radiance = l.emission.rgb;
        ls.pdf = pmf;
        ls.delta = true;
        ls.infinite = true;
        return true;
    }
#endif
    if (kind == LIGHT_ENVIRONMENT) {
        float pdf;
        ls.wi = env_sample(u, pdf);
        ls.radiance = env_radiance(ls.wi);
        ls.pdf = pmf * pdf;
        ls.infinite = true;
        return ls.pdf > 0.0;
    }
    return false;
}

bool sample_one_light(vec3 p, inout Rng rng, out LightSample ls) {
    float ul = rng_next(rng);
    vec2 u = rng_next2(rng);
    ls.pdf = 0.0;
    uint n = light_count();
    if (n == 0u) return false;
#ifdef LIGHT_SELECT_UNIFORM
    uint index = min(uint(ul * float(n)), n - 1u);
#else
    uint index = search_cdf(CDF_LIGHTS, 0u, n, ul);
#endif
    return light_sample_at(index, u, p, ls);
}

#ifdef LIGHT_SELECT_RIS
// Candidate lights per light sample: the path tracer's push word 5 (its `PathPasses::
// push_words`; only the path tracer compiles LIGHT_SELECT_RIS in).
uint ris_candidates() { return max(pc.method_words[5], 1u); }

// Resampled importance sampling (Talbot et al. 2005): ris_candidates() lights are drawn as
// NEE draws one, each weighed by its unshadowed emitted luminance over its pdf, and one is kept
// in proportion (a weighted reservoir). Its pdf becomes luminance x M / (sum of the weights):
// the estimator f Le / pdf is then the RIS estimator. With RIS_MIS it is combined with BSDF
// sampling by MIS weights computed from the candidate's own pdf (Bikker's MIS+RIS). The scene's lights must share a measure
// (solid angle: emissive triangles and the environment; the tracer refuses punctual lights).
bool sample_light(vec3 p, inout Rng rng, out LightSample ls) {
    uint m = ris_candidates();
    float wsum = 0.0;
    bool found = false;
    for (uint j = 0u; j < m; j++) {
        LightSample c;
        bool ok = sample_one_light(p, rng, c);
        float w = (ok && c.pdf > 0.0) ? luminance(c.radiance) / c.pdf : 0.0;
        wsum += w;
        if (w > 0.0 && rng_next(rng) * wsum < w) {
            ls = c;
            found = true;
        }
    }
    if (!found || !(wsum > 0.0)) return false;
    ls.mis_pdf = ls.pdf;
    ls.pdf = luminance(ls.radiance) * float(m) / wsum;
    return ls.pdf > 0.0;
}
#else
bool sample_light(vec3 p, inout Rng rng, out LightSample ls) {
    bool ok = sample_one_light(p, rng, ls);
    ls.mis_pdf = ls.pdf;
    return ok;
}
#endif
