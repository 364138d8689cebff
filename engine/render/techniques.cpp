// Names of the robustness techniques; tests/README.md "Numerical stability" tabulates what each costs.
#include "render/techniques.h"

#include <stdexcept>

#include "shared/layout.h"

namespace fh {

const std::vector<TechniqueInfo>& list_techniques() {
    static const std::vector<TechniqueInfo> techniques = {
        {"watertight", gpu::TECHNIQUE_WATERTIGHT, "Moller-Trumbore triangle test"},
        {"conservative-box", gpu::TECHNIQUE_CONSERVATIVE_BOX, "plain slab test (no padding, raw 1/dir)"},
        {"error-offsets", gpu::TECHNIQUE_ERROR_OFFSETS, "fixed 1e-4 ray-origin offset"},
        {"finite-guard", gpu::TECHNIQUE_FINITE_GUARD, "non-finite samples reach the film"},
        {"exact-film", gpu::TECHNIQUE_EXACT_FILM, "plain float film sums"},
        {"tie-break", gpu::TECHNIQUE_TIE_BREAK, "equal-t hits go to the first visited"},
        {"rebase", gpu::TECHNIQUE_REBASE, "render space = world space (float world coordinates)"},
    };
    return techniques;
}

uint32_t find_technique(const std::string& name) {
    std::string valid;
    for (const TechniqueInfo& t : list_techniques()) {
        if (name == t.name) return t.bit;
        valid += (valid.empty() ? "" : ", ") + std::string(t.name);
    }
    throw std::invalid_argument("unknown technique '" + name + "' (valid: " + valid + ")");
}

std::string name_techniques(uint32_t bits) {
    std::string out;
    for (const TechniqueInfo& t : list_techniques())
        if (bits & t.bit) out += (out.empty() ? "" : ",") + std::string(t.name);
    return out.empty() ? "none" : out;
}

}  // namespace fh
