// The device-memory estimate and the limit checks run before any allocation (no Vulkan device needed).
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "render/memory_estimate.h"
#include "render/device_defaults.h"

namespace {

// lavapipe (Mesa 22.3): maxStorageBufferRange 128 MiB, maxMemoryAllocationSize 2 GiB, one 2 GiB heap,
// maxTexelBufferElements 2^27.
const fh::DeviceMemoryLimits LAVAPIPE{uint64_t(128) << 20, uint64_t(2) << 30, uint64_t(2) << 30, uint64_t(1) << 27};

std::string check_error(const fh::MemoryEstimate& estimate, const fh::DeviceMemoryLimits& limits) {
    try {
        fh::check_render_memory(estimate, limits);
    } catch (const std::runtime_error& e) {
        return e.what();
    }
    return "";
}

uint64_t bytes_of(const fh::MemoryEstimate& e, const std::string& name) {
    for (const auto& b : e.buffers)
        if (b.name == name) return b.bytes;
    ADD_FAILURE() << "no buffer " << name;
    return 0;
}

TEST(MemoryEstimate, FilmIs52BytesAPixel) {
    const fh::PackedScene scene;
    const fh::MemoryEstimate e = fh::estimate_render_memory(scene, 8192, 8192, 1u << 18, 0u);
    EXPECT_EQ(bytes_of(e, "film"), uint64_t(52) << 26);  // an 8192 x 8192 film is 3.25 GiB (three 128-bit sums, a count)
    EXPECT_EQ(e.film_readback_bytes, uint64_t(52) << 26);
    EXPECT_EQ(bytes_of(e, "tri_positions"), sizeof(fh::gpu::TrianglePositions));  // empty arrays: one element
}

TEST(MemoryEstimate, WaveCapacityFollowsTheRenderer) {
    fh::RenderSettings s;
    s.width = 4;
    s.height = 4;
    s.spp = 2;  // 32 paths in all: the wave holds no more than that
    s.wave_paths = 1u << 18;
    const fh::MemoryEstimate e = fh::estimate_render_memory(fh::PackedScene{}, s);
    EXPECT_EQ(bytes_of(e, "paths"), 32 * sizeof(fh::gpu::PathState));
    EXPECT_EQ(bytes_of(e, "rays"), 2 * 32 * sizeof(fh::gpu::RayItem));
}

TEST(MemoryEstimate, RefusesAFilmBeyondTheStorageRangeWithTheNumbers) {
    EXPECT_EQ(check_error(fh::estimate_render_memory(fh::PackedScene{}, 1600, 1600, 1u << 18, 0u), LAVAPIPE), "");
    const std::string error = check_error(fh::estimate_render_memory(fh::PackedScene{}, 4096, 4096, 1u << 18, 0u), LAVAPIPE);
    EXPECT_NE(error.find("the film buffer needs 832.0 MiB (872415232 bytes)"), std::string::npos) << error;
    EXPECT_NE(error.find("maxStorageBufferRange of 128.0 MiB (134217728 bytes)"), std::string::npos) << error;
    EXPECT_NE(error.find("--width/--height (or --crop parts"), std::string::npos) << error;
}

// The scene's arrays are texel buffers (layout.h TEXELS): past maxStorageBufferRange, up to maxTexelBufferElements
// 16-byte texels (2 GiB on lavapipe, where its allocations also stop).
TEST(MemoryEstimate, NamesTheSceneArrayThatIsTooLarge) {
    fh::MemoryEstimate e = fh::estimate_render_memory(fh::PackedScene{}, 64, 64, 4096, 0u);
    for (auto& b : e.buffers)
        if (b.name == "tri_positions") b.bytes = uint64_t(200) << 20;
    EXPECT_EQ(check_error(e, LAVAPIPE), "");  // 200 MiB of triangles: more than a storage buffer reaches
    fh::DeviceMemoryLimits roomy = LAVAPIPE;
    roomy.max_allocation_size = roomy.device_local_heap = uint64_t(16) << 30;
    for (auto& b : e.buffers)
        if (b.name == "tri_positions") b.bytes = uint64_t(3) << 30;
    const std::string error = check_error(e, roomy);
    EXPECT_NE(error.find("the tri_positions buffer needs 3.00 GiB"), std::string::npos) << error;
    EXPECT_NE(error.find("maxTexelBufferElements of 134217728 16-byte texels (2.00 GiB"), std::string::npos) << error;
    EXPECT_NE(error.find("a smaller scene"), std::string::npos) << error;
}

TEST(MemoryEstimate, ChecksAllocationSizeAndTheHeap) {
    const fh::MemoryEstimate e = fh::estimate_render_memory(fh::PackedScene{}, 8192, 8192, 1u << 18, 0u);
    fh::DeviceMemoryLimits roomy{uint64_t(8) << 30, uint64_t(1) << 30, uint64_t(16) << 30, uint64_t(1) << 27};
    std::string error = check_error(e, roomy);
    EXPECT_NE(error.find("maxMemoryAllocationSize of 1.00 GiB"), std::string::npos) << error;
    roomy.max_allocation_size = uint64_t(4) << 30;
    roomy.device_local_heap = uint64_t(1) << 30;
    error = check_error(e, roomy);
    EXPECT_NE(error.find("more than the device-local heap of 1.00 GiB"), std::string::npos) << error;
    EXPECT_NE(error.find("largest: film, 3.25 GiB"), std::string::npos) << error;
}

}  // namespace

