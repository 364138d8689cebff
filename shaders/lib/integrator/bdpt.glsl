// Bidirectional path tracing (`--integrator bdpt`): the MIS weights of every strategy (s, t), power heuristic, without
// storing whole paths. Each subpath carries two running quantities, dvcm and dvc (Georgiev 2012, "Implementing vertex
// connection and merging", tech. report, with merging left out; cf. SmallVCM), from which the weight of a strategy
// follows at the vertex where it joins the subpaths: the sum, over every other strategy making the same path, of its
// density squared over this one's. The densities are the samplers' without Russian roulette and in area measure
// (geometric cosines): the weights then sum to one over the strategies that can make each path, so the estimate stays
// unbiased, and roulette only changes how often a strategy runs. Strategies BDPT runs (Veach 1997 notation, s light
// vertices and t camera vertices): s = 0 (a camera path hits a light, shade.comp), s = 1 (next-event estimation,
// shade.comp), t = 1 (a light vertex splatted onto the film, light_shade.comp), s, t >= 2 (connect_subpaths.comp).
// A camera ray that sees a light directly (path of one segment) is s = 0 alone: the light's own vertex is not splatted.
// Vertex connection and merging (`vcm`, FH_INTEGRATOR) adds a third quantity, dvm, and the merges' share eta to every
// sum (the same report's full recursion); merge.comp weights the merges (lib/integrator/vertex_merging.glsl).
#ifndef FH_BDPT_GLSL
#define FH_BDPT_GLSL
#include "lib/integrator/light_tracing.glsl"
#include "lib/light/lights.glsl"

float mis_power(float ratio) { return ratio * ratio; }

// The weight of a strategy whose competitors add up to `others` (relative to it); 0 where a density overflowed.
float mis_weight(float others) {
    float w = 1.0f / (1.0f + others);
    return w >= 0.0f ? w : 0.0f;
}

// Vertex merging's eta: how much denser the merges make a path than one connection, pi r^2 x the light subpaths they
// search (the wave's; StagePush.merge_radius). Both subpaths' stages of a wave see the same.
float merge_eta() {
    return PI * push.merge_radius * push.merge_radius * float(push.pixel_count * push.sample_count);
}

// What every connection's sum adds for the merges (SmallVCM's mMisVmWeightFactor), and what a merge's adds for the
// connections (mMisVcWeightFactor); vcm only.
float vm_weight_factor() { return mis_power(merge_eta()); }
float vc_weight_factor() { return mis_power(1.0f / merge_eta()); }

// A subpath's competitors where it joins the other at a vertex: its own dvcm, its dvc through the pdf `reverse` of
// drawing its previous direction from the joint, and with merging the merges there.
float joined_subpath_sum(PathMis m, float reverse) {
    float sum = m.dvcm + m.dvc * mis_power(reverse);
    if (vcm) sum += vm_weight_factor();
    return sum;
}

// True where a path of `segments` segments is made by every strategy, so BDPT's weights apply; a longer one is made
// by the camera subpath's next-event estimation and light hits alone, weighted as path tracing weights them
// (FrameParams.bdpt_depth: the light subpaths stop there).
bool bdpt_weighs(uint segments) { return bdpt && segments <= params.bdpt_depth; }

// What strategy (s, t) counts with MIS weight `mis`: --bdpt-strategy S,T keeps that strategy alone, unweighted.
float weight_strategy(uint s, uint t, float mis) {
    if (params.bdpt_strategy == 0u) return mis;
    return params.bdpt_strategy == (s << 16u | t) ? 1.0f : 0.0f;
}

// The subpath arrived at a surface after a segment of length dist, at geometric cosine cos_g to the arriving direction
// (no distance for the first segment from a light at infinity: its densities are per area already).
void account_segment(inout PathMis m, float dist, float cos_g, bool with_distance) {
    if (with_distance) m.dvcm *= mis_power(dist * dist);
    m.dvcm /= mis_power(cos_g);
    m.dvc /= mis_power(cos_g);
}

// The subpath left a surface along a direction drawn with solid-angle pdf `forward`, at geometric cosine cos_out;
// `reverse`: the pdf with which the other side's sampler, arriving along that direction, would draw the arriving one.
void account_scattering(inout PathMis m, float cos_out, float forward, float reverse) {
    float dvc_sum = m.dvc * mis_power(reverse) + m.dvcm;
    if (vcm) dvc_sum += vm_weight_factor();
    m.dvc = mis_power(cos_out / forward) * dvc_sum;
    m.dvcm = mis_power(1.0f / forward);
}

// With the light tree, NEE picks a light with another probability than the table light subpaths start by, which a
// light subpath's first dvcm (NEE's density over its own, light_subpath.glsl) assumes NEE shares. A light outside the tree (the environment, a directional light)
// has its share wherever NEE stands: folded in here. A tree light's pick depends on the point NEE stands at, the
// subpath's first vertex: its entry is kept for light_shade.comp, which folds it in there (fold_tree_pick_at_first_hit).
void fold_tree_pick_at_start(inout PathMis m, uint entry, float table_pick_pdf) {
    if (entry < params.light_tree_lights) m.flags |= (entry + 1u) << PATH_MIS_TREE_LIGHT_SHIFT;
    else m.dvcm *= mis_power(light_tree_share() / table_pick_pdf);
}

