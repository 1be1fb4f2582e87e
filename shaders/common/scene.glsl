// Scene layout: mirrors crates/platoon-accel/src/layout.rs and the Globals block of
// crates/platoon-tracer/src/globals.rs. Every array has a buffer device address in Globals, so
// none is bound by the 128 MiB storage-buffer range of lavapipe; arrays that fit it are read
// through storage-buffer bindings instead (scene_arrays.glsl), which lavapipe loads much faster.
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require

struct Vertex { vec4 position_u; vec4 normal_v; vec4 tangent; };
// TEXCOORD_1 and COLOR_0 (RGBA, 16-bit unorms two to a uint): GpuVertexExtra.
struct VertexExtra { vec2 uv1; uvec2 color; };
struct Triangle { uvec3 v; uint material; };
// An inner BVH2 node with both children's boxes and items (crates/platoon-accel/src/bvh.rs): an
// item is (index << 4) | count, count 0 naming inner node `index`, else `count` primitives.
struct BvhNode { vec3 min0; uint item0; vec3 max0; uint pad0; vec3 min1; uint item1; vec3 max1; uint pad1; };
struct Instance { vec4 w2o[3]; vec4 o2w[3]; uint blas_root; uint light_base; uint pad0; uint pad1; };
// uv_rows: per texture slot (TEXTURE_SLOT_*), the UV transform's two rows; the first's w is the UV set.
struct Material {
    vec4 base_color; vec4 emissive; vec4 params; vec4 specular;
    ivec4 textures0; ivec4 textures1; vec4 misc;
    vec4 clearcoat;     // KHR_materials_clearcoat: factor, roughness, normal scale
    ivec4 textures2;    // clearcoat, clearcoat roughness, clearcoat normal, diffuse transmission textures
    vec4 diffuse_transmission;  // KHR_materials_diffuse_transmission: colour rgb, w = factor
    ivec4 textures3;    // diffuse transmission colour, sheen colour, sheen roughness, iridescence textures
    vec4 sheen;         // KHR_materials_sheen: colour rgb, w = roughness
    vec4 volume;        // KHR_materials_volume: absorption per unit length rgb, w = 1 with a volume
    ivec4 textures4;    // iridescence thickness, anisotropy textures
    vec4 iridescence;   // KHR_materials_iridescence: factor, ior, thickness minimum, maximum (nm)
    vec4 uv_rows[34];
};
struct Texture { uint offset; uint width; uint height; uint wrap; };
struct Light { vec4 a; vec4 b; vec4 c; vec4 emission; uvec4 ids; };

layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer Vertices { Vertex v[]; };
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer Vec4s { vec4 v[]; };
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer VertexExtras { VertexExtra v[]; };
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer Triangles { Triangle v[]; };
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer Uints { uint v[]; };
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer Floats { float v[]; };
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer Nodes { BvhNode v[]; };
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer Instances { Instance v[]; };
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer Materials { Material v[]; };
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer Textures { Texture v[]; };
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer Lights { Light v[]; };
layout(buffer_reference, std430, buffer_reference_align = 16) buffer Accum { vec4 v[]; };
// stats: [0] rejected (NaN/Inf) samples, [1] pixels whose megakernel pass was cut short by the
// device's loop limit (path/pathtrace.comp), [2..3] unused, [4 + y] rays traced in row y
layout(buffer_reference, std430, buffer_reference_align = 16) buffer Stats { uint v[]; };
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer Globals {
    Vertices vertices;
    Vec4s tri_pos;
    Triangles triangles;
    Uints tri_lights;
    Nodes blas;
    Nodes tlas;
    Instances instances;
    Materials materials;
    Textures textures;
    Uints texels;
    Lights lights;
    Floats light_cdf;
    Vec4s env_texels;
    Floats env_marginal;
    Floats env_conditional;
    Accum accum;
    Stats stats;
    // The rendering method's buffers (MethodPasses::prepare in crates/platoon-tracer/src/method):
    // each method's shaders name and type them (IGI: igi/igi.glsl).
    uint64_t method_buffer0;
    uint64_t method_buffer1;
    uint64_t method_buffer2;
    uint64_t method_buffer3;
    VertexExtras vertex_extras;  // (an even count of addresses: the camera starts a vec4)
    vec4 cam_origin;   // xyz, lens radius
    vec4 cam_right;    // unit right, w = tan(fov_y/2) * aspect
    vec4 cam_up;       // unit up, w = tan(fov_y/2)
    vec4 cam_forward;  // unit forward, w = focus distance
    vec4 env_color;    // rgb, w = integral of the env sampling function
    uvec4 dims;        // width, height, env width, env height
    uvec4 counts;      // lights, instances, top-level root item, env kind (0 none, 1 constant, 2 map)
    uvec4 params;      // frame (the options the kernel reads are push words, pc.frame_words)
    vec4 scene_sphere; // the scene's bounding sphere: centre, radius
    uvec4 crop;        // the frame's first pixel in the camera's image, that image's size
};

