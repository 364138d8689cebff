// Light sampling for next-event estimation: pick a light in proportion to its power from the alias table
// over every light (Walker 1977; Vose 1991), or by its importance at the shading point from the light tree
// (EFFECT_LIGHT_TREE, lib/light/light_tree.glsl), then a point on it. Emissive triangles are sampled uniformly
// by area; punctual lights (KHR_lights_punctual: point, spot, directional) are delta lights, reached by NEE
// only, and never MIS-weighted.
#ifndef FH_LIGHTS_GLSL
#define FH_LIGHTS_GLSL
#include "lib/sampling/sampling.glsl"
#include "lib/geometry/ray_offset.glsl"
#include "lib/material/material.glsl"
#include "lib/light/environment.glsl"
#include "lib/light/light_tree.glsl"
#include "lib/sampling/spherical_triangle.glsl"

// Scenes without punctual lights (EFFECT_PUNCTUAL_LIGHTS) or emitting triangles (EFFECT_EMISSIVE_TRIANGLES)
// compile the code of that kind of light out: its entries cannot be in the light table.

// What a shading point at p needs to connect to a sampled light.
struct LightConnection {
    vec3 wi;                 // unit direction from p towards the light
    vec3 target;             // where the shadow ray ends (off an area light's surface by its error bound)
    vec3 radiance_over_pdf;  // incident radiance along wi divided by the solid-angle pdf of choosing wi
    float pdf;               // that solid-angle pdf (area lights, for MIS); 0 for delta lights
    // Bidirectional path tracing: the density of a light subpath starting at that point of the light in direction -wi
    // (light_subpath.glsl) over NEE's density, per unit of the shading point's projected area (times its geometric
    // cosine and over its distance squared, the latter folded in): emission pdf / (NEE's solid-angle pdf x cos at the
    // light), as SmallVCM's weights take them.
    float emission_over_direct;
    uint delta;              // 1: punctual light (no MIS: BSDF sampling can never hit it)
    uint at_infinity;        // 1: directional light (shadow ray unbounded; target unused)
    uint valid;              // 0: the light sends nothing towards p
};

// The entry of the light pick_emitter picks for u.
uint pick_emitter_entry(float u) {
    uint n = params.emitter_count;
    float scaled = u * float(n);
    uint i = min(uint(scaled), n - 1u);
    Emitter e = load_emitter(i);
    return (scaled - float(i) < e.alias_threshold) ? i : e.alias;
}

Emitter pick_emitter(float u) { return load_emitter(pick_emitter_entry(u)); }

// A scene with at most this many lights picks one with the first coordinate of the light's 2D sample and reuses
// what is left of it (below) rather than with a dimension of its own.
const uint LIGHT_PICK_REUSE_MAX = 16u;

// pick_emitter by u, which then becomes the position of u within the part of [0, 1) that picked the light: again uniform
// in [0, 1), and stratified wherever u was (Mitsuba 3's sample_reuse). A quad light is two triangles: the light's 2D
// samples then spread over the quad as one net instead of two random halves of it, one per triangle (README
// "Sampling"). Each light keeps 24 - log2(lights) bits of u and fewer where its alias share is small, hence the bound
// on the lights above.
Emitter pick_emitter_reusing(inout float u) {
    uint n = params.emitter_count;
    float scaled = u * float(n);
    uint i = min(uint(scaled), n - 1u);
    float f = min(scaled - float(i), ONE_BELOW_ONE);
    Emitter e = load_emitter(i);
    float t = e.alias_threshold;
    bool own = f < t;
    u = min(own ? f / t : (f - t) / (1.0f - t), ONE_BELOW_ONE);
    return own ? e : load_emitter(e.alias);
}

LightConnection make_invalid_connection() {
    LightConnection c;
    c.wi = vec3(0.0f, 0.0f, 1.0f);
    c.target = vec3(0.0f);
    c.radiance_over_pdf = vec3(0.0f);
    c.pdf = 0.0f;
    c.emission_over_direct = 0.0f;
    c.delta = 0u;
    c.at_infinity = 0u;
    c.valid = 0u;
    return c;
}

