// Sampling a triangle light by the solid angle it subtends (Arvo 1995, "Stratified Sampling of Spherical Triangles";
// the form of pbrt-v4's SampleSphericalTriangle): every direction towards the triangle equally likely, so next-event
// estimation no longer pays for the spread of distance and cosine over a large emitter seen from close by. Used with
// the light tree (EFFECT_LIGHT_TREE), whose per-path point lets an emitter hit find the same density again.
//
// Written in the GLSL subset that also compiles as C++ (lib/core/cpp_compat.h): tests/unit/scene/test_light_tree.cpp checks
// that the directions cover the triangle uniformly. Needs sampling.glsl (PI).
#ifndef FH_SPHERICAL_TRIANGLE_GLSL
#define FH_SPHERICAL_TRIANGLE_GLSL

// Solid angle sampling where the triangle subtends between these (steradians), area sampling elsewhere: below, the
// spherical angles' sum loses the digits the warp needs in float and the triangle is small enough that area
// sampling's density hardly varies over it; above, the triangle nearly fills a hemisphere and the warp is unstable
// (pbrt-v4 switches at 3e-4 and 6.22).
const float SPHERICAL_SAMPLING_MIN_SR = 0.01f;
const float SPHERICAL_SAMPLING_MAX_SR = 6.22f;

// The solid angle of triangle (p0, p1, p2) seen from p (Van Oosterom and Strackee 1983). NEE and the emitter hit both
// take the solid-angle density from this one function.
float spherical_triangle_solid_angle(vec3 p0, vec3 p1, vec3 p2, vec3 p) {
    vec3 a = normalize(p0 - p), b = normalize(p1 - p), c = normalize(p2 - p);
    return abs(2.0f * atan(dot(a, cross(b, c)), 1.0f + dot(a, b) + dot(a, c) + dot(b, c)));
}

bool use_spherical_sampling(float solid_angle) {
    return solid_angle >= SPHERICAL_SAMPLING_MIN_SR && solid_angle <= SPHERICAL_SAMPLING_MAX_SR;
}

float asin_clamped(float x) { return asin(clamp(x, -1.0f, 1.0f)); }

// The angle between unit vectors, accurate near 0 and pi.
float unit_angle_between(vec3 u, vec3 v) {
    return dot(u, v) < 0.0f ? PI - 2.0f * asin_clamped(length(u + v) * 0.5f) : 2.0f * asin_clamped(length(v - u) * 0.5f);
}

// v without its component along the unit vector w, normalized.
vec3 orthogonal_part(vec3 v, vec3 w) { return normalize(v - dot(v, w) * w); }

// The barycentrics (b1, b2 of p1, p2) of a direction from p uniform over the triangle's solid angle. valid false for a
// triangle seen edge-on (no spherical triangle).
struct SphericalTriangleSample {
    vec2 b;
    bool valid;
};

SphericalTriangleSample sample_spherical_triangle(vec3 p0, vec3 p1, vec3 p2, vec3 p, vec2 u) {
    SphericalTriangleSample s;
    s.b = vec2(0.0f);
    s.valid = false;
    vec3 a = normalize(p0 - p), b = normalize(p1 - p), c = normalize(p2 - p);
    vec3 n_ab = cross(a, b), n_bc = cross(b, c), n_ca = cross(c, a);
    if (!(dot(n_ab, n_ab) > 0.0f && dot(n_bc, n_bc) > 0.0f && dot(n_ca, n_ca) > 0.0f)) return s;
    n_ab = normalize(n_ab);
    n_bc = normalize(n_bc);
    n_ca = normalize(n_ca);
    // The spherical triangle's angles at a, b, c; its area is their sum minus pi.
    float alpha = unit_angle_between(n_ab, -n_ca);
    float beta = unit_angle_between(n_bc, -n_ab);
    float gamma = unit_angle_between(n_ca, -n_bc);
    // The sub-triangle (a, b, c') of area u.x x the whole: c' on the arc from a to c.
    float area_pi = PI + u.x * (alpha + beta + gamma - PI);
    float cos_alpha = cos(alpha), sin_alpha = sin(alpha);
    float sin_phi = sin(area_pi) * cos_alpha - cos(area_pi) * sin_alpha;
    float cos_phi = cos(area_pi) * cos_alpha + sin(area_pi) * sin_alpha;
    float k1 = cos_phi + cos_alpha;
    float k2 = sin_phi - sin_alpha * dot(a, b);
    float cos_bp = (k2 + (k2 * cos_phi - k1 * sin_phi) * cos_alpha) / ((k2 * sin_phi + k1 * cos_phi) * sin_alpha);
    cos_bp = clamp(cos_bp, -1.0f, 1.0f);
    vec3 cp = cos_bp * a + sqrt(max(0.0f, 1.0f - cos_bp * cos_bp)) * orthogonal_part(c, a);
    // Then a direction on the arc from b to c', with its cosine uniform: uniform over the sub-triangle's new sliver.
    float cos_theta = 1.0f - u.y * (1.0f - dot(cp, b));
    vec3 w = cos_theta * b + sqrt(max(0.0f, 1.0f - cos_theta * cos_theta)) * orthogonal_part(cp, b);
    // Where w meets the triangle's plane (Moller-Trumbore).
    vec3 e1 = p1 - p0, e2 = p2 - p0;
    vec3 s1 = cross(w, e2);
    float divisor = dot(s1, e1);
    if (!(abs(divisor) > 0.0f)) return s;
    vec3 d = p - p0;
    float b1 = clamp(dot(d, s1) / divisor, 0.0f, 1.0f);
    float b2 = clamp(dot(w, cross(d, e1)) / divisor, 0.0f, 1.0f);
    float sum = b1 + b2;
    if (sum > 1.0f) {
        b1 /= sum;
        b2 /= sum;
    }
    s.b = vec2(b1, b2);
    s.valid = !(isnan(b1) || isnan(b2));
    return s;
}

#endif