layout(push_constant) uniform Push {
    Globals g;
    uint y0;
    uint y1;
    // The band's pixels (row-major indices): it may start and end within a line.
    uint pixel_begin;
    uint pixel_end;
    uint sample_begin;
    uint sample_end;
    // Lines y0, y0 + stride, y0 + 2 * stride, ... below y1 (1: a contiguous band).
    uint stride;
    // What the kernel reads of the frame's options and path loop: read by the accessors of
    // generated/frame_words.glsl (a function per word, by its name there), which the
    // tracer makes from their tables (OPTION_WORDS, LOOP_WORDS: platoon-core's frame module).
    uint frame_words[8];
    // The rendering method's words (MethodPasses::push_words): each method's shaders name
    // them (IGI: igi/igi.glsl; the path tracer: path/path.glsl, path/world_cache.glsl and
    // common/lights.glsl's resampled light).
    uint method_words[9];
} pc;

#include "generated/frame_words.glsl"

#include "common/scene_arrays.glsl"

// Per-render constants, copied once per invocation from the frame block: Globals' constants
// (after its addresses, 176 bytes) bound as a uniform buffer (FRAME_BINDING in
// crates/platoon-tracer/src/memory.rs), which lavapipe loads once for all lanes, where a load
// through the buffer reference is a loop over the lanes one dword at a time (144 ns per lane
// for these nine vectors: a cost every invocation of the streaming kernels would pay).
// (Components are never read through the buffer reference: Mesa 22.3 lavapipe miscompiles a
// scalar access to a vector component behind one; pc.g.dims.z returned dims.x.)
layout(std140, set = 0, binding = 16) uniform FrameBlock {
    layout(offset = 176) vec4 cam_origin;
    vec4 cam_right;
    vec4 cam_up;
    vec4 cam_forward;
    vec4 env_color;
    uvec4 dims;
    uvec4 counts;
    uvec4 params;
    vec4 scene_sphere;
    uvec4 crop;
} frame_block;

struct FrameConstants {
    vec4 cam_origin; vec4 cam_right; vec4 cam_up; vec4 cam_forward; vec4 env_color;
    uvec4 dims; uvec4 counts; uvec4 params; vec4 scene_sphere; uvec4 crop;
};
FrameConstants F;

void load_frame_constants() {
    F.cam_origin = frame_block.cam_origin;
    F.cam_right = frame_block.cam_right;
    F.cam_up = frame_block.cam_up;
    F.cam_forward = frame_block.cam_forward;
    F.env_color = frame_block.env_color;
    F.dims = frame_block.dims;
    F.counts = frame_block.counts;
    F.params = frame_block.params;
    F.scene_sphere = frame_block.scene_sphere;
    F.crop = frame_block.crop;
}