// The disk of the scene's bounding sphere through which light from a directional light or the environment enters
// (light_subpath.glsl sample_scene_disk): its area.
float scene_disk_radius() { return 0.5f * length(params.scene_max.xyz - params.scene_min.xyz); }
float scene_disk_area() {
    float radius = scene_disk_radius();
    return PI * radius * radius;
}

// KHR_lights_punctual spot falloff: smooth from the outer cone (0) to the inner cone (1), squared.
float spot_attenuation(PunctualLight light, float cos_angle) {
    float scale = 1.0f / max(0.001f, light.cos_inner - light.cos_outer);
    float a = clamp((cos_angle - light.cos_outer) * scale, 0.0f, 1.0f);
    return a * a;
}

LightConnection connect_punctual_light(uint index, float pick_pdf, vec3 p) {
    PunctualLight light = load_punctual_light(index);
    LightConnection c = make_invalid_connection();
    c.delta = 1u;
    vec3 intensity = light.intensity.xyz / pick_pdf;
    if (light.type == LIGHT_DIRECTIONAL) {
        c.wi = -light.direction.xyz;
        c.radiance_over_pdf = intensity;  // irradiance normal to the light: a delta in direction
        c.at_infinity = 1u;
        c.emission_over_direct = 1.0f / scene_disk_area();
        c.valid = 1u;
        return c;
    }
    vec3 to_light = light.position.xyz - p;
    float dist2 = dot(to_light, to_light);
    if (!(dist2 > 0.0f)) return c;
    c.wi = to_light * inversesqrt(dist2);
    c.target = light.position.xyz;
    float falloff = 1.0f;
    if (light.type == LIGHT_SPOT) falloff = spot_attenuation(light, dot(-c.wi, light.direction.xyz));
    c.radiance_over_pdf = intensity * (falloff / dist2);  // inverse-square law
    float cone = light.type == LIGHT_SPOT ? TWO_PI * (1.0f - light.cos_outer) : 4.0f * PI;  // light_subpath.glsl
    c.emission_over_direct = 1.0f / (cone * dist2);
    c.valid = falloff > 0.0f ? 1u : 0u;
    return c;
}

// The area of a triangle light as NEE and the emitter hit (SurfaceHit.area) both compute it.
float light_triangle_area(vec3 p0, vec3 p1, vec3 p2) { return 0.5f * length(cross(p1 - p0, p2 - p0)); }

