// Distant light: constant colour (uniform sphere sampling) or an equirectangular map
// (piecewise-constant 2D importance sampling on luminance * sin(theta)).
// Mapping: u = atan(d.x, -d.z) / 2pi + 0.5, v = acos(d.y) / pi (top row = +Y).

vec2 direction_to_uv(vec3 d) {
    float u = atan(d.x, -d.z) * (0.5 * INV_PI) + 0.5;
    float v = acos(clamp(d.y, -1.0, 1.0)) * INV_PI;
    return vec2(u, v);
}

vec3 uv_to_direction(vec2 uv) {
    float phi = (uv.x - 0.5) * 2.0 * PI;
    float theta = uv.y * PI;
    float st = sin(theta);
    return vec3(st * sin(phi), cos(theta), -st * cos(phi));
}

#ifdef HAS_ENVIRONMENT_MAP
ivec2 env_texel(vec2 uv) {
    uvec4 d = F.dims;
    return ivec2(min(uint(uv.x * float(d.z)), d.z - 1u), min(uint(uv.y * float(d.w)), d.w - 1u));
}

// Discrete probability of texel (x, y) times the texel count: the uv-space density.
float env_uv_pdf(ivec2 t) {
    uvec2 size = env_size();
    uint w = size.x, h = size.y;
    float pm = env_marginal_at(t.y + 1) - env_marginal_at(t.y);
    uint row = uint(t.y) * (w + 1u);
    float pc_ = env_conditional_at(row + uint(t.x) + 1u) - env_conditional_at(row + uint(t.x));
    return pm * float(h) * pc_ * float(w);
}
#endif

vec3 env_radiance(vec3 d) {
    uint kind = env_kind();
    if (kind == ENV_NONE) return vec3(0.0);
#ifdef HAS_ENVIRONMENT_MAP
    if (kind == ENV_MAP) {
        ivec2 t = env_texel(direction_to_uv(d));
        return env_texel_at(uint(t.y) * env_size().x + uint(t.x)).rgb;
    }
#endif
    return F.env_color.rgb;
}

// Solid-angle density of env_sample for direction d.
float env_pdf(vec3 d) {
#ifdef HAS_ENVIRONMENT_MAP
    if (env_kind() == ENV_MAP) {
        vec2 uv = direction_to_uv(d);
        float st = sqrt(max(0.0, 1.0 - d.y * d.y));
        if (st <= 0.0) return 0.0;
        return env_uv_pdf(env_texel(uv)) / (2.0 * PI * PI * st);
    }
#endif
    return 1.0 / (4.0 * PI);
}

vec3 env_sample(vec2 u, out float pdf) {
#ifdef HAS_ENVIRONMENT_MAP
    if (env_kind() == ENV_MAP) {
        uvec2 size = env_size();
        uint w = size.x, h = size.y;
        uint y = search_cdf(CDF_ENV_ROWS, 0u, h, u.y);
        float c0 = env_marginal_at(y), c1 = env_marginal_at(y + 1u);
        float fy = c1 > c0 ? (u.y - c0) / (c1 - c0) : 0.5;
        uint row = y * (w + 1u);
        uint x = search_cdf(CDF_ENV_COLUMNS, row, w, u.x);
        float d0 = env_conditional_at(row + x), d1 = env_conditional_at(row + x + 1u);
        float fx = d1 > d0 ? (u.x - d0) / (d1 - d0) : 0.5;
        vec2 uv = vec2((float(x) + clamp(fx, 0.0, 0.999999)) / float(w), (float(y) + clamp(fy, 0.0, 0.999999)) / float(h));
        vec3 d = uv_to_direction(uv);
        float st = sin(uv.y * PI);
        pdf = st > 0.0 ? env_uv_pdf(ivec2(x, y)) / (2.0 * PI * PI * st) : 0.0;
        return d;
    }
#endif
    pdf = 1.0 / (4.0 * PI);
    return sample_uniform_sphere(u);
}
