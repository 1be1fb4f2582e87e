// The read-only scene arrays. Code reads element i of an array through its accessor
// (blas_at(i), vertex_at(i), ...), whatever the array's memory path, which the tracer chooses per
// array (crates/platoon-tracer/src/memory.rs, whose SCENE_ARRAYS order is the binding order here):
//   TEXEL_<NAME>: a uniform texel buffer of 32-bit uints (R32G32B32A32_UINT, or R32_UINT for
//       arrays of scalars), unpacked into the struct bit for bit. llvmpipe fetches texels with
//       straight-line vector loads, where a storage-buffer load is a loop over the SIMD lanes.
//   SSBO_<NAME>: a storage-buffer binding.
//   neither: the array's buffer device address in Globals (no size limit).

#define ADDRESS_ARRAY(T, at, field) \
    T at(uint i) { return pc.g.field.v[i]; }
#define STORAGE_ARRAY(T, at, b) \
    layout(std430, set = 0, binding = b) readonly buffer at##_block { T at##_v[]; }; \
    T at(uint i) { return at##_v[i]; }
#define TEXEL_ARRAY(T, at, b, unpack) \
    layout(set = 0, binding = b) uniform utextureBuffer at##_texels; \
    T at(uint i) { return unpack(at##_texels, i); }

vec4 fetch_vec4(utextureBuffer t, uint i) { return uintBitsToFloat(texelFetch(t, int(i))); }
uint unpack_uint(utextureBuffer t, uint i) { return texelFetch(t, int(i)).x; }
float unpack_float(utextureBuffer t, uint i) { return uintBitsToFloat(texelFetch(t, int(i)).x); }
vec4 unpack_vec4(utextureBuffer t, uint i) { return fetch_vec4(t, i); }
Vertex unpack_vertex(utextureBuffer t, uint i) {
    return Vertex(fetch_vec4(t, 3u * i), fetch_vec4(t, 3u * i + 1u), fetch_vec4(t, 3u * i + 2u));
}
Triangle unpack_triangle(utextureBuffer t, uint i) {
    uvec4 a = texelFetch(t, int(i));
    return Triangle(a.xyz, a.w);
}
BvhNode unpack_node(utextureBuffer t, uint i) {
    uvec4 a = texelFetch(t, int(4u * i)), b = texelFetch(t, int(4u * i + 1u));
    uvec4 c = texelFetch(t, int(4u * i + 2u)), d = texelFetch(t, int(4u * i + 3u));
    return BvhNode(uintBitsToFloat(a.xyz), a.w, uintBitsToFloat(b.xyz), b.w,
                   uintBitsToFloat(c.xyz), c.w, uintBitsToFloat(d.xyz), d.w);
}
Instance unpack_instance(utextureBuffer t, uint i) {
    uint b = 7u * i;
    uvec4 ids = texelFetch(t, int(b + 6u));
    return Instance(vec4[3](fetch_vec4(t, b), fetch_vec4(t, b + 1u), fetch_vec4(t, b + 2u)),
                    vec4[3](fetch_vec4(t, b + 3u), fetch_vec4(t, b + 4u), fetch_vec4(t, b + 5u)),
                    ids.x, ids.y, ids.z, ids.w);
}
Material unpack_material(utextureBuffer t, uint i) {
    uint b = 49u * i;
    // Written out: llvmpipe counts every loop iteration of an invocation against one limit.
    vec4 rows[34] = vec4[34](fetch_vec4(t, b + 15u), fetch_vec4(t, b + 16u), fetch_vec4(t, b + 17u), fetch_vec4(t, b + 18u), fetch_vec4(t, b + 19u), fetch_vec4(t, b + 20u), fetch_vec4(t, b + 21u), fetch_vec4(t, b + 22u), fetch_vec4(t, b + 23u), fetch_vec4(t, b + 24u), fetch_vec4(t, b + 25u), fetch_vec4(t, b + 26u), fetch_vec4(t, b + 27u), fetch_vec4(t, b + 28u), fetch_vec4(t, b + 29u), fetch_vec4(t, b + 30u), fetch_vec4(t, b + 31u), fetch_vec4(t, b + 32u), fetch_vec4(t, b + 33u), fetch_vec4(t, b + 34u), fetch_vec4(t, b + 35u), fetch_vec4(t, b + 36u), fetch_vec4(t, b + 37u), fetch_vec4(t, b + 38u), fetch_vec4(t, b + 39u), fetch_vec4(t, b + 40u), fetch_vec4(t, b + 41u), fetch_vec4(t, b + 42u), fetch_vec4(t, b + 43u), fetch_vec4(t, b + 44u), fetch_vec4(t, b + 45u), fetch_vec4(t, b + 46u), fetch_vec4(t, b + 47u), fetch_vec4(t, b + 48u));
    return Material(fetch_vec4(t, b), fetch_vec4(t, b + 1u), fetch_vec4(t, b + 2u), fetch_vec4(t, b + 3u),
                    ivec4(texelFetch(t, int(b + 4u))), ivec4(texelFetch(t, int(b + 5u))), fetch_vec4(t, b + 6u),
                    fetch_vec4(t, b + 7u), ivec4(texelFetch(t, int(b + 8u))),
                    fetch_vec4(t, b + 9u), ivec4(texelFetch(t, int(b + 10u))), fetch_vec4(t, b + 11u), fetch_vec4(t, b + 12u),
                    ivec4(texelFetch(t, int(b + 13u))), fetch_vec4(t, b + 14u), rows);
}
VertexExtra unpack_vertex_extra(utextureBuffer t, uint i) {
    uvec4 a = texelFetch(t, int(i));
    return VertexExtra(uintBitsToFloat(a.xy), a.zw);
}
Texture unpack_texture(utextureBuffer t, uint i) {
    uvec4 a = texelFetch(t, int(i));
    return Texture(a.x, a.y, a.z, a.w);
}
Light unpack_light(utextureBuffer t, uint i) {
    uint b = 5u * i;
    return Light(fetch_vec4(t, b), fetch_vec4(t, b + 1u), fetch_vec4(t, b + 2u), fetch_vec4(t, b + 3u),
                 texelFetch(t, int(b + 4u)));
}

#if defined(TEXEL_VERTICES)
TEXEL_ARRAY(Vertex, vertex_at, 0, unpack_vertex)
#elif defined(SSBO_VERTICES)
STORAGE_ARRAY(Vertex, vertex_at, 0)
#else
ADDRESS_ARRAY(Vertex, vertex_at, vertices)
#endif

#if defined(TEXEL_TRI_POS)
TEXEL_ARRAY(vec4, tri_pos_at, 1, unpack_vec4)
#elif defined(SSBO_TRI_POS)
STORAGE_ARRAY(vec4, tri_pos_at, 1)
#else
ADDRESS_ARRAY(vec4, tri_pos_at, tri_pos)
#endif

#if defined(TEXEL_TRIANGLES)
TEXEL_ARRAY(Triangle, triangle_at, 2, unpack_triangle)
#elif defined(SSBO_TRIANGLES)
STORAGE_ARRAY(Triangle, triangle_at, 2)
#else
ADDRESS_ARRAY(Triangle, triangle_at, triangles)
#endif

#if defined(TEXEL_TRI_LIGHTS)
TEXEL_ARRAY(uint, tri_light_at, 3, unpack_uint)
#elif defined(SSBO_TRI_LIGHTS)
STORAGE_ARRAY(uint, tri_light_at, 3)
#else
ADDRESS_ARRAY(uint, tri_light_at, tri_lights)
#endif

#if defined(TEXEL_BLAS)
TEXEL_ARRAY(BvhNode, blas_at, 4, unpack_node)
#elif defined(SSBO_BLAS)
STORAGE_ARRAY(BvhNode, blas_at, 4)
#else
ADDRESS_ARRAY(BvhNode, blas_at, blas)
#endif

#if defined(TEXEL_TLAS)
TEXEL_ARRAY(BvhNode, tlas_at, 5, unpack_node)
#elif defined(SSBO_TLAS)
STORAGE_ARRAY(BvhNode, tlas_at, 5)
#else
ADDRESS_ARRAY(BvhNode, tlas_at, tlas)
#endif

#if defined(TEXEL_INSTANCES)
TEXEL_ARRAY(Instance, instance_at, 6, unpack_instance)
#elif defined(SSBO_INSTANCES)
STORAGE_ARRAY(Instance, instance_at, 6)
#else
ADDRESS_ARRAY(Instance, instance_at, instances)
#endif

#if defined(TEXEL_MATERIALS)
TEXEL_ARRAY(Material, material_at, 7, unpack_material)
#elif defined(SSBO_MATERIALS)
STORAGE_ARRAY(Material, material_at, 7)
#else
ADDRESS_ARRAY(Material, material_at, materials)
#endif

#if defined(TEXEL_TEXTURES)
TEXEL_ARRAY(Texture, texture_at, 8, unpack_texture)
#elif defined(SSBO_TEXTURES)
STORAGE_ARRAY(Texture, texture_at, 8)
#else
ADDRESS_ARRAY(Texture, texture_at, textures)
#endif

#if defined(TEXEL_TEXELS)
TEXEL_ARRAY(uint, texel_at, 9, unpack_uint)
#elif defined(SSBO_TEXELS)
STORAGE_ARRAY(uint, texel_at, 9)
#else
ADDRESS_ARRAY(uint, texel_at, texels)
#endif

#if defined(TEXEL_LIGHTS)
TEXEL_ARRAY(Light, light_at, 10, unpack_light)
#elif defined(SSBO_LIGHTS)
STORAGE_ARRAY(Light, light_at, 10)
#else
ADDRESS_ARRAY(Light, light_at, lights)
#endif

#if defined(TEXEL_LIGHT_CDF)
TEXEL_ARRAY(float, light_cdf_at, 11, unpack_float)
#elif defined(SSBO_LIGHT_CDF)
STORAGE_ARRAY(float, light_cdf_at, 11)
#else
ADDRESS_ARRAY(float, light_cdf_at, light_cdf)
#endif

#if defined(TEXEL_ENV_TEXELS)
TEXEL_ARRAY(vec4, env_texel_at, 12, unpack_vec4)
#elif defined(SSBO_ENV_TEXELS)
STORAGE_ARRAY(vec4, env_texel_at, 12)
#else
ADDRESS_ARRAY(vec4, env_texel_at, env_texels)
#endif

#if defined(TEXEL_ENV_MARGINAL)
TEXEL_ARRAY(float, env_marginal_at, 13, unpack_float)
#elif defined(SSBO_ENV_MARGINAL)
STORAGE_ARRAY(float, env_marginal_at, 13)
#else
ADDRESS_ARRAY(float, env_marginal_at, env_marginal)
#endif

#if defined(TEXEL_ENV_CONDITIONAL)
TEXEL_ARRAY(float, env_conditional_at, 14, unpack_float)
#elif defined(SSBO_ENV_CONDITIONAL)
STORAGE_ARRAY(float, env_conditional_at, 14)
#else
ADDRESS_ARRAY(float, env_conditional_at, env_conditional)
#endif

#if defined(TEXEL_VERTEX_EXTRAS)
TEXEL_ARRAY(VertexExtra, vertex_extra_at, 15, unpack_vertex_extra)
#elif defined(SSBO_VERTEX_EXTRAS)
STORAGE_ARRAY(VertexExtra, vertex_extra_at, 15)
#else
ADDRESS_ARRAY(VertexExtra, vertex_extra_at, vertex_extras)
#endif
