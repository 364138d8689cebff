// fredholm info: scene statistics and the effect table (scene/effects.h), as text or JSON.
#include "app/info/info_command.h"

#include <CLI/CLI.hpp>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>

#include "app/cli/render_options.h"
#include "app/cli/session.h"
#include "app/cli/setting_table.h"
#include "render/device_defaults.h"
#include "render/memory_estimate.h"
#include "render/vertex_merging.h"
#include "scene/effects.h"

namespace fh {
namespace {

// The state of one effect in the compiled set, and why.
std::string describe_decision(const EffectDecision& d, EffectBits compiled) {
    const bool on = (compiled & d.bit) != 0;
    if (on == d.on) return d.why;
    return on ? "forced on (--force-effect); the scene: " + d.why : "disabled (--disable-effect); the scene: " + d.why;
}

}  // namespace

void add_info_options(CLI::App& app, InfoCommand& c) {
    app.add_option("scene", c.scene, "glTF 2.0 scene (.gltf or .glb)")->required()->check(CLI::ExistingFile);
    app.add_flag("--json", c.json, "print one JSON object instead of text");
    add_environment_options(app, c.settings);
    add_lens_options(app, c.settings);
    add_animation_options(app, c.settings);
    add_effect_options(app, c.settings);
    add_setting_options(app, c.settings, {"merge-radius"});
}

namespace {

// What a render of this scene takes (render/memory_estimate.h): the host's share, and the device's for the default
// film at the wave sizes the devices default to (the render itself checks the wave it chooses).
struct MemorySummary {
    uint64_t host = 0, device_cpu = 0, device_gpu = 0, limit = 0;
    double per_path = 0.0;
};

MemorySummary summarise_memory(const PreparedScene& p, const RenderSettings& settings) {
    const EffectBits effects = select_effects(p.packed.effects.bits, settings.forced_effects, settings.disabled_effects);
    const PathStore store = make_path_store(settings);
    const auto device = [&](uint32_t paths) {
        return estimate_render_memory(p.packed, settings.film_width(), settings.film_height(), paths, effects, store);
    };
    MemorySummary m;
    for (const MemoryUse& use : host_render_uses(p.scene, device(1))) m.host += use.bytes;
    m.device_cpu = device(CPU_WAVE_PATHS).device_bytes();
    m.device_gpu = device(GPU_WAVE_PATHS).device_bytes();
    m.per_path = bytes_per_path(p.packed, effects, store);
    m.limit = settings.resolved_memory_limit();
    return m;
}

// What each integrator's estimate is: path, light and BDPT are unbiased; VCM's merges make it consistent only.
std::string describe_estimators(const PreparedScene& p, const RenderSettings& settings) {
    const double scene_radius = scene_bounding_radius(p.packed);
    char vcm[256];
    std::snprintf(vcm, sizeof vcm,
                  "vcm consistent, not unbiased (merging radius %.3g scene units at the first sample, %g of the bounding "
                  "sphere's radius; x %.3g by sample 1024)",
                  double(merge_radius_at(settings, scene_radius, 0)), double(settings.merge_radius),
                  double(merge_radius_at(settings, 1.0, 1023)) / double(merge_radius_at(settings, 1.0, 0)));
    return std::string("path, light, bdpt unbiased; ") + vcm;
}

}  // namespace

int run_info(const InfoCommand& c) {
    const PreparedScene p = prepare_scene(c.scene, c.settings);
    const SceneEffects& effects = p.packed.effects;
    const EffectBits compiled = select_effects(effects.bits, c.settings.forced_effects, c.settings.disabled_effects);
    nlohmann::ordered_json j;
    j["scene"] = c.scene.string();
    j["triangles"] = p.scene.rendered_triangle_count();
    j["triangles_stored"] = p.scene.triangle_count();
    j["triangles_unique"] = p.scene.unique_triangle_count;
    j["instances"] = p.scene.instances.size();
    j["materials"] = p.scene.materials.size();
    j["textures"] = p.packed.texture_images.size();
    j["texture_bytes"] = p.packed.texels.size() * 4;
    j["emitters"] = p.packed.emitters.size();
    j["punctual_lights"] = p.packed.punctual_lights.size();
    j["light_sampler"] = describe_light_sampler(p.packed);
    j["cameras"] = p.scene.cameras.size();
    j["variants"] = p.scene.variants;
    j["animations"] = p.scene.animations;
    if (!p.scene.animation.empty()) {
        j["animation"] = p.scene.animation;
        j["animation_start"] = p.scene.animation_start;
        j["animation_end"] = p.scene.animation_end;
    }
    j["bounds_min"] = {p.scene.bounds_min.x, p.scene.bounds_min.y, p.scene.bounds_min.z};
    j["bounds_max"] = {p.scene.bounds_max.x, p.scene.bounds_max.y, p.scene.bounds_max.z};
    j["bvh_nodes"] = p.bvh_nodes;
    j["bvh_depth"] = p.bvh_depth;
    j["load_seconds"] = p.load_seconds;
    j["bvh_build_seconds"] = p.bvh_build_seconds;
    const MemorySummary memory = summarise_memory(p, c.settings);
    j["memory"] = {{"host_bytes", memory.host},
                   {"device_bytes_cpu_wave", memory.device_cpu},
                   {"device_bytes_gpu_wave", memory.device_gpu},
                   {"device_bytes_per_path", memory.per_path},
                   {"film", std::to_string(c.settings.film_width()) + "x" + std::to_string(c.settings.film_height())},
                   {"limit_bytes", memory.limit}};
    j["estimators"] = describe_estimators(p, c.settings);
    j["effects"] = describe_effects(compiled);
    nlohmann::ordered_json table = nlohmann::ordered_json::array();
    for (const EffectDecision& d : effects.decisions)
        table.push_back({{"effect", d.name}, {"on", (compiled & d.bit) != 0}, {"why", describe_decision(d, compiled)}});
    j["effect_table"] = table;
    if (c.json) {
        std::printf("%s\n", j.dump(2).c_str());
        return 0;
    }
    std::printf("%s\n", c.scene.string().c_str());
    std::printf("  triangles          %zu rendered, %zu stored, %zu unique; %zu instances\n",
                p.scene.rendered_triangle_count(), p.scene.triangle_count(), p.scene.unique_triangle_count,
                p.scene.instances.size());
    std::printf("  materials          %zu; textures %zu (%.1f MiB of texels)\n", p.scene.materials.size(),
                p.packed.texture_images.size(), double(p.packed.texels.size()) * 4.0 / (1024.0 * 1024.0));
    std::printf("  lights             %zu in the light table (%zu punctual); NEE: %s\n", p.packed.emitters.size(),
                p.packed.punctual_lights.size(), describe_light_sampler(p.packed).c_str());
    std::printf("  cameras            %zu\n", p.scene.cameras.size());
    if (!p.scene.animations.empty()) {
        std::string names;
        for (const std::string& a : p.scene.animations) names += (names.empty() ? "" : ", ") + a;
        std::printf("  animations         %s\n", names.c_str());
    }
    if (!p.scene.animation.empty())
        std::printf("  posed at           t = %g s by %s (keys from %g to %g s)\n", c.settings.time,
                    p.scene.animation.c_str(), p.scene.animation_start, p.scene.animation_end);
    std::printf("  bounds             (%g, %g, %g) to (%g, %g, %g)\n", p.scene.bounds_min.x, p.scene.bounds_min.y,
                p.scene.bounds_min.z, p.scene.bounds_max.x, p.scene.bounds_max.y, p.scene.bounds_max.z);
    std::printf("  BVH                %zu nodes, depth %u (load %.3f s, build %.3f s)\n", p.bvh_nodes, p.bvh_depth,
                p.load_seconds, p.bvh_build_seconds);
    std::printf("  memory             host %s; device %s with %u paths in flight (a CPU device's default), %s with "
                "%u (a GPU's), %.0f bytes per path, for %ux%u; limit %s\n",
                format_bytes(memory.host).c_str(), format_bytes(memory.device_cpu).c_str(), CPU_WAVE_PATHS,
                format_bytes(memory.device_gpu).c_str(), GPU_WAVE_PATHS, memory.per_path, c.settings.film_width(),
                c.settings.film_height(), format_bytes(memory.limit).c_str());
    std::printf("  estimators         %s\n", describe_estimators(p, c.settings).c_str());
    std::printf("effects compiled: %s\n", describe_effects(compiled).c_str());
    for (const EffectDecision& d : effects.decisions)
        std::printf("  %-3s %-27s %s\n", (compiled & d.bit) ? "on" : "off", d.name, describe_decision(d, compiled).c_str());
    return 0;
}

}  // namespace fh
