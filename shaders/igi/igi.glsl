// What IGI's kernels share (crates/platoon-core/src/method/igi, crates/platoon-tracer/src/method/igi.rs):
// its buffers, the method's buffers of Globals, and its options, the method's push-constant words.
// Included after common/scene.glsl.

// IGI's virtual point lights (igi/emit.comp), its gathering vertices (igi/camera.comp) and, with
// IGI_FILTERED, three vec4 per pixel for the filters after assembly (IgiTexel in
// crates/platoon-core/src/method/igi/mod.rs).
struct Vpl { vec4 position; vec4 normal; vec4 power; };
layout(buffer_reference, std430, buffer_reference_align = 16) buffer Vpls { Vpl v[]; };
// IGI's gathering vertex of a pixel's current sample: what the camera pass leaves for the gather
// passes, in world space on the side the path arrived from (igi/camera.comp says why deferred).
struct IgiVertex {
    vec4 position;  // xyz, w: coordinate magnitude (offset_ray)
    vec4 ns;        // shading normal, xyz; w: the specular layer's weight
    vec4 ng;        // geometric normal, xyz; w: 1 when the sample has a vertex to gather at
    vec4 wo;        // direction back along the path, xyz
    vec4 albedo;    // path throughput x dielectric weight x base colour, xyz
    vec4 f0;        // the specular layer's f0, xyz
};
layout(buffer_reference, std430, buffer_reference_align = 16) buffer IgiVertices { IgiVertex v[]; };


// Globals' method buffers as IGI's: VPLs, texels (with IGI_FILTERED), gathering vertices.
#define IGI_VPLS Vpls(pc.g.method_buffer0)
#define IGI_TEXELS Accum(pc.g.method_buffer1)
#define IGI_VERTICES IgiVertices(pc.g.method_buffer2)

// The push constants' method words as IGI's options (IgiPasses::push_words): light paths and
// VPLs per path, the bounded geometry term's minimum distance, the gather grid's cell size, the
// interleaving tile, and the VPL slots [vpl_first, vpl_end) a gather pass takes.
uint vpl_paths() { return pc.method_words[0]; }
uint vpl_bounces() { return pc.method_words[1]; }
float vpl_min_distance() { return uintBitsToFloat(pc.method_words[2]); }
uint igi_downsample() { return pc.method_words[3]; }
uvec2 igi_tile() { return uvec2(pc.method_words[4], pc.method_words[5]); }
uint vpl_first() { return pc.method_words[6]; }
uint vpl_end() { return pc.method_words[7]; }
