// GGX (Trowbridge-Reitz) microfacets with the height-correlated Smith G2, and visible normals
// sampled by spherical caps (Dupuy & Benyoub 2023): isotropic of alpha `a`, and anisotropic of
// alphas `a` = (along x, along y) for KHR_materials_anisotropy (Walter et al. 2007's
// stretched forms: the anisotropic distribution is the isotropic one of unit alpha seen through
// the stretch). Vectors in a frame with the normal along +z (for the anisotropic forms, x along
// the direction of alpha a.x). Included by bsdf.glsl.

float ggx_d(float a, float nh) {
    float a2 = a * a;
    float d = nh * nh * (a2 - 1.0) + 1.0;
    return a2 / (PI * d * d);
}

float ggx_lambda(float a, vec3 w) {
    float c2 = w.z * w.z;
    float t2 = max(0.0, 1.0 - c2) / max(c2, 1e-12);
    return 0.5 * (-1.0 + sqrt(1.0 + a * a * t2));
}

float ggx_g1(float a, vec3 w) { return 1.0 / (1.0 + ggx_lambda(a, w)); }
float ggx_g2(float a, vec3 wo, vec3 wi) { return 1.0 / (1.0 + ggx_lambda(a, wo) + ggx_lambda(a, wi)); }

// Density of visible normal h seen from wo (either hemisphere).
float ggx_vndf_pdf(float a, vec3 wo, vec3 h) {
    return ggx_g1(a, wo) / abs(wo.z) * ggx_d(a, h.z) * abs(dot(wo, h));
}

vec3 ggx_sample_vndf(float a, vec3 wo, vec2 u) {
    vec3 wh = normalize(vec3(a * wo.x, a * wo.y, wo.z));
    if (wh.z < 0.0) wh = -wh;
    float phi = 2.0 * PI * u.x;
    float z = (1.0 - u.y) * (1.0 + wh.z) - wh.z;
    float st = sqrt(clamp(1.0 - z * z, 0.0, 1.0));
    vec3 h = vec3(st * cos(phi), st * sin(phi), z) + wh;
    return normalize(vec3(a * h.x, a * h.y, max(h.z, 1e-7)));
}

#ifdef HAS_ANISOTROPY
float ggx_d_aniso(vec2 a, vec3 h) {
    float a2 = a.x * a.y;
    vec3 f = vec3(a.y * h.x, a.x * h.y, a2 * h.z);
    float w2 = a2 / dot(f, f);
    return a2 * w2 * w2 * INV_PI;
}

float ggx_lambda_aniso(vec2 a, vec3 w) {
    float c2 = w.z * w.z;
    float s2 = a.x * a.x * w.x * w.x + a.y * a.y * w.y * w.y;
    return 0.5 * (-1.0 + sqrt(1.0 + s2 / max(c2, 1e-12)));
}

float ggx_g1_aniso(vec2 a, vec3 w) { return 1.0 / (1.0 + ggx_lambda_aniso(a, w)); }
float ggx_g2_aniso(vec2 a, vec3 wo, vec3 wi) { return 1.0 / (1.0 + ggx_lambda_aniso(a, wo) + ggx_lambda_aniso(a, wi)); }

float ggx_vndf_pdf_aniso(vec2 a, vec3 wo, vec3 h) {
    return ggx_g1_aniso(a, wo) / abs(wo.z) * ggx_d_aniso(a, h) * abs(dot(wo, h));
}

vec3 ggx_sample_vndf_aniso(vec2 a, vec3 wo, vec2 u) {
    vec3 wh = normalize(vec3(a.x * wo.x, a.y * wo.y, wo.z));
    if (wh.z < 0.0) wh = -wh;
    float phi = 2.0 * PI * u.x;
    float z = (1.0 - u.y) * (1.0 + wh.z) - wh.z;
    float st = sqrt(clamp(1.0 - z * z, 0.0, 1.0));
    vec3 h = vec3(st * cos(phi), st * sin(phi), z) + wh;
    return normalize(vec3(a.x * h.x, a.y * h.y, max(h.z, 1e-7)));
}
#endif
