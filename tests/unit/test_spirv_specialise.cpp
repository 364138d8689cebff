// The host-side specialisation of the stages' SPIR-V (engine/vk/spirv_specialise.h) and its disk cache: what the
// driver is given is valid, has no specialization constants left, holds only the scene's effects, and comes back
// from the cache bit for bit.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>
#include <vector>

#include <spirv-tools/libspirv.hpp>

#include "shaders/extend.spv.h"
#include "shaders/shade.spv.h"
#include "scene/effects.h"
#include "shared/layout.h"
#include "vk/spirv_cache.h"
#include "vk/spirv_specialise.h"

namespace fs = std::filesystem;
using fh::vk::SpirvCache;
using fh::vk::specialise_spirv;

namespace {

// OpSpecConstantTrue (48) .. OpSpecConstantOp (52) in a module's instruction stream (after the 5-word header).
size_t count_spec_constants(std::span<const uint32_t> spirv) {
    size_t count = 0;
    for (size_t i = 5; i < spirv.size();) {
        uint32_t opcode = spirv[i] & 0xffffu, words = spirv[i] >> 16;
        if (opcode >= 48 && opcode <= 52) ++count;
        if (words == 0) ADD_FAILURE() << "instruction of 0 words at " << i;
        i += words ? words : 1;
    }
    return count;
}

// OpPhi (245) whose result is a float vector (OpTypeVector, 23, of an OpTypeFloat, 22): a ray's origin, direction or
// their inverses carried from one loop iteration to the next, or merged after a branch.
size_t count_float_vector_phis(std::span<const uint32_t> spirv) {
    std::vector<uint32_t> floats, float_vectors;
    size_t count = 0;
    for (size_t i = 5; i < spirv.size();) {
        const uint32_t opcode = spirv[i] & 0xffffu, words = spirv[i] >> 16;
        if (words == 0) break;
        if (opcode == 22) floats.push_back(spirv[i + 1]);
        if (opcode == 23 && std::find(floats.begin(), floats.end(), spirv[i + 2]) != floats.end())
            float_vectors.push_back(spirv[i + 1]);
        if (opcode == 245 && std::find(float_vectors.begin(), float_vectors.end(), spirv[i + 1]) != float_vectors.end())
            ++count;
        i += words;
    }
    return count;
}

bool is_valid_vulkan_spirv(const std::vector<uint32_t>& spirv) {
    spvtools::SpirvTools tools(SPV_ENV_VULKAN_1_1);
    return tools.Validate(spirv);
}

std::vector<uint32_t> spec_for(fh::EffectBits effects) {
    std::vector<uint32_t> spec(fh::gpu::SPEC_CONSTANT_COUNT, 0u);
    spec[fh::gpu::SPEC_EFFECTS] = fh::low_effect_word(effects);
    spec[fh::gpu::SPEC_EFFECTS_2] = fh::high_effect_word(effects);
    spec[fh::gpu::SPEC_SAMPLER] = fh::gpu::SAMPLER_SOBOL;
    return spec;
}

class TempDir {
public:
    TempDir() : path_(fs::temp_directory_path() / ("fh_spirv_cache_test_" + std::to_string(getpid()))) {
        fs::remove_all(path_);
    }
    ~TempDir() { fs::remove_all(path_); }
    const fs::path& path() const { return path_; }
    size_t file_count() const {
        if (!fs::exists(path_)) return 0;
        return size_t(std::distance(fs::directory_iterator(path_), fs::directory_iterator()));
    }

private:
    fs::path path_;
};

const fh::EffectBits CORNELL_EFFECTS = fh::gpu::EFFECT_EMISSIVE_TRIANGLES;  // what the Cornell box calls for
const fh::EffectBits ALL_EFFECTS = fh::SWITCHABLE_EFFECTS;

}  // namespace

TEST(SpirvSpecialise, CornellShadeKeepsOnlyItsEffectsAndNoSpecConstants) {
    ASSERT_GT(count_spec_constants(spv_shade), 0u);
    const SpirvCache no_cache({});
    std::vector<uint32_t> out = specialise_spirv(spv_shade, spec_for(CORNELL_EFFECTS), no_cache);
    ASSERT_FALSE(out.empty());
    EXPECT_EQ(out[0], 0x07230203u);
    EXPECT_EQ(count_spec_constants(out), 0u);
    EXPECT_TRUE(is_valid_vulkan_spirv(out));
    // The material extensions are gone: 50 KB of 866 KB when this was written (tests/bench/RESULTS.md "Time to first pixel").
    std::printf("shade for the Cornell box's effects: %zu of %zu bytes\n", out.size() * 4, std::size(spv_shade) * 4);
    EXPECT_LT(out.size() * 5, std::size(spv_shade)) << out.size() << " of " << std::size(spv_shade) << " words";
}

