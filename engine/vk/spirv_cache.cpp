// SpirvCache: one file per module, named by its key, written atomically.
#include "vk/spirv_cache.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <system_error>
#include <unistd.h>

namespace fh::vk {

namespace {

constexpr uint32_t SPIRV_MAGIC = 0x07230203u;

uint64_t hash_fnv1a(uint64_t h, std::span<const uint8_t> bytes, uint64_t prime) {
    for (uint8_t byte : bytes) h = (h ^ byte) * prime;
    return h;
}

}  // namespace

std::string SpirvKey::file_name() const {
    char name[40];
    std::snprintf(name, sizeof(name), "%016llx%016llx.spv", (unsigned long long)a, (unsigned long long)b);
    return name;
}

SpirvKey hash_spirv_key(std::initializer_list<std::span<const uint8_t>> parts) {
    // The standard 64-bit FNV-1a, and the same loop with another offset and another odd multiplier (the golden
    // ratio's bits); each part is closed by its length, so that parts cannot run together.
    SpirvKey key{0xcbf29ce484222325ull, 0x84222325cbf29ce4ull};
    for (std::span<const uint8_t> part : parts) {
        uint64_t size = part.size();
        std::span<const uint8_t> size_bytes(reinterpret_cast<const uint8_t*>(&size), sizeof(size));
        key.a = hash_fnv1a(hash_fnv1a(key.a, part, 0x100000001b3ull), size_bytes, 0x100000001b3ull);
        key.b = hash_fnv1a(hash_fnv1a(key.b, part, 0x9e3779b97f4a7c15ull), size_bytes, 0x9e3779b97f4a7c15ull);
    }
    return key;
}

SpirvCache SpirvCache::from_environment() {
    if (const char* dir = std::getenv("FREDHOLM_SPIRV_CACHE"); dir && *dir) {
        std::string value = dir;
        if (value == "off" || value == "0") return SpirvCache({});
        return SpirvCache(value);
    }
    if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg)
        return SpirvCache(std::filesystem::path(xdg) / "fredholm" / "spirv");
    if (const char* home = std::getenv("HOME"); home && *home)
        return SpirvCache(std::filesystem::path(home) / ".cache" / "fredholm" / "spirv");
    return SpirvCache({});
}

std::optional<std::vector<uint32_t>> SpirvCache::load(const SpirvKey& key) const {
    if (!enabled()) return std::nullopt;
    std::ifstream in(directory_ / key.file_name(), std::ios::binary | std::ios::ate);
    if (!in) return std::nullopt;
    std::streamoff size = in.tellg();
    if (size < 20 || size % 4 != 0 || size > (std::streamoff(1) << 30)) return std::nullopt;
    std::vector<uint32_t> words(size_t(size) / 4);
    in.seekg(0);
    if (!in.read(reinterpret_cast<char*>(words.data()), size) || words[0] != SPIRV_MAGIC) return std::nullopt;
    std::error_code error;  // the time of last use, for prune(): a read-only cache keeps its old times
    std::filesystem::last_write_time(directory_ / key.file_name(), std::filesystem::file_time_type::clock::now(),
                                     error);
    return words;
}

void SpirvCache::prune(size_t max_entries) const {
    std::error_code error;
    std::vector<std::pair<std::filesystem::file_time_type, std::filesystem::path>> entries;
    const auto now = std::filesystem::file_time_type::clock::now();
    for (const auto& entry : std::filesystem::directory_iterator(directory_, error)) {
        const auto written = entry.last_write_time(error);
        if (entry.path().extension() == ".spv") {
            entries.emplace_back(written, entry.path());
        } else if (entry.path().filename().string().find(".spv.tmp.") != std::string::npos &&
                   now - written > std::chrono::hours(1)) {
            std::filesystem::remove(entry.path(), error);  // left by a process killed while it wrote
        }
    }
    if (entries.size() <= max_entries) return;
    std::sort(entries.begin(), entries.end());
    for (size_t i = 0; i < entries.size() - max_entries / 2; ++i) std::filesystem::remove(entries[i].second, error);
}

void SpirvCache::store(const SpirvKey& key, std::span<const uint32_t> spirv) const {
    if (!enabled()) return;
    std::error_code error;
    std::filesystem::create_directories(directory_, error);
    if (error) return;
    static std::atomic<unsigned> counter{0};
    std::filesystem::path target = directory_ / key.file_name();
    std::filesystem::path temporary = target;
    temporary += ".tmp." + std::to_string(getpid()) + "." + std::to_string(counter++);
    {
        std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
        if (!out) return;
        out.write(reinterpret_cast<const char*>(spirv.data()), std::streamsize(spirv.size_bytes()));
        if (!out.flush()) {
            out.close();
            std::filesystem::remove(temporary, error);
            return;
        }
    }
    std::filesystem::rename(temporary, target, error);
    if (error) std::filesystem::remove(temporary, error);
    prune(MAX_ENTRIES);
}

}  // namespace fh::vk
