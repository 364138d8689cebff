// The ray sort before extend (tests/bench/RESULTS.md "Ray order"): each bounce's queue counted into keys of direction and origin
// (by shade as it pushes the rays, else bin_rays), the keys' starts (sum_ray_bins, then scan_ray_bins: a prefix sum
// in blocks) and the queue's order by key (scatter_rays), which extend follows.
#pragma once
#include <cstdint>

namespace fh {

// The most dispatches record_ray_sort records: bin_rays, sum_ray_bins, scan_ray_bins, scatter_rays.
inline constexpr uint32_t RAY_SORT_MAX_DISPATCHES = 4;

namespace vk {
class CommandRecorder;
}
class StageTable;
struct GpuBuffers;

// Records the sort stages over the ray queue of the push constants' depth (whose length extend_args holds), each
// after a barrier; `binned`: the stage that pushed the rays binned them (shade with StagePush.bin_pushed_rays), so
// bin_rays is left out. The caller then dispatches extend with StagePush.ray_order = RAY_ORDER_SORTED.
void record_ray_sort(vk::CommandRecorder& recorder, const StageTable& stages, const GpuBuffers& buffers,
                     bool binned = false);

}  // namespace fh
