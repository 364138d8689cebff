#include "app/cli/integrator_choice.h"

#include <algorithm>
#include <cmath>
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

// The mean of both films over every pixel and channel, and that mean's variance (each pixel's average of the two
// has the variance d^2 / 4, d their difference; the pixels are taken as independent).
struct FilmMean {
    double mean = 0.0;
    double variance = 0.0;
};

FilmMean estimate_mean(const Image& a, const Image& b) {
    FilmMean m;
    if (a.rgb.empty()) return m;
    const double n = double(a.rgb.size());
    for (size_t i = 0; i < a.rgb.size(); ++i) {
        const double d = double(a.rgb[i]) - double(b.rgb[i]);
        m.mean += 0.5 * (double(a.rgb[i]) + double(b.rgb[i])) / n;
        m.variance += 0.25 * d * d / (n * n);
    }
    return m;
}

struct Pilot {
    Integrator integrator;
    uint32_t spp;  // per film
    double score;  // relMSE x seconds for one film of the pilot: the time to reach relMSE e is score / e
    FilmMean mean;
};

// An integrator whose image's mean is far from path tracing's, beyond both pilots' noise (five standard errors) and 5%,
// misses light its strategies cannot reach in any affordable time (light tracing cannot see a lamp through smooth
// glass: its films agree, both nearly black, and would score best).
bool misses_light(const Pilot& candidate, const Pilot& path) {
    const double apart = std::abs(candidate.mean.mean - path.mean.mean);
    return apart > 5.0 * std::sqrt(candidate.mean.variance + path.mean.variance) &&
           apart > 0.05 * std::abs(path.mean.mean);
}

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
            return {settings.integrator, spp, estimate_relative_variance(a, b) * seconds, estimate_mean(a, b)};
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
            continue;  // a candidate the scene or settings rule out (unlit materials under light tracing, ...)
        }
        Pilot pilot = run_pilot(context, scene, camera, s, spp, max_spp);
        char text[160];
        const bool after_path = !pilots.empty() && pilots.front().integrator == Integrator::path;
        if (after_path && misses_light(pilot, pilots.front())) {
            std::snprintf(text, sizeof text, " %s misses light (mean %.3g against path's %.3g);",
                          to_string(candidate), pilot.mean.mean, pilots.front().mean.mean);
        } else {
            pilots.push_back(pilot);
            std::snprintf(text, sizeof text, " %s %.3g (%u spp);", to_string(candidate), pilot.score, pilot.spp);
        }
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
