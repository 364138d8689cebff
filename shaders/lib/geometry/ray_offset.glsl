// Spawning rays from surfaces without self-intersection at any scale: offset the origin along the geometric
// normal by the floating-point error bound of the interpolated hit point, then round away from the surface
// (pbrt-v4, Pharr, Jakob & Humphreys 2023, sections 6.8.4-6.8.6). Bounds scale with |p|, so the same code
// works for a scene of size 1e-4 or one translated to 1e5; no fixed epsilon.
#ifndef FH_RAY_OFFSET_GLSL
#define FH_RAY_OFFSET_GLSL
#include "lib/core/techniques.glsl"

// gamma(n) = n u / (1 - n u), u = 2^-24 (Higham 2002): bound on the relative error of n roundings.
float error_gamma(float n) {
    const float u = 5.9604645e-8f;
    return (n * u) / (1.0f - n * u);
}

float next_float_up(float v) {
    if (isinf(v) && v > 0.0f) return v;
    if (v == -0.0f) v = 0.0f;
    uint bits = floatBitsToUint(v);
    bits = (v >= 0.0f) ? bits + 1u : bits - 1u;
    return uintBitsToFloat(bits);
}

float next_float_down(float v) {
    if (isinf(v) && v < 0.0f) return v;
    if (v == 0.0f) v = -0.0f;
    uint bits = floatBitsToUint(v);
    bits = (v > 0.0f) ? bits - 1u : bits + 1u;
    return uintBitsToFloat(bits);
}

// Absolute error bound of p = b0 p0 + b1 p1 + b2 p2 computed in float (pbrt-v4 eq. 6.25 style).
vec3 bound_interpolation_error(vec3 p0, vec3 p1, vec3 p2, float b0, float b1, float b2) {
    return error_gamma(7.0f) * (abs(b0 * p0) + abs(b1 * p1) + abs(b2 * p2));
}

// Origin for a ray leaving point p (error bound p_error, geometric normal n) in direction w.
// Without TECHNIQUE_ERROR_OFFSETS: the classic fixed epsilon (1e-4 scene units), too large for a scene of
// size 1e-4 and too small for one at 1e5.
vec3 offset_ray_origin(vec3 p, vec3 p_error, vec3 n, vec3 w) {
    if (!FH_TECHNIQUE_ON(TECHNIQUE_ERROR_OFFSETS)) {
        const float fixed_epsilon = 1e-4f;
        return p + (dot(w, n) < 0.0f ? -fixed_epsilon : fixed_epsilon) * n;
    }
    float d = dot(abs(n), p_error);
    vec3 offset = d * n;
    if (dot(w, n) < 0.0f) offset = -offset;
    vec3 po = p + offset;
    for (int i = 0; i < 3; ++i) {
        if (offset[i] > 0.0f) po[i] = next_float_up(po[i]);
        else if (offset[i] < 0.0f) po[i] = next_float_down(po[i]);
    }
    return po;
}
#endif