TEST(SpirvSpecialise, MoreEffectsKeepMoreCode) {
    const SpirvCache no_cache({});
    std::vector<uint32_t> cornell = specialise_spirv(spv_shade, spec_for(CORNELL_EFFECTS), no_cache);
    std::vector<uint32_t> all = specialise_spirv(spv_shade, spec_for(ALL_EFFECTS), no_cache);
    ASSERT_FALSE(all.empty());
    std::printf("shade with every switchable effect: %zu bytes\n", all.size() * 4);
    EXPECT_EQ(count_spec_constants(all), 0u);
    EXPECT_TRUE(is_valid_vulkan_spirv(all));
    EXPECT_GT(all.size(), 4 * cornell.size());
}

// Returning from an instance (traverse.glsl LEAVE_INSTANCE_BELOW_BASE) sets the ray back to its world-space origin and
// direction. glslang turns that branch into selects, and a one-level scene's specialisation must fold them away, with
// the loop-carried copies of the ray they made: on lavapipe those cost 120 of the node loop's 800 instructions and 9%
// of the Cornell box's traced rays per second (tests/bench/RESULTS.md "Speed"). Only the origin triangle's normal is merged after a
// branch then.
TEST(SpirvSpecialise, OneLevelTraversalCarriesNoRayCopiesThroughItsLoops) {
    const SpirvCache no_cache({});
    std::vector<uint32_t> spec = spec_for(CORNELL_EFFECTS);
    const std::vector<uint32_t> one_level = specialise_spirv(spv_extend, spec, no_cache);
    spec[fh::gpu::SPEC_HAS_INSTANCES] = 1u;
    const std::vector<uint32_t> two_levels = specialise_spirv(spv_extend, spec, no_cache);
    ASSERT_FALSE(one_level.empty());
    ASSERT_FALSE(two_levels.empty());
    std::printf("float-vector phis in extend: %zu with one level, %zu with instances\n",
                count_float_vector_phis(one_level), count_float_vector_phis(two_levels));
    EXPECT_LE(count_float_vector_phis(one_level), 1u);
    EXPECT_GT(count_float_vector_phis(two_levels), 8u) << "the instanced traversal carries its ray as before";
}

TEST(SpirvSpecialise, SameInputsGiveTheSameModule) {
    const SpirvCache no_cache({});
    EXPECT_EQ(specialise_spirv(spv_extend, spec_for(CORNELL_EFFECTS), no_cache),
              specialise_spirv(spv_extend, spec_for(CORNELL_EFFECTS), no_cache));
}

TEST(SpirvSpecialise, CacheReturnsTheComputedModule) {
    TempDir dir;
    const SpirvCache cache(dir.path());
    const SpirvCache no_cache({});
    std::vector<uint32_t> computed = specialise_spirv(spv_extend, spec_for(CORNELL_EFFECTS), no_cache);
    EXPECT_EQ(specialise_spirv(spv_extend, spec_for(CORNELL_EFFECTS), cache), computed);
    ASSERT_EQ(dir.file_count(), 1u);
    // The second call reads the file: damage the stored module's body and the damage comes back.
    fs::path stored = fs::directory_iterator(dir.path())->path();
    {
        std::vector<uint32_t> marked = computed;
        marked.back() ^= 1u;
        std::ofstream(stored, std::ios::binary | std::ios::trunc)
            .write(reinterpret_cast<const char*>(marked.data()), std::streamsize(marked.size() * 4));
    }
    std::vector<uint32_t> reread = specialise_spirv(spv_extend, spec_for(CORNELL_EFFECTS), cache);
    ASSERT_EQ(reread.size(), computed.size());
    EXPECT_NE(reread.back(), computed.back());
    // Other constants are another entry.
    specialise_spirv(spv_extend, spec_for(ALL_EFFECTS), cache);
    EXPECT_EQ(dir.file_count(), 2u);
}

