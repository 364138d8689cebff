// The environment light (EFFECT_ENVIRONMENT): an equirectangular radiance map around the scene, importance
// sampled in proportion to luminance x sin(theta) (piecewise constant per texel; pbrt-v4's
// PiecewiseConstant2D), evaluated with the same piecewise-constant radiance so that sampling matches it.
// Mapping (Blender's world Environment Texture, for a glTF scene its importer turns Z-up; probed with Cycles):
// theta from +Y, the top row at +Y; the centre column (u = 0.5) is the direction +X, u = 0.25 is -Z and u = 0.75
// is +Z. --env-rotation turns the map about +Y.
#ifndef FH_ENVIRONMENT_GLSL
#define FH_ENVIRONMENT_GLSL

// Shared GLSL/C++ subset: the C++ unit test declares `params`, `env_radiance` and `env_cdf` itself.
#ifndef __cplusplus
layout(std430, binding = BINDING_ENV_RADIANCE) readonly buffer EnvRadianceBuffer { vec4 env_radiance[]; };
layout(std430, binding = BINDING_ENV_CDF) readonly buffer EnvCdfBuffer { float env_cdf[]; };
#endif

const float ENV_PI = 3.14159265358979f;

// Direction of map coordinates (u, v) in [0, 1)^2 (v = 0 at the top row).
vec3 env_direction(vec2 uv) {
    float phi = 2.0f * ENV_PI * (uv.x - 0.5f) + params.env_rotation;
    float theta = ENV_PI * uv.y;
    float s = sin(theta);
    return vec3(s * cos(phi), cos(theta), s * sin(phi));
}

vec2 env_texcoord(vec3 dir) {
    float phi = atan(dir.z, dir.x) - params.env_rotation;
    float u = phi * (0.5f / ENV_PI) + 0.5f;
    u -= floor(u);
    // atan2 rather than acos: acos loses theta near the poles (cos theta = 1 - theta^2 / 2 in float).
    float v = atan(sqrt(dir.x * dir.x + dir.z * dir.z), dir.y) * (1.0f / ENV_PI);
    return vec2(u, v);
}

uint env_texel_index(vec2 uv) {
    uint x = min(uint(uv.x * float(params.env_width)), params.env_width - 1u);
    uint y = min(uint(uv.y * float(params.env_height)), params.env_height - 1u);
    return y * params.env_width + x;
}

vec3 eval_environment(vec3 dir) { return vec3(env_radiance[env_texel_index(env_texcoord(dir))]); }

// Solid-angle pdf of sample_environment choosing `dir`. The sampling weight of a texel is stored in its
// alpha: luminance x sin(theta at the texel's centre), times width x height / total weight.
float pdf_environment(vec3 dir) {
    vec2 uv = env_texcoord(dir);
    float sin_theta = sqrt(dir.x * dir.x + dir.z * dir.z);
    if (!(sin_theta > 0.0f)) return 0.0f;
    float pdf_uv = env_radiance[env_texel_index(uv)].w;
    return pdf_uv / (2.0f * ENV_PI * ENV_PI * sin_theta);
}

// Largest k in [0, n) with cdf[first + k] <= u (cdf[first] = 0, cdf[first + n] = 1).
uint find_interval(uint first, uint n, float u) {
    uint lo = 0u;
    uint hi = n;  // invariant: cdf[first + lo] <= u < cdf[first + hi] (hi = n: 1 > u)
    while (hi - lo > 1u) {
        uint mid = (lo + hi) >> 1u;
        if (env_cdf[first + mid] <= u) lo = mid;
        else hi = mid;
    }
    return lo;
}

struct EnvironmentSample {
    vec3 dir;
    float pdf;  // solid angle
    vec3 radiance;
};

EnvironmentSample sample_environment(vec2 u) {
    uint w = params.env_width;
    uint h = params.env_height;
    uint row = find_interval(0u, h, u.y);
    float r0 = env_cdf[row];
    float r1 = env_cdf[row + 1u];
    float dv = r1 > r0 ? clamp((u.y - r0) / (r1 - r0), 0.0f, 0.99999994f) : 0.5f;
    uint first = h + 1u + row * (w + 1u);
    uint column = find_interval(first, w, u.x);
    float c0 = env_cdf[first + column];
    float c1 = env_cdf[first + column + 1u];
    float du = c1 > c0 ? clamp((u.x - c0) / (c1 - c0), 0.0f, 0.99999994f) : 0.5f;
    vec2 uv = vec2((float(column) + du) / float(w), (float(row) + dv) / float(h));
    EnvironmentSample s;
    s.dir = env_direction(uv);
    vec4 texel = env_radiance[row * w + column];
    s.radiance = vec3(texel);
    float sin_theta = sin(ENV_PI * uv.y);
    s.pdf = sin_theta > 0.0f ? texel.w / (2.0f * ENV_PI * ENV_PI * sin_theta) : 0.0f;
    return s;
}
#endif
