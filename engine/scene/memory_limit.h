// --memory-limit: how much memory a render may take, and the one-line refusal when a scene would need more. The loader
// checks what decoding its textures would take before any is decoded; the app checks the loaded scene and the device
// buffers before any is allocated (render/memory_estimate.h).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace fh {

// The default limit: three quarters of the machine's physical memory.
uint64_t default_memory_limit();

// The process's resident set now (/proc/self/statm; 0 where it cannot be read).
uint64_t resident_memory_bytes();

// A size as users write it: "100M", "1.5G", "512MiB", "2GB", "64k" (binary units K, M, G, T, with or without "iB" or
// "B") or plain bytes. Throws std::invalid_argument saying what a size looks like.
uint64_t parse_memory_size(const std::string& word);

// "1.50 GiB (1610612736 bytes)"
std::string format_bytes(uint64_t bytes);

// Something that takes memory, named for the user ("decoded textures", "device buffer texels").
struct MemoryUse {
    std::string name;
    uint64_t bytes = 0;
};

// One line when `uses` add up to more than `limit`: "<what> needs X, more than the memory limit of L (--memory-limit;
// largest: NAME X, NAME Y, NAME Z)"; empty when they fit.
std::string find_limit_problem(const std::vector<MemoryUse>& uses, uint64_t limit, const std::string& what);

}  // namespace fh
