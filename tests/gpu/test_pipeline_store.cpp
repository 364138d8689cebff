// The Context's PipelineStore: a second StageTable with the same options compiles nothing and gets the same pipelines,
// also after the first table (and the layout it was first built with) is gone; other options build their own.
#include <gtest/gtest.h>

#include <memory>

#include "render/stage_table.h"
#include "shared/layout.h"
#include "vk/context.h"

namespace {

std::unique_ptr<fh::vk::Context> make_context() {
    fh::vk::ContextOptions options;
    options.validation = true;
    return std::make_unique<fh::vk::Context>(options);
}

TEST(PipelineStore, ATableWithTheSameOptionsReusesEveryPipeline) {
    const auto context = make_context();
    fh::StageOptions options;
    VkPipeline shade = VK_NULL_HANDLE, extend = VK_NULL_HANDLE;
    {
        const fh::StageTable first(*context, options);
        shade = first[fh::Stage::shade].handle();
        extend = first[fh::Stage::extend].handle();
    }  // the first table's pipeline layout is destroyed here: the store's pipelines do not depend on it
    const size_t built = context->pipeline_store().size();
    EXPECT_GE(built, 6u);  // generate, extend, shade, advance, connect, accumulate
    const fh::StageTable second(*context, options);
    EXPECT_EQ(context->pipeline_store().size(), built);
    EXPECT_EQ(second[fh::Stage::shade].handle(), shade);
    EXPECT_EQ(second[fh::Stage::extend].handle(), extend);

    options.effects = fh::gpu::EFFECT_ALPHA;  // other specialisation constants: other pipelines
    const fh::StageTable textured(*context, options);
    EXPECT_GT(context->pipeline_store().size(), built);
    EXPECT_NE(textured[fh::Stage::shade].handle(), shade);
    EXPECT_EQ(context->validation_message_count(), 0u);
}

}  // namespace
