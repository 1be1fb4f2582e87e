// Resampled direct light (RIS_CONTRIBUTION, with LIGHT_SELECT_RIS): the first stage of ReSTIR DI
// (Bitterli et al. 2020) without reuse. ris_candidates() lights are drawn as NEE draws one
// (the power CDF), each weighed by its unshadowed contribution at the shading point (luminance
// of the BSDF's f cos times its radiance) over its pdf, and one is kept in proportion; it then
// takes one shadow ray. Its pdf becomes target x M / (sum of the weights), so f Le / pdf is the
// RIS estimator: unbiased. Punctual lights take part: each candidate's target and pdf are
// densities in its own light's measure (a point's pick probability, an area's solid angle),
// which is all RIS asks of a mixture.

// The target of candidate c: what it would add, unshadowed, to the path at this vertex.
float contribution_target(Bsdf bsdf, vec3 wo, vec3 t, vec3 b, vec3 n, vec3 ng_wo, LightSample c) {
    vec3 wl = to_local(c.wi, t, b, n);
    if (!sides_agree(ng_wo, c.wi, wl.z * wo.z)) return 0.0;
    float pdf;
    return luminance(bsdf_eval(bsdf, wo, wl, pdf) * c.radiance);
}

// The candidates' reservoir: the one kept (ls, its target `kept`) and the sum of the weights
// (`wsum`); false when none weighs anything. Light reuse (path/light_reuse.glsl) starts from it.
bool resample_candidates(vec3 p, Bsdf bsdf, vec3 wo, vec3 t, vec3 b, vec3 n, vec3 ng_wo,
                         inout Rng rng, out LightSample ls, out float kept, out float wsum) {
    uint m = ris_candidates();
    wsum = 0.0;
    kept = 0.0;
    for (uint j = 0u; j < m; j++) {
        LightSample c;
        bool ok = sample_one_light(p, rng, c) && c.pdf > 0.0;
        float target = ok ? contribution_target(bsdf, wo, t, b, n, ng_wo, c) : 0.0;
        float w = target > 0.0 ? target / c.pdf : 0.0;
        wsum += w;
        if (w > 0.0 && rng_next(rng) * wsum < w) {
            ls = c;
            kept = target;
        }
    }
    return kept > 0.0 && wsum > 0.0;
}

bool sample_light_toward(vec3 p, Bsdf bsdf, vec3 wo, vec3 t, vec3 b, vec3 n, vec3 ng_wo,
                         inout Rng rng, out LightSample ls) {
    float kept, wsum;
    if (!resample_candidates(p, bsdf, wo, t, b, n, ng_wo, rng, ls, kept, wsum)) return false;
    ls.mis_pdf = ls.pdf;
    ls.pdf = kept * float(ris_candidates()) / wsum;
    return ls.pdf > 0.0;
}
