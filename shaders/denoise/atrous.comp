#version 460
// The edge-avoiding a-trous filter on the device: the same arithmetic as the CPU reference,
// crates/platoon-aov/src/denoise/atrous.rs (its comment says why each weight), in three
// passes over planes of one buffer (method buffer 0), each plane a vec4 per pixel:
//   0: colour (rgb, w the variance; uploaded: the history's estimate, negative where it has
//      none), the source of odd iterations' output
//   1: colour, as plane 0 (the filter ping-pongs between them)
//   2: albedo (rgb), w = depth (infinite where the pixel sees no surface)
//   3: normal (xyz), w = the depth gradient (written by stage 0)
//   4: x = luminance, y = ln(1 + luminance), z = the standard deviation (stage 1's)
// Push words: 0 the stage, 1 the hole (pixels), 2 width, 3 height, 4 the source plane, 5 the
// destination plane. Stages:
//   0: once: the depth gradient, and plane 1 = the frame's colour (plane 0) with the history's
//      variance, or where it has none the variance of its luminance in the 3 x 3 window;
//   1: per iteration: luminance, log luminance and the 3 x 3 blurred variance's square root;
//   2: per iteration: the 5 x 5 taps, holes of push word 1.
// Whole vec4s are read through the buffer reference (scene.glsl: lavapipe 22.3 miscompiles a
// component read behind one).

layout(local_size_x = 64, local_size_y = 1, local_size_z = 1) in;

#include "common/scene.glsl"

layout(buffer_reference, std430, buffer_reference_align = 16) buffer Planes { vec4 v[]; };

#define PLANES Planes(pc.g.method_buffer0)

const float KERNEL[5] = float[5](1.0 / 16.0, 1.0 / 4.0, 3.0 / 8.0, 1.0 / 4.0, 1.0 / 16.0);
const uint NORMAL_POWER_LOG2 = 7u;
const float DEPTH_SIGMA = 1.0;
const float LUMINANCE_SIGMA = 2.0;
const float ALBEDO_SIGMA = 0.1;
const float LOG_LUMINANCE_SIGMA = 1.0;

uint W, H, N;

vec4 plane(uint k, uint p) { return PLANES.v[k * N + p]; }
void set_plane(uint k, uint p, vec4 v) { PLANES.v[k * N + p] = v; }

bool finite(float z) { return !isinf(z) && !isnan(z); }

// |a - b| where both depths are finite, else 0 (atrous.rs's depth_gradient).
float depth_step(float a, float b) { return finite(a) && finite(b) ? abs(a - b) : 0.0; }

void setup(uint p, uint x, uint y) {
    float gx = depth_step(plane(2u, y * W + min(x + 1u, W - 1u)).w,
                          plane(2u, y * W + (x > 0u ? x - 1u : 0u)).w) * 0.5;
    float gy = depth_step(plane(2u, min(y + 1u, H - 1u) * W + x).w,
                          plane(2u, (y > 0u ? y - 1u : 0u) * W + x).w) * 0.5;
    vec4 normal = plane(3u, p);
    set_plane(3u, p, vec4(normal.xyz, max(gx, gy)));
    // The luminance's variance in the 3 x 3 window (its mean first, as the CPU sums).
    float values[9];
    uint n = 0u;
    for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
            int qx = int(x) + dx, qy = int(y) + dy;
            if (qx >= 0 && qy >= 0 && qx < int(W) && qy < int(H)) {
                values[n] = luminance(plane(0u, uint(qy) * W + uint(qx)).rgb);
                n += 1u;
            }
        }
    }
    float mean = 0.0;
    for (uint i = 0u; i < n; ++i) mean += values[i];
    mean /= float(n);
    float variance = 0.0;
    for (uint i = 0u; i < n; ++i) variance += (values[i] - mean) * (values[i] - mean);
    vec4 own = plane(0u, p);
    set_plane(1u, p, vec4(own.rgb, own.w >= 0.0 ? own.w : variance / float(n)));
}

