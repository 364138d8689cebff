// The wavefront bounce loop (cf. pbrt-v4 WavefrontPathIntegrator::Render): per wave, generate camera
// paths; then per depth extend, shade, advance, connect; then accumulate into the film.
#include "render/renderer.h"

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <stdexcept>

#include "render/camera/camera_setup.h"
#include "render/camera/camera_medium.h"
#include "render/film.h"
#include "render/light_media.h"
#include "render/light_tracing.h"
#include "render/ray_sort.h"
#include "render/ray_tracer.h"
#include "render/vertex_merging.h"
#include "render/device_defaults.h"
#include "vk/context.h"

namespace fh {
void set_frame_scene_bounds(gpu::FrameParams& f, const PackedScene& scene) {
    if (scene.nodes.empty()) return;
    // Quantised boxes reach past their exact ones by up to two of their node's 255 steps (wide_bvh.cpp), so every box
    // the GPU tests lies inside the scene's box grown by 1/64 of its extent: the padding traversal derives from these
    // bounds then covers them all (intersect.glsl box_padding).
    const glm::vec3 grow = (scene.bounds_hi - scene.bounds_lo) * (1.0f / 64.0f);
    f.scene_min = glm::vec4(scene.bounds_lo - grow, 0.0f);
    f.scene_max = glm::vec4(scene.bounds_hi + grow, 0.0f);
}

namespace {

// With unlimited depth the host looks at the queue length every this many bounces (one readback per
// submission, never between stages). Also bounds the work per submission (GPU watchdogs).
constexpr uint32_t DEPTHS_PER_SUBMIT = 16;
// At most 9 per bounce (a light bounce: the whole sort, extend, light_shade, advance, splat; a VCM camera bounce:
// the sort but bin_rays, extend, connect_subpaths, merge, shade, advance, connect); 3 before light bounces.
constexpr uint32_t MAX_DISPATCHES_PER_SUBMIT = 4 + (RAY_SORT_MAX_DISPATCHES + 5) * DEPTHS_PER_SUBMIT;

uint32_t group_count(uint64_t invocations) {
    return uint32_t((invocations + gpu::WORKGROUP_SIZE - 1) / gpu::WORKGROUP_SIZE);
}

gpu::StagePush make_push(uint32_t depth, const Wave& wave) {
    gpu::StagePush push{};
    push.depth = depth;
    push.pixel_begin = wave.pixel_begin;
    push.pixel_count = wave.pixel_count;
    push.sample_begin = wave.sample_begin;
    push.sample_count = wave.sample_count;
    push.merge_radius = wave.merge_radius;
    return push;
}

gpu::FrameParams make_frame(const PackedScene& scene, const SceneCamera& camera, const RenderSettings& s) {
    gpu::FrameParams f{};
    set_frame_camera(f, camera, s.width, s.height, scene.origin);
    set_frame_scene_bounds(f, scene);
    f.width = s.width;
    f.height = s.height;
    f.max_depth = s.max_depth;
    f.seed = s.seed;
    f.filter_type = s.filter == PixelFilter::gaussian ? gpu::FILTER_GAUSSIAN : gpu::FILTER_BOX;
    f.filter_radius = s.filter_radius;
    f.flags = (s.nee ? gpu::RENDER_NEE : 0u) | (s.mis ? gpu::RENDER_MIS : 0u) |
              (s.russian_roulette ? gpu::RENDER_RR : 0u) | (s.light_pick_reuse ? gpu::RENDER_LIGHT_PICK_REUSE : 0u);
    f.emitter_count = uint32_t(scene.emitters.size());
    f.rr_start_depth = s.rr_start_depth;
    f.rr_survival_scale = s.rr_survival_scale;
    uint64_t pixels = uint64_t(s.film_width()) * s.film_height();
    f.wave_capacity = uint32_t(std::min<uint64_t>(s.wave_paths, pixels * s.spp));
    f.triangle_count = uint32_t(scene.positions.size());
    f.env_width = scene.environment.width;
    f.env_height = scene.environment.height;
    f.env_rotation = scene.environment.rotation;
    f.env_pick_pdf = scene.environment_pick_pdf;
    for (const gpu::Emitter& e : scene.emitters)  // light subpaths pick by the table, whatever NEE picks by
        if (e.light == gpu::ENVIRONMENT_LIGHT) f.env_emission_pick_pdf = e.pick_pdf;
    f.light_tree_lights = scene.light_tree_lights;
    f.motion_segments = scene.motion_segments;
    f.crop_x = s.has_crop() ? s.crop_x0 : 0u;
    f.crop_y = s.has_crop() ? s.crop_y0 : 0u;
    f.film_width = s.film_width();
    f.film_height = s.film_height();
    f.camera_medium = f.camera_medium_outer = f.camera_medium_outermost = gpu::INVALID_INDEX;
    f.light_vertex_slots = count_light_vertex_slots(s);
    f.bdpt_depth = connects_subpaths(s.integrator) ? bdpt_depth(s) : 0u;
    f.merge_grid_cells = s.integrator == Integrator::vcm ? count_merge_grid_cells(f.wave_capacity, f.light_vertex_slots) : 0u;
    f.bdpt_strategy = s.bdpt_strategy_t ? s.bdpt_strategy_s << 16 | s.bdpt_strategy_t : 0u;
    return f;
}

}  // namespace

const char* to_string(PixelFilter filter) { return filter == PixelFilter::gaussian ? "gaussian" : "box"; }
const char* to_string(Sampler sampler) { return sampler == Sampler::sobol ? "sobol" : "independent"; }
const char* to_string(Integrator integrator) {
    return integrator == Integrator::light       ? "light"
           : integrator == Integrator::bdpt      ? "bdpt"
           : integrator == Integrator::vcm       ? "vcm"
           : integrator == Integrator::automatic ? "auto"
                                                 : "path";
}

std::vector<Wave> plan_waves(uint32_t pixel_count, uint32_t sample_begin, uint32_t sample_end, uint32_t capacity) {
    std::vector<Wave> waves;
    if (pixel_count <= capacity) {
        uint32_t per_wave = capacity / pixel_count;
        for (uint32_t s = sample_begin; s < sample_end; s += per_wave)
            waves.push_back({0, pixel_count, s, std::min(per_wave, sample_end - s)});
    } else {
        for (uint32_t s = sample_begin; s < sample_end; ++s)
            for (uint32_t p = 0; p < pixel_count; p += capacity)
                waves.push_back({p, std::min(capacity, pixel_count - p), s, 1});
    }
    return waves;
}

namespace {

StageOptions make_stage_options(const PackedScene& scene, const RenderSettings& s, const SceneCamera& camera) {
    StageOptions o;
    o.disabled_techniques = s.disabled_techniques;
    // The environment cannot be forced or switched off: it follows --env / --background. The thin lens follows
    // the camera: a pinhole compiles no lens code.
    o.effects = select_effects(scene.effects.bits, s.forced_effects, s.disabled_effects) & ~EffectBits(gpu::EFFECT_THIN_LENS);
    if (camera.has_lens()) o.effects |= gpu::EFFECT_THIN_LENS;
    o.instances = !scene.instances.empty();
    o.sampler = s.sampler == Sampler::sobol ? gpu::SAMPLER_SOBOL : gpu::SAMPLER_INDEPENDENT;
    o.integrator = s.integrator;
    o.sort_rays = s.sort_rays.value_or(false);  // resolved (with_device_defaults) but for check_render_settings
    o.wide_stores = s.wide_stores;
    o.aovs = s.aovs;
    o.pixel_list = s.adaptive;
    o.splats_by_path = s.filter == PixelFilter::gaussian || (o.effects & gpu::EFFECT_MOTION_BLUR);
    check_light_tracing(scene.source.empty() ? std::string("scene") : scene.source, scene, s, camera, o.effects);
    return o;
}

}  // namespace

void check_render_settings(const PackedScene& scene, const SceneCamera& camera, const RenderSettings& settings) {
    (void)make_stage_options(scene, settings, camera);
}

Renderer::Renderer(const vk::Context& context, const PackedScene& scene, const SceneCamera& camera,
                   const RenderSettings& settings)
    : context_(context),
      settings_(with_device_defaults(settings, context, scene)),
      frame_(make_frame(scene, camera, settings_)),
      stages_(context, make_stage_options(scene, settings_, camera)),
      buffers_(create_gpu_buffers(context, scene, frame_, stages_.options().effects, make_path_store(settings_))),
      recorder_(context, MAX_DISPATCHES_PER_SUBMIT),
      has_lights_(!scene.emitters.empty()),
      origin_(scene.origin),
      scene_(scene) {
    bind_gpu_buffers(stages_.bindings(), buffers_);
    update_camera_medium();
    update_light_media();
    if (settings_.adaptive) {
        std::vector<uint32_t> identity(size_t(settings_.film_width()) * settings_.film_height());
        for (size_t i = 0; i < identity.size(); ++i) identity[i] = uint32_t(i);
        set_pixel_order(identity);
    }
}

void Renderer::set_pixel_order(const std::vector<uint32_t>& order) {
    if (!settings_.adaptive) throw std::logic_error("Renderer::set_pixel_order needs settings.adaptive");
    if (order.size() != size_t(settings_.film_width()) * settings_.film_height())
        throw std::logic_error("Renderer::set_pixel_order: the order must list every film pixel");
    vk::upload_to_buffer(context_, buffers_.pixel_list, order.data(), order.size() * sizeof(uint32_t));
}

std::vector<uint32_t> Renderer::read_pixel_work() const {
    if (!settings_.adaptive) throw std::logic_error("Renderer::read_pixel_work needs settings.adaptive");
    std::vector<uint32_t> work(size_t(settings_.film_width()) * settings_.film_height());
    vk::download_from_buffer(context_, buffers_.pixel_work, work.data(), work.size() * sizeof(uint32_t));
    return work;
}

void Renderer::set_seed(uint32_t seed) {
    settings_.seed = seed;
    frame_.seed = seed;
    vk::upload_to_buffer(context_, buffers_.params, &frame_, sizeof(frame_));
}

std::vector<gpu::HitItem> Renderer::trace_medium_probes(const std::vector<gpu::RayItem>& probes) {
    gpu::QueueCounters counters;  // the render's diagnostic counts survive the probes
    vk::download_from_buffer(context_, buffers_.counters, &counters, sizeof(counters));
    // At most a wave of them at a time, each its own path: stochastic alpha keys on paths[].rng, the same (zero) state
    // for the probes every time whatever the buffer held, and a probe's time (motion blur) is the shutter's centre.
    const size_t chunk = std::min<size_t>(frame_.wave_capacity, std::max<size_t>(probes.size(), 1));
    const std::vector<gpu::PathState> probe_paths(chunk, gpu::PathState{});
    vk::upload_to_buffer(context_, buffers_.paths, probe_paths.data(), probe_paths.size() * sizeof(gpu::PathState));
    if (stages_.options().effects & gpu::EFFECT_MOTION_BLUR) {
        const std::vector<float> centre(chunk, 0.5f);
        vk::upload_to_buffer(context_, buffers_.path_times, centre.data(), centre.size() * sizeof(float));
    }
    std::vector<gpu::HitItem> hits;
    hits.reserve(probes.size());
    for (size_t begin = 0; begin < probes.size(); begin += chunk) {
        std::vector<gpu::RayItem> rays(probes.begin() + begin, probes.begin() + std::min(probes.size(), begin + chunk));
        for (size_t k = 0; k < rays.size(); ++k) rays[k].path = uint32_t(k);
        const std::vector<gpu::HitItem> part = trace_ray_queue(context_, stages_, buffers_, rays, 1, false).hits;
        hits.insert(hits.end(), part.begin(), part.end());
    }
    vk::upload_to_buffer(context_, buffers_.counters, &counters, sizeof(counters));
    return hits;
}

void Renderer::update_light_media() {
    const bool light_subpaths = settings_.integrator != Integrator::path;
    if (!light_subpaths || (stages_.options().effects & gpu::EFFECT_VOLUME) == 0u || scene_.emitters.empty()) return;
    const std::vector<gpu::uvec4> media =
        find_light_media(scene_, [&](const std::vector<gpu::RayItem>& rays) { return trace_medium_probes(rays); });
    vk::upload_to_buffer(context_, buffers_.light_media, media.data(), media.size() * sizeof(gpu::uvec4));
}

void Renderer::update_camera_medium() {
    if ((stages_.options().effects & gpu::EFFECT_VOLUME) == 0u) return;
    const std::vector<gpu::RayItem> probes =
        make_medium_probe_rays(glm::vec3(frame_.camera_origin), std::min<uint32_t>(frame_.wave_capacity, 14u));
    const CameraMedia media = find_camera_media(
        scene_, probes, [&](const std::vector<gpu::RayItem>& rays) { return trace_medium_probes(rays); });
    frame_.camera_medium = media[0];
    frame_.camera_medium_outer = media[1];
    frame_.camera_medium_outermost = media[2];
    vk::upload_to_buffer(context_, buffers_.params, &frame_, sizeof(frame_));
}

RenderStats Renderer::render(const ProgressCallback& progress) {
    clear_film();
    return render_samples(0, settings_.spp, progress);
}

void Renderer::clear_film() {
    recorder_.begin();
    recorder_.fill_buffer(buffers_.film, 0);
    recorder_.fill_buffer(buffers_.aov_film, 0);
    recorder_.fill_buffer(buffers_.pixel_work, 0);
    recorder_.fill_buffer(buffers_.counters, 0);
    recorder_.submit_and_wait();
}

RenderStats Renderer::render_samples(uint32_t sample_begin, uint32_t sample_end, const ProgressCallback& progress) {
    return render_waves(0, settings_.film_width() * settings_.film_height(), sample_begin, sample_end, progress);
}

RenderStats Renderer::render_listed(uint32_t first, uint32_t count, uint32_t sample_begin, uint32_t sample_end,
                                    const ProgressCallback& progress) {
    if (!settings_.adaptive) throw std::logic_error("Renderer::render_listed needs settings.adaptive");
    if (first > settings_.film_width() * settings_.film_height() ||
        count > settings_.film_width() * settings_.film_height() - first)
        throw std::logic_error("Renderer::render_listed: entries past the film's pixels");
    return render_waves(first, count, sample_begin, sample_end, progress);
}

RenderStats Renderer::render_waves(uint32_t first, uint32_t pixels, uint32_t sample_begin, uint32_t sample_end,
                                   const ProgressCallback& progress) {
    RenderStats stats;
    stats.spp_done = sample_begin;
    const auto start = std::chrono::steady_clock::now();
    const uint32_t capacity = waves_hold_one_sample(settings_.integrator, stages_.options().effects)
                                  ? std::min(frame_.wave_capacity, pixels)
                                  : frame_.wave_capacity;
    for (Wave wave : plan_waves(pixels, sample_begin, sample_end, capacity)) {
        wave.pixel_begin += first;
        trace_wave(wave, stats);
        // A wave ends a sample index once it reaches the last pixel.
        if (wave.pixel_begin + wave.pixel_count == first + pixels) stats.spp_done = wave.sample_begin + wave.sample_count;
        if (progress && !progress(stats.spp_done, sample_end)) break;
    }
    stats.render_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return stats;
}

RenderStats Renderer::render_pixels(uint32_t pixel_begin, uint32_t pixel_count, uint32_t sample) {
    RenderStats stats;
    const uint32_t pixels = settings_.film_width() * settings_.film_height();
    if (pixel_begin > pixels || pixel_count > pixels - pixel_begin)
        throw std::invalid_argument("render_pixels: pixel range outside the film");
    const auto start = std::chrono::steady_clock::now();
    for (uint32_t p = pixel_begin; p < pixel_begin + pixel_count; p += frame_.wave_capacity)
        trace_wave({p, std::min(frame_.wave_capacity, pixel_begin + pixel_count - p), sample, 1}, stats);
    stats.spp_done = pixel_begin + pixel_count == pixels ? sample + 1 : sample;
    stats.render_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return stats;
}

void Renderer::trace_wave(const Wave& planned, RenderStats& stats) {
    Wave wave = planned;
    if (settings_.integrator == Integrator::vcm)
        wave.merge_radius = merge_radius_at(settings_, scene_bounding_radius(scene_), wave.sample_begin);
    recorder_.begin();
    recorder_.bind_table(stages_.bindings());
    // Bidirectional path tracing runs both phases on the same (pixel, sample) indices: the light subpaths first (their
    // vertices stored for the camera subpaths, their t = 1 splats added to the film), then the camera subpaths. Vertex
    // merging builds its grid over the wave's light vertices in between.
    if (settings_.integrator != Integrator::path) {
        trace_subpaths(wave, Subpaths::light, stats);
        if (settings_.integrator == Integrator::vcm) record_merge_grid(wave);
        if (connects_subpaths(settings_.integrator)) {
            submit(stats);
            add_wave_counters(stats);
            recorder_.begin();
            recorder_.bind_table(stages_.bindings());
        }
    }
    if (settings_.integrator != Integrator::light) trace_subpaths(wave, Subpaths::camera, stats);
    const uint32_t depth = settings_.max_depth;  // accumulate reads only the wave's ranges from the push
    gpu::StagePush push = make_push(depth, wave);
    recorder_.push_constants(&push, sizeof(push));
    recorder_.barrier_compute();
    recorder_.dispatch(stages_[Stage::accumulate], group_count(wave.pixel_count));
    submit(stats);
    add_wave_counters(stats);
}

// The hash grid over the wave's stored light vertices (lib/integrator/vertex_merging.glsl): count per bucket, the
// buckets' starts, each vertex's slot in its bucket, each bucket sorted.
void Renderer::record_merge_grid(const Wave& wave) {
    if (frame_.light_vertex_slots == 0) return;
    const gpu::StagePush push = make_push(0, wave);
    recorder_.push_constants(&push, sizeof(push));
    recorder_.barrier_compute();
    recorder_.fill_buffer(buffers_.merge_grid, 0, uint64_t(frame_.merge_grid_cells) * sizeof(uint32_t));
    recorder_.barrier_compute();
    const uint64_t slots = uint64_t(wave.pixel_count) * wave.sample_count * frame_.light_vertex_slots;
    recorder_.dispatch(stages_[Stage::merge_count], group_count(slots));
    recorder_.barrier_compute();
    recorder_.dispatch(stages_[Stage::merge_scan], 1);
    recorder_.barrier_compute();
    recorder_.dispatch(stages_[Stage::merge_scatter], group_count(slots));
    recorder_.barrier_compute();
    recorder_.dispatch(stages_[Stage::merge_sort], group_count(frame_.merge_grid_cells));
}

void Renderer::add_wave_counters(RenderStats& stats) const {
    const auto* counters = static_cast<const gpu::QueueCounters*>(buffers_.counters_readback.mapped());
    stats.traced_rays += counters->traced_rays;
    stats.traced_shadow_rays += counters->traced_shadow_rays;
    stats.nonfinite_samples += counters->nonfinite_samples;
    stats.escaped_rays += counters->escaped_rays;
}

void Renderer::trace_subpaths(const Wave& wave, Subpaths side, RenderStats& stats) {
    const bool light = side == Subpaths::light;
    gpu::StagePush push = make_push(0, wave);
    recorder_.push_constants(&push, sizeof(push));
    recorder_.dispatch(stages_[light ? Stage::light_generate : Stage::generate],
                       group_count(uint64_t(wave.pixel_count) * wave.sample_count));
    if (light) {
        // The light vertices' splats: advance as if after depth 1 hands the shadow queue to splat and leaves the
        // generated rays (queue 0) for the first extend.
        push = make_push(1, wave);
        recorder_.push_constants(&push, sizeof(push));
        recorder_.barrier_compute();
        recorder_.dispatch(stages_[Stage::advance], 1);
        recorder_.barrier_compute();
        recorder_.dispatch_indirect(stages_[Stage::splat], buffers_.counters, offsetof(gpu::QueueCounters, connect_args));
    }

    const uint32_t max_depth = settings_.max_depth;
    uint32_t depth = 0;
    while (true) {
        uint32_t chunk_end = depth + DEPTHS_PER_SUBMIT;
        if (max_depth) chunk_end = std::min(chunk_end, max_depth);
        for (; depth < chunk_end; ++depth) record_bounce(depth, wave, side);
        bool finished = max_depth && depth >= max_depth;
        if (!finished) {
            submit(stats);
            const auto* counters = static_cast<const gpu::QueueCounters*>(buffers_.counters_readback.mapped());
            finished = counters->ray_count[depth & 1u] == 0;
            recorder_.begin();
            recorder_.bind_table(stages_.bindings());
        }
        if (finished) break;
    }
}

void Renderer::record_bounce(uint32_t depth, const Wave& wave, Subpaths side) {
    const bool light = side == Subpaths::light;
    gpu::StagePush push = make_push(depth, wave);
    // Camera rays leave in pixel order, which is coherent already: their sort starts with the first bounce. Shade
    // bins the camera side's rays as it pushes them; light subpaths are binned by bin_rays.
    const bool sort = stages_.options().sort_rays;
    if (sort && (depth > 0 || light)) push.ray_order = gpu::RAY_ORDER_SORTED;
    // Only where a next extend follows (shade pushes nothing at the last depth; scan_ray_bins clears the counts).
    if (sort && !light && (settings_.max_depth == 0 || depth + 1 < settings_.max_depth)) push.bin_pushed_rays = 1u;
    const bool connect = !light && has_lights_ && settings_.nee;  // after advance, traces the shadow queue it hands on
    if (connect) push.count_handed_shadow_rays = 1u;
    recorder_.push_constants(&push, sizeof(push));
    if (push.ray_order == gpu::RAY_ORDER_SORTED) record_ray_sort(recorder_, stages_, buffers_, !light);
    recorder_.barrier_compute();
    recorder_.dispatch_indirect(stages_[Stage::extend], buffers_.counters, offsetof(gpu::QueueCounters, extend_args));
    if (!light && connects_subpaths(settings_.integrator) && frame_.light_vertex_slots > 0) {
        // The camera vertices just found, joined to the stored light vertices (before shade moves the paths on), and
        // merged with the wave's light vertices near them.
        recorder_.barrier_compute();
        recorder_.dispatch_indirect(stages_[Stage::connect_subpaths], buffers_.counters,
                                    offsetof(gpu::QueueCounters, extend_args));
        if (settings_.integrator == Integrator::vcm) {
            recorder_.barrier_compute();
            recorder_.dispatch_indirect(stages_[Stage::merge], buffers_.counters,
                                        offsetof(gpu::QueueCounters, extend_args));
        }
    }
    recorder_.barrier_compute();
    recorder_.dispatch_indirect(stages_[light ? Stage::light_shade : Stage::shade], buffers_.counters,
                                offsetof(gpu::QueueCounters, extend_args));
    recorder_.barrier_compute();
    recorder_.dispatch(stages_[Stage::advance], 1);
    if (light) {
        recorder_.barrier_compute();
        recorder_.dispatch_indirect(stages_[Stage::splat], buffers_.counters, offsetof(gpu::QueueCounters, connect_args));
    } else if (connect) {
        recorder_.barrier_compute();
        recorder_.dispatch_indirect(stages_[Stage::connect], buffers_.counters,
                                    offsetof(gpu::QueueCounters, connect_args));
    }
}

void Renderer::submit(RenderStats& stats) {
    recorder_.barrier_compute();
    recorder_.copy_buffer(buffers_.counters, 0, buffers_.counters_readback, 0, sizeof(gpu::QueueCounters));
    recorder_.submit_and_wait();
    for (const auto& [name, seconds] : recorder_.dispatch_seconds()) stats.stage_seconds[name] += seconds;
}

void Renderer::set_camera(const SceneCamera& camera) {
    if (camera.has_lens() != ((stages_.options().effects & gpu::EFFECT_THIN_LENS) != 0))
        throw std::logic_error("Renderer::set_camera: a lens added or removed needs a new Renderer (EFFECT_THIN_LENS)");
    set_frame_camera(frame_, camera, settings_.width, settings_.height, origin_);
    vk::upload_to_buffer(context_, buffers_.params, &frame_, sizeof(frame_));
    update_camera_medium();
}

std::vector<gpu::FilmPixel> Renderer::read_film_state() const {
    std::vector<gpu::FilmPixel> film(size_t(settings_.film_width()) * settings_.film_height());
    vk::download_from_buffer(context_, buffers_.film, film.data(), film.size() * sizeof(gpu::FilmPixel));
    return film;
}

void Renderer::write_film_state(const std::vector<gpu::FilmPixel>& film) {
    if (film.size() != size_t(settings_.film_width()) * settings_.film_height())
        throw std::invalid_argument("write_film_state: the film has a different size than the render");
    vk::upload_to_buffer(context_, buffers_.film, film.data(), film.size() * sizeof(gpu::FilmPixel));
}

std::vector<gpu::AovPixel> Renderer::read_aov_film() const {
    if (!settings_.aovs) throw std::logic_error("read_aov_film: the render has no AOVs");
    std::vector<gpu::AovPixel> aovs(size_t(settings_.film_width()) * settings_.film_height());
    vk::download_from_buffer(context_, buffers_.aov_film, aovs.data(), aovs.size() * sizeof(gpu::AovPixel));
    return aovs;
}

void Renderer::write_aov_film(const std::vector<gpu::AovPixel>& aovs) {
    if (!settings_.aovs || aovs.size() != size_t(settings_.film_width()) * settings_.film_height())
        throw std::invalid_argument("write_aov_film: the render has no AOVs, or they are another size");
    vk::upload_to_buffer(context_, buffers_.aov_film, aovs.data(), aovs.size() * sizeof(gpu::AovPixel));
}

Image Renderer::read_film() const {
    return resolve_film(read_film_state(), int(settings_.film_width()), int(settings_.film_height()));
}

}  // namespace fh
