// The shading point of a hit: world position, normals, texture coordinates and the material
// inputs of the glTF BSDF with every texture applied.

struct Surface {
    vec3 position;
    vec3 ng;        // geometric normal, world, front side by winding (object handedness kept)
    vec3 ns;        // shading normal, on the same side as ng
    float magnitude; // bound on the triangle's world coordinates, for offset_ray
    VertexAttributes attr;
    uint material;
    vec3 base_color;
    float metallic;
    float roughness;
    float transmission;
    float ior;
    float specular;
    vec3 specular_color;
    vec3 emission;
    bool double_sided;
    bool unlit;      // KHR_materials_unlit: base_color is emitted, nothing reflected
#ifdef HAS_CLEARCOAT
    float clearcoat;            // KHR_materials_clearcoat's weight and roughness
    float clearcoat_roughness;
    vec3 clearcoat_normal;      // world; the interpolated normal unless the coat's own map
#endif
#ifdef HAS_DIFFUSE_TRANSMISSION
    float diffuse_transmission;         // KHR_materials_diffuse_transmission's share
    vec3 diffuse_transmission_color;
#endif
#ifdef HAS_SHEEN
    vec3 sheen_color;           // KHR_materials_sheen's colour and roughness
    float sheen_roughness;
#endif
#ifdef HAS_VOLUME
    bool volume;                // KHR_materials_volume: the inside is a medium
    vec3 absorption;            // its absorption per unit length
#endif
#ifdef HAS_ANISOTROPY
    float anisotropy;           // KHR_materials_anisotropy's strength and direction: world, in
    vec3 anisotropy_direction;  // the shading normal's plane (apply_material: tangent space)
#endif
#ifdef HAS_DISPERSION
    float dispersion;           // KHR_materials_dispersion's 20 / Abbe number (0: none, and
                                // none on a thin wall: the spec disperses in a volume)
#endif
#ifdef HAS_IRIDESCENCE
    float iridescence;          // KHR_materials_iridescence's strength, the film's index and
    float iridescence_ior;      // its thickness in nanometres
    float iridescence_thickness;
#endif
};

vec3 instance_point(Instance inst, vec3 p) {
    return vec3(dot(inst.o2w[0], vec4(p, 1.0)), dot(inst.o2w[1], vec4(p, 1.0)), dot(inst.o2w[2], vec4(p, 1.0)));
}
vec3 instance_vector(Instance inst, vec3 v) {
    return vec3(dot(inst.o2w[0].xyz, v), dot(inst.o2w[1].xyz, v), dot(inst.o2w[2].xyz, v));
}
// Bound on the world coordinates of object points whose coordinates are at most `a` in magnitude.
float instance_magnitude(Instance inst, float a) {
    vec3 row_sums = vec3(dot(abs(inst.o2w[0].xyz), vec3(1.0)), dot(abs(inst.o2w[1].xyz), vec3(1.0)), dot(abs(inst.o2w[2].xyz), vec3(1.0)));
    return max3(row_sums * a + abs(vec3(inst.o2w[0].w, inst.o2w[1].w, inst.o2w[2].w)));
}
// Normals transform by the inverse transpose: the world-to-object rows as columns.
vec3 instance_normal(Instance inst, vec3 n) {
    return inst.w2o[0].xyz * n.x + inst.w2o[1].xyz * n.y + inst.w2o[2].xyz * n.z;
}

