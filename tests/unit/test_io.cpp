// Unit tests of engine/io: EXR round trips and format, atomic writes, PNG output and the display curves.
#include <gtest/gtest.h>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <half.h>
#include <unistd.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>

#include "io/atomic_write.h"
#include "io/exr.h"
#include "io/png.h"

#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#include <stb_image.h>
#pragma GCC diagnostic pop

namespace fs = std::filesystem;

namespace {

// Each test gets its own empty directory, so "nothing else was left behind" is a directory listing.
class IoTest : public ::testing::Test {
protected:
    void SetUp() override {
        dir = fs::temp_directory_path() /
              ("fh_test_io_" + std::to_string(getpid()) + "_" +
               ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir);
        fs::create_directories(dir);
    }
    void TearDown() override {
        fs::permissions(dir, fs::perms::owner_all, fs::perm_options::add);
        fs::remove_all(dir);
    }
    std::vector<std::string> listing() const {
        std::vector<std::string> names;
        for (const auto& entry : fs::directory_iterator(dir)) names.push_back(entry.path().filename().string());
        std::sort(names.begin(), names.end());
        return names;
    }
    fs::path dir;
};

fh::Image make_test_image(int width, int height) {
    fh::Image image{width, height, std::vector<float>(std::size_t(3) * width * height)};
    std::mt19937 random(7);
    std::uniform_real_distribution<float> value(-2.0f, 50.0f);
    for (float& v : image.rgb) v = value(random);
    // Values a lossy or converting path would damage.
    image.rgb[0] = -0.0f;
    image.rgb[1] = 1e-40f;  // subnormal
    image.rgb[2] = 3.0e38f;
    image.rgb[3] = std::numeric_limits<float>::infinity();
    image.rgb[4] = std::bit_cast<float>(0x7fc12345u);  // NaN with a payload
    image.rgb[5] = 1.0f + std::numeric_limits<float>::epsilon();
    return image;
}

void expect_same_bits(const fh::Image& a, const fh::Image& b) {
    ASSERT_EQ(a.width, b.width);
    ASSERT_EQ(a.height, b.height);
    ASSERT_EQ(a.rgb.size(), b.rgb.size());
    for (std::size_t i = 0; i < a.rgb.size(); ++i)
        ASSERT_EQ(std::bit_cast<std::uint32_t>(a.rgb[i]), std::bit_cast<std::uint32_t>(b.rgb[i])) << "value " << i;
}

// Writes an EXR directly through OpenEXR, for inputs fh::write_exr never produces.
void write_raw_exr(const fs::path& path, const Imath::Box2i& window, const std::vector<std::string>& channels,
                   std::vector<half>& data) {
    Imf::Header header(window, window);
    for (const auto& name : channels) header.channels().insert(name, Imf::Channel(Imf::HALF));
    Imf::FrameBuffer frame;
    const std::size_t n = channels.size();
    for (std::size_t c = 0; c < n; ++c)
        frame.insert(channels[c], Imf::Slice::Make(Imf::HALF, data.data() + c, window, n * sizeof(half),
                                                   n * sizeof(half) * std::size_t(window.max.x - window.min.x + 1)));
    Imf::OutputFile out(path.c_str(), header);
    out.setFrameBuffer(frame);
    out.writePixels(window.max.y - window.min.y + 1);
}

}  // namespace

TEST_F(IoTest, ExrRoundTripIsBitExactWithMetadata) {
    const fh::Image image = make_test_image(7, 5);
    const fh::ImageMetadata metadata = {
        {"fredholm:spp", "1024"}, {"fredholm:scene", "scenes/cornell.gltf"}, {"note", "spaces, ünïcödé & ;"},
        {"empty", ""}};
    fh::write_exr(dir / "a.exr", image, metadata);
    fh::ImageMetadata read_metadata{{"stale", "entry"}};
    const fh::Image read = fh::read_exr(dir / "a.exr", &read_metadata);
    expect_same_bits(image, read);
    EXPECT_EQ(read_metadata, metadata);
    EXPECT_EQ(listing(), std::vector<std::string>{"a.exr"});
}

