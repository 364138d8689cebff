// choose_light_sampler: the emitter table as NEE will read it, for the sampler the render asks for.
#include "scene/light/light_sampler.h"

#include <algorithm>
#include <cstdio>
#include <set>
#include <stdexcept>

#include "scene/light/alias_table.h"
#include "scene/effects.h"
#include "scene/light/light_tree.h"
#include "scene/pack.h"

namespace fh {
namespace {

constexpr size_t TREE_AT_MORE_LIGHTS_THAN = 16;  // lib/light/lights.glsl LIGHT_PICK_REUSE_MAX

bool is_triangle(uint32_t light) { return (light & gpu::PUNCTUAL_LIGHT_BIT) == 0u && light != gpu::ENVIRONMENT_LIGHT; }

// Lights with a place go in the tree; the environment and directional lights stay outside it.
bool has_place(const PackedScene& packed, uint32_t light) {
    if (is_triangle(light)) return true;
    if (light == gpu::ENVIRONMENT_LIGHT) return false;
    return packed.punctual_lights[light & ~gpu::PUNCTUAL_LIGHT_BIT].type != gpu::LIGHT_DIRECTIONAL;
}

glm::dvec3 corner(const gpu::TrianglePositions& t, int k) {
    if (k == 0) return {t.p0_x, t.p0_y, t.p0_z};
    if (k == 1) return {t.p1_x, t.p1_y, t.p1_z};
    return {t.p2_x, t.p2_y, t.p2_z};
}

double triangle_area(const gpu::TrianglePositions& t) {
    return 0.5 * glm::length(glm::cross(corner(t, 1) - corner(t, 0), corner(t, 2) - corner(t, 0)));
}

// Why the tree pays, or not: the kinds of light with a place (emitting materials, point and spot lights) and how many.
std::string tree_reason(const PackedScene& packed, size_t& sources, size_t& placed) {
    std::set<uint32_t> materials;
    size_t punctual = 0;
    placed = 0;
    for (const gpu::Emitter& e : packed.emitters) {
        if (!has_place(packed, e.light)) continue;
        ++placed;
        if (is_triangle(e.light)) materials.insert(packed.shading[e.light].material);
        else ++punctual;
    }
    sources = materials.size() + punctual;
    return std::to_string(placed) + " lights with a place: " + std::to_string(materials.size()) +
           " emitting material(s), " + std::to_string(punctual) + " point or spot light(s); " +
           std::to_string(packed.emitters.size() - placed) + " outside (environment, directional)";
}

// Equal weights: NEE picks each light as often (Mitsuba 3's rule).
void make_uniform(PackedScene& packed) {
    const std::vector<double> weights(packed.emitters.size(), 1.0);
    const std::vector<AliasEntry> table = build_alias_table(weights);
    const double pick_pdf = 1.0 / double(weights.size());
    for (size_t e = 0; e < packed.emitters.size(); ++e) {
        gpu::Emitter& entry = packed.emitters[e];
        entry = {entry.light, float(table[e].threshold), table[e].alias, float(pick_pdf)};
        if (is_triangle(entry.light))
            packed.shading[entry.light].light_pdf_area = float(pick_pdf / triangle_area(packed.positions[entry.light]));
        if (entry.light == gpu::ENVIRONMENT_LIGHT) packed.environment_pick_pdf = float(pick_pdf);
    }
}

LightBounds bounds_of(const PackedScene& packed, uint32_t light, double power) {
    if (!is_triangle(light)) return punctual_light_bounds(packed.punctual_lights[light & ~gpu::PUNCTUAL_LIGHT_BIT], power);
    const gpu::TrianglePositions& t = packed.positions[light];
    const bool two_sided = (packed.materials[packed.shading[light].material].flags & gpu::MATERIAL_DOUBLE_SIDED) != 0u;
    return triangle_light_bounds(corner(t, 0), corner(t, 1), corner(t, 2), power, two_sided);
}

// Tree lights first (leaf k is entry k), then the rest; the alias table rebuilt in that order (BDPT's, unused here).
void make_tree(PackedScene& packed) {
    std::vector<size_t> order(packed.emitters.size());
    for (size_t e = 0; e < order.size(); ++e) order[e] = e;
    const auto outside = std::stable_partition(order.begin(), order.end(),
                                               [&](size_t e) { return has_place(packed, packed.emitters[e].light); });
    const size_t placed = size_t(outside - order.begin());
    if (placed > gpu::MAX_TREE_LIGHTS)
        throw SceneError(packed.source + ": --light-sampler tree: " + std::to_string(placed) +
                         " lights, more than the light tree holds (" + std::to_string(gpu::MAX_TREE_LIGHTS) + ")");
    std::vector<uint32_t> lights(order.size());
    std::vector<double> power(order.size());
    for (size_t k = 0; k < order.size(); ++k) {
        lights[k] = packed.emitters[order[k]].light;
        power[k] = packed.emitter_power[order[k]];
    }
    const std::vector<AliasEntry> table = build_alias_table(power);
    std::vector<LightBounds> bounds(placed);
    for (size_t k = 0; k < order.size(); ++k) {
        packed.emitters[k] = {lights[k], float(table[k].threshold), table[k].alias, float(power[k] / packed.total_emitted_power)};
        if (k < placed) bounds[k] = bounds_of(packed, lights[k], power[k]);
        if (k < placed && is_triangle(lights[k])) packed.shading[lights[k]].flags |= uint32_t(k + 1) << gpu::TRIANGLE_LIGHT_SHIFT;
    }
    packed.emitter_power = power;
    LightTree tree = build_light_tree(bounds);
    packed.light_tree = std::move(tree.nodes);
    packed.light_tree_depth = tree.depth;
    packed.light_tree_build_seconds = tree.build_seconds;
    packed.light_tree_lights = uint32_t(placed);
    // lib/light/light_tree.glsl light_tree_share, in the same float arithmetic.
    const bool environment = std::any_of(lights.begin(), lights.end(), [](uint32_t l) { return l == gpu::ENVIRONMENT_LIGHT; });
    packed.environment_pick_pdf = environment ? 1.0f / float(uint32_t(order.size() - placed) + 1u) : 0.0f;
}

}  // namespace

const char* light_sampler_name(LightSampler sampler) {
    switch (sampler) {
    case LightSampler::automatic: return "auto";
    case LightSampler::tree: return "tree";
    case LightSampler::power: return "power";
    case LightSampler::uniform: return "uniform";
    }
    return "?";
}

LightSampler parse_light_sampler(const std::string& name) {
    for (LightSampler s : {LightSampler::automatic, LightSampler::tree, LightSampler::power, LightSampler::uniform})
        if (name == light_sampler_name(s)) return s;
    throw std::invalid_argument("'" + name + "' is not a light sampler (auto, tree, power, uniform)");
}

std::string describe_light_sampler(const PackedScene& packed) {
    const size_t lights = packed.emitters.size();
    if (packed.light_sampler != std::string("tree"))
        return std::string(packed.light_sampler) + " table over " + std::to_string(lights) + " lights";
    const double bytes = double(packed.light_tree.size() * sizeof(gpu::LightTreeNode));
    char text[200];
    std::snprintf(text, sizeof text, "tree over %u of %zu lights: depth %u, %zu nodes, %.1f KiB (%.0f bytes per light), built in %.4f s",
                  packed.light_tree_lights, lights, packed.light_tree_depth, packed.light_tree.size(), bytes / 1024.0,
                  bytes / double(std::max<uint32_t>(packed.light_tree_lights, 1)), packed.light_tree_build_seconds);
    return text;
}

void choose_light_sampler(PackedScene& packed, LightSampler requested, bool next_event) {
    if (requested == LightSampler::tree && !next_event)
        throw std::invalid_argument("--light-sampler tree picks lights for next-event estimation, which light tracing "
                                    "does not make: its light subpaths start by the table (use power or uniform)");
    size_t sources = 0, placed = 0;
    const std::string why = tree_reason(packed, sources, placed);
    const size_t lights = packed.emitters.size();  // placed < lights: an environment or a directional light besides
    LightSampler chosen = requested;
    if (chosen == LightSampler::automatic)
        chosen = next_event && placed > 0 && (sources >= 2 || placed > TREE_AT_MORE_LIGHTS_THAN || placed < lights)
                 ? LightSampler::tree
                 : LightSampler::power;
    if (placed == 0 && chosen == LightSampler::tree) chosen = LightSampler::power;  // nothing to put in it
    packed.light_sampler = light_sampler_name(chosen);
    if (chosen == LightSampler::uniform && !packed.emitters.empty()) make_uniform(packed);
    if (chosen == LightSampler::tree) make_tree(packed);
    const std::string how = chosen == LightSampler::tree ? "NEE walks the light tree" : std::string("NEE picks by the ") +
                                                                                          light_sampler_name(chosen) + " table";
    decide_light_tree_effect(packed.effects, chosen == LightSampler::tree,
                             how + (requested == LightSampler::automatic ? " (--light-sampler auto)" : "") + "; " + why);
}

}  // namespace fh
