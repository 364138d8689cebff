// specialise_spirv: SPIRV-Tools' optimiser with the passes that fold the frozen constants and drop dead code.
#include "vk/spirv_specialise.h"

#include <cstdlib>
#include <cstring>
#include <string>
#include <unordered_map>

#include <spirv-tools/libspirv.h>
#include <spirv-tools/optimizer.hpp>

#include "vk/spirv_cache.h"

namespace fh::vk {

namespace {

// Bump when the pass list changes, so that modules cached by another list are not reused.
constexpr char PASS_LIST_VERSION[] = "fredholm-specialise-2";

bool specialisation_enabled() {
    const char* value = std::getenv("FREDHOLM_SPECIALISE_SPIRV");
    return !value || (std::strcmp(value, "0") != 0 && std::strcmp(value, "off") != 0);
}

std::vector<uint32_t> run_optimiser(std::span<const uint32_t> spirv, std::span<const uint32_t> spec_constants) {
    spvtools::Optimizer optimiser(SPV_ENV_VULKAN_1_1);
    optimiser.SetMessageConsumer([](spv_message_level_t, const char*, const spv_position_t&, const char*) {});
    std::unordered_map<uint32_t, std::vector<uint32_t>> values;
    for (uint32_t id = 0; id < spec_constants.size(); ++id) values[id] = {spec_constants[id]};
    // The constants take the scene's values and stop being specialization constants; then the folds that make the
    // effect tests constant (ccp: after glslang's inlining, `scene_effects & EFFECT_X` is an instruction, not a
    // constant), the branches they decide, the selects and phis they make trivial (simplification: a one-level scene's
    // traversal kept copies of the ray in its loops without it, test_spirv_specialise), and the code nothing reaches
    // any more. Nothing is contracted. The simplification's folding rules may reassociate float constants, as glslang's
    // -Os (the same rules) did at build time; specialisation makes only integers and booleans constant, and renders
    // with it on and off (FREDHOLM_SPECIALISE_SPIRV=off) keep their bits (tests/bench/RESULTS.md "Speed").
    optimiser.RegisterPass(spvtools::CreateSetSpecConstantDefaultValuePass(values))
        .RegisterPass(spvtools::CreateFreezeSpecConstantValuePass())
        .RegisterPass(spvtools::CreateFoldSpecConstantOpAndCompositePass())
        .RegisterPass(spvtools::CreateCCPPass())
        .RegisterPass(spvtools::CreateDeadBranchElimPass())
        .RegisterPass(spvtools::CreateBlockMergePass())
        .RegisterPass(spvtools::CreateSimplificationPass())
        .RegisterPass(spvtools::CreateAggressiveDCEPass())
        .RegisterPass(spvtools::CreateEliminateDeadFunctionsPass());
    spvtools::OptimizerOptions options;
    options.set_run_validator(false);  // the module was validated by glslang at build time
    std::vector<uint32_t> out;
    if (!optimiser.Run(spirv.data(), spirv.size(), &out, options)) return {};
    return out;
}

template <class T>
std::span<const uint8_t> as_bytes(std::span<const T> values) {
    return {reinterpret_cast<const uint8_t*>(values.data()), values.size_bytes()};
}

}  // namespace

std::vector<uint32_t> specialise_spirv(std::span<const uint32_t> spirv, std::span<const uint32_t> spec_constants) {
    static const SpirvCache cache = SpirvCache::from_environment();
    return specialise_spirv(spirv, spec_constants, cache);
}

std::vector<uint32_t> specialise_spirv(std::span<const uint32_t> spirv, std::span<const uint32_t> spec_constants,
                                       const SpirvCache& cache) {
    if (!specialisation_enabled()) return {};
    const std::string version = std::string(PASS_LIST_VERSION) + " " + spvSoftwareVersionDetailsString();
    const SpirvKey key = hash_spirv_key({as_bytes(std::span<const char>(version)), as_bytes(spirv),
                                         as_bytes(spec_constants)});
    if (auto cached = cache.load(key)) return std::move(*cached);
    std::vector<uint32_t> out = run_optimiser(spirv, spec_constants);
    if (!out.empty()) cache.store(key, out);
    return out;
}

}  // namespace fh::vk
