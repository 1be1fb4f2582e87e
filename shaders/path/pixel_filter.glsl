// The pixel filter (crates/platoon-core/src/frame/pixel_filter.rs): where in the image plane a
// camera ray leaves, drawn from the filter itself (filter importance sampling), so that every
// sample weighs one and a pixel's estimate is its own samples' mean. pixel_position(u) maps
// two uniform numbers to a position in pixel units relative to the pixel's corner (the centre
// is 0.5, 0.5); each axis is drawn apart (the filters are separable).

#if defined(PIXEL_FILTER_GAUSSIAN)
// The inverse error function, Giles' single-precision approximation ("Approximating the
// erfinv function", GPU Computing Gems, 2011): relative error below 4e-7 on (-1, 1).
float erfinv(float x) {
    float w = -log((1.0 - x) * (1.0 + x));
    float p;
    if (w < 5.0) {
        w -= 2.5;
        p = 2.81022636e-08;
        p = 3.43273939e-07 + p * w;
        p = -3.5233877e-06 + p * w;
        p = -4.39150654e-06 + p * w;
        p = 0.00021858087 + p * w;
        p = -0.00125372503 + p * w;
        p = -0.00417768164 + p * w;
        p = 0.246640727 + p * w;
        p = 1.50140941 + p * w;
    } else {
        w = sqrt(w) - 3.0;
        p = -0.000200214257;
        p = 0.000100950558 + p * w;
        p = 0.00134934322 + p * w;
        p = -0.00367342844 + p * w;
        p = 0.00573950773 + p * w;
        p = -0.0076224613 + p * w;
        p = 0.00943887047 + p * w;
        p = 1.00167406 + p * w;
        p = 2.83297682 + p * w;
    }
    return p * x;
}

// Standard deviation 0.5 px, cut at 1.5 px (three of them): u spread over the kept mass,
// erf(3 / sqrt 2), then the normal's inverse CDF, sigma sqrt(2) erfinv(2u - 1).
vec2 pixel_position(vec2 u) {
    const float KEPT = 0.99730020;
    const float SIGMA_SQRT2 = 0.70710678;
    vec2 v = (2.0 * u - 1.0) * KEPT;
    return vec2(0.5) + SIGMA_SQRT2 * vec2(erfinv(v.x), erfinv(v.y));
}
#elif defined(PIXEL_FILTER_BLACKMAN_HARRIS)
// Blackman-Harris over 1.5 px: its CDF in closed form (t in [0, 1] across the support),
// inverted by bisection. Twenty halvings leave 1.5e-6 px; a fixed count keeps a SIMD group's
// lanes together.
float blackman_harris_cdf(float t) {
    const float TWO_PI = 6.28318530718;
    float v = TWO_PI * t;
    return t - (0.48829 * sin(v) - 0.14128 * 0.5 * sin(2.0 * v) + 0.01168 * sin(3.0 * v) / 3.0)
        / (0.35875 * TWO_PI);
}

float blackman_harris_inverse(float u) {
    float lo = 0.0, hi = 1.0;
    for (int i = 0; i < 20; ++i) {
        float mid = 0.5 * (lo + hi);
        if (blackman_harris_cdf(mid) < u) lo = mid; else hi = mid;
    }
    return 0.5 * (lo + hi);
}

vec2 pixel_position(vec2 u) {
    const float WIDTH = 1.5;
    vec2 t = vec2(blackman_harris_inverse(u.x), blackman_harris_inverse(u.y));
    return vec2(0.5) + WIDTH * (t - 0.5);
}
#else
// The box: uniform over the pixel.
vec2 pixel_position(vec2 u) {
    return u;
}
#endif
