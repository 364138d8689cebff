// What a render leaves to the device, chosen per device by measurement (tests/bench/RESULTS.md "Speed"): how many paths a wave holds
// when --wave-paths is not given, and whether the rays are sorted under --sort-rays auto.
#pragma once
#include <cstdint>

#include "render/memory_estimate.h"
#include "render/settings.h"
#include "scene/pack.h"

namespace fh {

namespace vk {
class Context;
}

// On a CPU device (lavapipe) 2^19 paths: with the stages 10% faster than when 2^18 was chosen, 2^19 rendered the
// Cornell box (256 x 256, 32 spp) in 0.971 of the time of 2^18 (8 paired runs; fewer dispatches, each a wake-up of
// lavapipe's threads), 2^20 no faster than 2^19. On a GPU 2^22: an H100 rendered the Cornell box at 1024 x 1024,
// 64 spp in 0.25 s with 2^18 and 0.094 s with 2^22 (the wave must fill the GPU and amortise each dispatch).
constexpr uint32_t CPU_WAVE_PATHS = 1u << 19;
constexpr uint32_t GPU_WAVE_PATHS = 1u << 22;
constexpr uint32_t MIN_AUTO_WAVE_PATHS = 1u << 16;
// Below MIN_AUTO_WAVE_PATHS a wave shrinks only to fit a buffer limit (BDPT's light vertices at a deep --max-depth).
constexpr uint32_t MIN_FITTING_WAVE_PATHS = 1u << 10;

// VK_PHYSICAL_DEVICE_TYPE_CPU (lavapipe): its device memory is host memory.
bool is_cpu_device(const vk::Context& context);

// The preferred size for the device, halved (not below MIN_AUTO_WAVE_PATHS) until every wave buffer keeps to the
// device's buffer limits and the wave's buffers take at most a quarter of its device-local memory; halved further
// (not below MIN_FITTING_WAVE_PATHS) while a buffer still passes its limit.
// `cpu_device`: VK_PHYSICAL_DEVICE_TYPE_CPU.
// The film (film_width x film_height) counts towards the device's memory with the wave.
uint32_t choose_wave_paths(bool cpu_device, const DeviceMemoryLimits& limits, const PackedScene& scene,
                           EffectBits effects, uint32_t film_width = 1, uint32_t film_height = 1,
                           const PathStore& store = {});
// With `memory_limit` (bytes, --memory-limit; 0: none), the device's memory counts as no more than that.
uint32_t choose_wave_paths(const vk::Context& context, const PackedScene& scene, EffectBits effects,
                           uint32_t film_width, uint32_t film_height, const PathStore& store = {},
                           uint64_t memory_limit = 0);

// Whether --sort-rays auto sorts: on a GPU for scenes of at least MIN_AUTO_SORT_TRIANGLES stored triangles, never on
// a CPU device. Measured (tests/bench/RESULTS.md "Ray order", bench --compare-ray-order, 1024 x 1024): on an H100 the sort saved 5 to
// 13% of the render time from 1,290 to 1,310,730 triangles (path, light and BDPT) and cost 6 to 12% on the Cornell box
// (42) and the door gap (20); on lavapipe it costs about what it saves at every size.
constexpr size_t MIN_AUTO_SORT_TRIANGLES = 1024;
bool choose_sort_rays(bool cpu_device, const PackedScene& scene);

// `settings` with what was left to the device chosen: wave_paths when it is 0 (--wave-paths not given), sort_rays
// when unset (--sort-rays auto); the rest as it is.
RenderSettings with_device_defaults(RenderSettings settings, const vk::Context& context, const PackedScene& scene);

}  // namespace fh
