#version 460
// Streaming path tracer, connection (path/stream/stream.glsl): each queued shadow ray of
// next-event estimation, any hit; its light joins its slot's when nothing blocks it.

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
    if (k >= ctl.shadow_count) return;
    SptShadow sh = shadows[k];
    uint i = floatBitsToUint(sh.dir.w);
    Hit blocker;
    bool blocked = trace(Ray(sh.origin.xyz, sh.dir.xyz, sh.origin.w), true, blocker);
    vec4 L = slots[i].L;
    if (!blocked) L.xyz += sh.light.xyz;
    slots[i].L = vec4(L.xyz, uintBitsToFloat(floatBitsToUint(L.w) + 1u));
}
