// The thin lens a render asks for (RenderSettings::lens), resolved onto its camera: the aperture's radius in world
// units (from an f-number through the focal length that yfov and the sensor height imply) and the distance in focus
// (given, or found by tracing the ray through a pixel).
#pragma once
#include <cstdint>
#include <string>

#include "render/settings.h"
#include "scene/pack.h"
#include "scene/scene.h"

namespace fh {

namespace vk {
class Context;
}

// Focal length in world units of a perspective camera whose yfov spans `sensor_height_mm` of film (metres per
// world unit, as glTF says): f = sensor height / 2 / tan(yfov / 2).
double focal_length(const SceneCamera& camera, double sensor_height_mm);

// The aperture radius the settings ask for: --aperture-radius as given, or focal length / (2 N) for --aperture N.
// Throws std::invalid_argument for an f-number on an orthographic camera (it has no focal length).
double resolve_aperture_radius(const SceneCamera& camera, const LensSettings& lens);

// Distance along the view direction to the surface seen through the centre of film position `pixel` (pixels, (0,0)
// the top-left corner) by the pinhole camera. Throws std::runtime_error when that ray meets nothing.
double find_focus_distance(const vk::Context& context, const PackedScene& scene, const SceneCamera& camera,
                           uint32_t width, uint32_t height, double pixel_x, double pixel_y);

// The camera with the lens applied: unchanged for a pinhole; else the aperture and the distance in focus
// (--focus-distance, else the surface at --focus-on, else the surface at the image centre).
SceneCamera apply_lens(const vk::Context& context, const PackedScene& scene, SceneCamera camera,
                       const RenderSettings& settings);

// "pinhole", or the lens options as given, e.g. "f/2.8 sensor 24 mm, focus-on 32,32, 6 blades rotated 15 deg"
// (what a resumed render must match).
std::string describe_lens(const LensSettings& lens);

// The command-line options that give this lens, e.g. "--aperture 2.8 --focus-on 32,32" ("" for a pinhole).
std::string format_lens_options(const LensSettings& lens);

}  // namespace fh