TEST_F(IoTest, ExrHoldsFloat32RgbWithZipCompression) {
    fh::write_exr(dir / "a.exr", make_test_image(4, 3));
    Imf::InputFile in((dir / "a.exr").c_str());
    std::vector<std::string> names;
    for (auto it = in.header().channels().begin(); it != in.header().channels().end(); ++it) {
        names.push_back(it.name());
        EXPECT_EQ(it.channel().type, Imf::FLOAT) << it.name();
    }
    EXPECT_EQ(names, (std::vector<std::string>{"B", "G", "R"}));  // OpenEXR keeps channels sorted
    EXPECT_EQ(in.header().compression(), Imf::ZIP_COMPRESSION);
}

TEST_F(IoTest, ReadsHalfChannelsAndOffsetDataWindow) {
    const Imath::Box2i window({10, 20}, {13, 22});  // 4 x 3 pixels, not at the origin
    std::vector<half> data(4 * 3 * 4);
    for (std::size_t i = 0; i < data.size(); ++i) data[i] = half(0.25f * float(i));
    write_raw_exr(dir / "half.exr", window, {"R", "G", "B", "A"}, data);
    const fh::Image image = fh::read_exr(dir / "half.exr");
    ASSERT_EQ(image.width, 4);
    ASSERT_EQ(image.height, 3);
    for (std::size_t pixel = 0; pixel < 12; ++pixel)
        for (std::size_t c = 0; c < 3; ++c) EXPECT_EQ(image.rgb[pixel * 3 + c], float(data[pixel * 4 + c]));
}

