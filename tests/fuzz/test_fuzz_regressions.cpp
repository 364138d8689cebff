// Loads every input that ever broke the loader (tests/fuzz/regressions/, found by the fuzzer) and every
// third-party malformed scene (tests/robustness/thirdparty/): each must load or throw a SceneError whose one
// line names the file. A crash, hang or sanitizer report here is a regression. Also: buffer URIs naming
// something other than a regular file (the fuzzer cannot make those exist) are refused without blocking.
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "scene/scene.h"

namespace {
namespace fs = std::filesystem;

const fs::path REGRESSIONS = FH_SOURCE_DIR "/tests/fuzz/regressions";
const fs::path THIRD_PARTY = FH_SOURCE_DIR "/tests/robustness/thirdparty";

// Fuzzer findings have no extension (crash-<sha1>, timeout-<sha1>); third-party folders also hold buffers,
// images and notes, so only their scenes are loaded.
bool is_input(const fs::path& file, bool scenes_only) {
    if (file.extension() == ".md") return false;
    return !scenes_only || file.extension() == ".gltf" || file.extension() == ".glb";
}

std::vector<fs::path> list_inputs() {
    std::vector<fs::path> inputs;
    for (const auto& [dir, scenes_only] : {std::pair{REGRESSIONS, false}, std::pair{THIRD_PARTY, true}}) {
        if (!fs::is_directory(dir)) continue;
        for (const auto& entry : fs::recursive_directory_iterator(dir))
            if (entry.is_regular_file() && is_input(entry.path(), scenes_only)) inputs.push_back(entry.path());
    }
    std::sort(inputs.begin(), inputs.end());
    return inputs;
}

// A test name from the path under tests/: letters, digits and underscores only.
std::string name_test(const testing::TestParamInfo<fs::path>& info) {
    std::string name = fs::relative(info.param, FH_SOURCE_DIR "/tests").string();
    for (char& c : name)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    return name;
}

class LoaderInput : public testing::TestWithParam<fs::path> {};

TEST_P(LoaderInput, LoadsOrFailsWithOneLineNamingTheFile) {
    const fs::path& file = GetParam();
    fh::LoadOptions options;
    options.memory_limit = uint64_t(512) << 20;  // as fuzz_load_gltf.cpp: textures of gigabytes are refused
    try {
        const fh::Scene scene = fh::load_gltf(file, options);
        EXPECT_GT(scene.triangle_count(), 0u);
    } catch (const fh::SceneError& e) {
        const std::string message = e.what();
        EXPECT_EQ(message.rfind(file.string() + ": ", 0), 0u) << message;
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
        EXPECT_GT(message.size(), file.string().size() + 2) << "no problem named: " << message;
    }
}

INSTANTIATE_TEST_SUITE_P(Files, LoaderInput, testing::ValuesIn(list_inputs()), name_test);
GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(LoaderInput);

// A scene with one 12-byte buffer at `uri`: the loader must refuse it naming the problem.
std::string load_with_buffer_uri(const fs::path& dir, const std::string& uri) {
    const fs::path scene = dir / "scene.gltf";
    std::ofstream(scene) << R"({"asset": {"version": "2.0"}, "buffers": [{"uri": ")" << uri
                         << R"(", "byteLength": 12}]})";
    try {
        (void)fh::load_gltf(scene);
    } catch (const fh::SceneError& e) {
        return e.what();
    }
    return "loaded";
}

TEST(BufferUri, RefusesWhatIsNotARegularFileWithoutBlocking) {
    const fs::path dir = fs::temp_directory_path() / ("fh_buffer_uri_" + std::to_string(getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    ASSERT_EQ(mkfifo((dir / "fifo").c_str(), 0600), 0);  // opening it for reading would wait for a writer
    // tinygltf joins even absolute URIs onto the scene's folder, so devices are reached through links.
    fs::create_symlink("/dev/zero", dir / "zero");
    fs::create_symlink("/dev/null", dir / "null");
    fs::create_symlink("/", dir / "root");
    for (const std::string uri : {"zero", "null", "fifo", "root", "."}) {
        const std::string message = load_with_buffer_uri(dir, uri);
        EXPECT_NE(message.find("not a regular file"), std::string::npos) << uri << ": " << message;
        EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    }
    // Over the size limit: refused from its size, before reading (a sparse file, no disk used).
    { std::ofstream create(dir / "huge.bin"); }
    fs::resize_file(dir / "huge.bin", (uint64_t(2) << 30) + 1);
    EXPECT_NE(load_with_buffer_uri(dir, "huge.bin").find("2147483649 bytes, more than the limit"), std::string::npos);
    fs::remove_all(dir);
}

}  // namespace
