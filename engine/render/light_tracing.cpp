#include "render/light_tracing.h"

#include <stdexcept>

#include "scene/effects.h"
#include "shared/layout.h"

namespace fh {

namespace {

// Effects whose transport light_shade.comp does not carry yet, with what each means to a user.
struct Unsupported {
    uint32_t bit;
    const char* what;
};
constexpr Unsupported UNSUPPORTED[] = {
    {gpu::EFFECT_TRANSMISSION, "transmission (KHR_materials_transmission)"},
    {gpu::EFFECT_VOLUME, "volumes (KHR_materials_volume)"},
    {gpu::EFFECT_DIFFUSE_TRANSMISSION, "diffuse transmission (KHR_materials_diffuse_transmission)"},
    {gpu::EFFECT_SPECTRAL, "dispersion (KHR_materials_dispersion)"},
    {gpu::EFFECT_UNLIT, "unlit materials (KHR_materials_unlit)"},
    {gpu::EFFECT_MOTION_BLUR, "motion blur (--shutter)"},
};

}  // namespace

std::string find_light_tracing_obstacle(const PackedScene& scene, const RenderSettings& settings,
                                        const SceneCamera& camera, uint32_t effects) {
    if (settings.lens.on() || camera.has_lens()) return "light tracing does not handle a thin lens (--aperture) yet";
    for (const Unsupported& u : UNSUPPORTED)
        if (effects & u.bit) return std::string("light tracing does not handle ") + u.what + " yet";
    if (scene.emitters.empty()) return "nothing in the scene emits, and there is no --env or --background";
    if (camera.orthographic && (effects & gpu::EFFECT_ENVIRONMENT))
        return "an orthographic camera sees the environment along one direction only, which no light subpath can "
               "sample (use a perspective camera, or no --env / --background)";
    if (settings.filter != PixelFilter::box) return "light tracing splats with the box filter only (--filter box)";
    return {};
}

void check_light_tracing(const std::string& where, const PackedScene& scene, const RenderSettings& settings,
                         const SceneCamera& camera, uint32_t effects) {
    if (settings.integrator != Integrator::light) return;
    const std::string obstacle = find_light_tracing_obstacle(scene, settings, camera, effects);
    if (!obstacle.empty())
        throw std::invalid_argument(where + ": --integrator light: " + obstacle + "; use --integrator path");
}

}  // namespace fh
