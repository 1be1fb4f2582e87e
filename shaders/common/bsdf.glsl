// The glTF BSDF (glTF 2.0 spec, appendix B, with KHR_materials_specular's fresnel_mix):
//   dielectric = (1 - s * max(F)) * diffuse + s * F * specular_brdf          F: Schlick, f0 from ior
//   metal      = Schlick(base_color) * specular_brdf
//   glass      = rough dielectric BTDF/BRDF (Walter et al. 2007) with exact Fresnel, tinted by base colour
//   bsdf       = mix(mix(dielectric, glass, transmission), metal, metallic)
//   diffuse    = mix(Lambert(base_color), Lambert transmitted(dt_color), dt)     KHR_materials_
//                diffuse_transmission: thin, the light leaving from the other side, weighed by
//                the specular layer's (1 - s max(F)) at wi mirrored to wo's side
//   sheened    = sheen_color * Charlie(wo, wi) + bsdf * min(1 - max3(sheen_color) E(wo),
//                1 - max3(sheen_color) E(wi))      KHR_materials_sheen: the Charlie lobe (Estevez
//                & Kulla 2017) over the base, scaled by E, its albedo (a table in the texel array)
//   coated     = mix(sheened, coat, clearcoat * Schlick(0.04, |wo.nc|))   KHR_materials_clearcoat:
//                coat = D G / (4 |wo.nc| |wi.nc|), GGX about the coat's own normal nc
//   anisotropy = the base's GGX (specular layer, metal, glass) of alphas mix(alpha, 1, strength^2)
//                along the direction and alpha across it: KHR_materials_anisotropy (ggx.glsl)
//   F          = mix(F, thin_film(F's f0), iridescence) in the dielectric, metal and glass lobes:
//                KHR_materials_iridescence (thin_film.glsl), the film under the coat; glass
//                samples reflection by the mean of its three channels
// GGX with height-correlated Smith G2; visible normals sampled by spherical caps (Dupuy & Benyoub 2023).
// Roughness below MIN_ROUGHNESS makes the specular lobes perfect (delta) mirrors and refractors.
// All vectors are in the local shading frame, n = +z on the front (outside) side.
// Without HAS_SPECULAR_LOBES (every material Lambertian: no metal, specular layer or glass) the
// GGX code is compiled out; the terms it would add are exactly zero, so the image keeps its bits.
// The same holds for HAS_CLEARCOAT: a material without a coat has weight 0 and its lobes'
// probabilities, weights and sampling decisions are those of the kernel without the code.
// HAS_SHEEN likewise. The sheen lobe is sampled uniformly over wo's hemisphere (it is broad and
// peaks at grazing angles, where a cosine-weighted choice would starve it).
// The coat's mix weight depends on wo alone (the spec's fresnel_coat), so a coated BSDF is not
// reciprocal.

const float MIN_ROUGHNESS = 0.01;

// Light passes (crates/platoon-aov/src/light_pass.rs): the pass a kernel renders, by the
// order of LightPass::ALL, and the BSDF's split into Cycles' parts for it: what of bsdf_eval's
// value (or of a delta sample) is diffuse, glossy and transmission. Without a light pass the
// macros are the plain sums, so the beauty keeps its bits.
#if defined(LIGHT_PASS_DIFFUSE_DIRECT)
#define LIGHT_PASS 0u
#elif defined(LIGHT_PASS_DIFFUSE_INDIRECT)
#define LIGHT_PASS 1u
#elif defined(LIGHT_PASS_GLOSSY_DIRECT)
#define LIGHT_PASS 2u
#elif defined(LIGHT_PASS_GLOSSY_INDIRECT)
#define LIGHT_PASS 3u
#elif defined(LIGHT_PASS_TRANSMISSION_DIRECT)
#define LIGHT_PASS 4u
#elif defined(LIGHT_PASS_TRANSMISSION_INDIRECT)
#define LIGHT_PASS 5u
#elif defined(LIGHT_PASS_EMISSION)
#define LIGHT_PASS 6u
#elif defined(LIGHT_PASS_ENVIRONMENT)
#define LIGHT_PASS 7u
#endif
const int PART_DIFFUSE = 0;
const int PART_GLOSSY = 1;
const int PART_TRANSMISSION = 2;
// A colour AOV's part (frame/light_pass.rs BsdfPart, shaders/path/aov.glsl) splits alike.
#if defined(OUTPUT_AOV_COLOR_DIFFUSE)
#define COLOR_PART PART_DIFFUSE
#elif defined(OUTPUT_AOV_COLOR_GLOSSY)
#define COLOR_PART PART_GLOSSY
#elif defined(OUTPUT_AOV_COLOR_TRANSMISSION)
#define COLOR_PART PART_TRANSMISSION
#endif
#if defined(LIGHT_PASS) || defined(COLOR_PART)
#define BSDF_PARTS
#endif
#ifdef BSDF_PARTS
vec3 eval_parts[3];
#define EVAL_CLEAR() { eval_parts[0] = vec3(0.0); eval_parts[1] = vec3(0.0); eval_parts[2] = vec3(0.0); }
#define EVAL_ADD(part, v) { vec3 v_ = (v); f += v_; eval_parts[part] += v_; }
#define EVAL_SCALE(k) { float k_ = (k); f *= k_; eval_parts[0] *= k_; eval_parts[1] *= k_; eval_parts[2] *= k_; }
#define DELTA_PART(part) { EVAL_CLEAR(); eval_parts[part] = vec3(1.0); }
#else
#define EVAL_CLEAR()
#define EVAL_ADD(part, v) { f += (v); }
#define EVAL_SCALE(k) { f *= (k); }
#define DELTA_PART(part)
#endif

