// The world cache (issue 43; crates/platoon-core/src/method/path/world_cache.rs keeps it): the
// radiance a surface reflects, averaged over cells of a grid in world space, one per side
// of a surface (the axis its geometric normal faces most). With WORLD_CACHE a path reaching
// its second vertex in a cell the cache knows takes the cell's light and ends there: the bounces
// after the first are the cache's (biased: a cell's mean over its area and the directions it was
// seen from). With WORLD_CACHE_TRAIN (path/world_cache_train.comp) paths keep going and note
// what they gathered from that vertex on, the cache's samples.
//
// The table (method buffer 0), a vec4 per slot: the cell's key (uint bits; 0 empty) and its
// mean reflected radiance. Push words 2-4: the cell size (float bits), the slot mask, and the
// training pattern's stride (one pixel in `stride` trains, rotating with the frame).

layout(buffer_reference, std430, buffer_reference_align = 16) readonly buffer CacheSlots { vec4 v[]; };
layout(buffer_reference, std430, buffer_reference_align = 16) buffer CacheRecords { vec4 v[]; };

float cache_cell_size() { return uintBitsToFloat(pc.method_words[2]); }
uint cache_slot_mask() { return pc.method_words[3]; }
uint cache_train_stride() { return pc.method_words[4]; }

// The key of the cell holding `position`, on the side `n` faces: never 0, and as a float's bits
// a normal number (exponent bits neither all 0 nor all 1), which every copy keeps as it is.
uint cache_key(vec3 position, vec3 n) {
    ivec3 c = ivec3(floor(position / cache_cell_size()));
    vec3 a = abs(n);
    uint face = a.x >= a.y && a.x >= a.z ? 0u : (a.y >= a.z ? 2u : 4u);
    face += (face == 0u ? n.x : (face == 2u ? n.y : n.z)) < 0.0 ? 1u : 0u;
    uint h = pcg_hash(face ^ 0x68bc21ebu);
    h = pcg_hash(h ^ uint(c.x));
    h = pcg_hash(h ^ (uint(c.y) * 0x85ebca6bu));
    h = pcg_hash(h ^ (uint(c.z) * 0xc2b2ae35u));
    return (h & 0xbfffffffu) | 0x00800001u;
}

// The slot a key lives in (world_cache.rs's slot_of).
uint cache_slot(uint key) { return (key >> 1) & cache_slot_mask(); }

#ifdef WORLD_CACHE
// The cell's mean reflected radiance, when the table holds it.
bool cache_lookup(uint key, out vec3 radiance) {
    vec4 v = CacheSlots(pc.g.method_buffer0).v[cache_slot(key)];
    radiance = v.yzw;
    return floatBitsToUint(v.x) == key;
}
#endif