void prefilter(uint p, uint x, uint y, uint source) {
    float sum = 0.0;
    uint n = 0u;
    for (int dy = -1; dy <= 1; ++dy) {
        for (int dx = -1; dx <= 1; ++dx) {
            int qx = int(x) + dx, qy = int(y) + dy;
            if (qx >= 0 && qy >= 0 && qx < int(W) && qy < int(H)) {
                sum += plane(source, uint(qy) * W + uint(qx)).w;
                n += 1u;
            }
        }
    }
    float lum = luminance(plane(source, p).rgb);
    set_plane(4u, p, vec4(lum, log(1.0 + lum), sqrt(sum / float(n)), 0.0));
}

// How much pixel q may stand in for p (atrous.rs's edge_weight).
float edge_weight(uint p, uint q, float distance, vec4 lp, float gradient, vec4 ap, vec4 np) {
    vec4 aq = plane(2u, q);
    float zp = ap.w, zq = aq.w;
    if (finite(zp) != finite(zq)) return 0.0;
    vec3 nq = plane(3u, q).xyz;
    float cosine = np.x * nq.x + np.y * nq.y + np.z * nq.z;
    float w_normal = 1.0;
    if (finite(zp)) {
        w_normal = max(cosine, 0.0);
        for (uint i = 0u; i < NORMAL_POWER_LOG2; ++i) w_normal *= w_normal;
    }
    float w_depth = finite(zp) ? -abs(zp - zq) / (DEPTH_SIGMA * gradient * distance + 1e-6) : 0.0;
    vec3 da = ap.rgb - aq.rgb;
    float w_albedo = -(da.x * da.x + da.y * da.y + da.z * da.z) / (ALBEDO_SIGMA * ALBEDO_SIGMA);
    vec4 lq = plane(4u, q);
    float w_luminance = -abs(lp.x - lq.x) / (LUMINANCE_SIGMA * lp.z + 1e-6)
        - abs(lp.y - lq.y) / LOG_LUMINANCE_SIGMA;
    return w_normal * exp(w_depth + w_albedo + w_luminance);
}

void taps(uint p, uint x, uint y, uint step, uint source, uint destination) {
    vec4 lp = plane(4u, p), ap = plane(2u, p), np = plane(3u, p);
    vec3 sum = vec3(0.0);
    float variance = 0.0, weights = 0.0;
    for (int ky = 0; ky < 5; ++ky) {
        for (int kx = 0; kx < 5; ++kx) {
            int qx = int(x) + (kx - 2) * int(step);
            int qy = int(y) + (ky - 2) * int(step);
            if (qx < 0 || qy < 0 || qx >= int(W) || qy >= int(H)) continue;
            uint q = uint(qy) * W + uint(qx);
            float weight = KERNEL[kx] * KERNEL[ky];
            if (q != p) {
                float d2 = float((qx - int(x)) * (qx - int(x)) + (qy - int(y)) * (qy - int(y)));
                weight *= edge_weight(p, q, sqrt(d2), lp, np.w, ap, np);
            }
            vec4 c = plane(source, q);
            sum += weight * c.rgb;
            variance += weight * weight * c.w;
            weights += weight;
        }
    }
    // The centre tap always counts: weights > 0.
    set_plane(destination, p, vec4(sum / weights, variance / (weights * weights)));
}

void main() {
    W = pc.method_words[2];
    H = pc.method_words[3];
    N = W * H;
    uint p = gl_GlobalInvocationID.x;
    if (p >= N) return;
    uint x = p % W, y = p / W;
    uint stage = pc.method_words[0];
    if (stage == 0u) {
        setup(p, x, y);
    } else if (stage == 1u) {
        prefilter(p, x, y, pc.method_words[4]);
    } else {
        taps(p, x, y, pc.method_words[1], pc.method_words[4], pc.method_words[5]);
    }
}