#ifdef BSDF_PARTS
// Of the BSDF's last evaluation or delta sample, part `part`'s share: the mean of its RGB over
// the whole's (Cycles' pass weight).
float share_of_part(int part) {
    vec3 whole = eval_parts[0] + eval_parts[1] + eval_parts[2];
    vec3 p = eval_parts[part];
    float total = whole.x + whole.y + whole.z;
    return total > 0.0 ? (p.x + p.y + p.z) / total : 0.0;
}
#endif

#ifdef HAS_SHEEN
// KHR_materials_sheen's albedo table (crates/platoon-accel/src/sheen_albedo.rs): f32 bits
// at the start of the texel array of a scene with a sheen, rows of roughness
// SHEEN_MIN_ROUGHNESS..1, columns of cos θ 0..1, both uniform.
const float SHEEN_MIN_ROUGHNESS = 0.07;
const int SHEEN_COS_POINTS = 32;
const int SHEEN_ROUGHNESS_POINTS = 32;
float sheen_table(int k) { return uintBitsToFloat(texel_at(uint(k))); }
#endif

struct Bsdf {
    vec3 base_color;
    float alpha;
    float ior;
    float specular;
    vec3 f0;            // dielectric specular-layer f0 (KHR_materials_specular)
    bool delta;         // specular lobes are perfect
    // lobe selection probabilities: dielectric diffuse, dielectric specular, metal, glass
    vec4 p;
    // lobe weights of the mix: dielectric, glass, metal (each times 1 - coat)
    vec3 w;
#ifdef HAS_DIFFUSE_TRANSMISSION
    float dt;           // the diffuse light's transmitted share, its colour, and the chance
    vec3 dt_color;      // that the diffuse lobe samples the other side
    float q_transmit;
#endif
#ifdef HAS_CLEARCOAT
    float coat;         // the coat's weight in the mix: clearcoat * Schlick(0.04, |wo.nc|)
    float p_coat;       // its selection probability (the base lobes' p share the rest)
    float coat_alpha;
    bool coat_delta;
    vec3 coat_t, coat_b, coat_n;   // the coat's frame in the shading frame
#endif
#ifdef HAS_ANISOTROPY
    bool aniso;         // KHR_materials_anisotropy: the base's GGX lobes stretched along
    vec2 aniso_dir;     // aniso_dir (cos, sin in the shading frame's xy) to alphas
    vec2 alpha2;        // (along, across)
#endif
#ifdef HAS_IRIDESCENCE
    float film;         // KHR_materials_iridescence's strength (0: none), the film's index,
    float film_ior;     // its thickness (nm) and the index above it (the coat's 1.5 or air's 1)
    float film_thickness;
    float film_outside;
#endif
#ifdef HAS_SHEEN
    vec3 sheen_color;   // KHR_materials_sheen's colour, times what the coat leaves (1 - coat)
    float sheen_roughness;
    float sheen_max;    // max3 of the colour alone: the albedo scaling's factor
    float sheen_e_o;    // the lobe's albedo E at wo
    float p_sheen;      // its selection probability (below the coat's in the interval)
#endif
};

#include "common/ggx.glsl"

#ifdef HAS_ANISOTROPY
// A shading-frame vector in the anisotropy's frame (x along its direction), and back.
vec3 aniso_local(Bsdf b, vec3 v) { return vec3(dot(v.xy, b.aniso_dir), b.aniso_dir.x * v.y - b.aniso_dir.y * v.x, v.z); }
vec3 aniso_shading(Bsdf b, vec3 v) { return vec3(b.aniso_dir.x * v.x - b.aniso_dir.y * v.y, b.aniso_dir.y * v.x + b.aniso_dir.x * v.y, v.z); }
#endif

