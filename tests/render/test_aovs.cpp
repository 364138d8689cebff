// `fredholm render --aov` through the real binary: on a diffuse plane of albedo 0.8 seen straight down from 2 away the
// layers read exactly its albedo, its normal, the distance and the samples; under a smooth thin glass sheet 1 above
// it the AOVs look through the glass (the plane's albedo, less what the glass reflects, not the glass's 0.5) while the
// depth is the glass's; the beauty image keeps its bits with AOVs on; a render with AOVs resumes and merges bit for
// bit; light tracing refuses them.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <string>

#include "io/exr.h"
#include "run_fredholm.h"

namespace {

namespace fs = std::filesystem;
const fs::path OUT = fs::path(FH_TEST_OUTPUT) / "aovs";

int fredholm(const std::string& args) { return fh::test::run_fredholm(FREDHOLM_EXE, OUT, args); }

fh::FloatChannels layers(const fs::path& file) {
    return fh::read_exr_float_channels(file, {"albedo.R", "albedo.G", "albedo.B", "normal.X", "normal.Y", "normal.Z",
                                              "depth.Z", "spp.N"});
}

TEST(Aovs, DiffusePlaneReadsItsAlbedoNormalAndDistance) {
    const fs::path file = OUT / "plane.exr";
    ASSERT_EQ(fredholm("render " ASSET_SCENES "/env_plane.gltf -o " + file.string() +
                       " --background 1,1,1 --width 16 --height 16 --spp 16 -q --aov albedo,normal,depth,spp"),
              0);
    const fh::FloatChannels l = layers(file);
    for (size_t p = 0; p < 256; ++p) {
        for (const char* c : {"albedo.R", "albedo.G", "albedo.B"}) ASSERT_NEAR(l.at(c)[p], 0.8f, 1e-6f) << c << " " << p;
        ASSERT_NEAR(l.at("normal.X")[p], 0.0f, 1e-6f);
        ASSERT_NEAR(l.at("normal.Y")[p], 0.0f, 1e-6f);
        ASSERT_NEAR(l.at("normal.Z")[p], 1.0f, 1e-6f);
        ASSERT_NEAR(l.at("depth.Z")[p], 2.0f, 1e-5f);
        ASSERT_EQ(l.at("spp.N")[p], 16.0f);
    }
}

TEST(Aovs, SmoothGlassIsSeenThrough) {
    const fs::path file = OUT / "glass.exr";
    ASSERT_EQ(fredholm("render " ASSET_SCENES "/aov_glass_over_plane.gltf -o " + file.string() +
                       " --background 1,1,1 --width 16 --height 16 --spp 64 -q --aov albedo,normal,depth,spp"),
              0);
    const fh::FloatChannels l = layers(file);
    double albedo = 0, normal_z = 0;
    for (size_t p = 0; p < 256; ++p) {
        albedo += l.at("albedo.G")[p] / 256.0;
        normal_z += l.at("normal.Z")[p] / 256.0;
        ASSERT_NEAR(l.at("depth.Z")[p], 1.0f, 1e-5f);  // the glass is the first hit
    }
    std::printf("[aovs] under the glass: mean albedo %.4f (the plane 0.8, the glass 0.5), normal z %.4f\n", albedo,
                normal_z);
    // About 4% of the paths reflect off the glass into the sky and record nothing.
    EXPECT_GT(albedo, 0.70);
    EXPECT_LE(albedo, 0.80);
    EXPECT_GT(normal_z, 0.88);
}

TEST(Aovs, LeaveTheBeautyImageAsItWas) {
    const std::string args = " --width 48 --height 48 --spp 8 --max-depth 10 -q";
    ASSERT_EQ(fredholm("render " CORNELL_SCENE " -o " + (OUT / "plain.exr").string() + args), 0);
    ASSERT_EQ(fredholm("render " CORNELL_SCENE " -o " + (OUT / "with_aovs.exr").string() + args +
                       " --aov albedo,normal,depth"),
              0);
    const fh::Image a = fh::read_exr(OUT / "plain.exr"), b = fh::read_exr(OUT / "with_aovs.exr");
    ASSERT_EQ(a.rgb.size(), b.rgb.size());
    EXPECT_EQ(std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)), 0);
}

TEST(Aovs, RefusedWhereThereAreNoCameraPaths) {
    const std::string out = " -o " + (OUT / "refused.exr").string() + " --width 16 --height 16 -q";
    EXPECT_EQ(fredholm("render " CORNELL_SCENE + out + " --spp 2 --integrator light --aov albedo"), 2);
    EXPECT_EQ(fredholm("render " CORNELL_SCENE + out + " --spp 2 --aov albedo,shadow"), 2);
}

void expect_same_layers(const fs::path& a, const fs::path& b) {
    const fh::FloatChannels la = layers(a), lb = layers(b);
    for (const auto& [name, values] : la)
        EXPECT_EQ(std::memcmp(values.data(), lb.at(name).data(), values.size() * sizeof(float)), 0)
            << a << " and " << b << " differ in " << name;
}

// The AOVs' sums are in the EXR like the film's: a render with them resumes, and parts merge, bit for bit.
TEST(Aovs, ResumeAndMergeBitForBit) {
    const std::string size = " --width 24 --height 20 --max-depth 6 -q --aov albedo,normal,depth,spp";
    auto path = [](const char* name) { return (OUT / name).string(); };
    ASSERT_EQ(fredholm("render " CORNELL_SCENE " -o " + path("straight.exr") + size + " --spp 9"), 0);
    ASSERT_EQ(fredholm("render " CORNELL_SCENE " -o " + path("resumed.exr") + size + " --spp 4"), 0);
    ASSERT_EQ(fredholm("render " CORNELL_SCENE " -o " + path("resumed.exr") + size + " --spp 9 --resume"), 0);
    expect_same_layers(OUT / "resumed.exr", OUT / "straight.exr");
    ASSERT_EQ(fredholm("render " CORNELL_SCENE " -o " + path("part_a.exr") + size + " --samples 0:5 --crop 0,0,24,11"), 0);
    ASSERT_EQ(fredholm("render " CORNELL_SCENE " -o " + path("part_b.exr") + size + " --samples 5:9 --crop 0,0,24,11"), 0);
    ASSERT_EQ(fredholm("render " CORNELL_SCENE " -o " + path("part_c.exr") + size + " --spp 9 --crop 0,11,24,20"), 0);
    ASSERT_EQ(fredholm("merge " + path("part_a.exr") + " " + path("part_b.exr") + " " + path("part_c.exr") + " -o " +
                       path("merged.exr") + " -q"),
              0);
    expect_same_layers(OUT / "merged.exr", OUT / "straight.exr");
    // A render with AOV sums continues only with them (one line, exit 1), and parts must agree on --aov.
    EXPECT_EQ(fredholm("render " CORNELL_SCENE " -o " + path("resumed.exr") + " --width 24 --height 20 --max-depth 6 -q "
                       "--spp 12 --resume"),
              1);
    ASSERT_EQ(fredholm("render " CORNELL_SCENE " -o " + path("part_plain.exr") +
                       " --width 24 --height 20 --max-depth 6 -q --samples 5:9 --crop 0,0,24,11"),
              0);
    EXPECT_EQ(fredholm("merge " + path("part_a.exr") + " " + path("part_plain.exr") + " " + path("part_c.exr") +
                       " -o " + path("bad.exr") + " -q"),
              1);
    const std::string last = fh::test::last_log_line(OUT);
    EXPECT_NE(last.find("cannot merge: "), std::string::npos) << last;
    EXPECT_NE(last.find("has --aov"), std::string::npos) << last;
}

}  // namespace
