#version 460
// Streaming path tracer (path/stream/stream.glsl): lists the band's pixels that the megakernel
// flagged (accumulation w = PIXEL_CUT_SHORT: its pass ran past the device's loop limit, path/pathtrace.comp),
// clearing the flags, so that a listed pass renders their samples.

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
    uint c = gl_GlobalInvocationID.x;
    if (c >= cell_count()) return;
    uint p = band_cell_pixel(c);
    vec4 a = pc.g.accum.v[p];
    if (a.w != PIXEL_CUT_SHORT) return;
    pc.g.accum.v[p] = vec4(a.xyz, 0.0);
    listed_pixels[atomicAdd(ctl.listed, 1u)] = p;
}
