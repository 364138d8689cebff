// One definition of the sampling options, so render and converge accept the same words.
#include "app/cli/render_options.h"

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "app/cli/setting_table.h"
#include "render/techniques.h"
#include "scene/effects.h"
#include "shared/layout.h"

namespace fh {

void add_tone_options(CLI::App& app, float& exposure_ev, ToneCurve& tone_curve, const std::string& what) {
    app.add_option("--exposure", exposure_ev, what + " exposure in stops");
    std::map<std::string, ToneCurve> curves{{"aces", ToneCurve::aces}, {"clamp", ToneCurve::clamp}};
    app.add_option("--tonemap", tone_curve, what + " tone curve: aces (Narkowicz ACES fit) or clamp")
        ->transform(CLI::CheckedTransformer(curves, CLI::ignore_case));
}

void add_integrator_option(CLI::App& app, RenderSettings& s) { add_setting_options(app, s, {"integrator"}); }

void add_sampling_options(CLI::App& app, RenderSettings& s) {
    add_setting_options(app, s,
                        {"filter", "filter-radius", "sampler", "integrator", "merge-radius", "microfacet", "nee", "mis", "rr", "rr-start-depth",
                         "rr-survival-scale", "light-pick", "light-sampler", "wave-paths", "sort-rays", "wide-stores"});
}

void add_ray_sort_option(CLI::App& app, std::optional<bool>& sort_rays) {
    add_setting_option(app, "sort-rays", [&sort_rays](const RenderSettings& s) { sort_rays = s.sort_rays; });
}

void add_robustness_options(CLI::App& app, RenderSettings& s) {
    std::string words;
    for (const TechniqueInfo& t : list_techniques()) words += (words.empty() ? "" : ", ") + std::string(t.name);
    app.add_option_function<std::vector<std::string>>(
           "--disable-technique",
           [&s](const std::vector<std::string>& names) {
               for (const std::string& name : names) s.disabled_techniques |= find_technique(name);
           },
           "switch a robustness technique off, to measure its cost or show what it prevents (" + words + ")")
        ->delimiter(',')
        ->check([](const std::string& name) {
            try {
                find_technique(name);
                return std::string();
            } catch (const std::invalid_argument& e) {
                return std::string(e.what());
            }
        });
    add_setting_options(app, s, {"bvh-leaf-size"});
    add_effect_options(app, s);
}

namespace {

// --force-effect / --disable-effect NAME[,NAME...] over the switchable effects (SWITCHABLE_EFFECTS).
void add_effect_list_option(CLI::App& app, const std::string& flag, EffectBits& bits, const std::string& help) {
    std::string words;
    for (const EffectInfo& e : list_effects())
        if (e.bit & SWITCHABLE_EFFECTS) words += (words.empty() ? "" : ", ") + std::string(e.name);
    app.add_option_function<std::vector<std::string>>(
           flag,
           [&bits](const std::vector<std::string>& names) {
               for (const std::string& name : names) bits |= find_switchable_effect(name);
           },
           help + " (" + words + ")")
        ->delimiter(',')
        ->check([](const std::string& name) {
            try {
                find_switchable_effect(name);
                return std::string();
            } catch (const std::invalid_argument& e) {
                return std::string(e.what());
            }
        });
}

}  // namespace

void add_disable_effect_option(CLI::App& app, EffectBits& bits) {
    add_effect_list_option(app, "--disable-effect", bits,
                           "compile an effect out although the scene uses it, to measure what it costs");
}

void add_effect_options(CLI::App& app, RenderSettings& s) {
    add_disable_effect_option(app, s.disabled_effects);
    add_effect_list_option(app, "--force-effect", s.forced_effects,
                           "compile an effect in although the scene does not use it (same image, its cost)");
}

void add_environment_options(CLI::App& app, RenderSettings& s) {
    add_setting_options(app, s, {"variant", "instancing", "tangents", "memory-limit"});
    auto* env = app.add_option("--env", s.environment_file,
                               "environment light: equirectangular OpenEXR or Radiance .hdr map around the scene")
                    ->check(CLI::ExistingFile);
    app.add_option("--env-intensity", s.environment_intensity, "scale of the --env radiance")
        ->check(CLI::Range(0.0f, 1.0e30f));
    app.add_option("--env-rotation", s.environment_rotation, "turn the --env map about +Y, degrees")
        ->check(CLI::Range(-36000.0f, 36000.0f));
    app.add_option_function<std::vector<float>>(
           "--background",
           [&s](const std::vector<float>& rgb) {
               s.has_background = true;
               for (int i = 0; i < 3; ++i) s.background[i] = rgb[size_t(i)];
           },
           "constant environment radiance R,G,B (default: none, black)")
        ->delimiter(',')
        ->expected(3)
        ->check(CLI::Range(0.0f, 1.0e30f))
        ->excludes(env);
}

void add_lens_options(CLI::App& app, RenderSettings& s) {
    LensSettings& lens = s.lens;
    auto* f_number = app.add_option("--aperture", lens.f_number,
                                    "thin lens: f-number (focal length from the camera's yfov over --sensor-height); "
                                    "default none, a pinhole")
                         ->check(CLI::Range(0.1, 1.0e6));
    app.add_option("--aperture-radius", lens.aperture_radius, "thin lens: aperture radius in scene units (0: pinhole)")
        ->check(CLI::Range(0.0, 1.0e30))
        ->excludes(f_number);
    app.add_option("--sensor-height", lens.sensor_height_mm,
                   "film height in mm that the vertical field of view spans, for --aperture (default 24: 35 mm full frame)")
        ->check(CLI::Range(0.01, 10000.0));
    auto* distance = app.add_option("--focus-distance", lens.focus_distance,
                                    "distance in focus along the view direction, scene units (default: the surface "
                                    "seen at the image centre)")
                         ->check(CLI::Range(1.0e-9, 1.0e30));
    app.add_option_function<std::vector<double>>(
           "--focus-on",
           [&lens](const std::vector<double>& xy) {
               lens.focus_on_given = true;
               lens.focus_on[0] = xy[0];
               lens.focus_on[1] = xy[1];
           },
           "focus on the surface seen at pixel X,Y (0,0: top left)")
        ->delimiter(',')
        ->expected(2)
        ->check(CLI::Range(0.0, 65536.0))
        ->excludes(distance);
    app.add_option("--aperture-blades", lens.blades, "aperture shape: 0 a disk (default), 3 or more a regular polygon")
        ->check(CLI::IsMember({0u, 3u, 4u, 5u, 6u, 7u, 8u, 9u, 10u, 11u, 12u, 13u, 14u, 15u, 16u}));
    app.add_option("--aperture-rotation", lens.rotation_degrees, "turn the polygonal aperture, degrees")
        ->check(CLI::Range(-360.0, 360.0));
}

std::string describe_shutter(const RenderSettings& s) {
    if (!s.has_shutter()) return "none";
    char text[64];
    std::snprintf(text, sizeof text, "%.9g,%.9g", s.shutter_open, s.shutter_close);
    return text;
}

void add_animation_options(CLI::App& app, RenderSettings& s) {
    app.add_option("--animation", s.animation, "glTF animation to pose the scene by, index or name (default the first)");
    app.add_option_function<double>(
           "--time",
           [&s](double t) {
               s.animate = true;
               s.time = t;
           },
           "pose the scene at this time, seconds, by --animation (default: the file's static transforms)")
        ->check(CLI::Range(-1.0e9, 1.0e9));
    app.add_option_function<std::vector<double>>(
           "--shutter",
           [&s](const std::vector<double>& v) {
               if (!(v[0] <= v[1])) throw CLI::ValidationError("--shutter", "OPEN must not come after CLOSE");
               if (!(std::abs(v[0]) <= 1.0e9 && std::abs(v[1]) <= 1.0e9))
                   throw CLI::ValidationError("--shutter", "times must lie within 1e9 seconds");
               s.shutter_open = v[0];
               s.shutter_close = v[1];
           },
           "motion blur: open and close the shutter at these times, seconds relative to --time (default 0,0: none)")
        ->delimiter(',')
        ->expected(2);
}

}  // namespace fh
