// `fredholm render --integrator auto` (shaders/lib/integrator/README.md "Bidirectional path tracing"): the integrator chosen by measurement, not
// by guessing. Every integrator the scene and settings allow renders a short pilot of two independent films; the one
// whose error times render time is least (the time it needs to reach any given relMSE) renders the image.
#pragma once
#include <string>

#include "render/settings.h"
#include "scene/pack.h"
#include "scene/scene.h"
#include "vk/context.h"

namespace fh {

// What the pilot found; `report` is one line naming each candidate's relMSE x seconds and the choice.
struct IntegratorChoice {
    Integrator integrator = Integrator::path;
    std::string report;
};

// `settings` as the render will use them (integrator auto; spp the render's, which bounds the pilot).
IntegratorChoice choose_integrator_by_pilot(const vk::Context& context, const PackedScene& scene,
                                            const SceneCamera& camera, const RenderSettings& settings);

}  // namespace fh
