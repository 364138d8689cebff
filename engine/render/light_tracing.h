// What light tracing (`--integrator light`, shaders/lib/integrator/README.md "Light tracing") and BDPT can render
// today, checked before any pipeline is built: a scene or setting they do not handle yet is refused with the reason
// (dispersion, a thin lens, motion blur and the Gaussian filter are carried: "Dispersion", "The camera's effects"; a
// light inside glass starts its subpaths in the glass's volume: render/light_media.h).
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

// Bidirectional path tracing makes paths of up to bdpt_depth(settings) segments by every strategy: its light subpaths,
// whose vertices are stored, stop there. Longer paths (up to --max-depth; unlimited by default) are made by the camera
// subpath's own two strategies, next-event estimation and hitting a light, weighted against each other as path
// tracing weights them (shaders/lib/integrator/README.md "Paths longer than the stored subpaths"). The depth is
// --max-depth where that is at most BDPT_MAX_DEPTH, else BDPT_MAX_DEPTH, and BDPT_DEFAULT_DEPTH without a --max-depth.
inline constexpr uint32_t BDPT_MAX_DEPTH = 64;
inline constexpr uint32_t BDPT_DEFAULT_DEPTH = 16;
uint32_t bdpt_depth(const RenderSettings& settings);

// The light subpath's vertices with 1 .. bdpt_depth - 2 segments are kept for the camera subpath to connect to (longer
// ones only reach the camera directly): this many per path in flight; 0 for the other integrators.
uint32_t count_light_vertex_slots(const RenderSettings& settings);

}  // namespace fh
