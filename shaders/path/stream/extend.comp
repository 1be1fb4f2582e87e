#version 460
// Streaming path tracer, extension (path/stream/stream.glsl): each live slot's ray to its
// closest hit. Nothing but the traversal, so SIMD lanes stay together in it.

layout(local_size_x = 64) in;

#include "common/scene.glsl"
#include "common/rng.glsl"
#include "common/sampling.glsl"
#include "common/textures.glsl"
#include "common/intersect.glsl"
#include "common/trace.glsl"
#include "common/surface.glsl"
#include "common/environment.glsl"
#include "common/bsdf.glsl"
#include "common/lights.glsl"
#include "path/path.glsl"
#include "path/stream/stream.glsl"

void main() {
    load_frame_constants();
    uint k = gl_GlobalInvocationID.x;
    if (k >= ctl.live_count) return;
    uint i = queue[live_queue() + k];
    vec4 origin = slots[i].origin;
    vec4 dir = slots[i].dir;
    Hit hit;
    bool found = trace(Ray(origin.xyz, dir.xyz, origin.w), false, hit);
    hits[k] = SptHit(vec4(hit.t, hit.b1, hit.b2, 0.0), uvec4(hit.instance, hit.triangle, found ? 1u : 0u, 0u));
}
