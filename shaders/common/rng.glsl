// Random numbers as a pure function of (pixel, sample, frame, seed): each sample starts a
// fresh PCG stream keyed by a hash of the four, so any split of the frame gives the same image.

uint pcg_hash(uint v) {
    uint state = v * 747796405u + 2891336453u;
    uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

struct Rng { uint state; };

Rng rng_init(uvec2 pixel, uint sample_index, uint frame, uint seed) {
    uint h = pcg_hash(seed ^ 0x9e3779b9u);
    h = pcg_hash(h ^ pixel.x);
    h = pcg_hash(h ^ (pixel.y * 0x85ebca6bu));
    h = pcg_hash(h ^ frame);
    h = pcg_hash(h ^ (sample_index * 0xc2b2ae35u));
    return Rng(h);
}

float rng_next(inout Rng rng) {
    rng.state = rng.state * 747796405u + 2891336453u;
    uint word = ((rng.state >> ((rng.state >> 28u) + 4u)) ^ rng.state) * 277803737u;
    word = (word >> 22u) ^ word;
    // 24 high bits: uniform in [0, 1), never 1.
    return float(word >> 8) * (1.0 / 16777216.0);
}

vec2 rng_next2(inout Rng rng) { return vec2(rng_next(rng), rng_next(rng)); }
