#version 460
// Streaming path tracer, shading (path/stream/stream.glsl): each live slot's vertex by the
// megakernel's path_shade (emission, next-event estimation, BSDF sample, roulette), its shadow
// ray queued for connect.comp; an ended slot joins the ended queue.

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
    SptSlot s = slots[i];
    SptHit h = hits[k];
    Path p = unpack_path(s);
    Rng rng = Rng(s.info.w);
    ShadowRay shadow;
#ifdef LIGHT_REUSE
    reuse_pixel = s.info.y;
#endif
    bool going = path_shade(p, h.ids.z != 0u, Hit(h.tb.x, h.tb.y, h.tb.z, h.ids.x, h.ids.y), rng, shadow);
    // The ray extend.comp traced counts here.
    store_path(i, p, going ? SLOT_LIVE : SLOT_ENDED, s.info.y, rng, floatBitsToUint(s.L.w) + 1u);
    uint at;
    QUEUE_APPEND(ctl.ended_appended, !going, at);
    if (!going) queue[ended_queue() + at] = i;
    QUEUE_APPEND(ctl.shadow_appended, shadow.valid, at);
    if (shadow.valid)
        shadows[at] = SptShadow(vec4(shadow.ray.origin, shadow.ray.tmax), vec4(shadow.ray.dir, uintBitsToFloat(i)), vec4(shadow.light, 0.0));
}