// The base's GGX lobes (dielectric specular layer, metal, glass): isotropic of alpha b.alpha, or
// anisotropic. The coat's GGX stays isotropic (the spec stretches the base's specular lobe).
float spec_d(Bsdf b, vec3 h) {
#ifdef HAS_ANISOTROPY
    if (b.aniso) return ggx_d_aniso(b.alpha2, aniso_local(b, h));
#endif
    return ggx_d(b.alpha, h.z);
}
float spec_g2(Bsdf b, vec3 wo, vec3 wi) {
#ifdef HAS_ANISOTROPY
    if (b.aniso) return ggx_g2_aniso(b.alpha2, aniso_local(b, wo), aniso_local(b, wi));
#endif
    return ggx_g2(b.alpha, wo, wi);
}
float spec_vndf_pdf(Bsdf b, vec3 wo, vec3 h) {
#ifdef HAS_ANISOTROPY
    if (b.aniso) return ggx_vndf_pdf_aniso(b.alpha2, aniso_local(b, wo), aniso_local(b, h));
#endif
    return ggx_vndf_pdf(b.alpha, wo, h);
}
vec3 spec_sample_vndf(Bsdf b, vec3 wo, vec2 u) {
#ifdef HAS_ANISOTROPY
    if (b.aniso) return aniso_shading(b, ggx_sample_vndf_aniso(b.alpha2, aniso_local(b, wo), u));
#endif
    return ggx_sample_vndf(b.alpha, wo, u);
}

vec3 schlick(vec3 f0, float c) {
    float m = clamp(1.0 - c, 0.0, 1.0);
    float m2 = m * m;
    return f0 + (1.0 - f0) * (m2 * m2 * m);
}

// Exact unpolarised Fresnel reflectance; eta = ior inside / ior outside, cos_i signed.
float fresnel_dielectric(float cos_i, float eta) {
    cos_i = clamp(cos_i, -1.0, 1.0);
    if (cos_i < 0.0) { eta = 1.0 / eta; cos_i = -cos_i; }
    float sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
    if (sin2_t >= 1.0) return 1.0;
    float cos_t = sqrt(max(0.0, 1.0 - sin2_t));
    float rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    float rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    return 0.5 * (rp * rp + rs * rs);
}

// Refracts wo about n (n on either side); false on total internal reflection.
bool refract_dir(vec3 wo, vec3 n, float eta, out float etap, out vec3 wi) {
    float c = dot(n, wo);
    if (c < 0.0) { eta = 1.0 / eta; c = -c; n = -n; }
    float sin2_t = max(0.0, 1.0 - c * c) / (eta * eta);
    if (sin2_t >= 1.0) return false;
    float cos_t = sqrt(1.0 - sin2_t);
    wi = -wo / eta + (c / eta - cos_t) * n;
    etap = eta;
    return true;
}

#if defined(HAS_IRIDESCENCE) || defined(HAS_DISPERSION)
#include "common/spectrum.glsl"
#endif
#ifdef HAS_IRIDESCENCE
#include "common/thin_film.glsl"
#endif

// The Fresnel reflectance at cos c (of wo to the microfacet) of a surface of normal-incidence
// reflectance f0: Schlick's, mixed with the thin film's where one lies over it.
vec3 filmed_fresnel(Bsdf b, vec3 f0, float c) {
    vec3 f = schlick(f0, c);
#ifdef HAS_IRIDESCENCE
    if (b.film > 0.0) f = mix(f, thin_film_fresnel(b.film_outside, b.film_ior, b.film_thickness, c, f0), b.film);
#endif
    return f;
}
// The dielectric's specular layer's, and the metal's (its base colour the f0).
vec3 layer_fresnel(Bsdf b, float c) { return filmed_fresnel(b, b.f0, c); }
vec3 metal_fresnel(Bsdf b, float c) { return filmed_fresnel(b, b.base_color, c); }

// Glass's reflectance at cos oh (below 0: from inside) and the chance with which reflection is
// sampled: the exact Fresnel, mixed with a film's as seen from outside (a lossless film reflects
// alike from both sides, at the angles Snell's law pairs), sampled by the mean of its channels.
vec3 glass_fresnel(Bsdf b, float oh, out float chance) {
    float F = fresnel_dielectric(oh, b.ior);
    chance = F;
#ifdef HAS_IRIDESCENCE
    if (b.film > 0.0 && F < 1.0) {
        float c = oh >= 0.0 ? oh : sqrt(max(0.0, 1.0 - b.ior * b.ior * (1.0 - oh * oh)));
        float g = (b.ior - 1.0) / (b.ior + 1.0);
        vec3 film = thin_film_fresnel(b.film_outside, b.film_ior, b.film_thickness, c, vec3(g * g));
        vec3 f = mix(vec3(F), film, b.film);
        chance = (f.x + f.y + f.z) / 3.0;
        return f;
    }
#endif
    return vec3(F);
}

