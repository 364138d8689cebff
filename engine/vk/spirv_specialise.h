// Specialises a SPIR-V module on the host: its specialization constants become constants and the code they switch
// off is removed, so that the driver translates only what the pipeline runs.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

namespace fh::vk {

class SpirvCache;

// Why: Mesa's lavapipe translates and optimises a module's *whole* SPIR-V in NIR every time it builds a pipeline,
// before it applies the specialization constants, and its shader cache keeps only the machine code. A stage with
// every material extension behind a constant (shade.comp, 0.87 MB) costs the Cornell box most of its start-up.
// Specialised once here and kept in the SpirvCache (keyed by the module, the constants and the optimiser's
// version), the module the driver sees is the scene's own (shade: 0.05 MB for the Cornell box).
//
// spec_constants[i] is the value of constant_id i (32 bits; a bool is 0 or 1). Returns the specialised module, or
// an empty vector when the optimiser refused it: the caller then passes the constants to the driver instead.
// FREDHOLM_SPECIALISE_SPIRV=0 (or off) always returns empty, to compare with the driver's own specialisation.
// The two-argument form uses SpirvCache::from_environment().
std::vector<uint32_t> specialise_spirv(std::span<const uint32_t> spirv, std::span<const uint32_t> spec_constants);
std::vector<uint32_t> specialise_spirv(std::span<const uint32_t> spirv, std::span<const uint32_t> spec_constants,
                                       const SpirvCache& cache);

}  // namespace fh::vk
