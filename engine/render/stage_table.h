// The named table of wavefront stages: one compute pipeline per shader, all sharing one binding table.
#pragma once
#include <array>
#include <memory>

#include "vk/pipeline.h"

namespace fh {

enum class Stage { generate, extend, shade, advance, connect, accumulate };
inline constexpr size_t STAGE_COUNT = 6;
const char* stage_name(Stage stage);

// What the pipelines are specialised for (layout.h SPEC_*): branches a scene does not need compile away.
struct StageOptions {
    uint32_t disabled_techniques = 0;       // layout.h TECHNIQUE_* bits switched off
    uint32_t effects = 0;                   // layout.h EFFECT_* bits (scene/effects.h)
    bool instances = false;                 // two-level BVH (pack.h PackedScene::instances)
    uint32_t sampler = 0;                   // layout.h SAMPLER_*
};

class StageTable {
public:
    explicit StageTable(const vk::Context& context, const StageOptions& options = {});
    const vk::ComputePipeline& operator[](Stage stage) const { return *pipelines_[size_t(stage)]; }
    vk::BindingTable& bindings() { return bindings_; }
    const vk::BindingTable& bindings() const { return bindings_; }
    const StageOptions& options() const { return options_; }

private:
    StageOptions options_;
    vk::BindingTable bindings_;
    std::array<std::unique_ptr<vk::ComputePipeline>, STAGE_COUNT> pipelines_;
};

}  // namespace fh
