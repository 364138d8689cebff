// The table of render settings (setting_table.h) and the consumers' loops over it.
#include "app/cli/setting_table.h"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "app/cli/render_options.h"
#include "render/camera/lens.h"
#include "render/techniques.h"
#include "scene/effects.h"
#include "scene/memory_limit.h"
#include "shared/layout.h"

namespace fh {
namespace {

std::string lowercase(std::string word) {
    for (char& c : word) c = char(std::tolower(static_cast<unsigned char>(c)));
    return word;
}

// One of `words` (any case), as its index; throws naming them.
size_t parse_choice(const std::string& word, std::initializer_list<const char*> words) {
    const std::string w = lowercase(word);
    std::string list;
    size_t i = 0;
    for (const char* choice : words) {
        if (w == choice) return i;
        list += (i++ ? (i == words.size() ? " or " : ", ") : "") + std::string(choice);
    }
    throw std::invalid_argument("'" + word + "' is not " + list);
}

bool parse_on_off(const std::string& word) { return parse_choice(word, {"off", "on"}) == 1; }

uint64_t parse_whole(const std::string& word, uint64_t low, uint64_t high) {
    size_t used = 0;
    unsigned long long value = 0;
    try {
        if (!word.empty() && std::isdigit(static_cast<unsigned char>(word[0]))) value = std::stoull(word, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used == 0 || used != word.size() || value < low || value > high)
        throw std::invalid_argument("'" + word + "' is not a whole number in [" + std::to_string(low) + ", " +
                                    std::to_string(high) + "]");
    return value;
}

double parse_real(const std::string& word, double low, double high) {
    size_t used = 0;
    double value = 0.0;
    try {
        value = std::stod(word, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used == 0 || used != word.size() || !(value >= low && value <= high)) {
        char range[64];
        std::snprintf(range, sizeof range, "[%g, %g]", low, high);
        throw std::invalid_argument("'" + word + "' is not a number in " + range);
    }
    return value;
}

std::string on_off(bool on) { return on ? "on" : "off"; }

std::string nine_digits(double value) {  // as the metadata has always written numbers
    char text[32];
    std::snprintf(text, sizeof text, "%.9g", value);
    return text;
}

std::string describe_environment(const RenderSettings& s) {
    char text[128];
    if (s.has_background) {
        std::snprintf(text, sizeof text, "background %.9g,%.9g,%.9g", double(s.background[0]), double(s.background[1]),
                      double(s.background[2]));
        return text;
    }
    if (s.environment_file.empty()) return "none";
    std::snprintf(text, sizeof text, " intensity %.9g rotation %.9g", double(s.environment_intensity),
                  double(s.environment_rotation));
    return std::filesystem::path(s.environment_file).filename().string() + text;
}

const char* instancing_name(Instancing i) {
    return i == Instancing::always ? "on" : i == Instancing::never ? "off" : "auto";
}

std::vector<SettingInfo> make_table() {
    using S = RenderSettings;
    using W = const std::string&;
    std::vector<SettingInfo> t;
    // Path length and seeds.
    t.push_back({"seed", "UINT", "random seed", "fredholm:seed", "seed", true, false, nullptr,
                 [](S& s, W w) { s.seed = uint32_t(parse_whole(w, 0, std::numeric_limits<uint32_t>::max())); },
                 [](const S& s) { return std::to_string(s.seed); }, [](const S& s) { return nlohmann::json(s.seed); }});
    t.push_back({"max-depth", "UINT", "longest path in segments after the camera (0 = unlimited)", "fredholm:max_depth",
                 "max_depth", true, true, nullptr,
                 [](S& s, W w) { s.max_depth = uint32_t(parse_whole(w, 0, 100000)); },
                 [](const S& s) { return std::to_string(s.max_depth); },
                 [](const S& s) { return nlohmann::json(s.max_depth); }});
    t.push_back({"camera", "INT", "glTF camera index (default: the first camera, or a camera that frames the scene)",
                 "fredholm:camera", nullptr, true, false, nullptr,
                 [](S& s, W w) { s.camera = int(parse_whole(w, 0, std::numeric_limits<int>::max())); },
                 [](const S& s) { return std::to_string(s.camera); }});
    // Pixel filter and sampler.
    t.push_back({"filter", "box|gaussian", "pixel filter: box (1 pixel) or gaussian (importance sampled)",
                 "fredholm:filter", nullptr, true, true, nullptr,
                 [](S& s, W w) { s.filter = parse_choice(w, {"box", "gaussian"}) ? PixelFilter::gaussian : PixelFilter::box; },
                 [](const S& s) { return std::string(to_string(s.filter)); }});
    t.push_back({"filter-radius", "FLOAT", "Gaussian truncation radius in pixels", "fredholm:filter_radius", nullptr,
                 true, false, nullptr, [](S& s, W w) { s.filter_radius = float(parse_real(w, 0.5, 8.0)); },
                 [](const S& s) { return nine_digits(double(s.filter_radius)); }});
    t.push_back({"sampler", "independent|sobol",
                 "sobol: Owen-scrambled Sobol' points, stratified (default); independent: a PCG stream per path",
                 "fredholm:sampler", "sampler", true, true, nullptr,
                 [](S& s, W w) { s.sampler = parse_choice(w, {"independent", "sobol"}) ? Sampler::sobol : Sampler::independent; },
                 [](const S& s) { return std::string(to_string(s.sampler)); }});
    // How the light transport equation is solved.
    t.push_back({"integrator", "path|light|bdpt|vcm|auto",
                 "path: path tracing from the camera with next-event estimation and MIS (default); light: light "
                 "tracing, light subpaths splatted onto the film through the camera; bdpt: bidirectional path "
                 "tracing, every strategy combined by MIS; vcm: BDPT and vertex merging by MIS (consistent, not "
                 "unbiased: its bias shrinks with the samples); auto (render only): a short pilot of path, light and "
                 "bdpt, the least error per second chosen",
                 "fredholm:integrator", "integrator", true, true, "path",
                 [](S& s, W w) {
                     const Integrator all[] = {Integrator::path, Integrator::light, Integrator::bdpt, Integrator::vcm,
                                               Integrator::automatic};
                     s.integrator = all[parse_choice(w, {"path", "light", "bdpt", "vcm", "auto"})];
                 },
                 [](const S& s) { return std::string(to_string(s.integrator)); }});
    t.push_back({"merge-radius", "FLOAT",
                 "with --integrator vcm: the merging radius at the first sample, as a fraction of the scene's "
                 "bounding-sphere radius (default 0.001); it shrinks as 1 / n^(1/8) over the samples",
                 "fredholm:merge_radius", "merge_radius", true, true, "0.001",
                 [](S& s, W w) { s.merge_radius = float(parse_real(w, 1.0e-6, 0.5)); },
                 [](const S& s) { return nine_digits(double(s.merge_radius)); },
                 [](const S& s) { return nlohmann::json(s.merge_radius); }});
    t.push_back({"bdpt-strategy", nullptr, "with --integrator bdpt: one strategy (S light, T camera vertices) alone",
                 "fredholm:bdpt_strategy", nullptr, true, false, "all", nullptr,
                 [](const S& s) {
                     return s.bdpt_strategy_t ? std::to_string(s.bdpt_strategy_s) + "," + std::to_string(s.bdpt_strategy_t)
                                              : std::string("all");
                 },
                 nullptr, "add_render_options (render/render_command.cpp)"});
    t.push_back({"microfacet", "compensated|single",
                 "rough GGX lobes (metals, specular layers, clear coats): compensated (default) gives back the light that bounces "
                 "between microfacets, so a white rough metal reflects all it receives; single: the glTF spec's "
                 "single-scattering GGX",
                 "fredholm:microfacet", "microfacet", true, true, "single",
                 [](S& s, W w) {
                     s.microfacet = parse_choice(w, {"compensated", "single"}) ? Microfacet::single : Microfacet::compensated;
                 },
                 [](const S& s) { return std::string(s.microfacet == Microfacet::single ? "single" : "compensated"); }});
    t.push_back({"nee", "on|off", "next-event estimation: on/off", "fredholm:nee", nullptr, true, true, nullptr,
                 [](S& s, W w) { s.nee = parse_on_off(w); }, [](const S& s) { return on_off(s.nee); }});
    t.push_back({"mis", "on|off", "multiple importance sampling: on/off", "fredholm:mis", nullptr, true, true, nullptr,
                 [](S& s, W w) { s.mis = parse_on_off(w); }, [](const S& s) { return on_off(s.mis); }});
    t.push_back({"rr", "on|off", "Russian roulette: on/off", "fredholm:rr", nullptr, true, true, nullptr,
                 [](S& s, W w) { s.russian_roulette = parse_on_off(w); },
                 [](const S& s) { return on_off(s.russian_roulette); }});
    t.push_back({"rr-start-depth", "UINT", "Russian roulette from this many segments on", "fredholm:rr_start_depth",
                 "rr_start_depth", true, true, nullptr,
                 [](S& s, W w) { s.rr_start_depth = uint32_t(parse_whole(w, 1, 1000)); },
                 [](const S& s) { return std::to_string(s.rr_start_depth); },
                 [](const S& s) { return nlohmann::json(s.rr_start_depth); }});
    t.push_back({"rr-survival-scale", "FLOAT",
                 "Russian roulette keeps a camera path with probability min(0.95, this x its largest throughput "
                 "component) (default 2, chosen by measured efficiency; 1: the textbook's)",
                 "fredholm:rr_survival_scale", "rr_survival_scale", true, true, nullptr,
                 [](S& s, W w) { s.rr_survival_scale = float(parse_real(w, 0.01, 1000.0)); },
                 [](const S& s) { return nine_digits(double(s.rr_survival_scale)); },
                 [](const S& s) { return nlohmann::json(s.rr_survival_scale); }});
    // Which light next-event estimation samples.
    t.push_back({"light-pick", "reuse|separate",
                 "how next-event estimation picks the light in scenes of up to 16 lights: reuse (default) the first "
                 "coordinate of the light point's 2D sample, so a quad's points stay stratified over the whole quad; "
                 "separate: a sample dimension of its own",
                 "fredholm:light_pick", "light_pick", true, true, nullptr,
                 [](S& s, W w) { s.light_pick_reuse = parse_choice(w, {"separate", "reuse"}) == 1; },
                 [](const S& s) { return std::string(s.light_pick_reuse ? "reuse" : "separate"); }});
    // The statistics hold the sampler auto resolved to (PackedScene::light_sampler), written by the render itself.
    t.push_back({"light-sampler", "auto|tree|power|uniform",
                 "how next-event estimation picks a light: tree (by each light's importance at the shading point: "
                 "power, distance, orientation), power (one table for the whole scene), uniform; auto (default): the "
                 "tree where the scene's lights differ in kind or material, number more than 16 or share the scene "
                 "with --env or a directional light, else power",
                 "fredholm:light_sampler", nullptr, true, true, "power",
                 [](S& s, W w) { s.light_sampler = parse_light_sampler(lowercase(w)); },
                 [](const S& s) { return std::string(light_sampler_name(s.light_sampler)); }});
    t.push_back({"memory-limit", "SIZE",
                 "the most memory the scene and the render may take, e.g. 100M, 1.5G (host and device; their sum on a CPU "
                 "device such as lavapipe); a scene that needs more is refused before its textures are decoded or its "
                 "buffers allocated (default: three quarters of physical memory)",
                 nullptr, "memory_limit", false, false, nullptr,
                 [](S& s, W w) { s.memory_limit = parse_memory_size(w); },
                 [](const S& s) { return s.memory_limit ? std::to_string(s.memory_limit) : std::string("default"); },
                 [](const S& s) { return nlohmann::json(s.resolved_memory_limit()); }});
    // How the device runs the wave: the same image either way.
    t.push_back({"wave-paths", "UINT",
                 "paths in flight per wave (default: 524288 on a CPU device such as lavapipe, 4194304 on a GPU, "
                 "halved until the wave fits the device's buffer limits and a quarter of its memory)",
                 nullptr, "wave_paths", false, false, nullptr,
                 [](S& s, W w) { s.wave_paths = uint32_t(parse_whole(w, 1024, 1u << 22)); },
                 [](const S& s) { return std::to_string(s.wave_paths); },
                 [](const S& s) { return nlohmann::json(s.wave_paths); }});
    t.push_back({"sort-rays", "auto|on|off",
                 "sort each bounce's rays by direction and origin before tracing them: auto/on/off (default auto: on "
                 "for a GPU and a scene of at least 1024 triangles, off on a CPU device such as lavapipe, where the "
                 "sort costs about what it saves); the image is the same",
                 nullptr, "sort_rays", false, true, nullptr,
                 [](S& s, W w) {
                     const size_t i = parse_choice(w, {"auto", "on", "off"});
                     if (i == 0) s.sort_rays.reset();
                     else s.sort_rays = i == 1;
                 },
                 [](const S& s) { return std::string(!s.sort_rays ? "auto" : *s.sort_rays ? "on" : "off"); },
                 [](const S& s) { return nlohmann::json(s.sort_rays.value_or(false)); }});
    t.push_back({"wide-stores", "on|off",
                 "shade stores its structs a texel (uvec4) at a time (on, the default) or field by field (off: to "
                 "measure the difference); the image is the same",
                 nullptr, "wide_stores", false, false, nullptr, [](S& s, W w) { s.wide_stores = parse_on_off(w); },
                 [](const S& s) { return on_off(s.wide_stores); },
                 [](const S& s) { return nlohmann::json(s.wide_stores); }});
    // Measurement switches: robustness techniques, the BVH, effects.
    t.push_back({"disable-technique", nullptr, "robustness techniques switched off", "fredholm:disabled_techniques",
                 "disabled_techniques", true, false, nullptr, nullptr,
                 [](const S& s) { return name_techniques(s.disabled_techniques); }, nullptr,
                 "add_robustness_options (render_options.cpp)"});
    t.push_back({"bvh-leaf-size", "UINT", "most triangles per BVH leaf", "fredholm:bvh_leaf_size", nullptr, false, false,
                 nullptr, [](S& s, W w) { s.bvh_max_leaf_size = uint32_t(parse_whole(w, 1, gpu::WIDE_MAX_LEAF)); },
                 [](const S& s) { return std::to_string(s.bvh_max_leaf_size); }});
    // What the scene shows: light from outside, the lens, the pose, the materials' variant.
    t.push_back({"environment", nullptr, "--env FILE, --env-intensity, --env-rotation or --background R,G,B",
                 "fredholm:environment", "environment", true, false, nullptr, nullptr, describe_environment, nullptr,
                 "add_environment_options (render_options.cpp)"});
    t.push_back({"lens", nullptr, "the thin lens: --aperture or --aperture-radius and the rest", "fredholm:lens",
                 "lens", true, false, nullptr, nullptr, [](const S& s) { return describe_lens(s.lens); }, nullptr,
                 "add_lens_options (render_options.cpp)"});
    t.push_back({"aperture", nullptr, "a thin lens's f-number (0: the pinhole)", nullptr, nullptr, false, true, nullptr,
                 [](S& s, W w) {
                     const double n = parse_real(w, 0.0, 1e6);
                     if (n != 0.0 && n < 0.1) throw std::invalid_argument("'" + w + "' is not 0 or an f-number");
                     s.lens.f_number = n;
                     s.lens.aperture_radius = 0.0;
                 },
                 [](const S& s) { return nine_digits(s.lens.f_number); }, nullptr, "add_lens_options (render_options.cpp)"});
    t.push_back({"aperture-radius", nullptr, "a thin lens's aperture radius in scene units", nullptr, nullptr, false,
                 true, nullptr,
                 [](S& s, W w) {
                     s.lens.aperture_radius = parse_real(w, 0.0, 1e30);
                     s.lens.f_number = 0.0;
                 },
                 [](const S& s) { return nine_digits(s.lens.aperture_radius); }, nullptr,
                 "add_lens_options (render_options.cpp)"});
    t.push_back({"animation", nullptr, "the glTF animation the scene is posed by", "fredholm:animation", nullptr, true,
                 false, nullptr, nullptr,
                 [](const S& s) { return !s.animate ? std::string("none") : s.animation.empty() ? "first" : s.animation; },
                 nullptr, "add_animation_options (render_options.cpp)"});
    t.push_back({"time", nullptr, "the time the scene is posed at", "fredholm:time", nullptr, true, false, nullptr,
                 nullptr, [](const S& s) { return s.animate ? nine_digits(s.time) : std::string("static"); }, nullptr,
                 "add_animation_options (render_options.cpp)"});
    t.push_back({"shutter", nullptr, "motion blur's shutter, OPEN,CLOSE", "fredholm:shutter", "shutter", true, false,
                 nullptr, nullptr, describe_shutter, nullptr, "add_animation_options (render_options.cpp)"});
    t.push_back({"variant", "TEXT", "KHR_materials_variants: render the materials of this variant", "fredholm:variant",
                 "variant", true, false, nullptr, [](S& s, W w) { s.variant = w; },
                 [](const S& s) { return s.variant.empty() ? std::string("default") : s.variant; }});
    t.push_back({"disable-effect", nullptr, "effects compiled out although the scene uses them",
                 "fredholm:disabled_effects", "disabled_effects", true, false, nullptr, nullptr,
                 [](const S& s) { return describe_effects(s.disabled_effects); }, nullptr,
                 "add_effect_options (render_options.cpp); converge --vary effect:NAME=on|off"});
    t.push_back({"force-effect", nullptr, "effects compiled in although the scene does not use them",
                 "fredholm:forced_effects", "forced_effects", true, false, nullptr, nullptr,
                 [](const S& s) { return describe_effects(s.forced_effects); }, nullptr,
                 "add_effect_options (render_options.cpp); converge --vary effect:NAME=on|off"});
    t.push_back({"instancing", "auto|on|off",
                 "meshes drawn by several nodes: auto (stored once when that saves >= 16384 triangles), on (always), "
                 "off (copied into world space)",
                 nullptr, nullptr, false, false, nullptr,
                 [](S& s, W w) {
                     const Instancing all[] = {Instancing::automatic, Instancing::always, Instancing::never};
                     s.instancing = all[parse_choice(w, {"auto", "on", "off"})];
                 },
                 [](const S& s) { return std::string(instancing_name(s.instancing)); }});
    t.push_back({"tangents", "mikktspace|triangle",
                 "without TANGENT: MikkTSpace tangents (default, what normal maps are baked against), or each "
                 "triangle's own frame (to compare with)",
                 "fredholm:tangents", "tangents", true, true, "triangle",
                 [](S& s, W w) {
                     s.tangents = parse_choice(w, {"mikktspace", "triangle"}) ? Tangents::triangle : Tangents::mikktspace;
                 },
                 [](const S& s) { return std::string(s.tangents == Tangents::triangle ? "triangle" : "mikktspace"); }});
    return t;
}

}  // namespace

const std::vector<SettingInfo>& setting_table() {
    static const std::vector<SettingInfo> table = make_table();
    return table;
}

const SettingInfo& find_setting(const std::string& name) {
    for (const SettingInfo& e : setting_table())
        if (name == e.name) return e;
    std::string names;
    for (const SettingInfo& e : setting_table()) names += (names.empty() ? "" : ", ") + std::string(e.name);
    throw std::invalid_argument("no setting '" + name + "' (" + names + ")");
}

namespace {

// The entry's option, each word parsed by `apply` after the same parser checked it on default settings.
void add_entry_option(CLI::App& app, const SettingInfo& e, std::function<void(const std::string&)> apply) {
    if (!e.values || !e.parse) throw std::logic_error(std::string("setting ") + e.name + " has its own options");
    app.add_option_function<std::string>(std::string("--") + e.name, std::move(apply), e.help)
        ->option_text(e.values)
        ->check(
            [&e](const std::string& word) {
                RenderSettings scratch;
                try {
                    e.parse(scratch, word);
                    return std::string();
                } catch (const std::invalid_argument& error) {
                    return std::string(error.what());
                }
            },
            e.values, e.name);
}

}  // namespace

void add_setting_options(CLI::App& app, RenderSettings& settings, std::initializer_list<const char*> names) {
    for (const char* name : names) {
        const SettingInfo& e = find_setting(name);
        add_entry_option(app, e, [&settings, &e](const std::string& word) { e.parse(settings, word); });
    }
}

void add_setting_option(CLI::App& app, const char* name, std::function<void(const RenderSettings&)> take) {
    const SettingInfo& e = find_setting(name);
    add_entry_option(app, e, [&e, take](const std::string& word) {
        RenderSettings parsed;
        e.parse(parsed, word);
        take(parsed);
    });
}

std::string vary_keys() {
    std::string keys;
    for (const SettingInfo& e : setting_table())
        if (e.can_vary) keys += std::string(keys.empty() ? "" : ", ") + e.name;
    return keys + ", effect:NAME";
}

void apply_vary(const std::string& key, const std::string& value, RenderSettings& settings) {
    if (key.rfind("effect:", 0) == 0) {
        // on: compiled in whether or not the scene uses it; off: compiled out although the scene uses it.
        const EffectBits bit = find_switchable_effect(key.substr(7));
        const bool on = parse_on_off(value);
        settings.forced_effects = on ? settings.forced_effects | bit : settings.forced_effects & ~bit;
        settings.disabled_effects = on ? settings.disabled_effects & ~bit : settings.disabled_effects | bit;
        return;
    }
    for (const SettingInfo& e : setting_table())
        if (e.can_vary && key == e.name) {
            try {
                e.parse(settings, value);
            } catch (const std::invalid_argument& error) {
                throw std::invalid_argument(key + ": " + error.what());
            }
            // A curve per integrator compares integrators; the pilot that picks one is not a curve.
            if (key == "integrator" && settings.integrator == Integrator::automatic)
                throw std::invalid_argument(key + ": '" + value + "' is not path, light, bdpt or vcm");
            return;
        }
    throw std::invalid_argument("unknown key '" + key + "' (" + vary_keys() + ")");
}

std::string describe_changed_options(const RenderSettings& settings) {
    const RenderSettings defaults;
    std::string line;
    for (const SettingInfo& e : setting_table()) {
        if (!e.values || !e.parse) continue;  // added by their own functions: printed by their own describers
        const std::string value = e.describe(settings);
        if (value != e.describe(defaults)) line += std::string(" --") + e.name + " " + value;
    }
    return line;
}

bool same_settings(const RenderSettings& a, const RenderSettings& b) {
    for (const SettingInfo& e : setting_table())
        if (e.describe(a) != e.describe(b)) return false;
    return true;
}

}  // namespace fh
