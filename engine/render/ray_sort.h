// The ray sort before extend (README "Ray order"): each bounce's queue counted into keys of direction and origin
// (by shade as it pushes the rays, else bin_rays), the keys' starts (scan_ray_bins) and the queue's order by key
// (scatter_rays), which extend follows.
#pragma once

namespace fh {

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