#ifdef HAS_SHEEN
// The Charlie distribution of half vectors, alpha = sheen roughness squared.
float charlie_d(float a, float nh) {
    float s2 = max(0.0, 1.0 - nh * nh);
    return (2.0 + 1.0 / a) * pow(s2, 0.5 / a) * (0.5 * INV_PI);
}

// Estevez and Kulla's fit of the Charlie lobe's Smith lambda (the spec's lambdaSheen).
float charlie_fit(float x, float a) {
    float t = (1.0 - a) * (1.0 - a);
    return mix(21.5473, 25.3245, t) / (1.0 + mix(3.82987, 3.32435, t) * pow(x, mix(0.19823, 0.16801, t)))
         + mix(-1.97760, -1.27393, t) * x + mix(-4.32054, -4.85967, t);
}
float charlie_lambda(float a, float c) {
    c = abs(c);
    return c < 0.5 ? exp(charlie_fit(c, a)) : exp(2.0 * charlie_fit(0.5, a) - charlie_fit(1.0 - c, a));
}

// The sheen lobe of colour 1 times cos(wi), o and i above the surface: D V |cos wi| with
// V = 1 / ((1 + lambda(o) + lambda(i)) 4 cos(o) cos(i)).
float sheen_cos(float roughness, vec3 o, vec3 i) {
    float a = roughness * roughness;
    vec3 h = normalize(o + i);
    return charlie_d(a, h.z) / ((1.0 + charlie_lambda(a, o.z) + charlie_lambda(a, i.z)) * 4.0 * o.z);
}

// E(|cos|, roughness), bilinear in the table.
float sheen_albedo(float c, float roughness) {
    float x = clamp(abs(c), 0.0, 1.0) * float(SHEEN_COS_POINTS - 1);
    float y = clamp((roughness - SHEEN_MIN_ROUGHNESS) / (1.0 - SHEEN_MIN_ROUGHNESS), 0.0, 1.0) * float(SHEEN_ROUGHNESS_POINTS - 1);
    int x0 = min(int(x), SHEEN_COS_POINTS - 2), y0 = min(int(y), SHEEN_ROUGHNESS_POINTS - 2);
    float fx = x - float(x0), fy = y - float(y0);
    int k = y0 * SHEEN_COS_POINTS + x0;
    float lo = mix(sheen_table(k), sheen_table(k + 1), fx);
    float hi = mix(sheen_table(k + SHEEN_COS_POINTS), sheen_table(k + SHEEN_COS_POINTS + 1), fx);
    return mix(lo, hi, fy);
}
#endif

// The sheen's albedo scaling of everything below it between wo and wi; 1 without a sheen.
float sheen_scale(Bsdf b, vec3 wi) {
#ifdef HAS_SHEEN
    // Clamped: the spec's lobe reflects more than it receives at grazing views of sheens
    // smoother than about 0.2 (E up to 2.7), where the base would turn negative.
    if (b.sheen_max > 0.0) return max(0.0, 1.0 - b.sheen_max * max(b.sheen_e_o, sheen_albedo(wi.z, b.sheen_roughness)));
#endif
    return 1.0;
}

// The scaling at the view alone (the spec's cheaper form): what the approximate methods' diffuse
// records take (IGI's and the vertex links' reflectance).
float sheen_view_scale(Bsdf b) {
#ifdef HAS_SHEEN
    return max(0.0, 1.0 - b.sheen_max * b.sheen_e_o);
#else
    return 1.0;
#endif
}

