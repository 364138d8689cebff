// Affine maps of a two-level BVH's instances (layout.h Instance: three rows of a 3x4 matrix), shared by
// traversal (rays into object space) and shading (surfaces back out). Shared GLSL/C++ subset.
#ifndef FH_INSTANCE_GLSL
#define FH_INSTANCE_GLSL

// The point p mapped by the 3x4 matrix with rows r0, r1, r2.
vec3 map_point(vec4 r0, vec4 r1, vec4 r2, vec3 p) {
    vec4 h = vec4(p, 1.0f);
    return vec3(dot(r0, h), dot(r1, h), dot(r2, h));
}

// The direction v mapped by the linear part of that matrix (no translation).
vec3 map_vector(vec4 r0, vec4 r1, vec4 r2, vec3 v) {
    return vec3(dot(vec3(r0), v), dot(vec3(r1), v), dot(vec3(r2), v));
}

// The most the linear part of that matrix stretches a distance measured along an axis (its largest row sum of
// absolute entries: |M v|_inf <= this |v|_inf), so that a padding bound in one space holds in the other.
float max_axis_stretch(vec4 r0, vec4 r1, vec4 r2) {
    return max(dot(abs(vec3(r0)), vec3(1.0f)), max(dot(abs(vec3(r1)), vec3(1.0f)), dot(abs(vec3(r2)), vec3(1.0f))));
}
#endif
