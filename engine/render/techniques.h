// The robustness techniques by name (layout.h TECHNIQUE_*), for `--disable-technique` and the cost table.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace fh {

struct TechniqueInfo {
    const char* name;     // command-line word
    uint32_t bit;         // layout.h TECHNIQUE_*
    const char* without;  // what replaces it when switched off
};

const std::vector<TechniqueInfo>& list_techniques();
// Throws std::invalid_argument naming the valid words for an unknown name.
uint32_t find_technique(const std::string& name);
// "watertight,error-offsets" for the bits set ("none" for 0).
std::string name_techniques(uint32_t bits);

}  // namespace fh
