#version 460
// The world cache's training paths (path/world_cache.glsl; crates/platoon-core/src/frame/
// world_cache.rs): in each frame one pixel in cache_train_stride() (a pattern fixed by the image
// pixel and the frame, so any split trains the same pixels) traces a path of its own random
// numbers, not reading the cache, and leaves in its record (method buffer 1, a vec4 per pixel of
// the frame) the key of its second vertex's cell and the light it gathered from there on per
// unit of throughput; zero where the pixel does not train or the path ended before going on
// from a second vertex. The beauty's estimator and options otherwise (the kernel variant's).

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

#undef WORLD_CACHE
#define WORLD_CACHE_TRAIN

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

// The training paths' sample index: one no beauty sample of a pixel reaches in practice, so
// their random numbers are their own.
const uint TRAIN_SAMPLE = 0xfffffff0u;

bool trains(uvec2 image) {
    return (pcg_hash(image.x ^ pcg_hash(image.y ^ 0x2545f491u)) + frame_index()) % cache_train_stride() == 0u;
}

void main() {
    load_frame_constants();
    uvec2 pixel;
    uint index;
    if (!band_pixel(pixel, index)) return;
    vec4 record = vec4(0.0);
    uint rays = 0u;
    if (trains(image_pixel(pixel))) {
        Rng rng = pixel_rng(pixel, TRAIN_SAMPLE);
        Path p = path_start(camera_ray(pixel, rng), TRAIN_SAMPLE);
        while (path_step(p, rng, rays)) {}
        vec3 light = p.L - p.cache_light;
        if (p.cache_key != 0u && all(greaterThan(p.cache_throughput, vec3(0.0)))) {
            vec3 radiance = light / p.cache_throughput;
            if (!any(isnan(radiance)) && !any(isinf(radiance)))
                record = vec4(uintBitsToFloat(p.cache_key), radiance);
        }
    }
    CacheRecords(pc.g.method_buffer1).v[index] = record;
    if (rays > 0u) atomicAdd(pc.g.stats.v[4u + pixel.y], rays);
}