// pick_pdf: the light tree's probability of this triangle (EFFECT_LIGHT_TREE); the alias table's is in the triangle's
// light_pdf_area.
LightConnection connect_triangle_light(uint tri, vec3 p, vec2 u_point, float pick_pdf) {
    TrianglePositions tp = load_triangle_positions(tri);
    TriangleShading ts = load_triangle_shading(tri);
    vec3 p0 = vec3(tp.p0_x, tp.p0_y, tp.p0_z);
    vec3 p1 = vec3(tp.p1_x, tp.p1_y, tp.p1_z);
    vec3 p2 = vec3(tp.p2_x, tp.p2_y, tp.p2_z);
    vec2 b = sample_uniform_triangle(u_point);
    // With the light tree, a triangle that subtends enough is sampled by solid angle (lib/sampling/spherical_triangle.glsl).
    float solid_angle = 0.0f;
    bool spherical = false;
    if (effect_on(EFFECT_LIGHT_TREE)) {
        solid_angle = spherical_triangle_solid_angle(p0, p1, p2, p);
        spherical = use_spherical_sampling(solid_angle);
        if (spherical) {
            SphericalTriangleSample st = sample_spherical_triangle(p0, p1, p2, p, u_point);
            if (!st.valid) return make_invalid_connection();
            b = st.b;
        }
    }
    float b0 = 1.0f - b.x - b.y;
    Material m = load_material(ts.material);
    // Textured emitters: the emission at the sampled point (the triangle was picked by its integrated power,
    // the point uniformly, so the estimate stays unbiased); cut-out or blended emitters count their coverage.
    if (effect_on(EFFECT_EMISSIVE_TEXTURE)) m = resolve_material(m, tri, b.x, b.y);
    if (effect_on(EFFECT_ALPHA)) m.emission.xyz *= eval_coverage(tri, b.x, b.y);
    vec3 q = b0 * p0 + b.x * p1 + b.y * p2;
    vec3 q_error = bound_interpolation_error(p0, p1, p2, b0, b.x, b.y);
    vec3 n = normalize(cross(p1 - p0, p2 - p0));
    LightConnection c = make_invalid_connection();
    vec3 to_light = q - p;
    float dist2 = dot(to_light, to_light);
    if (!(dist2 > 0.0f)) return c;
    c.wi = to_light * inversesqrt(dist2);
    float cos_light = -dot(n, c.wi);
    bool emits = cos_light > 0.0f || ((m.flags & MATERIAL_DOUBLE_SIDED) != 0u && cos_light < 0.0f);
    if (!emits) return c;
    float pdf_area = effect_on(EFFECT_LIGHT_TREE) ? pick_pdf / light_triangle_area(p0, p1, p2) : ts.light_pdf_area;
    c.pdf = spherical ? pick_pdf / solid_angle : pdf_area * dist2 / abs(cos_light);  // area to solid angle
    c.radiance_over_pdf = m.emission.xyz / c.pdf;
    c.emission_over_direct = abs(cos_light) * INV_PI * ((m.flags & MATERIAL_DOUBLE_SIDED) != 0u ? 0.5f : 1.0f) / dist2;
    // By solid angle, NEE's area density is pick_pdf cos_light / (solid_angle dist2), not pick_pdf / area.
    if (spherical) c.emission_over_direct *= solid_angle * dist2 / (light_triangle_area(p0, p1, p2) * abs(cos_light));
    c.target = offset_ray_origin(q, q_error, n, -c.wi);
    c.valid = c.pdf > 0.0f ? 1u : 0u;
    return c;
}

LightConnection connect_environment(float pick_pdf, vec2 u) {
    LightConnection c = make_invalid_connection();
    EnvironmentSample s = sample_environment(u);
    c.wi = s.dir;
    c.pdf = pick_pdf * s.pdf;
    c.at_infinity = 1u;
    if (!(c.pdf > 0.0f)) return c;
    c.radiance_over_pdf = s.radiance / c.pdf;
    c.emission_over_direct = 1.0f / scene_disk_area();
    c.valid = 1u;
    return c;
}

// The solid-angle density with which NEE at the path's last vertex (`from`, as shade stored it) samples the direction
// towards triangle `tri` of Emitter entry + 1 `light_entry` (0: not in the tree), `t` away, met at cos_light to its
// normal: the tree's pick, then solid angle or area as connect_triangle_light chooses.
float tree_emitter_hit_pdf(LightTreePoint from, uint tri, uint light_entry, float t, float cos_light) {
    if (light_entry == 0u) return 0.0f;
    float pick_pdf = tree_light_pick_pdf(from, light_entry - 1u);
    TrianglePositions tp = load_triangle_positions(tri);
    vec3 p0 = vec3(tp.p0_x, tp.p0_y, tp.p0_z);
    vec3 p1 = vec3(tp.p1_x, tp.p1_y, tp.p1_z);
    vec3 p2 = vec3(tp.p2_x, tp.p2_y, tp.p2_z);
    float solid_angle = spherical_triangle_solid_angle(p0, p1, p2, from.p);
    if (use_spherical_sampling(solid_angle)) return pick_pdf / solid_angle;
    return pick_pdf / light_triangle_area(p0, p1, p2) * t * t / cos_light;
}

