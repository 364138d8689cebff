// Where a light subpath starts (light_generate.comp): a light picked by power from the same alias table next-event
// estimation uses, a point on it and a first direction, with the throughput of that first segment (emitted radiance
// over the densities of all three choices), and the splat of the light's own vertex as the camera sees it.
// Emissive triangles: a uniform point and a cosine-weighted direction on an emitting side. Point lights: a uniform
// direction; spot lights: a uniform direction in the outer cone. Directional lights and the environment: a direction
// (the environment's importance sampling), then a point on the disk of the scene's bounding sphere facing it, so
// every point of the scene can be reached. Punctual lights are not seen by the camera (as in path tracing, where no
// ray can hit them); the environment is, through a splat along the sampled direction that must leave the scene.
#ifndef FH_LIGHT_SUBPATH_GLSL
#define FH_LIGHT_SUBPATH_GLSL
#include "lib/light/lights.glsl"
#include "lib/integrator/light_tracing.glsl"
#include "lib/geometry/surface.glsl"
#include "lib/integrator/bdpt.glsl"

struct LightStart {
    vec3 power;           // the first segment's throughput; 0: no subpath
    vec3 origin;
    vec3 dir;
    uint triangle;        // the emitting triangle (the first ray leaves it), or INVALID_INDEX
    ShadowRayItem splat;  // the light itself seen by the camera, or an empty splat
    PathMis mis;          // bidirectional path tracing's quantities at the light (lib/integrator/bdpt.glsl)
    uint emitter;         // the Emitter entry picked (its volumes: BINDING_LIGHT_MEDIA)
};

LightStart make_no_light_start() {
    LightStart s;
    s.power = vec3(0.0f);
    s.origin = vec3(0.0f);
    s.dir = vec3(0.0f, 0.0f, 1.0f);
    s.triangle = INVALID_INDEX;
    s.splat = make_empty_splat();
    s.mis.dvcm = s.mis.dvc = 0.0f;
    s.mis.light_vertices = 0u;
    s.mis.flags = 0u;
    s.emitter = 0u;
    return s;
}

// A ray along `dir` (unit) from the disk of the scene's bounding sphere that faces it (u: where on the disk); its
// area is returned in `area`.
vec3 sample_scene_disk(vec3 dir, vec2 u, out float area) {
    vec3 centre = 0.5f * (params.scene_min.xyz + params.scene_max.xyz);
    float radius = scene_disk_radius();
    area = scene_disk_area();
    Frame f = make_frame(dir);
    vec2 d = sample_concentric_disk(u) * radius;
    return centre - radius * dir + d.x * f.t + d.y * f.b;
}

LightStart start_on_triangle(uint triangle, vec2 u_point, vec2 u_dir, float u_side, SplatCamera cam, uint subpath) {
    LightStart start = make_no_light_start();
    vec2 b = sample_uniform_triangle(u_point);
    // The point as a hit there would be: pulled a hair towards the centroid (surface.glsl), or a subpath started on an
    // edge of a closed room can leave it through the corner.
    SurfaceHit q = load_surface(triangle, b.x, b.y);
    Material m = load_material(q.material);
    if (effect_on(EFFECT_EMISSIVE_TEXTURE)) m = resolve_material(m, triangle, b.x, b.y);
    if (effect_on(EFFECT_ALPHA)) m.emission.xyz *= eval_coverage(triangle, b.x, b.y);
    vec3 n = q.ng;
    bool double_sided = (m.flags & MATERIAL_DOUBLE_SIDED) != 0u;
    // light_pdf_area: the area density of the whole choice (triangle by power, point uniformly).
    vec3 emitted_over_pdf = max(m.emission.xyz, vec3(0.0f)) / q.light_pdf_area;
    if (!(q.light_pdf_area > 0.0f && max_value(emitted_over_pdf) > 0.0f)) return start;
    start.triangle = triangle;
    // The light's own vertex seen by the camera: Le cos / pdf_area, times the camera's importance.
    FilmSplat splat = project_to_film(cam, q.p);
    float cos_camera = dot(n, splat.to_camera);
    if (splat.valid && (cos_camera > 0.0f || (double_sided && cos_camera < 0.0f))) {
        vec3 contrib = emitted_over_pdf * (abs(cos_camera) * splat.importance);
        start.splat = make_splat_ray(q.p, q.p_error, cos_camera > 0.0f ? n : -n, splat, contrib, triangle, subpath);
    }
    // The first segment: cosine-weighted about the emitting side (either, at 1/2 each, when double sided), so
    // Le cos / (pdf_area pdf_dir) = Le pi / pdf_area (x 2).
    vec3 side = double_sided && u_side < 0.5f ? -n : n;
    vec3 local = sample_cosine_hemisphere(u_dir);
    if (!(local.z > 0.0f)) return start;
    start.dir = to_world(make_frame(side), local);
    start.power = emitted_over_pdf * (PI * (double_sided ? 2.0f : 1.0f));
    // MIS (SmallVCM's): NEE's area density over the emission density, and the cosine over the emission density.
    float side_share = double_sided ? 0.5f : 1.0f;
    start.mis.dvcm = mis_power(PI / (local.z * side_share));
    start.mis.dvc = mis_power(PI / (q.light_pdf_area * side_share));
    start.origin = offset_ray_origin(q.p, q.p_error, side, start.dir);
    return start;
}

