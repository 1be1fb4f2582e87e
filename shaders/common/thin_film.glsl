// KHR_materials_iridescence's thin film: Belcour and Barla's (2017) reflectance of a dielectric
// film over a base, integrated over the spectrum analytically (in Fourier space) and returned
// in linear Rec. 709, with the spec's approximations: Schlick's Fresnel at both interfaces, the
// base's index inferred from its normal-incidence reflectance as a dielectric's, phase shifts of
// 0 or pi by which side is denser, the first two orders of interference. The optical path
// difference takes the angle inside the film (the paper's and the Khronos sample viewer's; the
// spec's text writes the outside one). Included by bsdf.glsl after `schlick` and spectrum.glsl.

// The colour-matching functions fit by Gaussians (amplitude, centre, variance per X, Y, Z and a
// second lobe for X), integrated against the interference of optical path difference `opd` (nm)
// and phase `shift`: the Fourier transform of each Gaussian at that path.
vec3 film_sensitivity(float opd, vec3 shift) {
    float phase = 2.0 * PI * opd * 1e-9;
    const vec3 amplitude = vec3(5.4856e-13, 4.4201e-13, 5.2481e-13);
    const vec3 centre = vec3(1.6810e+06, 1.7953e+06, 2.2084e+06);
    const vec3 variance = vec3(4.3278e+09, 9.3046e+09, 6.6121e+09);
    vec3 xyz = amplitude * sqrt(2.0 * PI * variance) * cos(centre * phase + shift) * exp(-phase * phase * variance);
    xyz.x += 9.7470e-14 * sqrt(2.0 * PI * 4.5282e+09) * cos(2.2399e+06 * phase + shift.x) * exp(-4.5282e+09 * phase * phase);
    return XYZ_TO_REC709 * (xyz / 1.0685e-7);
}

// The reflectance at cos `c1` (outside) of a film of index `n2` and `thickness` nm between the
// outside's index `n1` and a base of normal-incidence reflectance `f0`.
vec3 thin_film_fresnel(float n1, float n2, float thickness, float c1, vec3 f0) {
    // A film thinning to nothing takes the outside's index, so that it vanishes.
    n2 = mix(n1, n2, smoothstep(0.0, 0.03, thickness));
    float s2 = (n1 / n2) * (n1 / n2) * (1.0 - c1 * c1);
    if (s2 >= 1.0) return vec3(1.0);    // total internal reflection into the film
    float c2 = sqrt(1.0 - s2);
    float r0 = (n2 - n1) / (n2 + n1);
    float r12 = schlick(vec3(r0 * r0), c1).x;
    float t121 = 1.0 - r12;
    vec3 root = sqrt(clamp(f0, vec3(0.0), vec3(0.9999)));
    vec3 n3 = (1.0 + root) / (1.0 - root);
    vec3 r1 = (n3 - n2) / (n3 + n2);
    vec3 r23 = schlick(r1 * r1, c2);
    // Half a wave is lost reflecting off the denser side: at the film's top from below when
    // the outside is denser, at the base when the film is.
    vec3 phase = vec3(n2 < n1 ? 0.0 : PI) + PI * vec3(lessThan(n3, vec3(n2)));
    float opd = 2.0 * n2 * thickness * c2;
    // Airy's sum: the incoherent part, then the interference terms m = 1, 2.
    vec3 r123 = clamp(r12 * r23, vec3(1e-5), vec3(0.9999));
    vec3 rs = t121 * t121 * r23 / (1.0 - r123);
    vec3 r = r12 + rs;
    vec3 cm = (rs - t121) * sqrt(r123);
    r += cm * 2.0 * film_sensitivity(opd, phase);
    cm *= sqrt(r123);
    r += cm * 2.0 * film_sensitivity(2.0 * opd, 2.0 * phase);
    // Out-of-gamut colours leave the unit range.
    return clamp(r, vec3(0.0), vec3(1.0));
}
