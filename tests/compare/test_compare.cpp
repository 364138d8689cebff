// `fredholm compare` through the real binary: renders of the same scene with different seeds are called the same at
// no more than the stated false-alarm rate (within its binomial noise), a 4% albedo change of one object and a texture
// shifted by half a checker cell are detected at 256 spp, identical files compare equal, and bad input exits 2 with
// one line.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <sys/wait.h>

#include "io/exr.h"

namespace {

namespace fs = std::filesystem;
const fs::path OUT = fs::path(FH_TEST_OUTPUT) / "compare";

struct Outcome {
    int exit_code = -1;
    std::string out, err;
};

std::string read_text(const fs::path& file) {
    std::ifstream in(file);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
}

// Each test's own files: ctest runs the tests of this file in parallel.
std::string test_name() { return testing::UnitTest::GetInstance()->current_test_info()->name(); }

Outcome fredholm(const std::string& args) {
    fs::create_directories(OUT);
    const fs::path out = OUT / (test_name() + ".stdout"), err = OUT / (test_name() + ".stderr");
    const std::string line = std::string(FREDHOLM_EXE) + " " + args + " >" + out.string() + " 2>" + err.string();
    const int status = std::system(line.c_str());
    Outcome r;
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128;
    r.out = read_text(out);
    r.err = read_text(err);
    return r;
}

fs::path render(const std::string& scene, const std::string& name, int size, int spp, unsigned seed,
                const std::string& more = "") {
    const fs::path file = OUT / (name + ".exr");
    const Outcome r = fredholm("render " + scene + " -o " + file.string() + " --width " + std::to_string(size) +
                           " --height " + std::to_string(size) + " --spp " + std::to_string(spp) + " --max-depth 8 " +
                           "--seed " + std::to_string(seed) + " -q " + more);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return file;
}

int compare(const fs::path& a, const fs::path& b, const std::string& more = "") {
    const Outcome r = fredholm("compare " + a.string() + " " + b.string() + " " + more);
    std::printf("%s", r.out.c_str());
    EXPECT_NE(r.out.find("fredholm compare: "), std::string::npos) << r.err;
    return r.exit_code;
}

// Pairs of renders that differ only in their seed, 50 per sampler (100 in all): at alpha 0.05, 2.5 false alarms
// expected per 50; 8 or more has a chance of 0.3% if the rate is right (binomial), so more means the test calls noise
// a difference too often. With Sobol' samples the batches overstate the variance (engine/render/README.md "Error
// estimate"), so false alarms are rarer still; the independent sampler's estimate is unbiased, which tests the
// statistics themselves.
void expect_false_alarm_rate(const std::string& sampler) {
    int differs = 0;
    const int pairs = 50;
    for (int i = 0; i < pairs; ++i) {
        const fs::path a = render(CORNELL_SCENE, sampler + "_a", 32, 32, 2 * i + 1, "--sampler " + sampler);
        const fs::path b = render(CORNELL_SCENE, sampler + "_b", 32, 32, 2 * i + 2, "--sampler " + sampler);
        const int code = compare(a, b, "--alpha 0.05 --tile 8");
        EXPECT_TRUE(code == 0 || code == 1);
        differs += code == 1;
    }
    std::printf("[compare] %s: %d of %d pairs of seeds called different at alpha 0.05\n", sampler.c_str(), differs,
                pairs);
    EXPECT_LE(differs, 7);
}

TEST(Compare, FalseAlarmsAtMostAlphaSobol) { expect_false_alarm_rate("sobol"); }
TEST(Compare, FalseAlarmsAtMostAlphaIndependent) { expect_false_alarm_rate("independent"); }

TEST(Compare, DetectsAFourPercentAlbedoChange) {
    const fs::path a = render(CORNELL_SCENE, "cornell_1", 64, 256, 1);
    const fs::path same = render(CORNELL_SCENE, "cornell_2", 64, 256, 2);
    const fs::path darker = render(SCENES_DIR "/cornell_cube_4pct.gltf", "cornell_cube_4pct", 64, 256, 3);
    EXPECT_EQ(compare(a, same), 0);
    EXPECT_EQ(compare(a, darker, "--heatmap " + (OUT / "albedo_heatmap.png").string()), 1);
    EXPECT_TRUE(fs::exists(OUT / "albedo_heatmap.png"));
}

TEST(Compare, DetectsAShiftedTexture) {
    const fs::path a = render(SCENES_DIR "/checker_room.gltf", "checker_1", 64, 256, 1);
    const fs::path same = render(SCENES_DIR "/checker_room.gltf", "checker_2", 64, 256, 2);
    const fs::path shifted = render(SCENES_DIR "/checker_room_shifted.gltf", "checker_shifted", 64, 256, 3);
    EXPECT_EQ(compare(a, same), 0);
    EXPECT_EQ(compare(a, shifted), 1);
}

TEST(Compare, IdenticalFilesAreTheSame) {
    const fs::path a = render(CORNELL_SCENE, "identical", 32, 16, 1);
    EXPECT_EQ(compare(a, a), 0);
}

TEST(Compare, BadInputExitsTwoWithOneLine) {
    const fs::path a = render(CORNELL_SCENE, "bad_a", 32, 16, 1);
    const fs::path small = render(CORNELL_SCENE, "bad_small", 16, 16, 1);
    const fs::path not_exr = OUT / (test_name() + "_not_an_exr.exr");
    std::ofstream(not_exr) << "not an image";
    for (const std::string& args : {"compare " + a.string() + " " + (OUT / "missing.exr").string(),
                                    "compare " + a.string() + " " + not_exr.string(),
                                    "compare " + a.string() + " " + small.string(),
                                    "compare " + a.string() + " " + a.string() + " --alpha 2",
                                    "compare " + a.string()}) {
        const Outcome r = fredholm(args);
        EXPECT_EQ(r.exit_code, 2) << args;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << args << ": " << r.err;
    }
}

// An image without a variance layer (another renderer's, or an older fredholm's): a warning, then the plain threshold.
TEST(Compare, WithoutVarianceLayersFallsBackToAThreshold) {
    const fs::path a = render(CORNELL_SCENE, "plain_a", 32, 64, 1);
    const fh::Image image = fh::read_exr(a);
    const fs::path plain = OUT / (test_name() + "_plain.exr");
    fh::write_exr(plain, image);
    Outcome r = fredholm("compare " + a.string() + " " + plain.string());
    EXPECT_EQ(r.exit_code, 0) << r.out;
    EXPECT_NE(r.err.find("has no variance layer"), std::string::npos) << r.err;
    fh::Image brighter = image;
    for (float& v : brighter.rgb) v *= 1.05f;
    fh::write_exr(plain, brighter);
    r = fredholm("compare " + a.string() + " " + plain.string());
    EXPECT_EQ(r.exit_code, 1) << r.out;
    r = fredholm("compare " + a.string() + " " + plain.string() + " --threshold 0.1");
    EXPECT_EQ(r.exit_code, 0) << r.out;
}

}  // namespace
