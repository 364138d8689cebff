// Command-line options shared by every sub-command that renders: the sampling switches of RenderSettings.
#pragma once

#include <string>

#include "io/tone_curve.h"
#include "render/settings.h"

namespace CLI {
class App;
}

namespace fh {

// --exposure and --tonemap of an image shown or previewed (`what`: "PNG", "display").
void add_tone_options(CLI::App& app, float& exposure_ev, ToneCurve& tone_curve, const std::string& what);

// --integrator path|light (RenderSettings::integrator).
void add_integrator_option(CLI::App& app, RenderSettings& settings);

// --filter, --filter-radius, --sampler, --integrator, --nee, --mis, --rr, --wave-paths, --sort-rays.
void add_sampling_options(CLI::App& app, RenderSettings& settings);
// --sort-rays on|off (render/ray_sort.h).
void add_ray_sort_option(CLI::App& app, std::optional<bool>& sort_rays);

// --disable-technique NAME[,NAME...] (robustness techniques, to measure their cost), --bvh-leaf-size,
// --disable-effect and --force-effect.
void add_robustness_options(CLI::App& app, RenderSettings& settings);

// --disable-effect NAME[,NAME...]: effects compiled out although the scene uses them (what they cost).
void add_disable_effect_option(CLI::App& app, EffectBits& bits);

// --disable-effect NAME[,NAME...] / --force-effect NAME[,NAME...]: material effects (textures, vertex colours,
// alpha, normal maps, transmission, volumes) compiled out although used, or in although unused.
void add_effect_options(CLI::App& app, RenderSettings& settings);

// --env FILE, --env-intensity, --env-rotation, --background R,G,B; and --variant NAME (what the scene shows).
void add_environment_options(CLI::App& app, RenderSettings& settings);

// --aperture N | --aperture-radius R, --sensor-height, --focus-distance D | --focus-on X,Y, --aperture-blades,
// --aperture-rotation: the thin lens (RenderSettings::lens).
void add_lens_options(CLI::App& app, RenderSettings& settings);

// --animation N|NAME, --time T: the scene posed by a glTF animation (RenderSettings::animate).
void add_animation_options(CLI::App& app, RenderSettings& settings);

// --shutter as EXR metadata and resume compare it: "none", or "OPEN,CLOSE" in seconds.
std::string describe_shutter(const RenderSettings& settings);

}  // namespace fh