LightStart start_on_punctual(uint index, float pick_pdf, vec2 u_dir, vec2 u_disk) {
    LightStart start = make_no_light_start();
    PunctualLight light = load_punctual_light(index);
    vec3 intensity = light.intensity.xyz / pick_pdf;
    if (light.type == LIGHT_DIRECTIONAL) {
        float area;
        start.dir = light.direction.xyz;
        start.origin = sample_scene_disk(start.dir, u_disk, area);
        start.power = intensity * area;  // irradiance over the disk's area density
        start.mis.dvcm = mis_power(area);  // delta in direction: dvc 0
        start.mis.flags = PATH_MIS_LIGHT_AT_INFINITY;
        return start;
    }
    // Point: the whole sphere; spot: its outer cone, uniformly in solid angle.
    float cos_max = light.type == LIGHT_SPOT ? light.cos_outer : -1.0f;
    float z = 1.0f - u_dir.x * (1.0f - cos_max);
    float r = sqrt(max(0.0f, 1.0f - z * z));
    float phi = TWO_PI * u_dir.y;
    vec3 axis = light.type == LIGHT_SPOT ? light.direction.xyz : vec3(0.0f, 0.0f, 1.0f);
    start.dir = to_world(make_frame(axis), vec3(r * cos(phi), r * sin(phi), z));
    float falloff = light.type == LIGHT_SPOT ? spot_attenuation(light, z) : 1.0f;
    start.power = intensity * (falloff * TWO_PI * (1.0f - cos_max));
    start.origin = light.position.xyz;
    start.mis.dvcm = mis_power(TWO_PI * (1.0f - cos_max));  // delta in position: dvc 0
    return start;
}

LightStart start_on_environment(float pick_pdf, vec2 u_dir, vec2 u_disk, SplatCamera cam, uint subpath) {
    LightStart start = make_no_light_start();
    EnvironmentSample e = sample_environment(u_dir);  // e.dir: towards the environment
    float pdf = pick_pdf * e.pdf;
    if (!(pdf > 0.0f)) return start;
    // The environment itself seen by the camera along e.dir.
    FilmSplat splat = project_direction_to_film(cam, e.dir);
    if (splat.valid)
        start.splat = make_escape_splat_ray(e.dir, splat, e.radiance * (splat.importance / pdf), subpath);
    float area;
    start.dir = -e.dir;
    start.origin = sample_scene_disk(start.dir, u_disk, area);
    start.power = e.radiance * (area / pdf);
    start.mis.dvcm = mis_power(area);
    start.mis.dvc = mis_power(area / pdf);
    start.mis.flags = PATH_MIS_LIGHT_AT_INFINITY;
    return start;
}

// cam: where the camera sees the light's own vertex from; subpath: the subpath's index (its splat's, splats_by_path).
LightStart start_light_subpath(float u_pick, vec2 u_point, vec2 u_dir, float u_side, SplatCamera cam, uint subpath) {
    uint entry = pick_emitter_entry(u_pick);
    Emitter e = load_emitter(entry);
    LightStart start = make_no_light_start();  // a kind of light compiled out (--disable-effect)
    if (effect_on(EFFECT_ENVIRONMENT) && e.light == ENVIRONMENT_LIGHT)
        start = start_on_environment(e.pick_pdf, u_dir, u_point, cam, subpath);
    else if (effect_on(EFFECT_PUNCTUAL_LIGHTS) && (e.light & PUNCTUAL_LIGHT_BIT) != 0u)
        start = start_on_punctual(e.light & ~PUNCTUAL_LIGHT_BIT, e.pick_pdf, u_dir, u_point);
    else if (effect_on(EFFECT_EMISSIVE_TRIANGLES) && (e.light & PUNCTUAL_LIGHT_BIT) == 0u && e.light != ENVIRONMENT_LIGHT)
        start = start_on_triangle(e.light, u_point, u_dir, u_side, cam, subpath);
    start.emitter = entry;
    if (effect_on(EFFECT_LIGHT_TREE)) fold_tree_pick_at_start(start.mis, entry, e.pick_pdf);
    return start;
}
#endif
