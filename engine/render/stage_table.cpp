// Builds the stage pipelines from the SPIR-V embedded at build time (shaders/CMakeLists.txt).
#include "render/stage_table.h"

#include <array>
#include <future>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "shaders/accumulate.spv.h"
#include "shaders/advance.spv.h"
#include "shaders/bin_rays.spv.h"
#include "shaders/connect.spv.h"
#include "shaders/connect_subpaths.spv.h"
#include "shaders/connect_subpaths_vcm.spv.h"
#include "shaders/extend.spv.h"
#include "shaders/generate.spv.h"
#include "shaders/generate_bdpt.spv.h"
#include "shaders/generate_vcm.spv.h"
#include "shaders/light_generate.spv.h"
#include "shaders/light_generate_bdpt.spv.h"
#include "shaders/light_generate_vcm.spv.h"
#include "shaders/light_shade.spv.h"
#include "shaders/light_shade_bdpt.spv.h"
#include "shaders/light_shade_vcm.spv.h"
#include "shaders/merge.spv.h"
#include "shaders/merge_count.spv.h"
#include "shaders/merge_scan.spv.h"
#include "shaders/merge_scatter.spv.h"
#include "shaders/merge_sort.spv.h"
#include "shaders/scan_ray_bins.spv.h"
#include "shaders/scatter_rays.spv.h"
#include "shaders/shade.spv.h"
#include "shaders/shade_bdpt.spv.h"
#include "shaders/shade_vcm.spv.h"
#include "shaders/shade_struct_stores.spv.h"
#include "shaders/splat.spv.h"
#include "shaders/sum_ray_bins.spv.h"
#include "shared/layout.h"
#include "vk/context.h"

