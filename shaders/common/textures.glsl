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

// Bilinear lookup (the texel under uv with magFilter NEAREST); sRGB textures are decoded per
// texel before filtering.
vec4 sample_level(Texture t, vec2 uv, bool srgb) {
    vec2 p = uv * vec2(t.width, t.height) - 0.5;
    if (any(isnan(p)) || any(isinf(p))) p = vec2(0.0);
    p = clamp(p, vec2(-1e7), vec2(1e7));
    if ((t.wrap & 16u) != 0u) {
        ivec2 n = ivec2(floor(p + 0.5));
        vec4 c = texel(t, n.x, n.y);
        return srgb ? srgb_to_linear(c) : c;
    }
    vec2 f = fract(p);
    ivec2 i = ivec2(floor(p));
    vec4 a = texel(t, i.x, i.y), b = texel(t, i.x + 1, i.y);
    vec4 c = texel(t, i.x, i.y + 1), d = texel(t, i.x + 1, i.y + 1);
    if (srgb) { a = srgb_to_linear(a); b = srgb_to_linear(b); c = srgb_to_linear(c); d = srgb_to_linear(d); }
    return mix(mix(a, b, f.x), mix(c, d, f.x), f.y);
}

#ifdef TEXTURE_LOD
// The mip levels stored after a texture's image (GpuTexture::wrap >> TEXTURE_MIPS_SHIFT).
uint texture_mips(Texture t) { return t.wrap >> 8; }

// The level `l` below `t`: stored after the one above, half its size on each axis (at least 1).
Texture texture_level(Texture t, uint l) {
    for (uint k = 0u; k < l; k++) {
        t.offset += t.width * t.height;
        t.width = max(t.width >> 1, 1u);
        t.height = max(t.height >> 1, 1u);
    }
    return t;
}
#endif

// Texture `index` at uv. `lod`: log2 of the lookup's footprint in UV units (-INF: a point),
// which with TEXTURE_LOD picks the mip level whose texels are that wide, blending the two
// nearest (trilinear); without, the image itself is read.
vec4 sample_texture(int index, vec2 uv, float lod, bool srgb) {
    Texture t = texture_at(index);
#ifdef TEXTURE_LOD
    float level = lod + 0.5 * log2(float(t.width) * float(t.height));
    if (level > 0.0 && texture_mips(t) > 0u) {
        level = min(level, float(texture_mips(t)));
        uint l = uint(level);
        float f = level - float(l);
        Texture above = texture_level(t, l);
        vec4 c = sample_level(above, uv, srgb);
        if (f > 0.0) c = mix(c, sample_level(texture_level(above, 1u), uv, srgb), f);
        return c;
    }
#endif
    return sample_level(t, uv, srgb);
}

// What a triangle's vertices give a point at barycentrics b: TEXCOORD_0, TEXCOORD_1 and COLOR_0
// (white without HAS_VERTEX_COLORS). TEXCOORD_1 is read only for materials that use it
// (MATERIAL_USES_UV1): the vertex extras exist whenever one does.
// With TEXTURE_LOD, the lookups' footprints at either UV set (log2, in UV units; -INF: a
// point, the image itself), which surface_at sets from the ray cone.
struct VertexAttributes {
    vec2 uv; vec2 uv1; vec4 color;
#ifdef TEXTURE_LOD
    float lod; float lod1;
#endif
};

vec4 unpack_color(uvec2 c) { return vec4(unpackUnorm2x16(c.x), unpackUnorm2x16(c.y)); }

// From the triangle's vertices as loaded (surface_at reads them for its normals too).
VertexAttributes vertex_attributes(Triangle T, Vertex v0, Vertex v1, Vertex v2, Material m, vec3 b) {
    VertexAttributes a;
    a.uv = b.x * vec2(v0.position_u.w, v0.normal_v.w) + b.y * vec2(v1.position_u.w, v1.normal_v.w) + b.z * vec2(v2.position_u.w, v2.normal_v.w);
    a.uv1 = vec2(0.0);
    a.color = vec4(1.0);
#ifdef TEXTURE_LOD
    a.lod = -INF;
    a.lod1 = -INF;
#endif
#if defined(HAS_VERTEX_COLORS) || defined(HAS_UV_TRANSFORMS)
#ifndef HAS_VERTEX_COLORS
    if ((m.textures1.w & MATERIAL_USES_UV1) != 0)
#endif
    {
        VertexExtra e0 = vertex_extra_at(T.v.x), e1 = vertex_extra_at(T.v.y), e2 = vertex_extra_at(T.v.z);
        a.uv1 = b.x * e0.uv1 + b.y * e1.uv1 + b.z * e2.uv1;
#ifdef HAS_VERTEX_COLORS
        a.color = b.x * unpack_color(e0.color) + b.y * unpack_color(e1.color) + b.z * unpack_color(e2.color);
#endif
    }
#endif
    return a;
}

VertexAttributes vertex_attributes(Triangle T, Material m, vec3 b) {
    return vertex_attributes(T, vertex_at(T.v.x), vertex_at(T.v.y), vertex_at(T.v.z), m, b);
}

// The UV at which material m reads texture slot `slot` (TEXTURE_SLOT_*): its UV set through its
// KHR_texture_transform.
vec2 slot_uv(Material m, int slot, VertexAttributes a) {
#ifdef HAS_UV_TRANSFORMS
    vec4 r0 = m.uv_rows[2 * slot], r1 = m.uv_rows[2 * slot + 1];
    vec3 uv = vec3(r0.w > 0.5 ? a.uv1 : a.uv, 1.0);
    return vec2(dot(r0.xyz, uv), dot(r1.xyz, uv));
#else
    return a.uv;
#endif
}

// log2 of the footprint of slot `slot`'s lookups: its UV set's, scaled by its
// KHR_texture_transform (the square root of the area the transform maps a unit square to).
float slot_lod(Material m, int slot, VertexAttributes a) {
#ifndef TEXTURE_LOD
    return -INF;
#elif defined(HAS_UV_TRANSFORMS)
    vec4 r0 = m.uv_rows[2 * slot], r1 = m.uv_rows[2 * slot + 1];
    float det = abs(r0.x * r1.y - r0.y * r1.x);
    return (r0.w > 0.5 ? a.lod1 : a.lod) + 0.5 * log2(max(det, 1e-30));
#else
    return a.lod;
#endif
}

// Texture `index` as material m's slot `slot` reads it at the point of `a`.
vec4 sample_slot(Material m, int index, int slot, VertexAttributes a, bool srgb) {
    return sample_texture(index, slot_uv(m, slot, a), slot_lod(m, slot, a), srgb);
}

// Alpha: the base colour's times its texture's and the vertex colour's.
float material_alpha(Material m, VertexAttributes a) {
    float alpha = m.base_color.a * a.color.a;
#ifdef HAS_BASE_COLOR_TEXTURES
    if (m.textures0.x >= 0) alpha *= sample_slot(m, m.textures0.x, TEXTURE_SLOT_BASE_COLOR, a, true).a;
#endif
    return alpha;
}

// The chance that a ray meets the surface there: 1 when opaque, 0 or 1 by the cutoff with
// alphaMode MASK, alpha itself with BLEND (stochastic transparency).
float material_coverage(Material m, VertexAttributes a) {
    int flags = m.textures1.w;
    if ((flags & (MATERIAL_ALPHA_MASK | MATERIAL_ALPHA_BLEND)) == 0) return 1.0;
    float alpha = material_alpha(m, a);
    if ((flags & MATERIAL_ALPHA_MASK) != 0) return alpha < m.misc.x ? 0.0 : 1.0;
    return alpha;
}