// Material inputs at s.attr, shared by surface shading and emissive-light sampling.
void apply_material(inout Surface s, Material m) {
    s.base_color = m.base_color.rgb * s.attr.color.rgb;
    s.metallic = m.params.x;
    s.roughness = m.params.y;
    s.transmission = m.params.z;
    s.ior = m.params.w;
    s.specular = m.specular.w;
    s.specular_color = m.specular.rgb;
    s.emission = m.emissive.rgb;
    s.double_sided = (m.textures1.w & MATERIAL_DOUBLE_SIDED) != 0;
    s.unlit = false;
#ifdef HAS_CLEARCOAT
    s.clearcoat = m.clearcoat.x;
    s.clearcoat_roughness = m.clearcoat.y;
#endif
#ifdef HAS_DIFFUSE_TRANSMISSION
    s.diffuse_transmission = m.diffuse_transmission.w;
    s.diffuse_transmission_color = m.diffuse_transmission.rgb;
#endif
#ifdef HAS_SHEEN
    s.sheen_color = m.sheen.rgb;
    s.sheen_roughness = m.sheen.w;
#endif
#ifdef HAS_VOLUME
    s.volume = m.volume.w > 0.0;
    s.absorption = m.volume.rgb;
#endif
#ifdef HAS_ANISOTROPY
    s.anisotropy = m.misc.y;
    s.anisotropy_direction = vec3(cos(m.misc.z), sin(m.misc.z), 0.0);
#endif
#ifdef HAS_DISPERSION
    s.dispersion = m.volume.w > 0.0 ? m.misc.w : 0.0;
#endif
#ifdef HAS_IRIDESCENCE
    s.iridescence = m.iridescence.x;
    s.iridescence_ior = m.iridescence.y;
    s.iridescence_thickness = m.iridescence.w;
#endif
#ifdef HAS_UNLIT
    s.unlit = (m.textures1.w & MATERIAL_UNLIT) != 0;
#endif
#ifdef HAS_TEXTURES
    // Only the slots some material of the scene fills are compiled in (features.rs): on
    // llvmpipe an empty slot's fetch still runs, masked, at every shading point.
    VertexAttributes a = s.attr;
#ifdef HAS_BASE_COLOR_TEXTURES
    if (m.textures0.x >= 0) s.base_color *= sample_slot(m, m.textures0.x, TEXTURE_SLOT_BASE_COLOR, a, true).rgb;
#endif
#ifdef HAS_METALLIC_ROUGHNESS_TEXTURES
    if (m.textures0.y >= 0) {
        vec4 mr = sample_slot(m, m.textures0.y, TEXTURE_SLOT_METALLIC_ROUGHNESS, a, false);
        s.roughness *= mr.g;
        s.metallic *= mr.b;
    }
#endif
#ifdef HAS_EMISSIVE_TEXTURES
    if (m.textures0.w >= 0) s.emission *= sample_slot(m, m.textures0.w, TEXTURE_SLOT_EMISSIVE, a, true).rgb;
#endif
#ifdef HAS_SPECULAR_TEXTURES
    if (m.textures1.x >= 0) s.specular *= sample_slot(m, m.textures1.x, TEXTURE_SLOT_SPECULAR, a, false).a;
    if (m.textures1.y >= 0) s.specular_color *= sample_slot(m, m.textures1.y, TEXTURE_SLOT_SPECULAR_COLOR, a, true).rgb;
#endif
#ifdef HAS_TRANSMISSION_TEXTURES
    if (m.textures1.z >= 0) s.transmission *= sample_slot(m, m.textures1.z, TEXTURE_SLOT_TRANSMISSION, a, false).r;
#endif
#ifdef HAS_DIFFUSE_TRANSMISSION_TEXTURES
    if (m.textures2.w >= 0) s.diffuse_transmission *= sample_slot(m, m.textures2.w, TEXTURE_SLOT_DIFFUSE_TRANSMISSION, a, false).a;
    if (m.textures3.x >= 0) s.diffuse_transmission_color *= sample_slot(m, m.textures3.x, TEXTURE_SLOT_DIFFUSE_TRANSMISSION_COLOR, a, true).rgb;
#endif
#ifdef HAS_SHEEN_TEXTURES
    if (m.textures3.y >= 0) s.sheen_color *= sample_slot(m, m.textures3.y, TEXTURE_SLOT_SHEEN_COLOR, a, true).rgb;
    if (m.textures3.z >= 0) s.sheen_roughness *= sample_slot(m, m.textures3.z, TEXTURE_SLOT_SHEEN_ROUGHNESS, a, false).a;
#endif
#ifdef HAS_IRIDESCENCE_TEXTURES
    if (m.textures3.w >= 0) s.iridescence *= sample_slot(m, m.textures3.w, TEXTURE_SLOT_IRIDESCENCE, a, false).r;
    // Without a texture the film is the maximum thick.
    if (m.textures4.x >= 0) s.iridescence_thickness = mix(m.iridescence.z, m.iridescence.w, sample_slot(m, m.textures4.x, TEXTURE_SLOT_IRIDESCENCE_THICKNESS, a, false).g);
#endif
#ifdef HAS_ANISOTROPY_TEXTURES
    if (m.textures4.y >= 0) {
        // A direction in tangent space (red, green in [-1, 1]) turned by the rotation, and the
        // strength (blue) times the factor.
        vec3 t = sample_slot(m, m.textures4.y, TEXTURE_SLOT_ANISOTROPY, a, false).rgb;
        vec2 d = t.rg * 2.0 - 1.0;
        d = dot(d, d) > 1e-12 ? normalize(d) : vec2(1.0, 0.0);
        vec2 r = s.anisotropy_direction.xy;
        s.anisotropy_direction = vec3(r.x * d.x - r.y * d.y, r.y * d.x + r.x * d.y, 0.0);
        s.anisotropy *= t.b;
    }
#endif
#ifdef HAS_CLEARCOAT_TEXTURES
    if (m.textures2.x >= 0) s.clearcoat *= sample_slot(m, m.textures2.x, TEXTURE_SLOT_CLEARCOAT, a, false).r;
    if (m.textures2.y >= 0) s.clearcoat_roughness *= sample_slot(m, m.textures2.y, TEXTURE_SLOT_CLEARCOAT_ROUGHNESS, a, false).g;
#endif
#endif
#ifndef HAS_TRANSMISSION
    s.transmission = 0.0;
#endif
}

