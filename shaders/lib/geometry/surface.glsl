// Reconstructs the surface at a hit from the triangle buffers: position, its error bound, normals.
#ifndef FH_SURFACE_GLSL
#define FH_SURFACE_GLSL
#include "lib/geometry/ray_offset.glsl"
#include "lib/geometry/instance.glsl"

struct SurfaceHit {
    vec3 p;          // interpolated from the vertices (more accurate than origin + t dir)
    vec3 p_error;    // absolute float error bound of p
    vec3 ng;         // unit geometric normal (winding order: (p1 - p0) x (p2 - p0))
    vec3 ns;         // unit shading normal, on the same side of the surface as ng
    vec3 nc;         // unit normal of a clear coat (KHR_materials_clearcoat): the interpolated normal, or its own map
    vec3 ta;         // direction of KHR_materials_anisotropy (tangent plane; 0: none), set by the caller
    uint material;
    float light_pdf_area;
    uint light_entry;  // EFFECT_LIGHT_TREE: the triangle's Emitter entry + 1 (0: none; layout.h TRIANGLE_LIGHT_SHIFT)
    float area;
};

SurfaceHit load_surface(uint triangle, float b1, float b2) {
    TrianglePositions tp = load_triangle_positions(triangle);
    TriangleShading ts = load_triangle_shading(triangle);
    vec3 p0 = vec3(tp.p0_x, tp.p0_y, tp.p0_z);
    vec3 p1 = vec3(tp.p1_x, tp.p1_y, tp.p1_z);
    vec3 p2 = vec3(tp.p2_x, tp.p2_y, tp.p2_z);
    float b0 = 1.0f - b1 - b2;
    SurfaceHit s;
    // The point is pulled 3 x 2^-18 of the way towards the centroid: a hit exactly on an edge or a vertex
    // (barycentrics of 0 come out of the float test) also lies on the planes of the neighbouring triangles,
    // and a ray spawned there can leave a closed room through its corner without crossing any triangle.
    const float nudge = 3.814697265625e-6f;  // 2^-18
    float c0 = b0 * (1.0f - 3.0f * nudge) + nudge;
    float c1 = b1 * (1.0f - 3.0f * nudge) + nudge;
    float c2 = b2 * (1.0f - 3.0f * nudge) + nudge;
    s.p = c0 * p0 + c1 * p1 + c2 * p2;
    s.p_error = bound_interpolation_error(p0, p1, p2, c0, c1, c2);
    vec3 c = cross(p1 - p0, p2 - p0);
    float len = length(c);
    s.area = 0.5f * len;
    s.ng = len > 0.0f ? c / len : vec3(0.0f, 0.0f, 1.0f);
    s.ns = s.ng;
    if ((ts.flags & TRIANGLE_HAS_NORMALS) != 0u) {
        vec3 n = b0 * vec3(ts.n0_x, ts.n0_y, ts.n0_z) + b1 * vec3(ts.n1_x, ts.n1_y, ts.n1_z) +
                 b2 * vec3(ts.n2_x, ts.n2_y, ts.n2_z);
        float n_len = length(n);
        if (n_len > 0.0f && !isnan(n_len) && !isinf(n_len)) {
            n /= n_len;
            s.ns = dot(n, s.ng) < 0.0f ? -n : n;
        }
    }
    s.nc = s.ns;
    s.ta = vec3(0.0f);
    s.material = ts.material;
    s.light_pdf_area = ts.light_pdf_area;
    s.light_entry = ts.flags >> TRIANGLE_LIGHT_SHIFT;
    return s;
}

// A surface loaded in a mesh's object space (load_surface of an instanced triangle) placed by its instance:
// the point by render_from_object with its error bound grown by the transform's rounding (pbrt-v4 sec. 6.8.5:
// gamma(3) of |M| |p| plus (1 + gamma(3)) |M| p_error), normals by the inverse transpose (the transpose of
// object_from_render), which keeps a mirrored instance's front side in front. Area is not transformed:
// instanced meshes are never lights (the loader flattens emissive meshes).
SurfaceHit place_surface(SurfaceHit s, Instance inst) {
    vec3 m0 = vec3(inst.render_from_object_0), m1 = vec3(inst.render_from_object_1), m2 = vec3(inst.render_from_object_2);
    vec3 placed = map_point(inst.render_from_object_0, inst.render_from_object_1, inst.render_from_object_2, s.p);
    vec3 ap = abs(s.p);
    vec3 rounding = vec3(dot(abs(m0), ap) + abs(inst.render_from_object_0.w),
                         dot(abs(m1), ap) + abs(inst.render_from_object_1.w),
                         dot(abs(m2), ap) + abs(inst.render_from_object_2.w));
    vec3 carried = vec3(dot(abs(m0), s.p_error), dot(abs(m1), s.p_error), dot(abs(m2), s.p_error));
    s.p_error = error_gamma(3.0f) * rounding + (1.0f + error_gamma(3.0f)) * carried;
    s.p = placed;
    // The transpose of object_from_render's linear part: n_render = sum_k n_object[k] * object_from_render_k
    // (mat3(a, b, c) takes columns).
    mat3 normal_from_object = mat3(vec3(inst.object_from_render_0), vec3(inst.object_from_render_1),
                                   vec3(inst.object_from_render_2));
    vec3 ng = normal_from_object * s.ng;
    vec3 ns = normal_from_object * s.ns;
    vec3 nc = normal_from_object * s.nc;
    float ng_len = length(ng);
    float ns_len = length(ns);
    float nc_len = length(nc);
    if (ng_len > 0.0f && !isinf(ng_len)) s.ng = ng / ng_len;
    if (ns_len > 0.0f && !isinf(ns_len)) s.ns = ns / ns_len;
    if (nc_len > 0.0f && !isinf(nc_len)) s.nc = nc / nc_len;
    s.ta = vec3(dot(m0, s.ta), dot(m1, s.ta), dot(m2, s.ta));  // a tangent: by the linear part itself
    return s;
}
#endif