TEST_F(IoTest, MissingChannelIsAnErrorNamingFileAndChannel) {
    std::vector<half> data(2 * 2, half(1.0f));
    write_raw_exr(dir / "gray.exr", Imath::Box2i({0, 0}, {1, 1}), {"Y"}, data);
    try {
        fh::read_exr(dir / "gray.exr");
        FAIL() << "no exception";
    } catch (const fh::IoError& e) {
        EXPECT_NE(std::string(e.what()).find("gray.exr: missing channel R"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("Y"), std::string::npos) << e.what();
    }
}

TEST_F(IoTest, ReadingAMissingFileNamesIt) {
    try {
        fh::read_exr(dir / "nope.exr");
        FAIL() << "no exception";
    } catch (const fh::IoError& e) {
        EXPECT_EQ(std::string(e.what()).rfind((dir / "nope.exr").string() + ":", 0), 0u) << e.what();
    }
}

TEST_F(IoTest, BadWritesThrowAndLeaveNothing) {
    EXPECT_THROW(fh::write_exr(dir / "a.exr", make_test_image(2, 2), {{"channels", "x"}}), fh::IoError);
    EXPECT_THROW(fh::write_exr(dir / "a.exr", make_test_image(2, 2), {{"type", "x"}}), fh::IoError);
    EXPECT_THROW(fh::write_exr(dir / "a.exr", fh::Image{2, 2, std::vector<float>(11)}), fh::IoError);
    EXPECT_THROW(fh::write_png(dir / "a.png", fh::Image{}), fh::IoError);
    EXPECT_THROW(fh::write_exr(dir / "missing" / "a.exr", make_test_image(2, 2)), fh::IoError);
    EXPECT_TRUE(listing().empty());
}

TEST_F(IoTest, AtomicWriteLeavesOnlyTheTarget) {
    fs::path seen;
    fh::write_file_atomically(dir / "out.txt", [&](const fs::path& temp) {
        seen = temp;
        EXPECT_EQ(temp.parent_path(), dir);  // same file system, so the rename is atomic
        EXPECT_FALSE(fs::exists(dir / "out.txt"));
        std::ofstream(temp) << "hello";
    });
    EXPECT_EQ(listing(), std::vector<std::string>{"out.txt"});
    EXPECT_NE(seen.filename(), "out.txt");
    std::ifstream in(dir / "out.txt");
    EXPECT_EQ(std::string(std::istreambuf_iterator<char>(in), {}), "hello");
}

TEST_F(IoTest, AtomicWriteThatThrowsLeavesNoTargetAndNoTemp) {
    struct WriterFailed : std::runtime_error {
        using runtime_error::runtime_error;
    };
    EXPECT_THROW(fh::write_file_atomically(dir / "out.txt",
                                           [](const fs::path& temp) {
                                               std::ofstream(temp) << "half";
                                               throw WriterFailed("disk full");
                                           }),
                 WriterFailed);
    EXPECT_TRUE(listing().empty());
}

TEST_F(IoTest, AtomicWriteThatThrowsKeepsTheOldTarget) {
    std::ofstream(dir / "out.txt") << "old";
    EXPECT_THROW(fh::write_file_atomically(dir / "out.txt",
                                           [](const fs::path& temp) {
                                               std::ofstream(temp) << "new but broken";
                                               throw std::runtime_error("oops");
                                           }),
                 std::runtime_error);
    EXPECT_EQ(listing(), std::vector<std::string>{"out.txt"});
    std::ifstream in(dir / "out.txt");
    EXPECT_EQ(std::string(std::istreambuf_iterator<char>(in), {}), "old");
}

TEST_F(IoTest, AtomicWriteReplacesAnExistingTarget) {
    fh::write_exr(dir / "a.exr", make_test_image(3, 3));
    const fh::Image second = make_test_image(5, 2);
    fh::write_exr(dir / "a.exr", second);
    expect_same_bits(fh::read_exr(dir / "a.exr"), second);
    EXPECT_EQ(listing(), std::vector<std::string>{"a.exr"});
}

TEST_F(IoTest, WriterThatCreatesNoFileIsAnError) {
    EXPECT_THROW(fh::write_file_atomically(dir / "out.txt", [](const fs::path&) {}), fh::IoError);
    EXPECT_TRUE(listing().empty());
}

TEST_F(IoTest, CheckWritable) {
    EXPECT_NO_THROW(fh::check_writable(dir / "new.exr"));
    EXPECT_THROW(fh::check_writable(dir / "missing" / "new.exr"), fh::IoError);
    EXPECT_THROW(fh::check_writable(dir), fh::IoError);  // a directory is not a file name
    std::ofstream(dir / "file") << "x";
    EXPECT_THROW(fh::check_writable(dir / "file" / "new.exr"), fh::IoError);
}

TEST_F(IoTest, CheckWritableRejectsAReadOnlyDirectory) {
    if (geteuid() == 0) GTEST_SKIP() << "root may write into read-only directories";
    fs::permissions(dir, fs::perms::owner_read | fs::perms::owner_exec, fs::perm_options::replace);
    EXPECT_THROW(fh::check_writable(dir / "new.exr"), fh::IoError);
}

TEST(ToneCurve, SrgbAtKnownPoints) {
    EXPECT_EQ(fh::encode_srgb(0.0f), 0.0f);
    EXPECT_FLOAT_EQ(fh::encode_srgb(1.0f), 1.0f);
    EXPECT_NEAR(fh::encode_srgb(0.001f), 0.01292f, 1e-7);              // linear segment
    EXPECT_NEAR(fh::encode_srgb(0.0031308f), 0.0404500f, 2e-6);        // knee: both pieces meet
    EXPECT_NEAR(fh::encode_srgb(0.00313081f), 0.0404500f, 2e-6);
    EXPECT_NEAR(fh::encode_srgb(0.18f), 0.4613561f, 1e-6);             // mid grey
    EXPECT_NEAR(fh::encode_srgb(0.5f), 0.7353570f, 1e-6);
    EXPECT_EQ(fh::encode_srgb(-1.0f), 0.0f);
    EXPECT_EQ(fh::encode_srgb(std::nanf("")), 0.0f);
    EXPECT_EQ(fh::encode_srgb(7.0f), 1.0f);
}

TEST(ToneCurve, ClampAndAces) {
    EXPECT_EQ(fh::apply_tone_curve(0.25f, fh::ToneCurve::clamp), 0.25f);
    EXPECT_EQ(fh::apply_tone_curve(3.0f, fh::ToneCurve::clamp), 1.0f);
    EXPECT_EQ(fh::apply_tone_curve(-3.0f, fh::ToneCurve::clamp), 0.0f);
    EXPECT_EQ(fh::apply_tone_curve(0.0f, fh::ToneCurve::aces), 0.0f);
    EXPECT_NEAR(fh::apply_tone_curve(1.0f, fh::ToneCurve::aces), 2.54f / 3.16f, 1e-6);  // "1 maps to ~0.8"
    EXPECT_NEAR(fh::apply_tone_curve(0.18f, fh::ToneCurve::aces), 0.0867240f / 0.3249320f, 1e-6);
    EXPECT_EQ(fh::apply_tone_curve(1e9f, fh::ToneCurve::aces), 1.0f);
    EXPECT_EQ(fh::apply_tone_curve(std::numeric_limits<float>::infinity(), fh::ToneCurve::aces), 1.0f);
    EXPECT_EQ(fh::apply_tone_curve(std::nanf(""), fh::ToneCurve::aces), 0.0f);
    float previous = 0;
    for (float x = 0.001f; x < 100; x *= 1.1f) {
        const float y = fh::apply_tone_curve(x, fh::ToneCurve::aces);
        EXPECT_GE(y, previous) << x;
        previous = y;
    }
}

TEST_F(IoTest, PngIsValidAndEncodesKnownValues) {
    // One row of linear values, with their expected 8-bit sRGB codes under the clamp curve.
    const std::vector<float> linear = {0.0f, 1.0f, 0.5f, std::nanf(""), -1.0f, 2.0f, 0.18f, 0.0031308f};
    const std::vector<int> expected = {0, 255, 188, 0, 0, 255, 118, 10};
    fh::Image image{int(linear.size()), 2, {}};
    for (int row = 0; row < 2; ++row)
        for (float v : linear) image.rgb.insert(image.rgb.end(), {v, v, row == 0 ? v : 0.0f});
    fh::write_png(dir / "a.png", image, 0, fh::ToneCurve::clamp);
    EXPECT_EQ(listing(), std::vector<std::string>{"a.png"});

    std::ifstream file(dir / "a.png", std::ios::binary);
    char signature[8];
    file.read(signature, 8);
    EXPECT_EQ(std::string(signature, 8), std::string("\x89PNG\r\n\x1a\n", 8));

    int width = 0, height = 0, channels = 0;
    unsigned char* pixels = stbi_load((dir / "a.png").c_str(), &width, &height, &channels, 0);
    ASSERT_NE(pixels, nullptr) << stbi_failure_reason();
    EXPECT_EQ(width, int(linear.size()));
    EXPECT_EQ(height, 2);
    EXPECT_EQ(channels, 3);
    for (std::size_t i = 0; i < linear.size(); ++i) {
        EXPECT_EQ(pixels[i * 3 + 0], expected[i]) << "linear " << linear[i];
        EXPECT_EQ(pixels[i * 3 + 2], expected[i]) << "top row first";
        EXPECT_EQ(pixels[(linear.size() + i) * 3 + 2], 0);
    }
    stbi_image_free(pixels);
}

TEST(ToneCurve, ExposureScalesBeforeTheCurve) {
    EXPECT_EQ(fh::encode_display_8bit(0.25f, 1.0f, fh::ToneCurve::clamp), 188);   // 0.25 * 2 = 0.5
    EXPECT_EQ(fh::encode_display_8bit(1.0f, -1.0f, fh::ToneCurve::clamp), 188);
    EXPECT_EQ(fh::encode_display_8bit(std::nanf(""), 3.0f, fh::ToneCurve::aces), 0);
    EXPECT_EQ(fh::encode_display_8bit(1e30f, 0.0f, fh::ToneCurve::aces), 255);
}