#if defined(HAS_NORMAL_MAPS) || defined(HAS_CLEARCOAT_TEXTURES)
// `n` turned by the tangent-space normal map `texture`, read as material m's slot `slot` at the
// point of `a` (its xy scaled by `scale`), in the frame of the interpolated tangent (object
// space `tangent`, made orthogonal to n) and the bitangent of handedness `sign`; n itself where
// the frame degenerates or the map would turn it below the geometric normal ng.
vec3 normal_mapped(vec3 n, vec3 ng, Instance inst, vec3 tangent, float sign, int texture, Material m, int slot, VertexAttributes a, float scale) {
    vec3 tw = instance_vector(inst, tangent);
    tw = tw - n * dot(n, tw);
    if (dot(tw, tw) <= 1e-12) return n;
    tw = normalize(tw);
    vec3 bw = cross(n, tw) * sign;
    vec3 tn = sample_slot(m, texture, slot, a, false).xyz * 2.0 - 1.0;
    tn.xy *= scale;
    vec3 mapped = tn.x * tw + tn.y * bw + tn.z * n;
    if (dot(mapped, mapped) <= 1e-12) return n;
    mapped = normalize(mapped);
    return dot(mapped, ng) > 0.0 ? mapped : n;
}
#endif

#ifdef TEXTURE_LOD
// log2 of the UV footprint of a ray cone `width` wide meeting a triangle of world area
// `world_area` (doubled) and UVs t0, t1, t2 at `cosine` to its normal, times the UV length per
// world length (the square root of the ratio of the triangle's areas). The cone leaves an
// ellipse of axes width and width / cosine; an isotropic level is chosen for their geometric
// mean (the circle of the same area): the major axis (Akenine-Möller et al.'s choice) blurs
// a grazing plane more than its supersampled image, the minor one aliases, and the mean is
// closest (tests/kernel/features.rs, the grazing checker: error 0.066 against 0.072 and 0.093).
// -INF for a cone of no width or a triangle without UV area.
float cone_lod(float world_area, vec2 t0, vec2 t1, vec2 t2, float width, float cosine) {
    vec2 e1 = t1 - t0, e2 = t2 - t0;
    float uv_area = abs(e1.x * e2.y - e2.x * e1.y);
    if (!(width > 0.0) || !(uv_area > 0.0) || !(world_area > 0.0)) return -INF;
    return log2(width / sqrt(max(cosine, 1e-8))) + 0.5 * log2(uv_area / world_area);
}
#endif