Bsdf make_bsdf(Surface s, vec3 wo) {
    Bsdf b;
    b.base_color = s.base_color;
    float r = max(s.roughness, 0.0);
    b.delta = r < MIN_ROUGHNESS;
    b.alpha = r * r;
    b.ior = s.ior;
    b.specular = s.specular;
    float f0 = (s.ior - 1.0) / (s.ior + 1.0);
    b.f0 = min(vec3(f0 * f0) * s.specular_color, vec3(1.0));
    b.w = vec3((1.0 - s.metallic) * (1.0 - s.transmission), (1.0 - s.metallic) * s.transmission, s.metallic);
#ifdef HAS_CLEARCOAT
    b.coat = 0.0;
    b.p_coat = 0.0;
    b.coat_alpha = 0.0;
    b.coat_delta = true;
    b.coat_t = vec3(1.0, 0.0, 0.0);
    b.coat_b = vec3(0.0, 1.0, 0.0);
    b.coat_n = vec3(0.0, 0.0, 1.0);
    if (s.clearcoat > 0.0) {
        // The coat's normal in the shading frame the callers build (make_frame of s.ns).
        vec3 t, bt;
        make_frame(s.ns, t, bt);
        b.coat_n = normalize(to_local(s.clearcoat_normal, t, bt, s.ns));
        make_frame(b.coat_n, b.coat_t, b.coat_b);
        float cr = max(s.clearcoat_roughness, 0.0);
        b.coat_delta = cr < MIN_ROUGHNESS;
        b.coat_alpha = cr * cr;
        b.coat = s.clearcoat * schlick(vec3(0.04), abs(dot(wo, b.coat_n))).x;
        // What the coat reflects the base does not: every base lobe weighs 1 - coat.
        b.w *= 1.0 - b.coat;
    }
#endif
#ifdef HAS_ANISOTROPY
    b.aniso = false;
    b.aniso_dir = vec2(1.0, 0.0);
    b.alpha2 = vec2(b.alpha);
    if (s.anisotropy > 0.0) {
        // The direction in the shading frame the callers build (make_frame of s.ns).
        vec3 t, bt;
        make_frame(s.ns, t, bt);
        vec2 d = vec2(dot(s.anisotropy_direction, t), dot(s.anisotropy_direction, bt));
        // The spec: alpha along the direction mix(alpha, 1, strength^2), across it the
        // material's (kept from a perfect mirror's 0: the lobe is then a finite streak). Too
        // weak to lift a mirror off MIN_ROUGHNESS, it stays the mirror.
        float along = mix(b.alpha, 1.0, s.anisotropy * s.anisotropy);
        if (dot(d, d) > 1e-12 && along >= MIN_ROUGHNESS * MIN_ROUGHNESS) {
            b.aniso = true;
            b.aniso_dir = normalize(d);
            b.alpha2 = vec2(along, max(b.alpha, MIN_ROUGHNESS * MIN_ROUGHNESS));
            b.delta = false;
        }
    }
#endif
#ifdef HAS_IRIDESCENCE
    b.film = s.iridescence;
    b.film_ior = s.iridescence_ior;
    b.film_thickness = s.iridescence_thickness;
    b.film_outside = 1.0;
#ifdef HAS_CLEARCOAT
    // The spec: under a coat the film's outside is the coat's index.
    if (s.clearcoat > 0.0) b.film_outside = 1.5;
#endif
#endif
#ifdef HAS_SHEEN
    b.sheen_color = vec3(0.0);
    b.sheen_roughness = 1.0;
    b.sheen_max = 0.0;
    b.sheen_e_o = 0.0;
    b.p_sheen = 0.0;
    if (max3(s.sheen_color) > 0.0) {
        b.sheen_max = max3(s.sheen_color);
        b.sheen_roughness = clamp(s.sheen_roughness, SHEEN_MIN_ROUGHNESS, 1.0);
        b.sheen_e_o = sheen_albedo(wo.z, b.sheen_roughness);
#ifdef HAS_CLEARCOAT
        b.sheen_color = s.sheen_color * (1.0 - b.coat);
#else
        b.sheen_color = s.sheen_color;
#endif
    }
#endif
    // The diffuse lobe's albedo (estimated by luminance), reflected and transmitted.
    float diffuse = luminance(s.base_color);
#ifdef HAS_DIFFUSE_TRANSMISSION
    b.dt = s.diffuse_transmission;
    b.dt_color = s.diffuse_transmission_color;
    b.q_transmit = 0.0;
    if (b.dt > 0.0) {
        float reflected = diffuse * (1.0 - b.dt), transmitted = luminance(b.dt_color) * b.dt;
        diffuse = reflected + transmitted;
        b.q_transmit = diffuse > 0.0 ? transmitted / diffuse : 0.0;
    }
#endif
#ifdef HAS_SPECULAR_LOBES
    float c = abs(wo.z);
    float fs = s.specular * max3(schlick(b.f0, c));
    vec4 p = vec4(b.w.x * (1.0 - fs) * diffuse, b.w.x * fs, b.w.z * luminance(schlick(s.base_color, c)), b.w.y);
#else
    vec4 p = vec4(b.w.x * diffuse, 0.0, 0.0, 0.0);
#endif
    float sum = p.x + p.y + p.z + p.w;
#ifdef HAS_SHEEN
    // The base loses at most what the sheen reflects at the view; the sheen reflects about
    // its colour times E.
    if (b.sheen_max > 0.0) {
        float sheen = luminance(b.sheen_color) * b.sheen_e_o;
        p *= sheen_view_scale(b);
        sum = p.x + p.y + p.z + p.w + sheen;
        b.p_sheen = sheen;
    }
#endif
#ifdef HAS_CLEARCOAT
    // A coat reflects about its weight (a mirror's albedo times the Fresnel), so it is chosen
    // in proportion to it.
    sum += b.coat;
    b.p_coat = sum > 0.0 ? b.coat / sum : 0.0;
#endif
    b.p = sum > 0.0 ? p / sum : vec4(0.0);
#ifdef HAS_SHEEN
    b.p_sheen = sum > 0.0 ? b.p_sheen / sum : 0.0;
#endif
    return b;
}

