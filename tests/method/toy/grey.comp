#version 460
// The toy method "grey" (tests/method/toy/grey.rs), brought from outside platoon's crates: after
// a band's path-tracing passes, each pixel's sums moved towards their luminance at the
// method's strength (push word 0). Linear, so the same on sums as on means, and per pixel, so
// the same on any split between devices. It includes shaders/'s files like a built-in kernel.

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

#include "common/scene.glsl"

void main() {
    load_frame_constants();
    uvec2 pixel;
    uint index;
    if (!band_pixel(pixel, index)) return;
    // A whole vec4 through the reference (scene.glsl: lavapipe 22.3 and component reads).
    vec4 sums = pc.g.accum.v[index];
    float strength = uintBitsToFloat(pc.method_words[0]);
    vec3 grey = vec3(luminance(sums.rgb));
    pc.g.accum.v[index] = vec4((1.0 - strength) * sums.rgb + strength * grey, sums.w);
}