// The light subpath (quantities m, their flags from its start) arrived at its first vertex q, dist along dir from the
// tree light it left (from triangle tri's surface, if that light is one): NEE's density at q for the subpath's
// starting point over the table's, which dvcm assumed, folded in.
void fold_tree_pick_at_first_hit(inout PathMis m, LightTreePoint q, uint tri, vec3 dir, float dist) {
    uint entry_plus_one = m.flags >> PATH_MIS_TREE_LIGHT_SHIFT;
    if (entry_plus_one == 0u) return;
    m.dvcm *= mis_power(tree_over_table_density(q, entry_plus_one - 1u, tri, dir, dist));
    m.flags &= (1u << PATH_MIS_TREE_LIGHT_SHIFT) - 1u;
}

// Vertex merging: dvm after a segment arriving at geometric cosine cos_g, and after a scattering (m: the quantities
// before account_scattering changes them).
float segment_dvm(float dvm, float cos_g) { return dvm / mis_power(cos_g); }
float scattered_dvm(float dvm, PathMis m, float cos_out, float forward, float reverse) {
    return mis_power(cos_out / forward) * (dvm * mis_power(reverse) + m.dvcm * vc_weight_factor() + 1.0f);
}

// A camera subpath's quantities at the eye, for a ray along dir (forward: the camera's axis at the ray's time): the
// light subpaths per sample index (the film's pixels) over the ray's solid-angle pdf, 1 / (pixel area x cos^3), from
// the pinhole or the ray's point on a thin lens alike (the lens point's density is the light side's too). An
// orthographic camera's rays are drawn per unit area of the image plane (1 / pixel area): its first segment has no
// distance to convert (camera_segment_has_distance). The Gaussian filter keeps the box's density (light_tracing.glsl).
PathMis start_camera_mis(vec3 dir, vec3 forward) {
    float c = params.camera_type == CAMERA_ORTHOGRAPHIC ? 1.0f : dot(dir, forward);
    PathMis m;
    m.dvcm = mis_power(c * c * c / film_importance_scale());
    m.dvc = 0.0f;
    m.light_vertices = 0u;
    m.flags = 0u;
    return m;
}

bool camera_segment_has_distance(uint segments) {
    return segments > 1u || params.camera_type != CAMERA_ORTHOGRAPHIC;
}

// s = 0 on an emissive triangle: the camera subpath (quantities at the hit) found light it could have reached by NEE
// (area density direct_pdf_area) or by a light subpath leaving that point (picked with area density table_pdf_area,
// then cosine-weighted, on either side of a double-sided emitter at 1/2 each). The two differ with the light tree, by
// which NEE picks while light subpaths start by the table.
float weight_emission_hit(PathMis m, float direct_pdf_area, float table_pdf_area, float cos_light, bool double_sided) {
    float emission_pdf = table_pdf_area * cos_light * INV_PI * (double_sided ? 0.5f : 1.0f);
    return mis_weight(mis_power(direct_pdf_area) * m.dvcm + mis_power(emission_pdf) * m.dvc);
}

// s = 0 on the environment: direct_pdf is NEE's solid-angle pdf of that direction, table_pdf a light subpath's (which
// then draws a point on the scene's disk).
float weight_environment_hit(PathMis m, float direct_pdf, float table_pdf) {
    return mis_weight(mis_power(direct_pdf) * m.dvcm + mis_power(table_pdf / scene_disk_area()) * m.dvc);
}

// s = 1: NEE from a camera vertex to a light along wi. bsdf_pdf: the camera side's pdf of drawing wi (0 for a delta
// light); light_pdf: NEE's; emission_over_direct (lights.glsl) times cos_g: a light subpath's density of reaching the
// vertex over NEE's; reverse: the light side's pdf of drawing wo there.
float weight_light_connection(PathMis m, float bsdf_pdf, float light_pdf, float emission_over_direct, float cos_g,
                              float reverse) {
    float others = light_pdf > 0.0f ? mis_power(bsdf_pdf / light_pdf) : 0.0f;
    others += mis_power(emission_over_direct * cos_g) * joined_subpath_sum(m, reverse);
    return mis_weight(others);
}

// t = 1: a light vertex (quantities at it) seen by the camera. importance_area: the splat's importance (the camera's
// density over the light subpaths per sample index) times the geometric cosine towards the camera; reverse: the camera
// side's pdf of drawing the light-side direction there.
float weight_camera_connection(PathMis m, float importance_area, float reverse) {
    return mis_weight(mis_power(importance_area) * joined_subpath_sum(m, reverse));
}

// s, t >= 2: camera vertex y and light vertex z joined by a segment of squared length dist2. Per side: the area density
// with which the other side's sampler reaches this vertex (its forward pdf times this vertex's cosine / dist2), and
// the pdf this side's sampler has of drawing its previous vertex's direction from the joint (reverse).
float weight_subpath_connection(PathMis camera, float camera_reverse, float light_forward_area, PathMis light,
                                float light_reverse, float camera_forward_area) {
    float w_light = mis_power(camera_forward_area) * joined_subpath_sum(light, light_reverse);
    float w_camera = mis_power(light_forward_area) * joined_subpath_sum(camera, camera_reverse);
    return mis_weight(w_light + w_camera);
}

// A merge of camera vertex y (quantities at it, with its dvm) with a light vertex near it (its dvcm and dvm), the
// light arriving along wl: camera_forward, the camera side's pdf of drawing wl at y; camera_reverse, the light side's
// of drawing the camera's previous direction there. Every connection, and the merges at the other vertices, compete.
float weight_merge(PathMis camera, float camera_dvm, float camera_reverse, float light_dvcm, float light_dvm,
                   float camera_forward) {
    float w_light = light_dvcm * vc_weight_factor() + light_dvm * mis_power(camera_forward);
    float w_camera = camera.dvcm * vc_weight_factor() + camera_dvm * mis_power(camera_reverse);
    return mis_weight(w_light + w_camera);
}
#endif
