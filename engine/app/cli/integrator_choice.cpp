#include "app/cli/integrator_choice.h"

#include <algorithm>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <vector>

#include "render/renderer.h"
#include "render/device_defaults.h"

namespace fh {

namespace {

// A pilot's films start at PILOT_SPP samples each (fewer for a render of fewer) and double until one takes
// PILOT_SECONDS of render time (so the time is not the waves' fixed cost, nor the error a handful of samples' luck),
// or until a film has a quarter of the render's samples.
constexpr uint32_t PILOT_SPP = 4;
constexpr double PILOT_SECONDS = 0.25;

// Estimated relMSE of one film (converge's definition, mean (x - r)^2 / (r^2 + 0.01)) from two independent ones: the
// variance of each is half the mean squared difference.
double estimate_relative_variance(const Image& a, const Image& b) {
    double sum = 0.0;
    for (size_t i = 0; i < a.rgb.size(); ++i) {
        const double mean = 0.5 * (double(a.rgb[i]) + double(b.rgb[i]));
        const double d = double(a.rgb[i]) - double(b.rgb[i]);
        sum += 0.5 * d * d / (mean * mean + 0.01);
    }
    return a.rgb.empty() ? 0.0 : sum / double(a.rgb.size());
}

struct Pilot {
    Integrator integrator;
    uint32_t spp;  // per film
    double score;  // relMSE x seconds for one film of the pilot: the time to reach relMSE e is score / e
};

Pilot run_pilot(const vk::Context& context, const PackedScene& scene, const SceneCamera& camera,
                const RenderSettings& settings, uint32_t spp, uint32_t max_spp) {
    Renderer renderer(context, scene, camera, settings);
    while (true) {
        renderer.clear_film();
        const RenderStats first = renderer.render_samples(0, spp);
        const Image a = renderer.read_film();
        renderer.clear_film();
        const RenderStats second = renderer.render_samples(spp, 2 * spp);
        const Image b = renderer.read_film();
        const double seconds = 0.5 * (first.render_seconds + second.render_seconds);
        if (seconds >= PILOT_SECONDS || 2 * spp > max_spp)
            return {settings.integrator, spp, estimate_relative_variance(a, b) * seconds};
        spp *= 2;
    }
}

}  // namespace

IntegratorChoice choose_integrator_by_pilot(const vk::Context& context, const PackedScene& scene,
                                            const SceneCamera& camera, const RenderSettings& settings) {
    const uint32_t spp = std::max(1u, std::min(PILOT_SPP, settings.spp / 8));
    const uint32_t max_spp = std::max(spp, settings.spp / 4);
    std::vector<Pilot> pilots;
    std::string report = "--integrator auto: pilots of two films each, relMSE x seconds:";
    for (Integrator candidate : {Integrator::path, Integrator::light, Integrator::bdpt}) {
        RenderSettings s = settings;
        s.integrator = candidate;
        s.spp = 2 * max_spp;
        s.bdpt_strategy_s = s.bdpt_strategy_t = 0;
        s = with_device_defaults(s, context, scene);  // as the render will choose it (an explicit --wave-paths stays)
        try {
            check_render_settings(scene, camera, s);
        } catch (const std::invalid_argument&) {
            report += std::string(" ") + to_string(candidate) + " not possible;";
            continue;  // a candidate the scene or settings rule out (dispersion under light subpaths, unbounded depth)
        }
        pilots.push_back(run_pilot(context, scene, camera, s, spp, max_spp));
        char text[96];
        std::snprintf(text, sizeof text, " %s %.3g (%u spp);", to_string(candidate), pilots.back().score,
                      pilots.back().spp);
        report += text;
    }
    const auto best = std::min_element(pilots.begin(), pilots.end(),
                                       [](const Pilot& x, const Pilot& y) { return x.score < y.score; });
    IntegratorChoice choice;
    choice.integrator = best->integrator;
    choice.report = report + " chose " + to_string(choice.integrator);
    return choice;
}

}  // namespace fh
