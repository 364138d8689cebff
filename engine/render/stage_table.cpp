// Builds the stage pipelines from the SPIR-V embedded at build time (shaders/CMakeLists.txt).
#include "render/stage_table.h"

#include <span>

#include "shaders/accumulate.spv.h"
#include "shaders/advance.spv.h"
#include "shaders/connect.spv.h"
#include "shaders/extend.spv.h"
#include "shaders/generate.spv.h"
#include "shaders/shade.spv.h"
#include "shared/layout.h"

namespace fh {

const char* stage_name(Stage stage) {
    constexpr const char* names[STAGE_COUNT] = {"generate", "extend", "shade", "advance", "connect", "accumulate"};
    return names[size_t(stage)];
}

StageTable::StageTable(const vk::Context& context)
    : bindings_(context, gpu::BINDING_COUNT, sizeof(gpu::StagePush)) {
    auto make = [&](Stage stage, std::span<const uint32_t> spirv) {
        pipelines_[size_t(stage)] = std::make_unique<vk::ComputePipeline>(context, bindings_, stage_name(stage), spirv);
    };
    make(Stage::generate, spv_generate);
    make(Stage::extend, spv_extend);
    make(Stage::shade, spv_shade);
    make(Stage::advance, spv_advance);
    make(Stage::connect, spv_connect);
    make(Stage::accumulate, spv_accumulate);
}

}  // namespace fh
