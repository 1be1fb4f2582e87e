// The streaming path tracer's state (Bikker 2012, section 6.3.3, after van Antwerpen 2011): a
// stream of path slots in memory, each following one pixel's samples one at a time (so a pixel's
// sums are added in sample order, the same bits for any split of the frame), advanced by small
// kernels that each do one thing over queues compacted by atomic counters:
//   regenerate.comp  the ended slots (every slot at a pass's start): adds a path's light to its
//                    pixel, starts the pixel's next sample or claims the band's next pixel;
//   compact.comp     queues the live slots in slot order (neighbouring slots hold neighbouring
//                    pixels' paths: SIMD groups of coherent rays);
//   queue.comp       turns the queues' counters into indirect dispatch sizes;
//   extend.comp      each live slot's ray to its closest hit;
//   shade.comp       each live slot's vertex: emission, BSDF sample, NEE (queues a shadow ray);
//                    an ended slot joins the ended queue;
//   connect.comp     each queued shadow ray: adds its light when nothing blocks it.
// listed.comp lists the pixels whose megakernel pass was cut short by the device's loop limit
// (path/pathtrace.comp flags them), for a pass of these kernels over them alone.
// The estimator and random numbers are the megakernel's (path/path.glsl: path_shade): the two
// render the same image. Buffers: set 1, owned by crates/platoon-tracer/src/method/stream.rs.

// Slot states (SptSlot::info.x, low two bits).
const uint SLOT_FRESH = 0u;    // has no pixel: claims one at the next regeneration
const uint SLOT_LIVE = 1u;     // has a ray to extend
const uint SLOT_ENDED = 2u;    // its path ended: its light goes to its pixel at the next regeneration
const uint SLOT_RETIRED = 3u;  // no pixel left in the band

// One path in flight, packed (std430, 80 bytes; 96 with a medium or a wavelength: StreamSlot in
// method/stream.rs sizes the larger, so a scene without volumes moves no more than it needs).
struct SptSlot {
    vec4 origin;      // ray origin, tmax
    vec4 dir;         // ray direction, the BSDF pdf it was sampled with
    vec4 L;           // light gathered so far; w: rays traced for the pixel (uint bits)
    vec4 throughput;  // w: path depth (uint bits)
    uvec4 info;       // state | after_delta << 2 | diffuse bounces << 8, pixel index, sample, rng
#if defined(HAS_VOLUME) || defined(HAS_DISPERSION)
    vec4 medium;      // Path::medium, w: Path::wavelength
#endif
#if defined(LIGHT_PASS) || defined(TEXTURE_LOD)
    vec4 extra;       // x: Path::pass_share (a light pass's kernel), y: Path::cone (StreamSlot
                      // has room for it)
#endif
};
// The closest hit of the ray of live-queue entry k (32 bytes): (t, b1, b2, -), (instance,
// triangle, found, -).
struct SptHit { vec4 tb; uvec4 ids; };
// A queued shadow ray (48 bytes): origin + tmax, direction + its slot (uint bits), light.
struct SptShadow { vec4 origin; vec4 dir; vec4 light; };

layout(std430, set = 1, binding = 0) buffer SptSlots { SptSlot slots[]; };
layout(std430, set = 1, binding = 1) buffer SptHits { SptHit hits[]; };
layout(std430, set = 1, binding = 2) buffer SptShadows { SptShadow shadows[]; };
// The live queue at [0, n), the ended queue at [n, 2n) (n slots).
layout(std430, set = 1, binding = 3) buffer SptQueues { uint queue[]; };
layout(std430, set = 1, binding = 4) buffer SptControl {
    uvec4 extend_args;      // indirect dispatch over the live queue (x, 1, 1)
    uvec4 connect_args;     // ... over the shadow rays
    uvec4 regenerate_args;  // ... over the ended queue
    uint live_appended;     // entries appended to the live queue (reset as it is taken)
    uint ended_appended;
    uint shadow_appended;
    uint live_count;        // the live queue's length for extend and shade
    uint ended_count;       // the ended queue's length for regenerate
    uint shadow_count;      // shadow rays for connect
    uint next_cell;         // the band's next unclaimed pixel
    uint iterations;        // iterations that found live slots (what the host reads)
    uint listed;            // pixels listed by listed.comp
    uint pad1;
    uint pad2;
    uint pad3;
} ctl;
// The pixels of a listed pass (listed.comp): those the megakernel could not finish.
layout(std430, set = 1, binding = 5) buffer SptListed { uint listed_pixels[]; };

