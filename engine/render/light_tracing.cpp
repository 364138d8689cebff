#include "render/light_tracing.h"

#include <algorithm>
#include <stdexcept>

#include "scene/effects.h"
#include "shared/layout.h"

namespace fh {

uint32_t bdpt_depth(const RenderSettings& settings) {
    return settings.max_depth == 0 ? BDPT_DEFAULT_DEPTH : std::min(settings.max_depth, BDPT_MAX_DEPTH);
}

uint32_t count_light_vertex_slots(const RenderSettings& settings) {
    if (settings.integrator == Integrator::vcm) return bdpt_depth(settings) - 1;
    if (settings.integrator != Integrator::bdpt || bdpt_depth(settings) < 3) return 0;
    return bdpt_depth(settings) - 2;
}

namespace {

// What BDPT's own settings rule out: its strategies need NEE and MIS, and --bdpt-strategy a path it makes.
std::string find_bdpt_settings_obstacle(const RenderSettings& settings) {
    if (!settings.nee || !settings.mis)
        return "bidirectional path tracing always samples lights and combines its strategies by MIS (leave --nee "
               "and --mis on)";
    const uint32_t s = settings.bdpt_strategy_s, t = settings.bdpt_strategy_t;
    const std::string strategy = "--bdpt-strategy " + std::to_string(s) + "," + std::to_string(t);
    if (t != 0 && s + t - 1 > bdpt_depth(settings))
        return strategy + " makes paths of " + std::to_string(s + t - 1) + " segments, more than the " +
               std::to_string(bdpt_depth(settings)) + " that every strategy reaches (--max-depth, at most " +
               std::to_string(BDPT_MAX_DEPTH) + ")";
    if (t != 0 && s + t < 3 && !(s == 0 && t == 2))
        return strategy + ": a path of one segment (the camera seeing a light) is made by (0,2) alone: BDPT does not "
                          "splat a light's own vertex";
    return {};
}

}  // namespace

std::string find_light_tracing_obstacle(const PackedScene& scene, const RenderSettings& settings,
                                        const SceneCamera& camera, EffectBits effects) {
    if (connects_subpaths(settings.integrator)) {
        const std::string obstacle = find_bdpt_settings_obstacle(settings);
        if (!obstacle.empty()) return obstacle;
    }
    if ((settings.lens.on() || camera.has_lens()) && camera.orthographic)
        return "an orthographic camera's thin lens (--aperture) is an aperture around every point of its image plane, "
               "which no light subpath can aim at (use a perspective camera, or no --aperture)";
    if ((effects & gpu::EFFECT_MOTION_BLUR) && scene.moving_emitting_triangles > 0 &&
        settings.integrator == Integrator::light)
        return "light tracing does not start light subpaths on emitters that move over the shutter (" +
               std::to_string(scene.moving_emitting_triangles) +
               " triangles; --integrator bdpt sees them through its camera subpaths)";
    // Unlit materials are seen by the camera's own rays only, which BDPT has and light tracing has not.
    if ((effects & gpu::EFFECT_UNLIT) && settings.integrator == Integrator::light)
        return "light tracing does not render unlit materials (KHR_materials_unlit: only camera rays see them; "
               "--integrator bdpt does)";
    if (scene.emitters.empty() && !(connects_subpaths(settings.integrator) && scene.moving_emitting_triangles > 0))
        return "nothing in the scene emits, and there is no --env or --background";
    if (camera.orthographic && (effects & gpu::EFFECT_ENVIRONMENT))
        return "an orthographic camera sees the environment along one direction only, which no light subpath can "
               "sample (use a perspective camera, or no --env / --background)";
    return {};
}

void check_light_tracing(const std::string& where, const PackedScene& scene, const RenderSettings& settings,
                         const SceneCamera& camera, EffectBits effects) {
    if (settings.bdpt_strategy_t != 0 && settings.integrator != Integrator::bdpt)
        throw std::invalid_argument(where + ": --bdpt-strategy needs --integrator bdpt");
    if (settings.integrator == Integrator::automatic)
        throw std::invalid_argument(where + ": --integrator auto is chosen by fredholm render's pilot only; name an "
                                            "integrator here (or compare them with converge --vary integrator=...)");
    if (settings.integrator == Integrator::path) return;
    const std::string obstacle = find_light_tracing_obstacle(scene, settings, camera, effects);
    if (!obstacle.empty())
        throw std::invalid_argument(where + ": --integrator " + to_string(settings.integrator) + ": " + obstacle +
                                    "; use --integrator path");
}

}  // namespace fh
