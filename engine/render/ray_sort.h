// The ray sort before extend (README "Ray order"): each bounce's queue counted into keys of direction and origin
// (bin_rays), the keys' starts (scan_ray_bins) and the queue's order by key (scatter_rays), which extend follows.
#pragma once
#include <cstdint>


namespace fh {

namespace vk {
class CommandRecorder;
}
class StageTable;
struct GpuBuffers;

// Records the three sort stages over the ray queue of the push constants' depth (whose length extend_args holds),
// each after a barrier. The caller then dispatches extend with StagePush.ray_order = RAY_ORDER_SORTED.
void record_ray_sort(vk::CommandRecorder& recorder, const StageTable& stages, const GpuBuffers& buffers);

}  // namespace fh
