// `fredholm render --target-error`: on the Cornell box against Mitsuba 3's converged image (../shared/references), a
// render stops by itself once its estimate reaches the target, the estimate is within a factor of 1.5 of the image's
// true error, the limits (--max-spp) stop it with a message, and a target render resumed to a smaller target ends
// where one straight render to that target ends, bit for bit.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <sys/wait.h>

#include "io/exr.h"

namespace {

namespace fs = std::filesystem;
const fs::path OUT = fs::path(CONVERGE_OUT) / "target_error";
constexpr int SIZE = 64;  // the 256 x 256 reference averaged over 4 x 4 blocks

struct Outcome {
    int exit_code = -1;
    std::string err;
};

Outcome render(const std::string& name, const std::string& args) {
    fs::create_directories(OUT);
    const fs::path err = OUT / (name + ".err");
    const std::string line = std::string(FREDHOLM_EXE) + " render " + CORNELL_SCENE + " -o " + (OUT / (name + ".exr")).string() +
                             " --width 64 --height 64 --max-depth 10 " + args + " 2>" + err.string();
    std::printf("%s\n", line.c_str());
    const int status = std::system(line.c_str());
    std::ifstream in(err);
    std::stringstream text;
    text << in.rdbuf();
    return {WIFEXITED(status) ? WEXITSTATUS(status) : 128, text.str()};
}

std::vector<double> reference_luminance() {
    const fh::Image full = fh::read_exr(CORNELL_REFERENCE);
    std::vector<double> y(size_t(SIZE) * SIZE, 0.0);
    for (int r = 0; r < full.height; ++r)
        for (int x = 0; x < full.width; ++x) {
            const float* p = &full.rgb[(size_t(r) * full.width + x) * 3];
            y[size_t(r / 4) * SIZE + x / 4] += (0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]) / 16;
        }
    return y;
}

// The image's relative error against the reference, as error_estimate.h defines it.
double true_error(const fh::Image& image, const std::vector<double>& reference) {
    double sum = 0;
    for (size_t p = 0; p < reference.size(); ++p) {
        const double y = 0.2126 * image.rgb[3 * p] + 0.7152 * image.rgb[3 * p + 1] + 0.0722 * image.rgb[3 * p + 2];
        sum += (y - reference[p]) * (y - reference[p]) / (reference[p] * reference[p] + 0.01);
    }
    return std::sqrt(sum / double(reference.size()));
}

fh::ImageMetadata metadata_of(const std::string& name) {
    fh::ImageMetadata m;
    fh::read_exr(OUT / (name + ".exr"), &m);
    return m;
}

TEST(TargetError, StopsAtTheTargetWithAnHonestEstimate) {
    const std::vector<double> reference = reference_luminance();
    for (unsigned seed : {1u, 2u, 3u}) {
        const std::string name = "target_" + std::to_string(seed);
        const Outcome run = render(name, "--target-error 0.03 --seed " + std::to_string(seed));
        ASSERT_EQ(run.exit_code, 0) << run.err;
        EXPECT_NE(run.err.find("stopped by the target error"), std::string::npos) << run.err;
        const fh::ImageMetadata m = metadata_of(name);
        const double reported = std::stod(m.at("fredholm:relative_error"));
        const double truth = true_error(fh::read_exr(OUT / (name + ".exr")), reference);
        std::printf("[target error] seed %u: %s spp, reported %.4f, true (against Mitsuba) %.4f, ratio %.3f\n", seed,
                    m.at("fredholm:spp").c_str(), reported, truth, reported / truth);
        EXPECT_LE(reported, 0.03);
        EXPECT_LT(std::stoi(m.at("fredholm:spp")), 65536);
        EXPECT_GT(reported / truth, 1 / 1.5);
        EXPECT_LT(reported / truth, 1.5);
    }
}

TEST(TargetError, ASampleLimitStopsItAndSaysSo) {
    const Outcome run = render("limited", "--target-error 0.001 --max-spp 24");
    ASSERT_EQ(run.exit_code, 0) << run.err;
    EXPECT_NE(run.err.find("stopped by the sample limit before the target error"), std::string::npos) << run.err;
    EXPECT_EQ(metadata_of("limited").at("fredholm:spp"), "24");
}

TEST(TargetError, ResumedToASmallerTargetEqualsAStraightRender) {
    ASSERT_EQ(render("straight", "--target-error 0.03").exit_code, 0);
    ASSERT_EQ(render("resumed", "--target-error 0.06").exit_code, 0);
    const std::string first_spp = metadata_of("resumed").at("fredholm:spp");
    const Outcome more = render("resumed", "--target-error 0.03 --resume");
    ASSERT_EQ(more.exit_code, 0) << more.err;
    const fh::ImageMetadata a = metadata_of("straight"), b = metadata_of("resumed");
    EXPECT_LT(std::stoi(first_spp), std::stoi(b.at("fredholm:spp")));
    EXPECT_EQ(a.at("fredholm:spp"), b.at("fredholm:spp"));
    EXPECT_EQ(a.at("fredholm:relative_error"), b.at("fredholm:relative_error"));
    const fh::Image ia = fh::read_exr(OUT / "straight.exr"), ib = fh::read_exr(OUT / "resumed.exr");
    EXPECT_EQ(std::memcmp(ia.rgb.data(), ib.rgb.data(), ia.rgb.size() * sizeof(float)), 0);
}

}  // namespace
