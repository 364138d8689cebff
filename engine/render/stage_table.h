// The named table of wavefront stages: one compute pipeline per shader, all sharing one binding table.
#pragma once
#include <array>
#include <memory>

#include "vk/pipeline.h"

namespace fh {

enum class Stage { generate, extend, shade, advance, connect, accumulate };
inline constexpr size_t STAGE_COUNT = 6;
const char* stage_name(Stage stage);

class StageTable {
public:
    // scene_in_uniform_buffers: traversal reads the uniform bindings (pack.h fits_uniform_buffers).
    explicit StageTable(const vk::Context& context, bool scene_in_uniform_buffers = false);
    const vk::ComputePipeline& operator[](Stage stage) const { return *pipelines_[size_t(stage)]; }
    vk::BindingTable& bindings() { return bindings_; }

private:
    vk::BindingTable bindings_;
    std::array<std::unique_ptr<vk::ComputePipeline>, STAGE_COUNT> pipelines_;
};

}  // namespace fh