#ifdef HAS_CLEARCOAT
vec3 coat_local(Bsdf b, vec3 v) { return to_local(v, b.coat_t, b.coat_b, b.coat_n); }
#endif

bool bsdf_all_delta(Bsdf b) {
#ifdef HAS_CLEARCOAT
    if (b.p_coat > 0.0 && !b.coat_delta) return false;
#endif
#ifdef HAS_SHEEN
    if (b.p_sheen > 0.0) return false;
#endif
    return b.delta && b.p.x == 0.0;
}

// Whether light through the surface reaches the other side by a lobe that is not a delta (rough
// glass, diffuse transmission): where a light sample may count behind the surface.
bool bsdf_transmits(Bsdf b) {
#ifdef HAS_DIFFUSE_TRANSMISSION
    if (b.dt > 0.0) return true;
#endif
    return b.w.y > 0.0 && !b.delta;
}

// The share of the diffuse lobe reflected (the rest is transmitted) and the chance that it
// samples the reflected side.
float diffuse_reflected(Bsdf b) {
#ifdef HAS_DIFFUSE_TRANSMISSION
    return 1.0 - b.dt;
#else
    return 1.0;
#endif
}
float diffuse_reflect_chance(Bsdf b) {
#ifdef HAS_DIFFUSE_TRANSMISSION
    return 1.0 - b.q_transmit;
#else
    return 1.0;
#endif
}

// Albedo of the dielectric's diffuse reflection, under specular-layer reflectance fr.
vec3 diffuse_reflectance(Bsdf b, vec3 fr) { return b.w.x * (1.0 - b.specular * max3(fr)) * b.base_color * diffuse_reflected(b); }

// The diffuse term of bsdf_eval alone, times |cos(wi)|: what IGI's VPLs stand in for.
vec3 bsdf_diffuse(Bsdf b, vec3 wo, vec3 wi) {
    if (wo.z * wi.z <= 0.0) return vec3(0.0);
    vec3 o = wo.z < 0.0 ? -wo : wo;
    vec3 i = wo.z < 0.0 ? -wi : wi;
    vec3 h = normalize(o + i);
    return diffuse_reflectance(b, layer_fresnel(b, dot(o, h))) * INV_PI * i.z * sheen_scale(b, wi);
}