namespace fh {

const char* stage_name(Stage stage) {
    constexpr const char* names[STAGE_COUNT] = {"generate",   "extend",         "shade",       "advance",
                                                "connect",    "accumulate",     "light_generate", "light_shade",
                                                "splat",      "connect_subpaths", "bin_rays",    "sum_ray_bins",
                                                "scan_ray_bins", "scatter_rays", "merge_count", "merge_scan",
                                                "merge_scatter", "merge_sort",  "merge"};
    return names[size_t(stage)];
}

std::array<VkDescriptorType, gpu::BINDING_COUNT> binding_types() {
    std::array<VkDescriptorType, gpu::BINDING_COUNT> types;
    types.fill(VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);
    types[gpu::BINDING_PARAMS] = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
    types[gpu::BINDING_GGX_ALBEDO_UNIFORM] = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
    for (uint32_t texels : {gpu::BINDING_BVH_NODES, gpu::BINDING_TRI_POSITIONS, gpu::BINDING_TRI_SHADING,
                            gpu::BINDING_MATERIALS, gpu::BINDING_EMITTERS, gpu::BINDING_PUNCTUAL_LIGHTS,
                            gpu::BINDING_TRI_ATTRIBUTES, gpu::BINDING_INSTANCES, gpu::BINDING_MATERIAL_LAYERS,
                            gpu::BINDING_TEXTURE_SLOTS, gpu::BINDING_TEXTURE_IMAGES, gpu::BINDING_TEXELS,
                            gpu::BINDING_PATH_TEXELS, gpu::BINDING_RAY_TEXELS, gpu::BINDING_HIT_TEXELS,
                            gpu::BINDING_SHADOW_RAY_TEXELS, gpu::BINDING_LIGHT_TREE})
        types[texels] = VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;  // layout.h TEXELS bindings
    return types;
}

StageTable::StageTable(const vk::Context& context, const StageOptions& options)
    : options_(options), bindings_(context, binding_types(), sizeof(gpu::StagePush)) {
    std::array<uint32_t, gpu::SPEC_CONSTANT_COUNT> spec{};
    spec[gpu::SPEC_DISABLED_TECHNIQUES] = options.disabled_techniques;
    spec[gpu::SPEC_EFFECTS] = low_effect_word(options.effects);
    spec[gpu::SPEC_EFFECTS_2] = high_effect_word(options.effects);
    spec[gpu::SPEC_HAS_INSTANCES] = options.instances ? 1u : 0u;
    spec[gpu::SPEC_SAMPLER] = options.sampler;
    spec[gpu::SPEC_SORT_RAYS] = options.sort_rays ? 1u : 0u;
    spec[gpu::SPEC_AOVS] = options.aovs ? 1u : 0u;
    spec[gpu::SPEC_PIXEL_LIST] = options.pixel_list ? 1u : 0u;
    spec[gpu::SPEC_SPLATS_BY_PATH] = options.splats_by_path ? 1u : 0u;
    // Each pipeline is built on a thread of its own: its specialisation (vk/spirv_specialise.h) and the driver's
    // compile are CPU work, and the stages do not depend on each other. A failure is rethrown here, after every
    // thread has finished (a std::async future waits in its destructor).
    std::vector<std::future<void>> builds;
    auto make = [&](Stage stage, std::span<const uint32_t> spirv) {
        builds.push_back(std::async(std::launch::async, [this, &context, &spec, stage, spirv] {
            pipelines_[size_t(stage)] =
                std::make_unique<vk::ComputePipeline>(context, bindings_, stage_name(stage), spirv, spec);
        }));
    };
    // The stages BDPT and VCM share with path or light tracing have a SPIR-V of their own for each
    // (shaders/CMakeLists.txt): `of` picks the integrator's.
    const Integrator integrator = options.integrator;
    using Spirv = std::span<const uint32_t>;
    auto of = [integrator](Spirv other, Spirv bdpt, Spirv vcm) {
        return integrator == Integrator::vcm ? vcm : integrator == Integrator::bdpt ? bdpt : other;
    };
    make(Stage::extend, spv_extend);
    make(Stage::advance, spv_advance);
    make(Stage::accumulate, spv_accumulate);
    if (options.sort_rays) {
        make(Stage::bin_rays, spv_bin_rays);
        make(Stage::sum_ray_bins, spv_sum_ray_bins);
        make(Stage::scan_ray_bins, spv_scan_ray_bins);
        make(Stage::scatter_rays, spv_scatter_rays);
    }
    if (options.integrator != Integrator::path) {
        make(Stage::light_generate, of(spv_light_generate, spv_light_generate_bdpt, spv_light_generate_vcm));
        make(Stage::light_shade, of(spv_light_shade, spv_light_shade_bdpt, spv_light_shade_vcm));
        make(Stage::splat, spv_splat);
    }
    if (options.integrator != Integrator::light) {
        make(Stage::generate, of(spv_generate, spv_generate_bdpt, spv_generate_vcm));
        // A uvec4 store is one per-lane loop on lavapipe where its four words are four (tests/bench/RESULTS.md "Speed"); with
        // --wide-stores off the same stage stores field by field, to the same bytes (kept to measure the difference).
        make(Stage::shade, of(options.wide_stores ? Spirv(spv_shade) : Spirv(spv_shade_struct_stores), spv_shade_bdpt,
                              spv_shade_vcm));
        make(Stage::connect, spv_connect);
    }
    if (connects_subpaths(integrator))
        make(Stage::connect_subpaths, of(spv_connect_subpaths, spv_connect_subpaths, spv_connect_subpaths_vcm));
    if (integrator == Integrator::vcm) {
        make(Stage::merge_count, spv_merge_count);
        make(Stage::merge_scan, spv_merge_scan);
        make(Stage::merge_scatter, spv_merge_scatter);
        make(Stage::merge_sort, spv_merge_sort);
        make(Stage::merge, spv_merge);
    }
    for (std::future<void>& build : builds) build.get();
}

const vk::ComputePipeline& StageTable::operator[](Stage stage) const {
    const auto& pipeline = pipelines_[size_t(stage)];
    if (!pipeline) throw std::logic_error(std::string("StageTable: stage ") + stage_name(stage) + " was not built");
    return *pipeline;
}

}  // namespace fh