// Push words (pc.method_words, method/stream.rs).
uint slot_count() { return pc.method_words[0]; }
// Pixels of the band: with stride 1 the indices [pixel_begin, pixel_begin + cells); else whole
// lines y0, y0 + stride, ... (interleaved bands).
uint cell_count() { return pc.method_words[1]; }
// queue.comp's step: 0 after regeneration, 1 after shading.
uint queue_step() { return pc.method_words[2]; }
// Regeneration over every slot (a pass's first iteration) instead of the ended queue.
bool regenerate_all() { return pc.method_words[3] != 0u; }
// The pass's pixels are the listed ones (cell c: listed_pixels[c]) instead of the band's.
bool listed_pass() { return pc.method_words[4] != 0u; }

uint live_queue() { return 0u; }
uint ended_queue() { return slot_count(); }

const uint STREAM_GROUP = 64u;

// The pixel index of band cell c.
uint band_cell_pixel(uint c) {
    if (pc.stride == 1u) return pc.pixel_begin + c;
    uint width = F.dims.x;
    return (pc.y0 + (c / width) * pc.stride) * width + c % width;
}

// The pixel of the pass's cell c.
uint cell_pixel(uint c) {
    return listed_pass() ? listed_pixels[c] : band_cell_pixel(c);
}

uint slot_state(SptSlot s) { return s.info.x & 3u; }

Path unpack_path(SptSlot s) {
    Path p;
    p.ray = Ray(s.origin.xyz, s.dir.xyz, s.origin.w);
    p.L = s.L.xyz;
    p.throughput = s.throughput.xyz;
    p.after_delta = (s.info.x & 4u) != 0u;
    p.bsdf_pdf = s.dir.w;
    p.depth = floatBitsToUint(s.throughput.w);
    p.sample_index = s.info.z;
    p.diffuse = s.info.x >> 8;
#ifdef HAS_VOLUME
    p.medium = s.medium.xyz;
#endif
#ifdef HAS_DISPERSION
    p.wavelength = s.medium.w;
#endif
#ifdef LIGHT_PASS
    p.pass_share = s.extra.x;
#endif
#ifdef TEXTURE_LOD
    p.cone = s.extra.y;
#endif
    return p;
}

// Writes path `p` (its pixel `pixel`, stream `rng`, `rays` traced) into slot `i` as `state`.
void store_path(uint i, Path p, uint state, uint pixel, Rng rng, uint rays) {
    uint flags = state | (p.after_delta ? 4u : 0u) | (p.diffuse << 8);
    slots[i] = SptSlot(vec4(p.ray.origin, p.ray.tmax), vec4(p.ray.dir, p.bsdf_pdf),
                       vec4(p.L, uintBitsToFloat(rays)), vec4(p.throughput, uintBitsToFloat(p.depth)),
                       uvec4(flags, pixel, p.sample_index, rng.state)
#if defined(HAS_VOLUME) && defined(HAS_DISPERSION)
                       , vec4(p.medium, p.wavelength)
#elif defined(HAS_VOLUME)
                       , vec4(p.medium, 0.0)
#elif defined(HAS_DISPERSION)
                       , vec4(vec3(0.0), p.wavelength)
#endif
#if defined(LIGHT_PASS) && defined(TEXTURE_LOD)
                       , vec4(p.pass_share, p.cone, 0.0, 0.0)
#elif defined(LIGHT_PASS)
                       , vec4(p.pass_share, 0.0, 0.0, 0.0)
#elif defined(TEXTURE_LOD)
                       , vec4(0.0, p.cone, 0.0, 0.0)
#endif
                       );
}

// Appends to the queue counted by `counter` where `want`: `at` is this invocation's entry. One
// atomic per subgroup (the queue's order within a subgroup follows its lanes).
#extension GL_KHR_shader_subgroup_ballot : require
#define QUEUE_APPEND(counter, want, at) { \
    uvec4 ballot_ = subgroupBallot(want); \
    uint total_ = subgroupBallotBitCount(ballot_); \
    uint base_ = 0u; \
    if (subgroupElect() && total_ > 0u) base_ = atomicAdd(counter, total_); \
    at = subgroupBroadcastFirst(base_) + subgroupBallotExclusiveBitCount(ballot_); \
}