// Without --wave-paths the wave is sized for the device: 2^19 paths on a CPU device, 2^22 on a GPU, halved until the
// wave's buffers keep to the device's limits and to a quarter of its memory.
TEST(WaveSize, ChosenByDeviceKindAndHalvedToFitTheLimits) {
    const fh::PackedScene scene;
    EXPECT_EQ(fh::choose_wave_paths(true, LAVAPIPE, scene, 0u), fh::CPU_WAVE_PATHS);
    // A GPU with lavapipe's 128 MiB storage range: the rays buffer (two 32-byte rays per path) caps it at 2^21.
    EXPECT_EQ(fh::choose_wave_paths(false, LAVAPIPE, scene, 0u), 1u << 21);
    fh::DeviceMemoryLimits large = LAVAPIPE;
    large.max_storage_buffer_range = large.max_allocation_size = uint64_t(4) << 30;
    large.device_local_heap = uint64_t(80) << 30;
    EXPECT_EQ(fh::choose_wave_paths(false, large, scene, 0u), fh::GPU_WAVE_PATHS);
    // A quarter of a 1 GiB heap holds 2^20 paths of this size, not 2^21.
    fh::DeviceMemoryLimits small = large;
    small.device_local_heap = uint64_t(1) << 30;
    const double per_path = fh::bytes_per_path(scene, 0u);
    ASSERT_GT(per_path * (1u << 21), 0.25 * double(small.device_local_heap));
    ASSERT_LE(per_path * (1u << 20), 0.25 * double(small.device_local_heap));
    EXPECT_EQ(fh::choose_wave_paths(false, small, scene, 0u), 1u << 20);
}

TEST(WaveSize, AnEstimateNeedsAChosenWave) {
    fh::RenderSettings s;
    EXPECT_THROW(fh::estimate_render_memory(fh::PackedScene{}, s), std::logic_error);
}

// --sort-rays auto: never on a CPU device (lavapipe: the sort costs about what it saves), on a GPU from
// MIN_AUTO_SORT_TRIANGLES stored triangles (an H100 saved 5 to 13% from 1,290 triangles up, lost 6 to 12% at 20 and 42).
TEST(RaySortChoice, ChosenByDeviceKindAndSceneSize) {
    fh::PackedScene scene;
    scene.positions.resize(42);
    EXPECT_FALSE(fh::choose_sort_rays(true, scene));
    EXPECT_FALSE(fh::choose_sort_rays(false, scene));
    scene.positions.resize(fh::MIN_AUTO_SORT_TRIANGLES);
    EXPECT_FALSE(fh::choose_sort_rays(true, scene));
    EXPECT_TRUE(fh::choose_sort_rays(false, scene));
}

namespace {
std::string size_error(const std::string& word) {
    try {
        fh::parse_memory_size(word);
    } catch (const std::invalid_argument& e) {
        return e.what();
    }
    return "";
}
}  // namespace

TEST(MemoryLimit, ParsesSizesInBinaryUnits) {
    EXPECT_EQ(fh::parse_memory_size("100M"), uint64_t(100) << 20);
    EXPECT_EQ(fh::parse_memory_size("100MiB"), uint64_t(100) << 20);
    EXPECT_EQ(fh::parse_memory_size("1.5G"), uint64_t(3) << 29);
    EXPECT_EQ(fh::parse_memory_size("2gb"), uint64_t(2) << 30);
    EXPECT_EQ(fh::parse_memory_size("64k"), uint64_t(64) << 10);
    EXPECT_EQ(fh::parse_memory_size("1T"), uint64_t(1) << 40);
    EXPECT_EQ(fh::parse_memory_size("4096"), 4096u);
    for (const char* bad : {"", "M", "10Q", "-1G", "0", "1e400", "5 G", "1Gx", "nan"})
        EXPECT_NE(size_error(bad).find("is not a size"), std::string::npos) << bad;
    EXPECT_GT(fh::default_memory_limit(), uint64_t(0));
}

TEST(MemoryLimit, NamesTheLargestUsesWhenTheirSumIsTooLarge) {
    const std::vector<fh::MemoryUse> uses{{"a", 10}, {"b", 300}, {"c", 20}, {"d", 5}};
    EXPECT_EQ(fh::find_limit_problem(uses, 335, "x"), "");
    EXPECT_EQ(fh::find_limit_problem(uses, 0, "x"), "");  // no limit
    const std::string error = fh::find_limit_problem(uses, 334, "the thing");
    EXPECT_EQ(error.rfind("the thing needs 0.0 MiB (335 bytes), more than the memory limit of 0.0 MiB (334 bytes) "
                          "(--memory-limit; largest: b 0.0 MiB (300 bytes), c 0.0 MiB (20 bytes), a 0.0 MiB (10 bytes))", 0),
              0u)
        << error;
}

// On a CPU device the host's share and the device buffers are one pool; on a GPU each must fit on its own.
TEST(MemoryLimit, SumsHostAndDeviceOnlyOnACpuDevice) {
    const fh::MemoryEstimate device = fh::estimate_render_memory(fh::PackedScene{}, 64, 64, 4096, 0u);
    const uint64_t device_bytes = device.device_bytes();
    const std::vector<fh::MemoryUse> host{{"host scene textures", device_bytes}};
    const uint64_t limit = device_bytes + device_bytes / 2;
    EXPECT_EQ(fh::find_memory_limit_problem(host, device, limit, false), "");
    const std::string error = fh::find_memory_limit_problem(host, device, limit, true);
    EXPECT_NE(error.find("the render (host and device memory: one on a CPU device) needs"), std::string::npos) << error;
    EXPECT_NE(error.find("largest: host scene textures"), std::string::npos) << error;
    EXPECT_NE(fh::find_memory_limit_problem(host, device, device_bytes - 1, false).find("the render's host memory"),
              std::string::npos);
}
