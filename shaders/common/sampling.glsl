// Warps from the unit square and orthonormal frames.

// Duff et al. 2017, "Building an Orthonormal Basis, Revisited".
void make_frame(vec3 n, out vec3 t, out vec3 b) {
    float s = n.z >= 0.0 ? 1.0 : -1.0;
    float a = -1.0 / (s + n.z);
    float c = n.x * n.y * a;
    t = vec3(1.0 + s * n.x * n.x * a, s * c, -s * n.x);
    b = vec3(c, s + n.y * n.y * a, -n.y);
}

vec3 to_local(vec3 v, vec3 t, vec3 b, vec3 n) { return vec3(dot(v, t), dot(v, b), dot(v, n)); }
vec3 to_world(vec3 v, vec3 t, vec3 b, vec3 n) { return v.x * t + v.y * b + v.z * n; }

vec2 sample_disk_concentric(vec2 u) {
    vec2 o = 2.0 * u - 1.0;
    if (o.x == 0.0 && o.y == 0.0) return vec2(0.0);
    float r, theta;
    if (abs(o.x) > abs(o.y)) { r = o.x; theta = (PI / 4.0) * (o.y / o.x); }
    else { r = o.y; theta = PI / 2.0 - (PI / 4.0) * (o.x / o.y); }
    return r * vec2(cos(theta), sin(theta));
}

vec3 sample_cosine_hemisphere(vec2 u) {
    vec2 d = sample_disk_concentric(u);
    float z = sqrt(max(0.0, 1.0 - dot(d, d)));
    return vec3(d, z);
}

vec3 sample_uniform_sphere(vec2 u) {
    float z = 1.0 - 2.0 * u.x;
    float r = sqrt(max(0.0, 1.0 - z * z));
    float phi = 2.0 * PI * u.y;
    return vec3(r * cos(phi), r * sin(phi), z);
}

// Uniform barycentrics (Heitz 2019, "A Low-Distortion Map Between Triangle and Square").
vec3 sample_triangle(vec2 u) {
    float b0, b1;
    if (u.y > u.x) { b0 = u.x * 0.5; b1 = u.y - b0; }
    else { b1 = u.y * 0.5; b0 = u.x - b1; }
    return vec3(b0, b1, 1.0 - b0 - b1);
}

float power_heuristic(float a, float b) {
    float a2 = a * a, b2 = b * b;
    // Infinite pdfs (delta-like) take all the weight; 0/0 gives 0.
    if (isinf(a2)) return 1.0;
    return a2 + b2 > 0.0 ? a2 / (a2 + b2) : 0.0;
}

// The discrete distributions sampled by binary search: light selection, and the rows and
// columns of the environment map. Selected by name because GLSL will not pass a readonly
// buffer reference to a function.
const uint CDF_LIGHTS = 0u;
const uint CDF_ENV_ROWS = 1u;
const uint CDF_ENV_COLUMNS = 2u;

float cdf_value(uint cdf, uint i) {
    return cdf == CDF_LIGHTS ? light_cdf_at(i) : (cdf == CDF_ENV_ROWS ? env_marginal_at(i) : env_conditional_at(i));
}

// First index i in [0, n) with cdf[base + i] <= u < cdf[base + i + 1], skipping zero-width intervals.
uint search_cdf(uint cdf, uint base, uint n, float u) {
    uint lo = 0u, hi = n;
    while (lo + 1u < hi) {
        uint mid = (lo + hi) >> 1;
        if (cdf_value(cdf, base + mid) <= u) lo = mid; else hi = mid;
    }
    return lo;
}