TEST(SpirvSpecialise, DamagedCacheEntryIsAMissAndIsRewritten) {
    TempDir dir;
    const SpirvCache cache(dir.path());
    std::vector<uint32_t> computed = specialise_spirv(spv_extend, spec_for(CORNELL_EFFECTS), cache);
    fs::path stored = fs::directory_iterator(dir.path())->path();
    // A truncated write (not whole words), and whole words that are not SPIR-V (no magic number).
    for (std::string damage : {std::string("not spir-v"), std::string(24, 'x')}) {
        std::ofstream(stored, std::ios::binary | std::ios::trunc).write(damage.data(), std::streamsize(damage.size()));
        EXPECT_EQ(specialise_spirv(spv_extend, spec_for(CORNELL_EFFECTS), cache), computed) << damage;
        EXPECT_EQ(fs::file_size(stored), computed.size() * 4);
        EXPECT_EQ(dir.file_count(), 1u);  // no temporary file left behind
    }
}

TEST(SpirvSpecialise, EnvironmentTurnsItOff) {
    const SpirvCache no_cache({});
    ::setenv("FREDHOLM_SPECIALISE_SPIRV", "off", 1);
    std::vector<uint32_t> off = specialise_spirv(spv_extend, spec_for(CORNELL_EFFECTS), no_cache);
    ::unsetenv("FREDHOLM_SPECIALISE_SPIRV");
    EXPECT_TRUE(off.empty());
    EXPECT_FALSE(specialise_spirv(spv_extend, spec_for(CORNELL_EFFECTS), no_cache).empty());
}

TEST(SpirvCache, EnvironmentChoosesTheDirectory) {
    ::setenv("FREDHOLM_SPIRV_CACHE", "off", 1);
    EXPECT_FALSE(SpirvCache::from_environment().enabled());
    ::setenv("FREDHOLM_SPIRV_CACHE", "/some/where", 1);
    EXPECT_EQ(SpirvCache::from_environment().directory(), fs::path("/some/where"));
    ::unsetenv("FREDHOLM_SPIRV_CACHE");
    ::setenv("XDG_CACHE_HOME", "/xdg", 1);
    EXPECT_EQ(SpirvCache::from_environment().directory(), fs::path("/xdg/fredholm/spirv"));
    ::unsetenv("XDG_CACHE_HOME");
}

TEST(SpirvCache, KeysSeparateTheirParts) {
    const uint8_t ab[] = {'a', 'b'}, a[] = {'a'}, b[] = {'b'};
    auto joined = fh::vk::hash_spirv_key({ab});
    auto split = fh::vk::hash_spirv_key({a, b});
    EXPECT_NE(joined.file_name(), split.file_name());
    EXPECT_EQ(split.file_name(), fh::vk::hash_spirv_key({a, b}).file_name());
    EXPECT_EQ(split.file_name().size(), 36u);
}

TEST(SpirvCache, PruneKeepsTheEntriesUsedLast) {
    TempDir dir;
    const SpirvCache cache(dir.path());
    const uint32_t module[5] = {0x07230203u, 0x00010300u, 0u, 1u, 0u};  // a header alone
    std::vector<fh::vk::SpirvKey> keys;
    for (uint8_t i = 0; i < 8; ++i) {
        const uint8_t part[1] = {i};
        keys.push_back(fh::vk::hash_spirv_key({part}));
        cache.store(keys.back(), module);
        fs::last_write_time(dir.path() / keys.back().file_name(),
                            fs::file_time_type::clock::now() - std::chrono::hours(100 - i));  // older first
    }
    EXPECT_TRUE(cache.load(keys[0]).has_value());  // a use makes the oldest the newest
    // Temporary files of killed writers go once they are an hour old; a fresh one may still be being written.
    const fs::path stale = dir.path() / (keys[0].file_name() + ".tmp.1.0");
    const fs::path fresh = dir.path() / (keys[0].file_name() + ".tmp.2.0");
    std::ofstream(stale) << "x";
    std::ofstream(fresh) << "x";
    fs::last_write_time(stale, fs::file_time_type::clock::now() - std::chrono::hours(2));
    cache.prune(6);
    EXPECT_FALSE(fs::exists(stale));
    EXPECT_TRUE(fs::exists(fresh));
    fs::remove(fresh);
    EXPECT_EQ(dir.file_count(), 3u);
    EXPECT_TRUE(cache.load(keys[0]).has_value());
    EXPECT_TRUE(cache.load(keys[7]).has_value());
    EXPECT_FALSE(cache.load(keys[1]).has_value());
}