// Non-delta part of the BSDF times |cos(wi)|, and the matching sampling pdf (solid angle).
vec3 bsdf_eval(Bsdf b, vec3 wo, vec3 wi, out float pdf) {
    pdf = 0.0;
    vec3 f = vec3(0.0);
    EVAL_CLEAR();
    if (wo.z == 0.0 || wi.z == 0.0) return f;
    // Opaque lobes shade both sides alike: mirror into wo's hemisphere.
    if (wo.z * wi.z > 0.0) {
        vec3 o = wo.z < 0.0 ? -wo : wo;
        vec3 i = wo.z < 0.0 ? -wi : wi;
#ifdef HAS_SPECULAR_LOBES
        vec3 h = normalize(o + i);
        float oh = dot(o, h);
        vec3 fr = layer_fresnel(b, oh);
        EVAL_ADD(PART_DIFFUSE, diffuse_reflectance(b, fr) * INV_PI * i.z);
        pdf += b.p.x * diffuse_reflect_chance(b) * i.z * INV_PI;
        if (!b.delta) {
            float spec = spec_d(b, h) * spec_g2(b, o, i) / (4.0 * o.z);
            EVAL_ADD(PART_GLOSSY, (b.w.x * b.specular * fr + b.w.z * metal_fresnel(b, oh)) * spec);
            pdf += (b.p.y + b.p.z) * spec_vndf_pdf(b, o, h) / (4.0 * oh);
        }
#else
        // diffuse_reflectance with a specular layer of zero: w.x * (1 - 0) * base colour.
        EVAL_ADD(PART_DIFFUSE, b.w.x * b.base_color * diffuse_reflected(b) * INV_PI * i.z);
        pdf += b.p.x * diffuse_reflect_chance(b) * i.z * INV_PI;
#endif
    }
#ifdef HAS_DIFFUSE_TRANSMISSION
    if (b.dt > 0.0 && wo.z * wi.z < 0.0) {
        vec3 o = wo.z < 0.0 ? -wo : wo;
        vec3 i = wo.z < 0.0 ? -wi : wi;
        float layer = 1.0;
#ifdef HAS_SPECULAR_LOBES
        // The specular layer's Fresnel at wi mirrored to wo's side (thin: no refraction).
        vec3 h = normalize(o + vec3(i.x, i.y, -i.z));
        layer = 1.0 - b.specular * max3(layer_fresnel(b, dot(o, h)));
#endif
        EVAL_ADD(PART_DIFFUSE, b.w.x * layer * b.dt * b.dt_color * INV_PI * abs(i.z));
        pdf += b.p.x * b.q_transmit * abs(i.z) * INV_PI;
    }
#endif
#ifdef HAS_TRANSMISSION
    if (b.w.y > 0.0 && !b.delta) {
        bool reflect = wo.z * wi.z > 0.0;
        float etap = reflect ? 1.0 : (wo.z > 0.0 ? b.ior : 1.0 / b.ior);
        vec3 h = wi * etap + wo;
        if (dot(h, h) > 0.0) {
            h = normalize(h);
            if (h.z < 0.0) h = -h;
            float oh = dot(wo, h), ih = dot(wi, h);
            if (oh * wo.z > 0.0 && ih * wi.z > 0.0) {
                float chance;
                vec3 F = glass_fresnel(b, oh, chance);
                float D = spec_d(b, h);
                float G = spec_g2(b, wo, wi);
                if (reflect) {
                    EVAL_ADD(PART_GLOSSY, b.w.y * D * G * F / (4.0 * abs(wo.z)));
                    pdf += b.p.w * spec_vndf_pdf(b, wo, h) / (4.0 * abs(oh)) * chance;
                } else {
                    float denom = ih + oh / etap;
                    denom *= denom;
                    // Radiance is compressed by 1/etap^2 on entering a denser medium.
                    vec3 ft = D * (1.0 - F) * G * abs(ih * oh / (denom * wo.z)) / (etap * etap);
                    EVAL_ADD(PART_TRANSMISSION, b.w.y * b.base_color * ft);
                    pdf += b.p.w * spec_vndf_pdf(b, wo, h) * abs(ih) / denom * (1.0 - chance);
                }
            }
        }
    }
#endif
#ifdef HAS_SHEEN
    if (b.sheen_max > 0.0) {
        // Everything above is the base the sheen lies over.
        EVAL_SCALE(sheen_scale(b, wi));
        if (wo.z * wi.z > 0.0) {
            vec3 o = wo.z < 0.0 ? -wo : wo;
            vec3 i = wo.z < 0.0 ? -wi : wi;
            EVAL_ADD(PART_DIFFUSE, b.sheen_color * sheen_cos(b.sheen_roughness, o, i));
            pdf += b.p_sheen * 0.5 * INV_PI;
        }
    }
#endif
#ifdef HAS_CLEARCOAT
    if (b.p_coat > 0.0 && !b.coat_delta && wo.z * wi.z > 0.0) {
        // Both sides alike, as the opaque lobes.
        vec3 oc = coat_local(b, wo.z < 0.0 ? -wo : wo);
        vec3 ic = coat_local(b, wo.z < 0.0 ? -wi : wi);
        if (oc.z > 0.0 && ic.z > 0.0) {
            vec3 h = normalize(oc + ic);
            float spec = ggx_d(b.coat_alpha, h.z) * ggx_g2(b.coat_alpha, oc, ic) / (4.0 * oc.z * ic.z);
            EVAL_ADD(PART_GLOSSY, vec3(b.coat * spec * abs(wi.z)));
            pdf += b.p_coat * ggx_vndf_pdf(b.coat_alpha, oc, h) / (4.0 * dot(oc, h));
        }
    }
#endif
    return f;
}

struct BsdfSample { vec3 wi; vec3 weight; float pdf; bool delta; };

