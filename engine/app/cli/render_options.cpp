// One definition of the sampling options, so render and converge accept the same words.
#include "app/cli/render_options.h"

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

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

void add_integrator_option(CLI::App& app, RenderSettings& s) {
    std::map<std::string, Integrator> integrators{
        {"path", Integrator::path}, {"light", Integrator::light}, {"bdpt", Integrator::bdpt},
        {"auto", Integrator::automatic}};
    app.add_option("--integrator", s.integrator,
                   "path: path tracing from the camera with next-event estimation and MIS (default); light: light "
                   "tracing, light subpaths splatted onto the film through the camera; bdpt: bidirectional path "
                   "tracing, every strategy combined by MIS (needs --max-depth); auto (render only): a short pilot of "
                   "each, the least error per second chosen")
        ->transform(CLI::CheckedTransformer(integrators, CLI::ignore_case));
}

void add_sampling_options(CLI::App& app, RenderSettings& s) {
    std::map<std::string, PixelFilter> filters{{"box", PixelFilter::box}, {"gaussian", PixelFilter::gaussian}};
    app.add_option("--filter", s.filter, "pixel filter: box (1 pixel) or gaussian (importance sampled)")
        ->transform(CLI::CheckedTransformer(filters, CLI::ignore_case));
    app.add_option("--filter-radius", s.filter_radius, "Gaussian truncation radius in pixels")
        ->check(CLI::Range(0.5f, 8.0f));
    std::map<std::string, Sampler> samplers{{"independent", Sampler::independent}, {"sobol", Sampler::sobol}};
    app.add_option("--sampler", s.sampler,
                   "sobol: Owen-scrambled Sobol' points, stratified (default); independent: a PCG stream per path")
        ->transform(CLI::CheckedTransformer(samplers, CLI::ignore_case));
    add_integrator_option(app, s);
    std::map<std::string, bool> on_off{{"on", true}, {"off", false}};
    app.add_option("--nee", s.nee, "next-event estimation: on/off")->transform(CLI::CheckedTransformer(on_off));
    app.add_option("--mis", s.mis, "multiple importance sampling: on/off")->transform(CLI::CheckedTransformer(on_off));
    app.add_option("--rr", s.russian_roulette, "Russian roulette: on/off")->transform(CLI::CheckedTransformer(on_off));
    app.add_option("--rr-start-depth", s.rr_start_depth, "Russian roulette from this many segments on")
        ->check(CLI::Range(1u, 1000u));
    app.add_option("--rr-survival-scale", s.rr_survival_scale,
                   "Russian roulette keeps a camera path with probability min(0.95, this x its largest throughput "
                   "component) (default 2, chosen by measured efficiency; 1: the textbook's)")
        ->check(CLI::Range(0.01f, 1000.0f));
    std::map<std::string, bool> picks{{"reuse", true}, {"separate", false}};
    app.add_option("--light-pick", s.light_pick_reuse,
                   "how next-event estimation picks the light in scenes of up to 16 lights: reuse (default) the first "
                   "coordinate of the light point's 2D sample, so a quad's points stay stratified over the whole quad; "
                   "separate: a sample dimension of its own")
        ->transform(CLI::CheckedTransformer(picks, CLI::ignore_case));
    app.add_option("--light-sampler", s.light_sampler,
                   "how next-event estimation picks a light: tree (by each light's importance at the shading point: "
                   "power, distance, orientation), power (one table for the whole scene), uniform; auto (default): the "
                   "tree where the scene's lights differ in kind or material, number more than 16 or share the scene "
                   "with --env or a directional light, else power")
        ->transform(CLI::CheckedTransformer(std::map<std::string, LightSampler>{{"auto", LightSampler::automatic},
                                                                                {"tree", LightSampler::tree},
                                                                                {"power", LightSampler::power},
                                                                                {"uniform", LightSampler::uniform}},
                                            CLI::ignore_case));
    app.add_option("--wave-paths", s.wave_paths,
                   "paths in flight per wave (default: 524288 on a CPU device such as lavapipe, 4194304 on a GPU, "
                   "halved until the wave fits the device's buffer limits and a quarter of its memory)")
        ->check(CLI::Range(1024u, 1u << 22));
    add_ray_sort_option(app, s.sort_rays);
    app.add_option("--wide-stores", s.wide_stores,
                   "shade stores its structs a texel (uvec4) at a time (on, the default) or field by field (off: to "
                   "measure the difference); the image is the same")
        ->transform(CLI::CheckedTransformer(on_off));
}

void add_ray_sort_option(CLI::App& app, std::optional<bool>& sort_rays) {
    app.add_option_function<std::string>(
           "--sort-rays",
           [&sort_rays](const std::string& v) {
               if (v == "auto") sort_rays.reset();
               else sort_rays = v == "on";
           },
           "sort each bounce's rays by direction and origin before tracing them: auto/on/off (default auto: on for a "
           "GPU and a scene of at least 1024 triangles, off on a CPU device such as lavapipe, where the sort costs "
           "about what it saves); the image is the same")
        ->check(CLI::IsMember({"auto", "on", "off"}));
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
    app.add_option("--bvh-leaf-size", s.bvh_max_leaf_size, "most triangles per BVH leaf")
        ->check(CLI::Range(1u, gpu::WIDE_MAX_LEAF));
    add_effect_options(app, s);
}

namespace {

// --force-effect / --disable-effect NAME[,NAME...] over the switchable effects (layout.h EFFECT_SWITCHABLE).
void add_effect_list_option(CLI::App& app, const std::string& flag, uint32_t& bits, const std::string& help) {
    std::string words;
    for (const EffectInfo& e : list_effects())
        if (e.bit & gpu::EFFECT_SWITCHABLE) words += (words.empty() ? "" : ", ") + std::string(e.name);
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

void add_disable_effect_option(CLI::App& app, uint32_t& bits) {
    add_effect_list_option(app, "--disable-effect", bits,
                           "compile an effect out although the scene uses it, to measure what it costs");
}

void add_effect_options(CLI::App& app, RenderSettings& s) {
    add_disable_effect_option(app, s.disabled_effects);
    add_effect_list_option(app, "--force-effect", s.forced_effects,
                           "compile an effect in although the scene does not use it (same image, its cost)");
}

void add_environment_options(CLI::App& app, RenderSettings& s) {
    app.add_option("--variant", s.variant, "KHR_materials_variants: render the materials of this variant");
    const std::map<std::string, Instancing> instancing{{"auto", Instancing::automatic},
                                                                    {"on", Instancing::always},
                                                                    {"off", Instancing::never}};
    app.add_option("--instancing", s.instancing,
                   "meshes drawn by several nodes: auto (stored once when that saves >= 16384 triangles), on (always), "
                   "off (copied into world space)")
        ->transform(CLI::CheckedTransformer(instancing, CLI::ignore_case));
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
