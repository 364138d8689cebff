// Emissive-triangle light sampling: pick a triangle in proportion to its power from the alias table
// (Walker 1977; Vose 1991), then a uniform point on it. Pdfs are per unit area; solid angle conversion
// (dist^2 / cos) happens at the caller.
#ifndef FH_LIGHTS_GLSL
#define FH_LIGHTS_GLSL
#include "sampling.glsl"

struct LightSample {
    vec3 p;
    vec3 p_error;
    vec3 n;              // unit normal of the emitting triangle
    vec3 radiance;       // emitted radiance towards the front (double-sided: both sides)
    float pdf_area;      // pick probability / area
    uint double_sided;
};

uint pick_emitter(float u) {
    uint n = params.emitter_count;
    float scaled = u * float(n);
    uint i = min(uint(scaled), n - 1u);
    Emitter e = load_emitter(i);
    return (scaled - float(i) < e.alias_threshold) ? e.triangle : load_emitter(e.alias).triangle;
}

LightSample sample_light(float u_pick, vec2 u_point) {
    uint tri = pick_emitter(u_pick);
    TrianglePositions tp = load_triangle_positions(tri);
    TriangleShading ts = load_triangle_shading(tri);
    vec3 p0 = vec3(tp.p0_x, tp.p0_y, tp.p0_z);
    vec3 p1 = vec3(tp.p1_x, tp.p1_y, tp.p1_z);
    vec3 p2 = vec3(tp.p2_x, tp.p2_y, tp.p2_z);
    vec2 b = sample_uniform_triangle(u_point);
    float b0 = 1.0f - b.x - b.y;
    Material m = load_material(ts.material);
    LightSample s;
    s.p = b0 * p0 + b.x * p1 + b.y * p2;
    s.p_error = bound_interpolation_error(p0, p1, p2, b0, b.x, b.y);
    s.n = normalize(cross(p1 - p0, p2 - p0));
    s.radiance = m.emission.xyz;
    s.pdf_area = ts.light_pdf_area;
    s.double_sided = m.flags & MATERIAL_DOUBLE_SIDED;
    return s;
}
#endif