// Samples a lobe with ul and a direction in it with u (and a Fresnel choice from rng).
bool bsdf_sample_with(Bsdf b, vec3 wo, float ul, vec2 u, inout Rng rng, out BsdfSample bs) {
    bs.delta = false;
    bs.pdf = 0.0;
    if (wo.z == 0.0) return false;
    float side = wo.z < 0.0 ? -1.0 : 1.0;
    vec3 o = wo * side;
#ifdef HAS_CLEARCOAT
    if (b.p_coat > 0.0 && ul >= 1.0 - b.p_coat) {
        // The coat, in its own frame; back in the shading frame a reflection must stay on wo's
        // side. Both sides alike: wo's side is mirrored through the origin, as bsdf_eval does.
        vec3 i;
        if (b.coat_delta) {
            i = reflect(-o, b.coat_n);
            if (i.z <= 0.0) return false;
            bs.wi = i * side;
            bs.weight = vec3(b.coat / b.p_coat);
            bs.delta = true;
            DELTA_PART(PART_GLOSSY);
            return true;
        }
        vec3 oc = coat_local(b, o);
        if (oc.z <= 0.0) return false;
        vec3 ic = reflect(-oc, ggx_sample_vndf(b.coat_alpha, oc, u));
        if (ic.z <= 0.0) return false;
        i = to_world(ic, b.coat_t, b.coat_b, b.coat_n);
        if (i.z <= 0.0) return false;
        bs.wi = i * side;
        vec3 f = bsdf_eval(b, wo, bs.wi, bs.pdf);
        if (!(bs.pdf > 0.0)) return false;
        bs.weight = f / bs.pdf;
        return true;
    }
#endif
#ifdef HAS_SHEEN
    float below_coat = 1.0;
#ifdef HAS_CLEARCOAT
    below_coat -= b.p_coat;
#endif
    if (b.p_sheen > 0.0 && ul >= below_coat - b.p_sheen) {
        // Uniform over the hemisphere: cos θ uniform in (0, 1]; weighed below like the others.
        float c = 1.0 - u.y, sn = sqrt(max(0.0, 1.0 - c * c)), phi = 2.0 * PI * u.x;
        bs.wi = vec3(sn * cos(phi), sn * sin(phi), c * side);
    } else
#endif
    if (ul < b.p.x) {
        // The first p.x * q_transmit of the diffuse interval goes through to the other side.
        float through = 1.0;
#ifdef HAS_DIFFUSE_TRANSMISSION
        if (ul < b.p.x * b.q_transmit) through = -1.0;
#endif
        bs.wi = sample_cosine_hemisphere(u) * vec3(1.0, 1.0, side * through);
    }
#ifdef HAS_SPECULAR_LOBES
    else if (ul < b.p.x + b.p.y + b.p.z) {
        if (b.delta) {
            bool metal = ul >= b.p.x + b.p.y;
            vec3 fr = metal ? b.w.z * metal_fresnel(b, o.z) / b.p.z
                            : b.w.x * b.specular * layer_fresnel(b, o.z) / b.p.y;
            bs.wi = vec3(-wo.x, -wo.y, wo.z);
            bs.weight = fr * sheen_scale(b, bs.wi);
            bs.delta = true;
            DELTA_PART(PART_GLOSSY);
            return true;
        }
        vec3 h = spec_sample_vndf(b, o, u);
        vec3 i = reflect(-o, h);
        if (i.z <= 0.0) return false;
        // Mirrored through the origin, as bsdf_eval mirrors wo's side (a mirror in z alone
        // turned a back-side reflection into a retro-reflection).
        bs.wi = i * side;
    }
#endif
    else {
#ifdef HAS_TRANSMISSION
        if (b.p.w <= 0.0) return false;
        vec3 h = b.delta ? vec3(0.0, 0.0, 1.0) : spec_sample_vndf(b, wo, u);
        float oh = dot(wo, h);
        float chance;
        vec3 F = glass_fresnel(b, oh, chance);
        // A film's colour is what its reflectance weighs against the chance sampled.
        vec3 tint = vec3(1.0);
        if (rng_next(rng) < chance) {
            bs.wi = reflect(-wo, h);
            if (bs.wi.z * wo.z <= 0.0) return false;
#ifdef HAS_IRIDESCENCE
            if (b.film > 0.0) tint = F / chance;
#endif
            if (b.delta) { bs.weight = vec3(b.w.y / b.p.w) * tint * sheen_scale(b, bs.wi); bs.delta = true; DELTA_PART(PART_GLOSSY); return true; }
        } else {
            float etap;
            if (!refract_dir(wo, h, b.ior, etap, bs.wi)) return false;
            if (bs.wi.z * wo.z >= 0.0 || bs.wi.z == 0.0) return false;
#ifdef HAS_IRIDESCENCE
            if (b.film > 0.0) tint = (1.0 - F) / (1.0 - chance);
#endif
            if (b.delta) { bs.weight = b.w.y * b.base_color * tint * sheen_scale(b, bs.wi) / (b.p.w * etap * etap); bs.delta = true; DELTA_PART(PART_TRANSMISSION); return true; }
        }
#else
        return false;
#endif
    }
    vec3 f = bsdf_eval(b, wo, bs.wi, bs.pdf);
    if (!(bs.pdf > 0.0)) return false;
    bs.weight = f / bs.pdf;
    return true;
}

bool bsdf_sample(Bsdf b, vec3 wo, inout Rng rng, out BsdfSample bs) {
    float ul = rng_next(rng);
    vec2 u = rng_next2(rng);
    return bsdf_sample_with(b, wo, ul, u, rng, bs);
}
