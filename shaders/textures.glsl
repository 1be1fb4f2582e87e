// Textures live in one RGBA8 texel array; bilinear filtering and wrap modes are done here, so
// the kernel needs no sampler descriptors and any number of textures fits.

int wrap_coord(int i, int n, uint mode) {
    if (mode == 2u) return clamp(i, 0, n - 1);
    if (mode == 1u) {
        int p = 2 * n;
        int m = ((i % p) + p) % p;
        return m < n ? m : p - 1 - m;
    }
    return ((i % n) + n) % n;
}

vec4 texel(Texture t, int x, int y) {
    uint xi = uint(wrap_coord(x, int(t.width), t.wrap & 3u));
    uint yi = uint(wrap_coord(y, int(t.height), (t.wrap >> 2) & 3u));
    return unpackUnorm4x8(texel_at(t.offset + yi * t.width + xi));
}

vec4 srgb_to_linear(vec4 c) {
    vec3 lo = c.rgb / 12.92;
    vec3 hi = pow((c.rgb + 0.055) / 1.055, vec3(2.4));
    return vec4(mix(lo, hi, greaterThan(c.rgb, vec3(0.04045))), c.a);
}

// Bilinear lookup; sRGB textures are decoded per texel before filtering.
vec4 sample_texture(int index, vec2 uv, bool srgb) {
    Texture t = texture_at(index);
    vec2 p = uv * vec2(t.width, t.height) - 0.5;
    if (any(isnan(p)) || any(isinf(p))) p = vec2(0.0);
    p = clamp(p, vec2(-1e7), vec2(1e7));
    vec2 f = fract(p);
    ivec2 i = ivec2(floor(p));
    vec4 a = texel(t, i.x, i.y), b = texel(t, i.x + 1, i.y);
    vec4 c = texel(t, i.x, i.y + 1), d = texel(t, i.x + 1, i.y + 1);
    if (srgb) { a = srgb_to_linear(a); b = srgb_to_linear(b); c = srgb_to_linear(c); d = srgb_to_linear(d); }
    return mix(mix(a, b, f.x), mix(c, d, f.x), f.y);
}
