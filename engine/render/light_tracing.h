// What light tracing (`--integrator light`, shaders/lib/integrator/README.md "Light tracing") can render today, checked before any pipeline is
// built: a scene or setting it does not handle yet is refused with the reason. One case is not detected: light
// subpaths start outside every volume, so a light inside a closed glass volume (KHR_materials_volume) is refracted as
// if it stood outside it (shaders/lib/integrator/README.md "Light tracing"; thin-walled glass around a lamp is right).
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
                                        const SceneCamera& camera, EffectBits effects);

// Throws std::invalid_argument "WHERE: --integrator light: REASON" (or bdpt) when find_light_tracing_obstacle finds one
// (and only with --integrator light or bdpt); `where` names the scene file.
void check_light_tracing(const std::string& where, const PackedScene& scene, const RenderSettings& settings,
                         const SceneCamera& camera, EffectBits effects);

// Bidirectional path tracing keeps the light subpath's vertices with 1 .. max_depth - 2 segments for the camera
// subpath to connect to (longer ones only reach the camera directly): this many per path in flight; 0 for the other
// integrators. Bounded because BDPT needs a finite --max-depth (BDPT_MAX_DEPTH at most).
inline constexpr uint32_t BDPT_MAX_DEPTH = 64;
uint32_t count_light_vertex_slots(const RenderSettings& settings);

}  // namespace fh
