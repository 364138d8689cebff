// Runs `fredholm converge`: reference, then per configuration one film grown at doubling spp, then the report.
#include "app/cli/render_options.h"
#include "app/cli/progress.h"
#include "app/converge/converge_command.h"
#include "render/camera/lens.h"

#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <map>
#include <memory>
#include <stdexcept>

#include "app/converge/converge_report.h"
#include "app/cli/interrupt.h"
#include "app/cli/session.h"
#include "app/cli/setting_table.h"
#include "io/atomic_write.h"
#include "io/exr.h"
#include "io/png.h"
#include "render/camera/camera_setup.h"
#include "render/renderer.h"
#include "scene/effects.h"

namespace fh {
namespace {

constexpr uint32_t REFERENCE_SEED_OFFSET = 0x5bd1e995u;  // independent streams (rng.glsl hashes the seed)
constexpr uint32_t SECOND_SEED_OFFSET = 0x9e3779b9u;

std::string slug(const std::string& name) {
    std::string s = name;
    for (char& c : s)
        if (c == '=' || c == ':') c = '-';
    return s;
}

// One film grown progressively: samples [spp, next) are added on each step; the previous image is kept for
// the variance estimate.
struct Film {
    std::unique_ptr<Renderer> renderer;
    uint32_t spp = 0;
    double seconds = 0;
    Image image, previous;
    uint32_t previous_spp = 0;

    // Returns false (and leaves the film's record unchanged) when interrupted during the step.
    bool grow(uint32_t next) {
        RenderStats stats = renderer->render_samples(spp, next, [](uint32_t, uint32_t) { return !interrupt_requested(); });
        if (stats.spp_done < next) return false;
        seconds += stats.render_seconds;
        previous = std::move(image);
        previous_spp = spp;
        spp = stats.spp_done;
        image = renderer->read_film();
        return true;
    }
    EarlierImage earlier() const { return previous_spp ? EarlierImage{&previous, previous_spp, spp} : EarlierImage{}; }
};

struct Session {
    const ConvergeCommand& command;
    PreparedScene prepared;
    SceneCamera camera;
    std::unique_ptr<vk::Context> context;
    std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
    // The scene set up for another light sampler, integrator or microfacet model than the command's (--vary
    // light-sampler=..., integrator=..., microfacet=...): prepared again, once per combination.
    mutable std::map<std::string, PreparedScene> other_lights;

    const PackedScene& packed_for(const RenderSettings& settings) const {
        if (settings.light_sampler == command.settings.light_sampler &&
            settings.integrator == command.settings.integrator && settings.microfacet == command.settings.microfacet)
            return prepared.packed;
        const std::string key = std::string(light_sampler_name(settings.light_sampler)) + "/" +
                                to_string(settings.integrator) + (settings.microfacet == Microfacet::single ? "/single" : "");
        auto it = other_lights.find(key);
        if (it == other_lights.end()) it = other_lights.emplace(key, prepare_scene(command.scene, settings)).first;
        return it->second.packed;
    }

