// What light tracing (`--integrator light`, README "Light tracing") can render today, checked before any pipeline is
// built: a scene or setting it does not handle yet is refused with the reason, never rendered wrong.
#pragma once
#include <cstdint>
#include <string>

#include "render/settings.h"
#include "scene/pack.h"
#include "scene/scene.h"

namespace fh {

// Empty when light tracing can render `scene` with `settings` through `camera`, whose stages are compiled for
// `effects` (layout.h EFFECT_*); else why not, as one phrase ("the scene has an environment light ...").
std::string find_light_tracing_obstacle(const PackedScene& scene, const RenderSettings& settings,
                                        const SceneCamera& camera, uint32_t effects);

// Throws std::invalid_argument "WHERE: --integrator light: REASON" when find_light_tracing_obstacle finds one (and
// only with --integrator light); `where` names the scene file.
void check_light_tracing(const std::string& where, const PackedScene& scene, const RenderSettings& settings,
                         const SceneCamera& camera, uint32_t effects);

}  // namespace fh