const float PI = 3.14159265358979323846;
const float INV_PI = 0.31830988618379067154;
const float INF = 1.0 / 0.0;

// The per-render constants by name (Globals' vectors pack them; crates/platoon-tracer/src/globals.rs).
uint light_count() { return F.counts.x; }
uint instance_count() { return F.counts.y; }
uint tlas_root() { return F.counts.z; }
uint env_kind() { return F.counts.w; }
uvec2 env_size() { return F.dims.zw; }
uint frame_index() { return F.params.x; }
// A frame pixel's place in the image the camera frames (a border render is a window of it,
// FrameParams::crop): camera rays and random numbers are the image pixel's.
uvec2 image_pixel(uvec2 pixel) { return pixel + F.crop.xy; }
vec2 image_size() { return vec2(F.crop.zw); }

// env_kind(): GpuEnvironment::kind (crates/platoon-accel/src/layout.rs).
const uint ENV_NONE = 0u;
const uint ENV_CONSTANT = 1u;
const uint ENV_MAP = 2u;

const uint LIGHT_TRIANGLE = 0u;
const uint LIGHT_POINT = 1u;
const uint LIGHT_SPOT = 2u;
const uint LIGHT_DIRECTIONAL = 3u;
const uint LIGHT_ENVIRONMENT = 4u;

const int MATERIAL_DOUBLE_SIDED = 1;
const int MATERIAL_ALPHA_MASK = 2;
const int MATERIAL_ALPHA_BLEND = 4;
const int MATERIAL_UNLIT = 8;
const int MATERIAL_USES_UV1 = 16;
// The w of a triangle's first corner when its material lets light through by its alpha (Must
// match GPU side: flatten/layout.rs).
const float CORNER_ALPHA_TESTED = 1.0;
const int TEXTURE_SLOT_BASE_COLOR = 0;
const int TEXTURE_SLOT_METALLIC_ROUGHNESS = 1;
const int TEXTURE_SLOT_NORMAL = 2;
const int TEXTURE_SLOT_EMISSIVE = 3;
const int TEXTURE_SLOT_SPECULAR = 4;
const int TEXTURE_SLOT_SPECULAR_COLOR = 5;
const int TEXTURE_SLOT_TRANSMISSION = 6;
const int TEXTURE_SLOT_CLEARCOAT = 7;
const int TEXTURE_SLOT_CLEARCOAT_ROUGHNESS = 8;
const int TEXTURE_SLOT_CLEARCOAT_NORMAL = 9;
const int TEXTURE_SLOT_DIFFUSE_TRANSMISSION = 10;
const int TEXTURE_SLOT_DIFFUSE_TRANSMISSION_COLOR = 11;
const int TEXTURE_SLOT_SHEEN_COLOR = 12;
const int TEXTURE_SLOT_SHEEN_ROUGHNESS = 13;
const int TEXTURE_SLOT_IRIDESCENCE = 14;
const int TEXTURE_SLOT_IRIDESCENCE_THICKNESS = 15;
const int TEXTURE_SLOT_ANISOTROPY = 16;

float max3(vec3 v) { return max(v.x, max(v.y, v.z)); }
float min3(vec3 v) { return min(v.x, min(v.y, v.z)); }
float luminance(vec3 c) { return dot(c, vec3(0.2126, 0.7152, 0.0722)); }

// The band pixel of this invocation and its row-major index; false outside the band.
bool band_pixel(out uvec2 pixel, out uint index) {
    pixel = uvec2(gl_GlobalInvocationID.x, pc.y0 + gl_GlobalInvocationID.y * pc.stride);
    uint width = F.dims.x;
    index = pixel.y * width + pixel.x;
    // Sample indices may wrap past 2^32 (a view converging for days): compare for equality.
    if (pixel.x >= width || pixel.y >= pc.y1 || pc.sample_begin == pc.sample_end) return false;
    return index >= pc.pixel_begin && index < pc.pixel_end;
}
