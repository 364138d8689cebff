// A directory of SPIR-V modules keyed by a hash of what made them, so that work done on a module once (here: its
// specialisation, spirv_specialise.h) is not repeated by the next process.
#pragma once
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace fh::vk {

// 128 bits from two 64-bit FNV-1a-style hashes (different offsets and multipliers) over the parts, in order.
struct SpirvKey {
    uint64_t a = 0, b = 0;
    std::string file_name() const;  // 32 hex digits + ".spv"
};
SpirvKey hash_spirv_key(std::initializer_list<std::span<const uint8_t>> parts);

class SpirvCache {
public:
    // The cache directory: $FREDHOLM_SPIRV_CACHE if set ("off" or "0" turn the cache off), else
    // $XDG_CACHE_HOME/fredholm/spirv, else $HOME/.cache/fredholm/spirv; none of those: no cache.
    static SpirvCache from_environment();
    explicit SpirvCache(std::filesystem::path directory) : directory_(std::move(directory)) {}

    bool enabled() const { return !directory_.empty(); }
    const std::filesystem::path& directory() const { return directory_; }
    // A stored module, or nothing when it is missing or not a SPIR-V module (a damaged entry is a miss).
    std::optional<std::vector<uint32_t>> load(const SpirvKey& key) const;
    // Writes a temporary file and renames it into place, so a reader never sees half a module; a cache that cannot
    // be written is not an error (the next run does the work again).
    // After a store, more than MAX_ENTRIES modules (about 60 KB each for a simple scene's shade, 0.9 MB with every
    // effect) are pruned to the MAX_ENTRIES / 2 used last; prune also removes temporary files over an hour old (a
    // writer killed before its rename).
    void store(const SpirvKey& key, std::span<const uint32_t> spirv) const;
    void prune(size_t max_entries) const;
    static constexpr size_t MAX_ENTRIES = 2048;

private:
    std::filesystem::path directory_;  // empty: disabled
};

}  // namespace fh::vk
