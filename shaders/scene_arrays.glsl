// The read-only scene arrays, each read through a storage-buffer binding (SSBO_<NAME> defined:
// the array fits the device's storage-buffer range) or through its buffer device address in
// Globals. The tracer decides per array (crates/platoon-tracer/src/memory.rs, whose SCENE_ARRAYS
// order is the binding order here: must match). Code reads NAME[i] either way.

#ifdef SSBO_VERTICES
layout(std430, set = 0, binding = 0) readonly buffer VerticesSsbo { Vertex vertices_ssbo[]; };
#define VERTICES vertices_ssbo
#else
#define VERTICES pc.g.vertices.v
#endif
#ifdef SSBO_TRI_POS
layout(std430, set = 0, binding = 1) readonly buffer TriPosSsbo { vec4 tri_pos_ssbo[]; };
#define TRI_POS tri_pos_ssbo
#else
#define TRI_POS pc.g.tri_pos.v
#endif
#ifdef SSBO_TRIANGLES
layout(std430, set = 0, binding = 2) readonly buffer TrianglesSsbo { Triangle triangles_ssbo[]; };
#define TRIANGLES triangles_ssbo
#else
#define TRIANGLES pc.g.triangles.v
#endif
#ifdef SSBO_TRI_LIGHTS
layout(std430, set = 0, binding = 3) readonly buffer TriLightsSsbo { uint tri_lights_ssbo[]; };
#define TRI_LIGHTS tri_lights_ssbo
#else
#define TRI_LIGHTS pc.g.tri_lights.v
#endif
#ifdef SSBO_BLAS
layout(std430, set = 0, binding = 4) readonly buffer BlasSsbo { BvhNode blas_ssbo[]; };
#define BLAS blas_ssbo
#else
#define BLAS pc.g.blas.v
#endif
#ifdef SSBO_TLAS
layout(std430, set = 0, binding = 5) readonly buffer TlasSsbo { BvhNode tlas_ssbo[]; };
#define TLAS tlas_ssbo
#else
#define TLAS pc.g.tlas.v
#endif
#ifdef SSBO_INSTANCES
layout(std430, set = 0, binding = 6) readonly buffer InstancesSsbo { Instance instances_ssbo[]; };
#define INSTANCES instances_ssbo
#else
#define INSTANCES pc.g.instances.v
#endif
#ifdef SSBO_MATERIALS
layout(std430, set = 0, binding = 7) readonly buffer MaterialsSsbo { Material materials_ssbo[]; };
#define MATERIALS materials_ssbo
#else
#define MATERIALS pc.g.materials.v
#endif
#ifdef SSBO_TEXTURES
layout(std430, set = 0, binding = 8) readonly buffer TexturesSsbo { Texture textures_ssbo[]; };
#define TEXTURES textures_ssbo
#else
#define TEXTURES pc.g.textures.v
#endif
#ifdef SSBO_TEXELS
layout(std430, set = 0, binding = 9) readonly buffer TexelsSsbo { uint texels_ssbo[]; };
#define TEXELS texels_ssbo
#else
#define TEXELS pc.g.texels.v
#endif
#ifdef SSBO_LIGHTS
layout(std430, set = 0, binding = 10) readonly buffer LightsSsbo { Light lights_ssbo[]; };
#define LIGHTS lights_ssbo
#else
#define LIGHTS pc.g.lights.v
#endif
#ifdef SSBO_LIGHT_CDF
layout(std430, set = 0, binding = 11) readonly buffer LightCdfSsbo { float light_cdf_ssbo[]; };
#define LIGHT_CDF light_cdf_ssbo
#else
#define LIGHT_CDF pc.g.light_cdf.v
#endif
#ifdef SSBO_ENV_TEXELS
layout(std430, set = 0, binding = 12) readonly buffer EnvTexelsSsbo { vec4 env_texels_ssbo[]; };
#define ENV_TEXELS env_texels_ssbo
#else
#define ENV_TEXELS pc.g.env_texels.v
#endif
#ifdef SSBO_ENV_MARGINAL
layout(std430, set = 0, binding = 13) readonly buffer EnvMarginalSsbo { float env_marginal_ssbo[]; };
#define ENV_MARGINAL env_marginal_ssbo
#else
#define ENV_MARGINAL pc.g.env_marginal.v
#endif
#ifdef SSBO_ENV_CONDITIONAL
layout(std430, set = 0, binding = 14) readonly buffer EnvConditionalSsbo { float env_conditional_ssbo[]; };
#define ENV_CONDITIONAL env_conditional_ssbo
#else
#define ENV_CONDITIONAL pc.g.env_conditional.v
#endif
