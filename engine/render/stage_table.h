// The named table of wavefront stages: one compute pipeline per shader, all sharing one binding table.
#pragma once
#include <array>
#include <memory>

#include "render/settings.h"
#include "vk/pipeline.h"

namespace fh {

enum class Stage {
    generate, extend, shade, advance, connect, accumulate, light_generate, light_shade, splat, connect_subpaths,
    bin_rays, sum_ray_bins, scan_ray_bins, scatter_rays, merge_count, merge_scan, merge_scatter, merge_sort, merge
};
inline constexpr size_t STAGE_COUNT = 19;
const char* stage_name(Stage stage);

// What the pipelines are specialised for (layout.h SPEC_*): branches a scene does not need compile away.
struct StageOptions {
    uint32_t disabled_techniques = 0;       // layout.h TECHNIQUE_* bits switched off
    EffectBits effects = 0;                   // layout.h EFFECT_* bits (scene/effects.h)
    bool instances = false;                 // two-level BVH (pack.h PackedScene::instances)
    uint32_t sampler = 0;                   // layout.h SAMPLER_*
    Integrator integrator = Integrator::path;  // which stages are built, and which SPIR-V (FH_INTEGRATOR): BDPT builds both sides'
    bool sort_rays = false;                 // the ray sort's stages (bin_rays, sum_ray_bins, scan_ray_bins, scatter_rays) are built
    bool wide_stores = true;                // shade stores a uvec4 at a time; off: field by field (FH_STRUCT_STORES)
    bool aovs = false;                      // shade records the AOVs and accumulate sums them (SPEC_AOVS)
    bool pixel_list = false;                // waves take their pixels from the pixel list (SPEC_PIXEL_LIST, --adaptive)
    bool splats_by_path = false;            // splats land by film position (SPEC_SPLATS_BY_PATH)
};

class StageTable {
public:
    explicit StageTable(const vk::Context& context, const StageOptions& options = {});
    // A stage of the other integrator is not built: asking for it is a logic error.
    const vk::ComputePipeline& operator[](Stage stage) const;
    vk::BindingTable& bindings() { return bindings_; }
    const vk::BindingTable& bindings() const { return bindings_; }
    const StageOptions& options() const { return options_; }

private:
    StageOptions options_;
    vk::BindingTable bindings_;
    std::array<std::unique_ptr<vk::ComputePipeline>, STAGE_COUNT> pipelines_;
};

}  // namespace fh
