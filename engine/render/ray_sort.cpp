// Records the ray sort's stages (see ray_sort.h).
#include "render/ray_sort.h"

#include <cstddef>

#include "render/gpu_buffers.h"
#include "render/stage_table.h"
#include "vk/commands.h"

namespace fh {

static_assert(gpu::RAY_SORT_BINS % gpu::RAY_SORT_BLOCK_BINS == 0, "the scan's blocks tile the keys");

void record_ray_sort(vk::CommandRecorder& recorder, const StageTable& stages, const GpuBuffers& buffers,
                     bool binned) {
    const VkDeviceSize queue = offsetof(gpu::QueueCounters, extend_args);
    if (!binned) {
        recorder.barrier_compute();
        recorder.dispatch_indirect(stages[Stage::bin_rays], buffers.counters, queue);
    }
    recorder.barrier_compute();
    recorder.dispatch(stages[Stage::sum_ray_bins], gpu::RAY_SORT_BLOCKS);
    recorder.barrier_compute();
    recorder.dispatch(stages[Stage::scan_ray_bins], gpu::RAY_SORT_BLOCKS);
    recorder.barrier_compute();
    recorder.dispatch_indirect(stages[Stage::scatter_rays], buffers.counters, queue);
}

}  // namespace fh
