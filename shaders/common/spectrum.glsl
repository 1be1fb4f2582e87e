// Wavelengths in RGB: what KHR_materials_iridescence's film integrates over and what a path
// that meets a dispersive surface (KHR_materials_dispersion) carries from there on. Included by
// bsdf.glsl.

// CIE XYZ to linear Rec. 709 (sRGB primaries, D65), columns.
const mat3 XYZ_TO_REC709 = mat3(3.2404542, -0.9692660, 0.0556434,
                                -1.5371385, 1.8760108, -0.2040259,
                                -0.4985314, 0.0415560, 1.0572252);

#ifdef HAS_DISPERSION
// The visible range a path's wavelength is drawn from, uniformly (nm).
const float WAVELENGTH_MIN = 380.0;
const float WAVELENGTH_MAX = 780.0;
// Each channel's sensitivity integrated over the range: what the weights divide by so that a
// wavelength drawn uniformly leaves white white (crates/platoon-core/src/scene/graph.rs'
// `dispersion` notes; tests/kernel/dispersion.rs integrates it afresh).
const vec3 SENSITIVITY_INTEGRAL = vec3(176.17732, 115.38557, 109.31846);

// One lobe of Wyman, Sloan and Shirley's (2013) fit of the CIE 1931 colour-matching functions:
// a Gaussian of centre `mu` and widths `below`, `above` on either side.
float cie_lobe(float l, float mu, float below, float above) {
    float t = (l - mu) / (l < mu ? below : above);
    return exp(-0.5 * t * t);
}

vec3 cie_xyz(float l) {
    return vec3(1.056 * cie_lobe(l, 599.8, 37.9, 31.0) + 0.362 * cie_lobe(l, 442.0, 16.0, 26.7) - 0.065 * cie_lobe(l, 501.1, 20.4, 26.2),
                0.821 * cie_lobe(l, 568.8, 46.9, 40.5) + 0.286 * cie_lobe(l, 530.9, 16.3, 31.1),
                1.217 * cie_lobe(l, 437.0, 11.8, 36.0) + 0.681 * cie_lobe(l, 459.0, 26.0, 13.8));
}

// A wavelength drawn uniformly by `u`, and its weight: the channels' sensitivities there (the
// colour-matching functions in linear Rec. 709, clamped at 0: out-of-gamut spectral colours
// desaturate rather than subtract) over the pdf and each channel's integral. Its expectation is
// 1 in every channel: a path that turns spectral keeps the colour of what it does not disperse.
float sample_wavelength(float u, out vec3 weight) {
    float l = mix(WAVELENGTH_MIN, WAVELENGTH_MAX, u);
    weight = max(XYZ_TO_REC709 * cie_xyz(l), vec3(0.0)) * (WAVELENGTH_MAX - WAVELENGTH_MIN) / SENSITIVITY_INTEGRAL;
    return l;
}

// The index at wavelength `l` of a material of index `ior` at 587.6 nm and dispersion 20 / V
// (V its Abbe number): the spec's two-term Cauchy equation, at least 1.
float dispersed_ior(float ior, float dispersion, float l) {
    return max(ior + (ior - 1.0) * dispersion / 20.0 * (523655.0 / (l * l) - 1.5168), 1.0);
}
#endif