// The shading point of `hit`; with TEXTURE_LOD its textures read at the mip level of a ray cone
// `cone_width` wide there, met along `dir` (0: the image itself).
Surface surface_at(Hit hit, vec3 dir, float cone_width) {
    Surface s;
    Instance inst = instance_at(hit.instance);
    Triangle T = triangle_at(hit.triangle);
    float b0 = 1.0 - hit.b1 - hit.b2;
    vec3 p0 = tri_pos_at(3u * hit.triangle).xyz;
    vec3 p1 = tri_pos_at(3u * hit.triangle + 1u).xyz;
    vec3 p2 = tri_pos_at(3u * hit.triangle + 2u).xyz;
    // Barycentric interpolation is more accurate than origin + t * dir.
    s.position = instance_point(inst, b0 * p0 + hit.b1 * p1 + hit.b2 * p2);
    s.ng = normalize(instance_normal(inst, cross(p1 - p0, p2 - p0)));
    s.magnitude = instance_magnitude(inst, coordinate_magnitude(p0, p1, p2));
    Vertex v0 = vertex_at(T.v.x), v1 = vertex_at(T.v.y), v2 = vertex_at(T.v.z);
    Material m = material_at(T.material);
    s.attr = vertex_attributes(T, v0, v1, v2, m, vec3(b0, hit.b1, hit.b2));
#ifdef TEXTURE_LOD
    float world_area = length(cross(instance_vector(inst, p1 - p0), instance_vector(inst, p2 - p0)));
    float cosine = abs(dot(s.ng, dir));
    s.attr.lod = cone_lod(world_area, vec2(v0.position_u.w, v0.normal_v.w), vec2(v1.position_u.w, v1.normal_v.w),
                          vec2(v2.position_u.w, v2.normal_v.w), cone_width, cosine);
    s.attr.lod1 = s.attr.lod;
#ifdef HAS_UV_TRANSFORMS
    if ((m.textures1.w & MATERIAL_USES_UV1) != 0)
        s.attr.lod1 = cone_lod(world_area, vertex_extra_at(T.v.x).uv1, vertex_extra_at(T.v.y).uv1,
                               vertex_extra_at(T.v.z).uv1, cone_width, cosine);
#endif
#endif
    vec3 n = b0 * v0.normal_v.xyz + hit.b1 * v1.normal_v.xyz + hit.b2 * v2.normal_v.xyz;
    s.ns = dot(n, n) > 1e-12 ? normalize(instance_normal(inst, n)) : s.ng;
    if (dot(s.ns, s.ng) < 0.0) s.ns = -s.ns;
    s.material = T.material;
    apply_material(s, m);
#if defined(HAS_NORMAL_MAPS) || defined(HAS_CLEARCOAT_TEXTURES) || defined(HAS_ANISOTROPY)
    vec3 tangent = (b0 * v0.tangent + hit.b1 * v1.tangent + hit.b2 * v2.tangent).xyz;
    float sign = v0.tangent.w < 0.0 ? -1.0 : 1.0;
#endif
#ifdef HAS_CLEARCOAT
    // The coat has a normal map of its own, or none: not the base's.
    s.clearcoat_normal = s.ns;
#ifdef HAS_CLEARCOAT_TEXTURES
    if (m.textures2.z >= 0)
        s.clearcoat_normal = normal_mapped(s.ns, s.ng, inst, tangent, sign, m.textures2.z, m, TEXTURE_SLOT_CLEARCOAT_NORMAL, s.attr, m.clearcoat.z);
#endif
#endif
#ifdef HAS_NORMAL_MAPS
    if (m.textures0.z >= 0)
        s.ns = normal_mapped(s.ns, s.ng, inst, tangent, sign, m.textures0.z, m, TEXTURE_SLOT_NORMAL, s.attr, m.emissive.w);
#endif
#ifdef HAS_ANISOTROPY
    if (s.anisotropy > 0.0) {
        // Tangent space about the final shading normal; without tangents (a file without
        // TANGENT, UVs or a normal map to make them from) the shading frame's own.
        vec3 tw = instance_vector(inst, tangent);
        tw -= s.ns * dot(s.ns, tw);
        vec3 bw;
        if (dot(tw, tw) > 1e-12) {
            tw = normalize(tw);
            bw = cross(s.ns, tw) * sign;
        } else {
            make_frame(s.ns, tw, bw);
        }
        s.anisotropy_direction = s.anisotropy_direction.x * tw + s.anisotropy_direction.y * bw;
    }
#endif
    return s;
}

// The shading point of `hit`, its textures read at the image itself (what methods without a
// ray cone see).
Surface surface_at(Hit hit) {
    return surface_at(hit, vec3(0.0), 0.0);
}
