// The tests' window on the kernel's own BSDF code (frame::Output::BsdfSample / BsdfValue): the
// surface the ray through the pixel centre hits first, its BSDF made as path_step makes it, then
// one direction sampled (OUTPUT_BSDF_SAMPLE) or the pdf and values at the direction the pixel
// stands for (OUTPUT_BSDF_VALUE), all in the hit's shading frame. tests/lobes.rs bins the
// samples against the pdf (chi-square), integrates the pdf and checks reciprocity.

vec3 bsdf_probe(uvec2 pixel) {
    vec2 size = vec2(F.dims.xy);
    // Every pixel probes the one point at the view's centre, where the camera looks.
    Ray ray = Ray(F.cam_origin.xyz, normalize(F.cam_forward.xyz), INF);
    Hit hit;
    if (!trace(ray, false, hit)) return vec3(0.0);
    Surface s = surface_at(hit);
    vec3 t, b;
    make_frame(s.ns, t, b);
    vec3 wo = to_local(-ray.dir, t, b, s.ns);
    Bsdf bsdf = make_bsdf(s, wo);
#ifdef OUTPUT_BSDF_SAMPLE
    Rng rng = rng_init(pixel, pc.sample_begin, frame_index(), render_seed());
    BsdfSample bs;
    if (!bsdf_sample(bsdf, wo, rng, bs) || bs.delta) return vec3(0.0);
    return bs.wi;
#else
    float c = 1.0 - 2.0 * (float(pixel.y) + 0.5) / size.y;
    float phi = 2.0 * PI * (float(pixel.x) + 0.5) / size.x;
    float sn = sqrt(max(0.0, 1.0 - c * c));
    vec3 wi = vec3(sn * cos(phi), sn * sin(phi), c);
    float pdf, reverse_pdf;
    vec3 f = bsdf_eval(bsdf, wo, wi, pdf);
    vec3 fr = bsdf_eval(make_bsdf(s, wi), wi, wo, reverse_pdf);
    return vec3(pdf, luminance(f) / abs(wi.z), luminance(fr) / abs(wo.z));
#endif
}