    Film make_film(RenderSettings settings, uint32_t spp_total) const {
        settings.spp = spp_total;
        Film f;
        const PackedScene& packed = packed_for(settings);
        f.renderer = std::make_unique<Renderer>(*context, packed, apply_lens(*context, packed, camera, settings), settings);
        f.renderer->clear_film();
        return f;
    }
};

// Doubling schedule: stop at max_spp, or before a step that at the rate so far would end past the budget.
uint32_t next_spp(const Film& f, uint32_t max_spp, double budget, std::string& stop_reason) {
    if (f.spp >= max_spp) return stop_reason = "max-spp", 0;
    const uint32_t next = std::min(max_spp, f.spp * 2);
    if (f.seconds + f.seconds * double(next - f.spp) / f.spp > budget) return stop_reason = "time budget", 0;
    return next;
}

Film render_reference(Session& s, ReferenceInfo& info) {
    const ConvergeCommand& c = s.command;
    RenderSettings settings = c.settings;
    settings.seed = c.settings.seed + REFERENCE_SEED_OFFSET;
    info.kind = ReferenceInfo::rendered;
    info.seed = settings.seed;
    info.spp_asked = c.reference_spp ? c.reference_spp : std::min(16 * c.max_spp, 4096u);
    info.seconds_budget = c.reference_seconds > 0 ? c.reference_seconds : 4 * c.max_seconds;
    std::fprintf(stderr, "converge: reference: default configuration, seed %u, up to %u spp or %.0f s\n", info.seed,
                 info.spp_asked, info.seconds_budget);
    Film f = s.make_film(settings, info.spp_asked);
    std::string reason;
    for (uint32_t next = 1; next; next = next_spp(f, info.spp_asked, info.seconds_budget, reason)) {
        if (!f.grow(next)) break;
        std::fprintf(stderr, "converge: reference: %u spp, %.2f s render (%.1f s elapsed)\n", f.spp, f.seconds,
                     seconds_since(s.start));
    }
    if (interrupt_requested()) throw std::runtime_error("interrupted while rendering the reference");
    info.spp = f.spp;
    info.seconds = f.seconds;
    info.variance = estimate_variance(f.image, f.earlier());
    if (f.spp < info.spp_asked)
        std::fprintf(stderr, "converge: reference stopped at %u of %u spp by its time bound (%.0f s; --reference-seconds)\n",
                     f.spp, info.spp_asked, info.seconds_budget);
    info.source = (c.output_dir / "reference.exr").string();
    write_exr(info.source, f.image, {{"fredholm:spp", std::to_string(f.spp)}, {"fredholm:seed", std::to_string(info.seed)}});
    return f;
}

ConvergeCurve render_curve(Session& s, const NamedSettings& config, const Film* reference, size_t index,
                           size_t count) {
    const ConvergeCommand& c = s.command;
    ConvergeCurve curve{config.name, config.settings, {}, ""};
    Film a = s.make_film(config.settings, c.max_spp), b;
    if (c.two_seeds) {
        RenderSettings second = config.settings;
        second.seed += SECOND_SEED_OFFSET;
        b = s.make_film(second, c.max_spp);
    }
    for (uint32_t next = 1; next; next = next_spp(a, c.max_spp, c.max_seconds, curve.stop_reason)) {
        if (!a.grow(next) || (c.two_seeds && !b.grow(next))) {
            curve.stop_reason = "interrupted";
            break;
        }
        ConvergeStep step{a.spp, a.seconds, {}};
        step.errors = c.two_seeds ? measure_two_seed_errors(a.image, b.image)
                                  : measure_errors(a.image, reference->image, a.earlier(), reference->earlier());
        curve.steps.push_back(step);
        if (c.keep_images) {
            char name[64];
            std::snprintf(name, sizeof name, "_spp%05u.exr", a.spp);
            write_exr(c.output_dir / "images" / (slug(config.name) + name), a.image,
                      {{"fredholm:spp", std::to_string(a.spp)}, {"fredholm:config", config.name}});
        }
        std::fprintf(stderr, "converge: [%zu/%zu] %s: %u spp, %.3f s render (%.1f s elapsed), relMSE %.4g\n", index + 1,
                     count, config.name.c_str(), a.spp, a.seconds, seconds_since(s.start), step.errors.relmse);
    }
    if (!a.image.rgb.empty()) write_png(c.output_dir / (slug(config.name) + ".png"), a.image);
    return curve;
}

std::string describe_command(const ConvergeCommand& c) {
    const RenderSettings& s = c.settings;
    std::string line = "fredholm converge " + c.scene.string() + " -o " + c.output_dir.string();
    if (!c.reference.empty()) line += " --reference " + c.reference.string();
    if (c.two_seeds) line += " --two-seeds";
    if (c.reference_spp) line += " --reference-spp " + std::to_string(c.reference_spp);
    char budget[32];
    std::snprintf(budget, sizeof budget, "%g", c.max_seconds);
    line += " --max-seconds " + std::string(budget) + " --max-spp " + std::to_string(c.max_spp);
    for (const std::string& v : c.vary) line += " --vary " + v;
    line += " --width " + std::to_string(s.width) + " --height " + std::to_string(s.height) +
            describe_changed_options(s);
    if (s.forced_effects) line += " --force-effect " + describe_effects(s.forced_effects);
    if (s.disabled_effects) line += " --disable-effect " + describe_effects(s.disabled_effects);
    if (s.lens.on()) line += " " + format_lens_options(s.lens);
    if (s.animate) {
        char time[48];
        std::snprintf(time, sizeof time, " --time %.9g", s.time);
        line += time;
        if (!s.animation.empty()) line += " --animation '" + s.animation + "'";
    }
    if (s.has_shutter()) line += " --shutter " + describe_shutter(s);
    return line;
}

}  // namespace

std::vector<NamedSettings> make_configurations(const RenderSettings& base, const std::vector<std::string>& vary) {
    std::vector<NamedSettings> configs{{"default", base}};
    for (const std::string& spec : vary) {
        const size_t eq = spec.find('=');
        if (eq == std::string::npos || eq == 0 || eq + 1 == spec.size())
            throw std::invalid_argument("'" + spec + "': expected KEY=V1,V2,...");
        const std::string key = spec.substr(0, eq);
        size_t pos = eq + 1;
        while (pos <= spec.size()) {
            const size_t comma = std::min(spec.find(',', pos), spec.size());
            const std::string value = spec.substr(pos, comma - pos);
            RenderSettings s = base;
            apply_vary(key, value, s);
            bool known = false;
            for (const NamedSettings& n : configs) known = known || same_settings(n.settings, s);
            if (!known) configs.push_back({key + "=" + value, s});
            pos = comma + 1;
        }
    }
    return configs;
}

void add_converge_options(CLI::App& app, ConvergeCommand& c) {
    RenderSettings& s = c.settings;
    app.add_option("scene", c.scene, "glTF 2.0 scene (.gltf or .glb)")->required();
    app.add_option("-o,--output", c.output_dir, "report directory (created if missing)")->required();
    auto* ref = app.add_option("--reference", c.reference, "reference OpenEXR, taken as exact");
    auto* ref_spp = app.add_option("--reference-spp", c.reference_spp,
                                   "spp of the reference rendered when none is given (default min(16 x max-spp, 4096))")
                        ->check(CLI::Range(1u, 1u << 20));
    app.add_option("--reference-seconds", c.reference_seconds, "time bound of that reference (default 4 x max-seconds)")
        ->check(CLI::PositiveNumber);
    auto* two = app.add_flag("--two-seeds", c.two_seeds, "no reference: variance from two independent renders");
    ref->excludes(two)->excludes(ref_spp);
    two->excludes(ref_spp);
    app.add_option("--max-seconds", c.max_seconds, "render-time budget per configuration")->check(CLI::PositiveNumber);
    app.add_option("--max-spp", c.max_spp, "largest spp of the doubling sequence")->check(CLI::Range(1u, 1u << 20));
    app.add_option("--vary", c.vary,
                   "KEY=V1,V2,...: one curve per value, KEY one of " + vary_keys() +
                       " (effect:NAME=on,off compiles an effect in or out: a material or light effect, or "
                       "motion-blur, e.g. effect:transmission=on,off)")
        ->check(CLI::Validator(
            [](std::string& spec) {
                try {
                    make_configurations(RenderSettings{}, {spec});
                    return std::string();
                } catch (const std::invalid_argument& e) {
                    return std::string(e.what());
                }
            },
            "KEY=V1,V2,...", "vary"));
    app.add_flag("--keep-images", c.keep_images, "write every step's image to REPORT_DIR/images/");
    app.add_option("--width", s.width, "image width in pixels")->check(CLI::Range(1u, 16384u));
    app.add_option("--height", s.height, "image height in pixels")->check(CLI::Range(1u, 16384u));
    add_setting_options(app, s, {"max-depth", "seed", "camera"});
    add_sampling_options(app, s);
    add_robustness_options(app, s);
    add_environment_options(app, s);
    add_lens_options(app, s);
    add_animation_options(app, s);
    app.add_flag("--validate", c.validation, "enable Vulkan validation layers (also FREDHOLM_VALIDATION=1)");
    app.add_option("--device", c.device, "use the first Vulkan device whose name contains this");
}

int run_converge(const ConvergeCommand& c) {
    std::vector<NamedSettings> configs;
    try {
        configs = make_configurations(c.settings, c.vary);
    } catch (const std::invalid_argument& e) {
        std::fprintf(stderr, "fredholm: usage error: --vary: %s\n", e.what());
        return 2;
    }
    // As in render: without roulette and without a depth limit a path that never escapes never ends (its
    // throughput can even stick at the smallest denormal instead of reaching 0).
    for (const NamedSettings& n : configs)
        if (!n.settings.russian_roulette && n.settings.max_depth == 0) {
            std::fprintf(stderr, "fredholm: usage error: configuration %s has rr off and no depth limit: give "
                                 "--max-depth N (paths that never escape would never end)\n", n.name.c_str());
            return 2;
        }
    std::filesystem::create_directories(c.output_dir);
    check_writable(c.output_dir / "summary.json");
    if (c.keep_images) std::filesystem::create_directories(c.output_dir / "images");

    ConvergeReport report;
    report.command_line = describe_command(c);
    Session s{c, prepare_scene(c.scene, c.settings), {}, nullptr};
    s.camera = choose_camera(s.prepared.scene, c.settings.camera);
    for (const NamedSettings& n : configs) check_render_settings(s.packed_for(n.settings), s.camera, n.settings);
    Film reference;
    if (!c.reference.empty()) {
        reference.image = read_exr(c.reference);
        if (reference.image.width != int(c.settings.width) || reference.image.height != int(c.settings.height))
            throw std::runtime_error(c.reference.string() + ": reference is " + std::to_string(reference.image.width) +
                                     "x" + std::to_string(reference.image.height) + " but the render is " +
                                     std::to_string(c.settings.width) + "x" + std::to_string(c.settings.height));
        report.reference.kind = ReferenceInfo::file;
        report.reference.source = c.reference.string();
    }
    s.context = make_compute_context(c.validation, c.device);
    install_interrupt_handlers();
    if (c.two_seeds) report.reference.kind = ReferenceInfo::two_seeds;
    else if (c.reference.empty()) reference = render_reference(s, report.reference);

    report.scene = c.scene.filename().string();
    report.device = s.context->device_name();
    report.width = c.settings.width, report.height = c.settings.height;
    report.max_seconds = c.max_seconds, report.max_spp = c.max_spp;
    for (size_t i = 0; i < configs.size() && !interrupt_requested(); ++i) {
        report.curves.push_back(render_curve(s, configs[i], &reference, i, configs.size()));
        report.summaries.push_back(summarize_curve(report.curves.back(), report.width, report.height));
    }
    if (report.curves.empty() || report.curves[0].steps.empty()) throw std::runtime_error("interrupted before any step");
    write_convergence_csv(c.output_dir / "convergence.csv", report);
    write_summary_json(c.output_dir / "summary.json", report);
    write_plot_svg(c.output_dir / "plot.svg", report);
    write_report_markdown(c.output_dir / "report.md", report);

    std::fprintf(stderr, "converge: %-16s %6s %9s %10s %7s %10s\n", "configuration", "spp", "seconds", "relMSE", "slope",
                 "floor");
    for (size_t i = 0; i < report.curves.size(); ++i) {
        const ConvergeCurve& curve = report.curves[i];
        const CurveSummary& sum = report.summaries[i];
        if (curve.steps.empty()) continue;
        std::fprintf(stderr, "converge: %-16s %6u %9.3f %10.4g %7.2f %10s\n", curve.name.c_str(), curve.steps.back().spp,
                     curve.steps.back().seconds, curve.steps.back().errors.relmse, sum.slope_relmse_seconds,
                     !sum.has_bias ? "n/a" : sum.floor_significant ? "bias" : "none");
    }
    std::fprintf(stderr, "converge: wrote %s (report.md, plot.svg, convergence.csv, summary.json)\n",
                 c.output_dir.string().c_str());
    if (s.context->validation_message_count() > 0) {
        std::fprintf(stderr, "fredholm: error: %u Vulkan validation message(s)\n", s.context->validation_message_count());
        return 1;
    }
    return interrupt_requested() ? 130 : 0;
}

}  // namespace fh