// The light of Emitter entry e, picked with probability pick_pdf, seen from p.
LightConnection connect_light_of(Emitter e, float pick_pdf, vec3 p, vec2 u_point) {
    if (effect_on(EFFECT_ENVIRONMENT) && e.light == ENVIRONMENT_LIGHT) return connect_environment(pick_pdf, u_point);
    if (effect_on(EFFECT_PUNCTUAL_LIGHTS) && (e.light & PUNCTUAL_LIGHT_BIT) != 0u)
        return connect_punctual_light(e.light & ~PUNCTUAL_LIGHT_BIT, pick_pdf, p);
    if (effect_on(EFFECT_EMISSIVE_TRIANGLES) && (e.light & PUNCTUAL_LIGHT_BIT) == 0u && e.light != ENVIRONMENT_LIGHT)
        return connect_triangle_light(e.light, p, u_point, pick_pdf);
    return make_invalid_connection();  // a kind of light compiled out (--disable-effect)
}

// connect_light_of, and for BDPT's weights the light subpaths' pick (by the table: e.pick_pdf) over NEE's, which
// differ with the light tree.
LightConnection connect_emitter(Emitter e, float pick_pdf, vec3 p, vec2 u_point) {
    LightConnection c = connect_light_of(e, pick_pdf, p, u_point);
    if (effect_on(EFFECT_LIGHT_TREE)) c.emission_over_direct *= e.pick_pdf / pick_pdf;
    return c;
}

// BDPT with the light tree: a light subpath left tree light `entry` along dir (from a point of triangle tri, when the
// light is one) and first arrived at q, dist away. NEE at q would have sampled where it left with another density than
// the table's, which the subpath's dvcm assumed (light_subpath.glsl): their ratio, per unit area (for a point or spot
// light, of the picks alone).
float tree_over_table_density(LightTreePoint q, uint entry, uint tri, vec3 dir, float dist) {
    Emitter e = load_emitter(entry);
    if (!effect_on(EFFECT_EMISSIVE_TRIANGLES) || (e.light & PUNCTUAL_LIGHT_BIT) != 0u)
        return tree_light_pick_pdf(q, entry) / e.pick_pdf;
    TrianglePositions tp = load_triangle_positions(tri);
    vec3 p0 = vec3(tp.p0_x, tp.p0_y, tp.p0_z);
    float cos_light = abs(dot(normalize(cross(vec3(tp.p1_x, tp.p1_y, tp.p1_z) - p0, vec3(tp.p2_x, tp.p2_y, tp.p2_z) - p0)), dir));
    float direct_pdf = tree_emitter_hit_pdf(q, tri, entry + 1u, dist, cos_light);  // per solid angle
    return direct_pdf * cos_light / (dist * dist * load_triangle_shading(tri).light_pdf_area);
}

// The light tree's pick: one share for the tree, one for each light outside it (light_tree_share), then the walk.
LightConnection sample_light_tree_connection(LightTreePoint q, float u, vec2 u_point, bool reuse) {
    uint outside = params.emitter_count - params.light_tree_lights;
    float scaled = u * float(outside + 1u);
    uint slot = min(uint(scaled), outside);
    u = min(scaled - float(slot), ONE_BELOW_ONE);
    uint entry = params.light_tree_lights + slot;
    float pick_pdf = light_tree_share();
    if (slot == outside) {
        LightTreeWalk walk = walk_light_tree(q, u, 0u, false);
        if (!(walk.pdf > 0.0f)) return make_invalid_connection();
        entry = walk.entry;
        pick_pdf *= walk.pdf;
        u = walk.u;
    }
    if (reuse) u_point.x = u;
    return connect_emitter(load_emitter(entry), pick_pdf, q.p, u_point);
}

// q: the shading point (its normal is read by the light tree alone).
LightConnection sample_light_connection(LightTreePoint q, float u_pick, vec2 u_point) {
    bool reuse = (params.flags & RENDER_LIGHT_PICK_REUSE) != 0u && params.emitter_count <= LIGHT_PICK_REUSE_MAX;
    if (effect_on(EFFECT_LIGHT_TREE)) return sample_light_tree_connection(q, reuse ? u_point.x : u_pick, u_point, reuse);
    Emitter e = reuse ? pick_emitter_reusing(u_point.x) : pick_emitter(u_pick);
    return connect_emitter(e, e.pick_pdf, q.p, u_point);
}
#endif
