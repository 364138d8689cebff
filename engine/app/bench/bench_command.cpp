// Benchmark: median of N renders per resolution, timing only the render (not loading, BVH or pipelines).
#include "app/bench/bench_command.h"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>

#include "app/cli/progress.h"
#include "app/cli/setting_table.h"
#include "app/cli/render_options.h"
#include "app/cli/session.h"
#include "scene/instancing.h"
#include "scene/bvh/scene_bvh.h"
#include "io/atomic_write.h"
#include "io/image.h"
#include "render/camera/camera_setup.h"
#include "render/memory_estimate.h"
#include "render/ray_tracer.h"
#include "render/renderer.h"
#include "render/device_defaults.h"
#include "render/techniques.h"
#include "scene/effects.h"
#include "shared/layout.h"

namespace fh {
namespace {

#ifndef FREDHOLM_DEFAULT_SCENE
#define FREDHOLM_DEFAULT_SCENE "scenes/cornell.gltf"
#endif

}  // namespace

void add_bench_options(CLI::App& app, BenchCommand& c) {
    app.add_option("scene", c.scene, "glTF scene (default: the shipped Cornell box)");
    app.add_option("--sizes", c.sizes, "square image sizes to time")->check(CLI::Range(16u, 8192u));
    app.add_option("--spp", c.spp, "samples per pixel")->check(CLI::Range(1u, 1u << 16));
    add_setting_option(app, "max-depth", [&c](const RenderSettings& s) { c.max_depth = s.max_depth; });
    std::map<std::string, Integrator> integrators{
        {"path", Integrator::path}, {"light", Integrator::light}, {"bdpt", Integrator::bdpt}, {"vcm", Integrator::vcm}};
    app.add_option("--integrator", c.integrator, "integrator to time: path (default), light, bdpt or vcm")
        ->transform(CLI::CheckedTransformer(integrators, CLI::ignore_case));
    app.add_option("--repeats", c.repeats, "renders per size; the median is reported")->check(CLI::Range(1u, 100u));
    app.add_flag("--techniques", c.techniques,
                 "also time each robustness technique switched off (the cost of each; rebase: load time)");
    app.add_flag("--textures", c.textures,
                 "also time the scene with its material effects compiled out (factors only), and report texture memory");
    app.add_flag("--effects", c.effects,
                 "also time the scene compiled for its own effects against every material effect compiled in "
                 "(but spectral; render time per sample and pipeline build time): what effects on demand save");
    app.add_flag("--instancing", c.instancing,
                 "also load the scene with every instance copied into world space: stored triangles, scene memory, "
                 "load + BVH time and render time of both");
    app.add_flag("--motion", c.motion,
                 "also time the render with its --shutter's motion blur against motion blur switched off (everything "
                 "where it is at the shutter's centre) and against no shutter (the scene posed there): what it costs");
    add_animation_options(app, c.pose);
    app.add_option("--env", c.environment_file, "environment light (OpenEXR or .hdr), for scenes without lights")
        ->check(CLI::ExistingFile);
    app.add_option_function<std::vector<float>>(
           "--background", [&c](const std::vector<float>& rgb) {
               c.has_background = true;
               for (int i = 0; i < 3; ++i) c.background[i] = rgb[size_t(i)];
           }, "constant environment radiance R,G,B")
        ->delimiter(',')
        ->expected(3);
    CLI::Option* trace = app.add_option("--trace-rays", c.trace_rays,
                   "only time the extend stage over the rays of this file (six float32 per ray: world-space origin, "
                   "direction), median of --repeats")
        ->check(CLI::ExistingFile);
    app.add_option("--hits-out", c.hits_out,
                   "with --trace-rays: write each ray's hit distance (float32, inf: miss; with --any-hit 1 where occluded, "
                   "else 0)");
    app.add_flag("--any-hit", c.any_hit,
                 "with --trace-rays: the rays are shadow rays (seven float32 per ray: origin, direction, t_max), timed "
                 "through the connect stage (any hit, as next-event estimation traces them); the rays in file order")
        ->needs(trace);
    app.add_option("--json", c.json, "also write the figures as JSON");
    app.add_option("--device", c.device, "use the first Vulkan device whose name contains this");
    add_setting_option(app, "bvh-leaf-size", [&c](const RenderSettings& s) { c.bvh_leaf_size = s.bvh_max_leaf_size; });
    add_ray_sort_option(app, c.sort_rays);
    add_disable_effect_option(app, c.disabled_effects);
    app.add_flag("--compare-ray-order", c.compare_ray_order,
                 "also time the render with the ray sort on against off, alternating (what sorting buys or costs)");
    app.add_flag("--compare-stores", c.compare_stores,
                 "also time the render with shade's uvec4 stores against field-by-field ones (render --wide-stores), alternating");
}

namespace {

RenderStats median_run(std::vector<RenderStats> runs) {
    std::sort(runs.begin(), runs.end(),
              [](const RenderStats& a, const RenderStats& b) { return a.render_seconds < b.render_seconds; });
    return runs[runs.size() / 2];
}

// The median-time render of `repeats` (one Renderer: pipelines are built once, outside the timing, and one
// untimed sample per pixel first lets drivers that compile at first dispatch, such as lavapipe, do so).
RenderStats time_render(const vk::Context& context, const PreparedScene& prepared, const SceneCamera& camera,
                        const RenderSettings& settings, uint32_t repeats) {
    Renderer renderer(context, prepared.packed, camera, settings);
    renderer.render_samples(0, 1);
    std::vector<RenderStats> runs;
    for (uint32_t r = 0; r < repeats; ++r) runs.push_back(renderer.render());
    return median_run(runs);
}

std::string format_stage_seconds(const RenderStats& m) {
    std::string stages;
    for (const auto& [name, seconds] : m.stage_seconds) {
        char buf[64];
        std::snprintf(buf, sizeof buf, "%s %.3f  ", name.c_str(), seconds);
        stages += buf;
    }
    return stages;
}

nlohmann::json describe_run(uint32_t size, const RenderStats& m, const std::string& disabled) {
    const double samples = double(size) * size * m.spp_done;
    const double rays = double(m.traced_rays + m.traced_shadow_rays);
    return {{"width", size},
            {"height", size},
            {"spp", m.spp_done},
            {"disabled_technique", disabled},
            {"render_seconds", m.render_seconds},
            {"samples_per_second", samples / m.render_seconds},
            {"rays_per_second", rays / m.render_seconds},
            {"stage_seconds", m.stage_seconds},
            {"nonfinite_samples", m.nonfinite_samples}};
}

// What a feature costs at one size: renders with it and without it, alternating (the machine's speed drifts), printed
// as "WITH a s, WITHOUT b s: FEATURE costs +x% of the render time". The
// variant with it is `with` rendered with `with_settings`, the one without it `without` with `without_settings`.
struct FeatureNames {
    const char* with;     // "with textures"
    const char* without;  // "factors only"
    const char* feature;  // "textures"
};

std::pair<RenderStats, RenderStats> time_feature(const vk::Context& context, const SceneCamera& camera,
                                                 RenderSettings with_settings, RenderSettings without_settings,
                                                 uint32_t size, uint32_t repeats, const PreparedScene& with,
                                                 const PreparedScene& without, const FeatureNames& names) {
    with_settings.width = with_settings.height = without_settings.width = without_settings.height = size;
    // Both renderers built first, then their renders alternate (with, without, with, ...): the machine's speed
    // drifts within seconds, and blocks of repeats would charge the drift to the feature. Both renderers' buffers
    // are held at once (twice a single render's device memory).
    Renderer with_renderer(context, with.packed, camera, with_settings);
    Renderer without_renderer(context, without.packed, camera, without_settings);
    with_renderer.render_samples(0, 1);
    without_renderer.render_samples(0, 1);
    std::vector<RenderStats> with_runs, without_runs;
    for (uint32_t r = 0; r < repeats; ++r) {
        with_runs.push_back(with_renderer.render());
        without_runs.push_back(without_renderer.render());
    }
    const RenderStats a = median_run(with_runs), b = median_run(without_runs);
    std::printf("%4ux%-4u %s %.3f s, %s %.3f s (alternating, medians of %u): %s cost %+.1f%% of the render time\n",
                size, size, names.with, a.render_seconds, names.without, b.render_seconds, repeats, names.feature,
                100.0 * (a.render_seconds - b.render_seconds) / b.render_seconds);
    std::printf("%9s %s: %s\n%9s %s: %s\n", "", names.with, format_stage_seconds(a).c_str(), "", names.without,
                format_stage_seconds(b).c_str());
    return {a, b};
}

// What building the stages costs: constructing a Renderer (pipelines, buffers) plus the first dispatch over
// what a second one takes (drivers such as lavapipe compile at first use), at 16x16 and 1 spp. Drivers keep
// their own on-disk shader caches (Mesa: ~/.cache/mesa_shader_cache, MESA_SHADER_CACHE_DISABLE=true to time
// a cold build), so a repeated run measures the warm build.
double time_pipeline_build(const vk::Context& context, const PreparedScene& prepared, const SceneCamera& camera,
                           RenderSettings settings) {
    settings.width = settings.height = 16;
    settings.spp = 1;
    const auto start = std::chrono::steady_clock::now();
    Renderer renderer(context, prepared.packed, camera, settings);
    const double constructed = seconds_since(start);
    const double first = renderer.render().render_seconds;
    const double second = renderer.render().render_seconds;
    return constructed + std::max(0.0, first - second);
}

void write_bytes_atomically(const std::filesystem::path& file, const void* data, size_t size) {
    write_file_atomically(file, [&](const std::filesystem::path& temp) {
        std::ofstream out(temp, std::ios::binary);
        out.write(static_cast<const char*>(data), std::streamsize(size));
        if (!out) throw IoError(file.string() + ": cannot write");
    });
}

// The float32 values of a ray file (`per_ray` per ray, no header).
std::vector<float> read_ray_file(const std::filesystem::path& file, size_t per_ray) {
    std::ifstream in(file, std::ios::binary);
    in.seekg(0, std::ios::end);
    const std::streamoff bytes = in ? std::streamoff(in.tellg()) : -1;
    if (bytes <= 0 || bytes % std::streamoff(per_ray * sizeof(float)) != 0)
        throw IoError(file.string() + ": not a ray file (" + std::to_string(per_ray) +
                      " float32 per ray, at least one ray)");
    std::vector<float> values(size_t(bytes) / sizeof(float));
    in.seekg(0);
    in.read(reinterpret_cast<char*>(values.data()), bytes);
    if (!in) throw IoError(file.string() + ": cannot read");
    return values;
}

struct TraceFigures {
    std::vector<double> seconds;  // sorted
    double median = 0.0;
    std::vector<float> per_ray;   // what --hits-out writes
    nlohmann::json json;          // what the stage counted
};

// One queue item per `per_ray` values of a ray file, made by make(values of the ray, its index).
template <typename Item, typename Make>
std::vector<Item> make_ray_items(const std::vector<float>& values, size_t per_ray, Make make) {
    std::vector<Item> items(values.size() / per_ray);
    for (size_t i = 0; i < items.size(); ++i) items[i] = make(&values[per_ray * i], uint32_t(i));
    return items;
}

// The extend stage over closest-hit rays (six float32 each: world-space origin, direction).
TraceFigures trace_closest_hits(RayTracer& tracer, const std::vector<float>& values, const glm::dvec3& origin,
                                uint32_t repeats) {
    const std::vector<gpu::RayItem> rays = make_ray_items<gpu::RayItem>(values, 6, [&](const float* v, uint32_t i) {
        return gpu::RayItem{float(v[0] - origin.x), float(v[1] - origin.y), float(v[2] - origin.z), i,
                            v[3], v[4], v[5], gpu::INVALID_INDEX};
    });
    tracer.trace(rays, 1, false);  // lavapipe compiles at the first dispatch
    // Extend as a render runs it: the escaped rays counted from the hits on the host, not by an atomic in extend.
    TracedRays traced = tracer.trace(rays, repeats, false);
    TraceFigures f;
    f.seconds = traced.seconds;
    for (const gpu::HitItem& hit : traced.hits)
        f.per_ray.push_back(hit.triangle == gpu::INVALID_INDEX ? std::numeric_limits<float>::infinity() : hit.t);
    f.json = {{"escaped_rays", traced.escaped_rays}};
    return f;
}

// The connect stage over shadow rays (seven float32 each: world-space origin, direction, t_max).
TraceFigures trace_any_hits(RayTracer& tracer, const std::vector<float>& values, const glm::dvec3& origin,
                            uint32_t repeats) {
    const std::vector<gpu::ShadowRayItem> rays =
        make_ray_items<gpu::ShadowRayItem>(values, 7, [&](const float* v, uint32_t) {
            gpu::ShadowRayItem r{};
            r.origin_x = float(v[0] - origin.x);
            r.origin_y = float(v[1] - origin.y);
            r.origin_z = float(v[2] - origin.z);
            r.dir_x = v[3];
            r.dir_y = v[4];
            r.dir_z = v[5];
            r.t_max = v[6];
            r.origin_triangle = gpu::INVALID_INDEX;
            return r;
        });
    tracer.trace_shadow_rays(rays, 1);  // lavapipe compiles at the first dispatch
    TracedShadowRays traced = tracer.trace_shadow_rays(rays, repeats);
    TraceFigures f;
    f.seconds = traced.seconds;
    f.per_ray.assign(traced.occluded.begin(), traced.occluded.end());
    f.json = {{"occluded_rays", std::count(traced.occluded.begin(), traced.occluded.end(), uint8_t(1))}};
    return f;
}

// --trace-rays: the extend stage alone over the rays of a file (six float32 each, world-space origin and direction,
// no header), or with --any-hit the connect stage over shadow rays (seven: t_max too), median GPU time of --repeats
// dispatches; --hits-out writes each ray's hit distance (float32, +inf for a miss; any hit: 1 occluded, 0 not) in the
// same order, to compare with another tracer (tests/bench/compare_embree.py).
int trace_ray_file(const vk::Context& context, const PreparedScene& prepared, const RenderSettings& settings,
                   const BenchCommand& c) {
    const std::vector<float> values = read_ray_file(c.trace_rays, c.any_hit ? 7 : 6);
    const size_t count = values.size() / (c.any_hit ? 7 : 6);
    const glm::dvec3 origin = prepared.packed.origin;  // render space: the scene's arrays are rebased
    const bool sort = !c.any_hit && settings.sort_rays.value();  // resolved by with_device_defaults; connect never sorts
    RayTracer tracer(context, prepared.packed, uint32_t(count), sort, settings.disabled_effects);
    TraceFigures f = c.any_hit ? trace_any_hits(tracer, values, origin, c.repeats)
                               : trace_closest_hits(tracer, values, origin, c.repeats);
    std::sort(f.seconds.begin(), f.seconds.end());
    f.median = f.seconds[f.seconds.size() / 2];
    if (c.any_hit)
        std::printf("trace-rays: %zu shadow rays from %s: connect %.4f s (median of %u; the rays in file order), "
                    "%.3f Mrays/s; %s occluded\n",
                    count, c.trace_rays.string().c_str(), f.median, c.repeats, double(count) / f.median * 1e-6,
                    f.json["occluded_rays"].dump().c_str());
    else
        std::printf("trace-rays: %zu rays from %s: extend %.4f s (median of %u; %s), %.3f Mrays/s; %s escaped\n",
                    count, c.trace_rays.string().c_str(), f.median, c.repeats,
                    sort ? "the rays sorted first, the sort's time included" : "the rays in file order",
                    double(count) / f.median * 1e-6, f.json["escaped_rays"].dump().c_str());
    // The build again, timed as compare_embree.py times Embree's: the median of --repeats builds in this warm process
    // (prepared.bvh_build_seconds is the first, cold one: fresh pages, threads started for the first time).
    std::vector<double> builds;
    for (uint32_t r = 0; r < c.repeats; ++r)
        builds.push_back(build_scene_bvh(prepared.scene, make_bvh_options(settings)).build_seconds);
    std::sort(builds.begin(), builds.end());
    const double build_median = builds[builds.size() / 2];
    std::printf("BVH build: %.4f s the first time, %.4f s the median of %u more\n", prepared.bvh_build_seconds,
                build_median, c.repeats);
    if (!c.hits_out.empty()) write_bytes_atomically(c.hits_out, f.per_ray.data(), f.per_ray.size() * sizeof(float));
    if (!c.json.empty()) {
        nlohmann::json j = {{"rays", count}, {"seconds", f.seconds}, {"median_seconds", f.median},
                            {"rays_per_second", double(count) / f.median}, {"any_hit", c.any_hit},
                            {"sorted", sort},
                            {"triangles_stored", prepared.scene.triangle_count()},
                            {"bvh_build_seconds", prepared.bvh_build_seconds},
                            {"bvh_build_seconds_median", build_median}};
        j.update(f.json);
        const std::string text = j.dump(1) + "\n";
        write_bytes_atomically(c.json, text.data(), text.size());
    }
    return 0;
}

// Device memory per path in flight (the wave's buffers, from the estimate at two wave sizes) and per stored triangle
// (the scene's arrays: positions, shading, attributes and the BVH), and the scene's total: what a render needs
// beyond its film.
void print_memory_figures(const PreparedScene& prepared, const RenderSettings& settings) {
    const EffectBits effects = select_effects(prepared.packed.effects.bits, settings.forced_effects, settings.disabled_effects);
    const double per_path = bytes_per_path(prepared.packed, effects, make_path_store(settings));
    uint64_t scene_bytes = 0, triangle_bytes = 0;
    for (const BufferEstimate& b : estimate_render_memory(prepared.packed, 16, 16, 1, effects).buffers) {
        if (b.name == "tri_positions" || b.name == "tri_shading" || b.name == "tri_attributes" || b.name == "nodes")
            triangle_bytes += b.bytes;
        if (b.binding == BufferBinding::texels) scene_bytes += b.bytes;
    }
    const size_t stored = std::max<size_t>(prepared.scene.triangle_count(), 1);
    std::printf("memory: %.0f bytes per path in flight (%.1f MiB for this device's wave of %u paths); %.1f bytes per "
                "stored triangle (positions, shading, attributes, BVH; %zu stored); scene arrays %.1f MiB\n",
                per_path, per_path * settings.wave_paths / double(1 << 20), settings.wave_paths,
                double(triangle_bytes) / double(stored), stored,
                double(scene_bytes) / double(1 << 20));
}

}  // namespace

int run_bench(const BenchCommand& c) {
    std::filesystem::path scene_file = c.scene.empty() ? std::filesystem::path(FREDHOLM_DEFAULT_SCENE) : c.scene;
    RenderSettings base;
    base.spp = c.spp;
    base.max_depth = c.max_depth;
    base.integrator = c.integrator;
    base.bvh_max_leaf_size = c.bvh_leaf_size;
    base.sort_rays = c.sort_rays;
    base.disabled_effects = c.disabled_effects;
    base.environment_file = c.environment_file;
    base.has_background = c.has_background;
    for (int i = 0; i < 3; ++i) base.background[i] = c.background[i];
    base.animate = c.pose.animate;
    base.animation = c.pose.animation;
    base.time = c.pose.time;
    base.shutter_open = c.pose.shutter_open;
    base.shutter_close = c.pose.shutter_close;
    if (c.motion && !base.has_shutter()) throw std::invalid_argument("--motion needs --shutter OPEN,CLOSE");
    PreparedScene prepared = prepare_scene(scene_file, base);
    auto context = make_compute_context(false, c.device);
    base = with_device_defaults(base, *context, prepared.packed);
    SceneCamera camera = choose_camera(prepared.scene, -1);
    std::printf("scene %s: %zu triangles (%zu stored, %zu instances), loaded in %.3f s, BVH %zu nodes built in %.3f s "
                "(SAH cost %.2f binary, %.2f 4-wide)\n",
                scene_file.string().c_str(), prepared.scene.rendered_triangle_count(), prepared.scene.triangle_count(),
                prepared.scene.instances.size(), prepared.load_seconds,
                prepared.bvh_nodes, prepared.bvh_build_seconds, prepared.sah_cost, prepared.wide_sah_cost);
    std::printf("light sampling: %s\n", describe_light_sampler(prepared.packed).c_str());
    print_memory_figures(prepared, base);
    if (!c.trace_rays.empty()) return trace_ray_file(*context, prepared, base, c);
    std::printf("device %s; integrator %s, %u spp, max depth %u, waves of %u paths, rays %s, median of %u\n",
                context->device_name().c_str(), to_string(c.integrator), c.spp, c.max_depth, base.wave_paths,
                base.sort_rays.value() ? "sorted" : "in queue order", c.repeats);
    // Start-up: the stages for the scene's effects, with the caches as this machine has them (the driver's, and
    // Fredholm's specialised SPIR-V: a first run on a machine pays both; tests/bench/RESULTS.md "Time to first pixel").
    const double pipeline_build = time_pipeline_build(*context, prepared, camera, base);
    std::printf("pipelines built in %.3f s (construction + first-dispatch compile, 16x16; shader caches as they are)\n\n",
                pipeline_build);
    std::printf("%-9s %-18s %10s %12s %12s   %s\n", "size", "disabled", "seconds", "Msamples/s", "Mrays/s",
                "stage seconds (GPU timestamps)");

    // The host-only technique (rebase) costs load time, not render time.
    std::vector<TechniqueInfo> switched;
    if (c.techniques)
        for (const TechniqueInfo& t : list_techniques())
            if (t.bit != gpu::TECHNIQUE_REBASE) switched.push_back(t);

    nlohmann::json results = nlohmann::json::array();
    for (uint32_t size : c.sizes) {
        RenderSettings settings = base;
        settings.width = settings.height = size;
        auto print_run = [&](const std::string& disabled, const RenderStats& m) {
            const double samples = double(size) * size * m.spp_done;
            const double rays = double(m.traced_rays + m.traced_shadow_rays);
            std::printf("%4ux%-4u %-18s %10.3f %12.3f %12.3f   %s\n", size, size, disabled.c_str(), m.render_seconds,
                        samples / m.render_seconds * 1e-6, rays / m.render_seconds * 1e-6,
                        format_stage_seconds(m).c_str());
            results.push_back(describe_run(size, m, disabled));
        };
        settings.disabled_techniques = 0;
        print_run("none", time_render(*context, prepared, camera, settings, c.repeats));
        // Each technique is timed against a baseline measured right before it, so that a machine whose speed
        // drifts (other load, clocks) does not show up as a technique's cost.
        for (const TechniqueInfo& t : switched) {
            settings.disabled_techniques = 0;
            const RenderStats with = time_render(*context, prepared, camera, settings, c.repeats);
            settings.disabled_techniques = t.bit;
            const RenderStats without = time_render(*context, prepared, camera, settings, c.repeats);
            print_run(t.name, without);
            std::printf("%-28s with it %.3f s, without %.3f s: it costs %+.1f%% of the render time\n", "",
                        with.render_seconds, without.render_seconds,
                        100.0 * (with.render_seconds - without.render_seconds) / without.render_seconds);
        }
    }
    // A feature's cost at every size (time_feature); each run without it is recorded with `without_key` =
    // `without_value` and the time with it as `with_key`.
    auto time_at_sizes = [&](const PreparedScene& with, const RenderSettings& with_settings,
                             const PreparedScene& without, const RenderSettings& without_settings,
                             const FeatureNames& names, const char* without_key, const std::string& without_value,
                             const char* with_key) {
        for (uint32_t size : c.sizes) {
            const auto [a, b] = time_feature(*context, camera, with_settings, without_settings, size, c.repeats, with,
                                             without, names);
            nlohmann::json run = describe_run(size, b, "none");
            run[without_key] = without_value;
            run[with_key] = a.render_seconds;
            run["with_stage_seconds"] = a.stage_seconds;
            results.push_back(run);
        }
    };
    if (c.textures) {
        const PackedScene& p = prepared.packed;
        const EffectBits material_effects = p.effects.bits & ATTRIBUTE_EFFECTS;
        std::printf("\ntextures: %zu images, %zu texels, %.1f MiB (RGBA8: 4 bytes per texel, stored once); vertex "
                    "attributes %.1f MiB (%zu bytes per triangle); effects %s\n",
                    p.texture_images.size(), p.texels.size(), double(p.texels.size()) * 4.0 / double(1 << 20),
                    double(p.attributes.size() * sizeof(gpu::TriangleAttributes)) / double(1 << 20),
                    p.attributes.empty() ? size_t(0) : sizeof(gpu::TriangleAttributes),
                    describe_effects(p.effects.bits).c_str());
        RenderSettings factors_only = base;
        factors_only.disabled_effects = material_effects;
        time_at_sizes(prepared, base, prepared, factors_only, {"with textures", "factors only", "textures"},
                      "disabled_effects", describe_effects(material_effects), "with_textures_seconds");
    }
    if (c.instancing) {
        RenderSettings copied_settings = base;
        copied_settings.instancing = Instancing::never;
        const PreparedScene copied = prepare_scene(scene_file, copied_settings);
        auto scene_bytes = [](const PackedScene& p) {
            return double(p.positions.size() * sizeof(gpu::TrianglePositions) + p.shading.size() * sizeof(gpu::TriangleShading) +
                          p.attributes.size() * sizeof(gpu::TriangleAttributes) +
                          p.nodes.size() * sizeof(gpu::BvhWideNode) + p.instances.size() * sizeof(gpu::Instance));
        };
        std::printf("\ninstancing: %zu instances; stored triangles %zu vs %zu copied; triangles, attributes, BVH and "
                    "instances %.2f MiB vs %.2f MiB (%.4f); load + BVH %.3f s vs %.3f s\n",
                    prepared.scene.instances.size(), prepared.scene.triangle_count(), copied.scene.triangle_count(),
                    scene_bytes(prepared.packed) / double(1 << 20), scene_bytes(copied.packed) / double(1 << 20),
                    scene_bytes(prepared.packed) / scene_bytes(copied.packed),
                    prepared.load_seconds + prepared.bvh_build_seconds, copied.load_seconds + copied.bvh_build_seconds);
        time_at_sizes(prepared, base, copied, base, {"two-level", "copied", "instancing"}, "instancing", "off",
                      "instanced_seconds");
    }
    if (c.compare_ray_order) {
        // Same image either way (extend writes each hit at its ray's queue index): only the time differs.
        std::printf("\nray order (%zu stored triangles):\n", prepared.packed.positions.size());
        RenderSettings sorted = base, unsorted = base;
        sorted.sort_rays = true;
        unsorted.sort_rays = false;
        time_at_sizes(prepared, sorted, prepared, unsorted, {"rays sorted", "queue order", "the sort"}, "ray_order",
                      "queue", "sorted_seconds");
    }
    if (c.compare_stores) {
        // Same image either way (the same bytes reach memory): only the time differs.
        std::printf("\nshade's stores:\n");
        RenderSettings narrow = base;
        narrow.wide_stores = false;
        time_at_sizes(prepared, base, prepared, narrow, {"uvec4 stores", "field stores", "uvec4 stores"},
                      "wide_stores", "off", "wide_stores_seconds");
    }
    if (c.motion) {
        std::printf("\nmotion blur: shutter %s, %zu moving instance(s)%s; effects %s\n", describe_shutter(base).c_str(),
                    prepared.scene.moving_instances, camera.moves ? ", the camera moves" : "",
                    describe_effects(prepared.packed.effects.bits).c_str());
        RenderSettings frozen = base;
        frozen.disabled_effects |= gpu::EFFECT_MOTION_BLUR;
        time_at_sizes(prepared, base, prepared, frozen, {"motion blur", "switched off", "motion blur"}, "disabled_effects",
                      "motion-blur", "motion_blur_seconds");
        RenderSettings still = base;
        still.animate = true;
        still.time = base.time + 0.5 * (base.shutter_open + base.shutter_close);
        still.shutter_open = still.shutter_close = 0.0;
        const PreparedScene posed = prepare_scene(scene_file, still);
        time_at_sizes(prepared, base, posed, still, {"motion blur", "no shutter", "motion blur"}, "shutter", "none",
                      "motion_blur_seconds");
    }
    if (c.effects) {
        // The scene compiled for its own effects against every switchable effect compiled in: what effects on
        // demand save (the images are identical; tests/render checks the bits). Not the spectral path: it changes
        // the estimator, not only the code (its cost: `--vary effect:spectral=on,off`, shaders/lib/bsdf/README.md "Dispersion").
        RenderSettings every = base;
        every.forced_effects = SWITCHABLE_EFFECTS & ~EffectBits(gpu::EFFECT_SPECTRAL);
        const EffectBits own = prepared.packed.effects.bits;
        const EffectBits all = select_effects(own, every.forced_effects, 0);
        const double own_build = pipeline_build;  // measured above, before the first render
        const double all_build = time_pipeline_build(*context, prepared, camera, every);
        std::printf("\neffects: own %s; every effect %s\npipeline build (construction + first-dispatch compile, "
                    "16x16): own %.3f s, every effect %.3f s\n",
                    describe_effects(own).c_str(), describe_effects(all).c_str(), own_build, all_build);
        const size_t first = results.size();
        time_at_sizes(prepared, every, prepared, base, {"every effect", "own effects", "unused effects"},
                      "effects", describe_effects(own), "every_effect_seconds");
        for (size_t i = first; i < results.size(); ++i) {
            results[i]["every_effect"] = describe_effects(all);
            results[i]["pipeline_build_seconds"] = own_build;
            results[i]["every_effect_pipeline_build_seconds"] = all_build;
        }
    }
    if (c.techniques) {
        RenderSettings world = base;
        world.disabled_techniques = gpu::TECHNIQUE_REBASE;
        const PreparedScene without = prepare_scene(scene_file, world);
        std::printf("\nrebase (host): load %.4f s with, %.4f s without\n", prepared.load_seconds, without.load_seconds);
    }
    if (!c.json.empty()) {
        nlohmann::json j{{"scene", scene_file.string()}, {"device", context->device_name()},
                         {"wave_paths", base.wave_paths}, {"sort_rays", base.sort_rays.value()}, {"max_depth", c.max_depth}, {"repeats", c.repeats},
                         {"integrator", to_string(c.integrator)}, {"pipeline_build_seconds", pipeline_build},
                         {"results", results}};
        write_file_atomically(c.json, [&](const std::filesystem::path& temp) { std::ofstream(temp) << j.dump(2) << "\n"; });
    }
    return 0;
}

}  // namespace fh
