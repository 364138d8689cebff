// Which volumes each light stands in (KHR_materials_volume), where light tracing's and BDPT's subpaths start: a lamp
// inside a closed glass bulb starts its subpaths in the glass's volume, as a camera inside one starts its paths there
// (camera/camera_medium.h, whose probes these are). An emissive triangle is probed from its centroid (the triangle
// itself skipped), a point or spot light from its position; the environment and directional lights stand outside
// everything.
#pragma once
#include <vector>

#include "render/camera/camera_medium.h"
#include "scene/pack.h"
#include "shared/layout.h"

namespace fh {

// Beyond this many lights, each emitting material is probed once, at its first triangle, and all its triangles take
// that answer (a scene of thousands of emissive triangles: a probe of 14 rays each would cost more than the render).
inline constexpr size_t MAX_PROBED_LIGHTS = 4096;
inline constexpr uint32_t LIGHT_PROBE_RAYS = 14;

// Per Emitter entry of `scene`, its volumes innermost first (INVALID_INDEX past the last), as BINDING_LIGHT_MEDIA holds
// them. `trace` traces any number of probes.
std::vector<gpu::uvec4> find_light_media(const PackedScene& scene, const TraceProbes& trace);

}  // namespace fh
