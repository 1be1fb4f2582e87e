#version 460
// Streaming path tracer, regeneration (path/stream/stream.glsl), over the ended slots (every
// slot, fresh, at a pass's start): an ended path's light is added to its pixel (NaN/Inf samples
// are counted and dropped, as the megakernel does), then the pixel's next sample starts, or
// the slot claims the band's next pixel (not a converged one), or retires.

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
    uint i;
    if (regenerate_all()) {
        if (k >= slot_count()) return;
        i = k;
    } else {
        if (k >= ctl.ended_count) return;
        i = queue[ended_queue() + k];
    }
    SptSlot s = slots[i];
    uint width = F.dims.x;
    uint pixel_index = s.info.y;
    uint sample_index = s.info.z;
    uint rays = floatBitsToUint(s.L.w);
    bool next_sample = false;
    if (slot_state(s) == SLOT_ENDED) {
        if (any(isnan(s.L.xyz)) || any(isinf(s.L.xyz))) atomicAdd(pc.g.stats.v[0], 1u);
        else pc.g.accum.v[pixel_index] += vec4(s.L.xyz, 0.0);
        // Sample indices may wrap past 2^32 (a view converging for days): compare for equality.
        next_sample = ++sample_index != pc.sample_end;
        if (!next_sample) {
            atomicAdd(pc.g.stats.v[4u + pixel_index / width], rays);
            rays = 0u;
        }
    }
    if (!next_sample) {
        // Adaptive sampling's converged pixels are passed over. (A while loop: the same claim
        // as a do-while lost other lanes' claims on llvmpipe, Mesa 22.3.)
        uint c = atomicAdd(ctl.next_cell, 1u);
        while (c < cell_count() && pc.g.accum.v[cell_pixel(c)].w == PIXEL_CONVERGED) {
            c = atomicAdd(ctl.next_cell, 1u);
        }
        if (c >= cell_count()) {
            slots[i].info = uvec4(SLOT_RETIRED, 0u, 0u, 0u);
            return;
        }
        pixel_index = cell_pixel(c);
        sample_index = pc.sample_begin;
    }
    uvec2 pixel = uvec2(pixel_index % width, pixel_index / width);
    Rng rng = pixel_rng(pixel, sample_index);
    Path p = path_start(camera_ray(pixel, rng), sample_index);
    store_path(i, p, SLOT_LIVE, pixel_index, rng, rays);
}
