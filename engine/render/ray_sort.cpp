// Records the ray sort's stages (see ray_sort.h).
#include "render/ray_sort.h"

#include <cstddef>

#include "render/gpu_buffers.h"
#include "render/stage_table.h"
#include "vk/commands.h"

namespace fh {

void record_ray_sort(vk::CommandRecorder& recorder, const StageTable& stages, const GpuBuffers& buffers,
                     bool binned) {
    const VkDeviceSize queue = offsetof(gpu::QueueCounters, extend_args);
    if (!binned) {
        recorder.barrier_compute();
        recorder.dispatch_indirect(stages[Stage::bin_rays], buffers.counters, queue);
    }
    recorder.barrier_compute();
    recorder.dispatch(stages[Stage::scan_ray_bins], 1);
    recorder.barrier_compute();
    recorder.dispatch_indirect(stages[Stage::scatter_rays], buffers.counters, queue);
}

}  // namespace fh
