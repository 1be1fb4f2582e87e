#version 460
// Vertex links, a shooting frame: pixel (d, e) traces element e's ray in direction d (the
// element frame's fixed cosine directions), or, in a frame of single rays (revalidation's),
// pixel i traces entry i's one ray in direction fan.z; each leaves its closest hit for the CPU's reduction
// (instance and triangle as bits, b1, b2; instance ~0u where it leaves the scene). Back faces
// and the corners' elements are the reduction's (method/links/shoot_cpu.rs: link_of_hit), so
// the CPU's shooting and the devices' differ only in their traversal.

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

#include "common/scene.glsl"
#include "links/links.glsl"
#include "common/intersect.glsl"
#include "common/trace.glsl"

void main() {
    load_frame_constants();
    uvec2 pixel;
    uint index;
    if (!band_pixel(pixel, index)) return;
    bool single = links_single_rays();
    uint entry = single ? index : pixel.y;
    vec4 out_hit = vec4(uintBitsToFloat(~0u), uintBitsToFloat(~0u), 0.0, 0.0);
    if (entry >= links_elements()) {
        LINKS_OUTPUT.v[index] = out_hit;  // past the last single ray of the frame
        return;
    }
    ElementRay e = LINKS_ELEMENTS.v[entry];
    vec3 d = LINKS_DIRECTIONS.v[single ? e.fan.z : pixel.x].xyz;
    // As the CPU's ray_direction, unfused.
    precise vec3 dir = e.tangent.xyz * d.x + e.bitangent.xyz * d.y + e.normal.xyz * d.z;
    Hit hit;
    if (trace(Ray(e.origin.xyz, normalize(dir), INF), false, hit))
        out_hit = vec4(uintBitsToFloat(hit.instance), uintBitsToFloat(hit.triangle), hit.b1, hit.b2);
    LINKS_OUTPUT.v[index] = out_hit;
    atomicAdd(pc.g.stats.v[4u + pixel.y], 1u);
}
