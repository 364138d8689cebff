// A path-traced render of one scene and camera: owns the stage pipelines, buffers and film.
#pragma once
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "io/image.h"
#include "render/camera/camera_medium.h"
#include "render/gpu_buffers.h"
#include "render/settings.h"
#include "render/stage_table.h"
#include "scene/pack.h"
#include "scene/scene.h"
#include "vk/commands.h"

namespace fh {

struct RenderStats {
    uint32_t spp_done = 0;
    double render_seconds = 0;              // wall time of the wave loop (GPU work; no loading or setup)
    std::map<std::string, double> stage_seconds;  // GPU timestamps, summed per stage name
    uint64_t traced_rays = 0;
    uint64_t traced_shadow_rays = 0;
    uint64_t nonfinite_samples = 0;
    uint64_t escaped_rays = 0;
};

// Pixel and sample ranges one wave covers (see StagePush).
struct Wave {
    uint32_t pixel_begin, pixel_count, sample_begin, sample_count;
    float merge_radius = 0.0f;  // `--integrator vcm`: set per wave by the renderer (render/vertex_merging.h)
};
// Splits samples [sample_begin, sample_end) of `pixel_count` pixels into waves of at most `capacity` paths.
std::vector<Wave> plan_waves(uint32_t pixel_count, uint32_t sample_begin, uint32_t sample_end, uint32_t capacity);

// FrameParams::scene_min / scene_max: the scene's box grown to hold every quantised box; traversal pads its boxes by a
// bound computed from them.
void set_frame_scene_bounds(gpu::FrameParams& frame, const PackedScene& scene);

// Called after each wave with the samples per pixel finished so far; return false to stop early.
using ProgressCallback = std::function<bool(uint32_t spp_done, uint32_t spp_total)>;

// Throws std::invalid_argument, naming the scene file, when the stages cannot render `scene` through `camera` with
// `settings` (today: what light tracing does not handle yet, render/light_tracing.h). A Renderer checks this when it
// is built; a command that renders several configurations checks them all first.
void check_render_settings(const PackedScene& scene, const SceneCamera& camera, const RenderSettings& settings);

class Renderer {
public:
    // The camera is in world space; the scene's arrays are in render space (PackedScene::origin).
    Renderer(const vk::Context& context, const PackedScene& scene, const SceneCamera& camera,
             const RenderSettings& settings);

    // Renders settings.spp samples per pixel into a cleared film.
    RenderStats render(const ProgressCallback& progress = {});
    // Adds samples [sample_begin, sample_end) of every pixel to the film as it is (no clearing), e.g. to
    // continue a render or to grow one progressively; spp_done in the result is the sample index reached.
    RenderStats render_samples(uint32_t sample_begin, uint32_t sample_end, const ProgressCallback& progress = {});
    void clear_film();
    // With settings.adaptive (render/adaptive_render.h): the order the waves take the film's pixels in, a permutation
    // of them (the identity until set), and a render of samples [sample_begin, sample_end) of the pixels at entries
    // [first, first + count) of that order. Without it both throw std::logic_error.
    void set_pixel_order(const std::vector<uint32_t>& order);
    RenderStats render_listed(uint32_t first, uint32_t count, uint32_t sample_begin, uint32_t sample_end,
                              const ProgressCallback& progress = {});
    // Per film pixel, the work its samples since the film was cleared took, in PATH_WORK_* units (settings.adaptive).
    std::vector<uint32_t> read_pixel_work() const;
    // The seed of the samples rendered from now on (adaptive sampling's pilot draws with a seed of its own).
    void set_seed(uint32_t seed);
    // Adds sample index `sample` of pixels [pixel_begin, pixel_begin + pixel_count) only: a slice of one pass,
    // so an interactive frame stays short. The film receives the same samples render_samples would add.
    RenderStats render_pixels(uint32_t pixel_begin, uint32_t pixel_count, uint32_t sample);
    // The film's mean radiance per pixel (scene-linear Rec.709).
    Image read_film() const;
    // The raw film (exact fixed-point sums and sample counts), to save a render and resume it bit-exactly.
    std::vector<gpu::FilmPixel> read_film_state() const;
    void write_film_state(const std::vector<gpu::FilmPixel>& film);
    // The AOVs' exact sums per pixel (settings.aovs; render/aov_image.h turns them into layers).
    std::vector<gpu::AovPixel> read_aov_film() const;
    void write_aov_film(const std::vector<gpu::AovPixel>& aovs);

    // Moves the camera (same film size); the film keeps its samples, so clear it to start afresh. Its lens may
    // change but not appear or vanish (the stages are compiled with or without EFFECT_THIN_LENS): throws
    // std::logic_error then.
    void set_camera(const SceneCamera& camera);
    const RenderSettings& settings() const { return settings_; }
    uint32_t wave_capacity() const { return frame_.wave_capacity; }  // paths per wave
    // The film buffer (gpu::FilmPixel[width * height]), e.g. for a display pass that reads it in place.
    const vk::Buffer& film_buffer() const { return buffers_.film; }
    // The volumes (material indices) the camera stands in, innermost first, where its paths start; INVALID_INDEX past
    // the last (render/camera/camera_medium.h; probed only when the scene has volumes).
    CameraMedia camera_media() const {
        return {frame_.camera_medium, frame_.camera_medium_outer, frame_.camera_medium_outermost};
    }

private:
    // Probes which volumes the camera stands in (EFFECT_VOLUME only) and sets FrameParams.camera_medium*.
    void update_camera_medium();
    // Probes which volumes each light stands in (light tracing and BDPT with EFFECT_VOLUME only; render/light_media.h)
    // into BINDING_LIGHT_MEDIA.
    void update_light_media();
    // Closest hits of any number of medium probes, a wave at a time; the render's counters are kept.
    std::vector<gpu::HitItem> trace_medium_probes(const std::vector<gpu::RayItem>& probes);
    enum class Subpaths { camera, light };
    void trace_wave(const Wave& planned, RenderStats& stats);
    void record_merge_grid(const Wave& wave);
    // Samples [sample_begin, sample_end) of the wave pixels [first, first + pixels) (film pixels, or the pixel list's
    // entries).
    RenderStats render_waves(uint32_t first, uint32_t pixels, uint32_t sample_begin, uint32_t sample_end,
                             const ProgressCallback& progress);
    // One side's subpaths of a wave, generated and extended to the end (submitting every DEPTHS_PER_SUBMIT bounces).
    void trace_subpaths(const Wave& wave, Subpaths side, RenderStats& stats);
    void record_bounce(uint32_t depth, const Wave& wave, Subpaths side);
    void add_wave_counters(RenderStats& stats) const;
    void submit(RenderStats& stats);

    const vk::Context& context_;
    RenderSettings settings_;
    gpu::FrameParams frame_{};
    StageTable stages_;
    GpuBuffers buffers_;
    vk::CommandRecorder recorder_;
    bool has_lights_;
    glm::dvec3 origin_;  // world position of the render-space origin
    const PackedScene& scene_;  // outlives the Renderer (read again when the camera moves)
};

}  // namespace fh
