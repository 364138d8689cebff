// `fredholm render --adaptive` through the real binary: each pixel holds exactly the samples a uniform render of its
// count gives it (the pixel list maps waves to the right pixels and sample indices), counts differ across the image,
// the image is deterministic and carries its variance layer and error; what adaptive films cannot do is refused.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <string>

#include "io/exr.h"
#include "run_fredholm.h"

namespace {

namespace fs = std::filesystem;
const fs::path OUT = fs::path(FH_TEST_OUTPUT) / "adaptive";
const std::string SIZE = " --width 40 --height 32 --max-depth 8 -q";

int fredholm(const std::string& args) { return fh::test::run_fredholm(FREDHOLM_EXE, OUT, args); }
std::string last_log_line() { return fh::test::last_log_line(OUT); }

std::string path(const char* name) { return (OUT / name).string(); }

// The raw film: fredholm.sum.{R,G,B}.{0..3} and fredholm.count.
fh::ExtraChannels film(const std::string& file) {
    std::vector<std::string> names{"fredholm.count"};
    for (const char* c : {"R", "G", "B"})
        for (int w = 0; w < 4; ++w) names.push_back(std::string("fredholm.sum.") + c + "." + std::to_string(w));
    return fh::read_exr_channels(file, names);
}

TEST(Adaptive, EachPixelHoldsTheSamplesOfAUniformRenderOfItsCount) {
    ASSERT_EQ(fredholm("render " CORNELL_SCENE " -o " + path("adaptive.exr") + SIZE + " --spp 16 --adaptive --aov spp"), 0);
    const fh::ExtraChannels a = film(path("adaptive.exr"));
    const std::vector<uint32_t>& counts = a.at("fredholm.count");
    const std::vector<float> spp = fh::read_exr_float_channels(path("adaptive.exr"), {"spp.N"}).at("spp.N");
    std::map<uint32_t, size_t> pixels_per_count;
    for (size_t p = 0; p < counts.size(); ++p) {
        ASSERT_EQ(float(counts[p]), spp[p]);
        ++pixels_per_count[counts[p]];
    }
    // Adaptive: the pilot found the light and the walls' noise unequal.
    ASSERT_GE(pixels_per_count.size(), 3u);
    for (const auto& [n, pixels] : pixels_per_count) {
        std::printf("[adaptive] %zu pixels with %u samples\n", pixels, n);
        EXPECT_EQ(n & (n - 1), 0u) << "counts are powers of two";
    }
    // Every pixel's sums are those of the uniform render of its count, bit for bit.
    for (const auto& [n, pixels] : pixels_per_count) {
        const std::string uniform = path("uniform.exr");
        ASSERT_EQ(fredholm("render " CORNELL_SCENE " -o " + uniform + SIZE + " --spp " + std::to_string(n)), 0);
        const fh::ExtraChannels u = film(uniform);
        size_t checked = 0;
        for (size_t p = 0; p < counts.size(); ++p) {
            if (counts[p] != n) continue;
            for (const auto& [name, values] : u) ASSERT_EQ(values[p], a.at(name)[p]) << name << " pixel " << p;
            ++checked;
        }
        EXPECT_EQ(checked, pixels);
    }
}

TEST(Adaptive, DeterministicWithItsVarianceAndError) {
    ASSERT_EQ(fredholm("render " CORNELL_SCENE " -o " + path("once.exr") + SIZE + " --spp 16 --adaptive"), 0);
    ASSERT_EQ(fredholm("render " CORNELL_SCENE " -o " + path("twice.exr") + SIZE + " --spp 16 --adaptive"), 0);
    EXPECT_EQ(film(path("once.exr")), film(path("twice.exr")));
    fh::ImageMetadata metadata;
    fh::read_exr(path("once.exr"), &metadata);
    ASSERT_TRUE(metadata.count("fredholm:adaptive"));
    EXPECT_NE(metadata.at("fredholm:adaptive").find("pilot 4 spp"), std::string::npos) << metadata.at("fredholm:adaptive");
    const double error = std::stod(metadata.at("fredholm:relative_error"));
    EXPECT_GT(error, 0.0);
    EXPECT_LT(error, 1.0);
    const std::vector<float> variance = fh::read_exr_float_channels(path("once.exr"), {"variance.Y"}).at("variance.Y");
    for (float v : variance) ASSERT_TRUE(std::isfinite(v) && v >= 0.0f);
    // Another seed: another pilot and another image.
    ASSERT_EQ(fredholm("render " CORNELL_SCENE " -o " + path("seed.exr") + SIZE + " --spp 16 --adaptive --seed 3"), 0);
    EXPECT_NE(film(path("once.exr")), film(path("seed.exr")));
}

TEST(Adaptive, ToATargetError) {
    ASSERT_EQ(fredholm("render " CORNELL_SCENE " -o " + path("target.exr") + SIZE + " --target-error 0.08 --adaptive "
                       "--stats " + path("target.json")),
              0);
    fh::ImageMetadata metadata;
    fh::read_exr(path("target.exr"), &metadata);
    EXPECT_LE(std::stod(metadata.at("fredholm:relative_error")), 0.08 * 1.05);  // its pilot's prediction, ladder-rounded
    EXPECT_NE(metadata.at("fredholm:adaptive").find("pilot 8 spp"), std::string::npos);
}

TEST(Adaptive, WhatItCannotDoIsRefused) {
    EXPECT_EQ(fredholm("render " CORNELL_SCENE " -o " + path("x.exr") + SIZE + " --spp 4 --adaptive"), 2);
    EXPECT_NE(last_log_line().find("--spp 8 or more"), std::string::npos) << last_log_line();
    EXPECT_EQ(fredholm("render " CORNELL_SCENE " -o " + path("x.exr") + SIZE + " --spp 16 --adaptive --integrator bdpt"), 2);
    EXPECT_NE(last_log_line().find("--integrator path"), std::string::npos) << last_log_line();
    EXPECT_EQ(fredholm("render " CORNELL_SCENE " -o " + path("x.exr") + SIZE + " --samples 0:16 --adaptive"), 2);
    // An adaptive film's pixels hold different counts: it cannot be continued or merged (one line, exit 1).
    ASSERT_EQ(fredholm("render " CORNELL_SCENE " -o " + path("film.exr") + SIZE + " --spp 16 --adaptive"), 0);
    EXPECT_EQ(fredholm("render " CORNELL_SCENE " -o " + path("film.exr") + SIZE + " --spp 32 --resume"), 1);
    EXPECT_NE(last_log_line().find("adaptive render"), std::string::npos) << last_log_line();
    EXPECT_EQ(fredholm("merge " + path("film.exr") + " " + path("once.exr") + " -o " + path("merged.exr") + " -q"), 1);
    EXPECT_NE(last_log_line().find("adaptive render"), std::string::npos) << last_log_line();
    EXPECT_FALSE(fs::exists(path("merged.exr")));
}

}  // namespace
