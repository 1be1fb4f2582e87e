// What vertex links' kernels share (crates/platoon-core/src/method/links, crates/platoon-tracer/src/method/links.rs):
// the elements a shooting or lighting frame reads (ElementRay in links/job.rs), the solution
// an image frame reads, and the method's push words. Included after common/scene.glsl.

struct ElementRay {
    vec4 origin;     // xyz: where its rays leave, lifted off the surface
    vec4 tangent;    // the element frame: tangent, bitangent, normal (xyz)
    vec4 bitangent;
    vec4 normal;
    uvec4 corner;    // instance, scene triangle, corner (0-2): where its material is read
    uvec4 fan;       // its fan's first entry and count in LINKS_FANS
};
layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer ElementRays { ElementRay v[]; };

layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer FanEntries { uvec4 v[]; };

// Shooting and lighting frames: the elements, the directions (shooting) or the elements' fans
// (lighting: triangle, the element's corner, cumulative area as float bits), the per-pixel
// output read back (a ray's hit, or an element's albedo).
#define LINKS_ELEMENTS ElementRays(pc.g.method_buffer0)
#define LINKS_DIRECTIONS Vec4s(pc.g.method_buffer1)
#define LINKS_FANS FanEntries(pc.g.method_buffer1)
#define LINKS_OUTPUT Accum(pc.g.method_buffer2)
// Image frames: the indirect irradiance of every element (xyz), and the table of each
// instance's first element followed by each scene vertex's element within its mesh.
#define LINKS_IRRADIANCE Vec4s(pc.g.method_buffer0)
#define LINKS_TABLE Uints(pc.g.method_buffer1)

// Push words (LinksPasses::push_words): the frame's element count (shooting, lighting) and
// whether its entries are single rays (shooting); the
// solution's instance count (image frames: where the table's vertices start), its table's and
// its irradiance's lengths (a solution of another scene reads nothing out of bounds).
uint links_elements() { return pc.method_words[0]; }
bool links_single_rays() { return pc.method_words[1] != 0u; }
uint links_instances() { return pc.method_words[0]; }
uint links_table_length() { return pc.method_words[1]; }
uint links_irradiance_length() { return pc.method_words[2]; }
