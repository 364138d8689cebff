// Runs the real `fredholm render`: a render continued with --resume equals an uninterrupted one bit for bit,
// SIGINT/SIGTERM write a resumable partial image (exit 130, no temporary files), mismatched resumes fail; parts of
// a render (--samples, --crop) joined by `fredholm merge` equal the whole render bit for bit, and bad sets of parts
// are refused with one line.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "io/exr.h"

namespace {
namespace fs = std::filesystem;

const std::string CORNELL = FH_SOURCE_DIR "/scenes/cornell.gltf";
const std::vector<std::string> FILM = {"fredholm.sum.R.0", "fredholm.sum.R.1", "fredholm.sum.R.2", "fredholm.sum.R.3",
                                       "fredholm.sum.G.0", "fredholm.sum.G.1", "fredholm.sum.G.2", "fredholm.sum.G.3",
                                       "fredholm.sum.B.0", "fredholm.sum.B.1", "fredholm.sum.B.2", "fredholm.sum.B.3",
                                       "fredholm.count"};
// Long enough (several seconds on lavapipe) that a signal after one second always lands mid-render: one
// sample per wave, so it stops within milliseconds.
const std::vector<std::string> LONG_RENDER = {"--width", "32", "--height", "32", "--spp", "600", "--seed", "5",
                                              "--wave-paths", "1024"};

struct Outcome {
    int exit_code = -1;  // 128 + signal when killed by one
    bool killed = false;  // by a signal, not exited
    std::string err;
};

fs::path work_dir() {
    const auto* info = testing::UnitTest::GetInstance()->current_test_info();
    fs::path dir = fs::path(FH_TEST_OUTPUT) / "robustness" / (std::string(info->test_suite_name()) + "." + info->name());
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

fs::path err_file_of(pid_t parent) {
    return fs::temp_directory_path() / ("fh_robustness_" + std::to_string(parent) + ".err");
}

// Starts `fredholm COMMAND args...` with stderr to err_file_of(getpid()).
pid_t start_fredholm(const std::vector<std::string>& args, const char* command = "render") {
    const fs::path err_file = err_file_of(getpid());
    std::vector<std::string> argv_strings = {FH_FREDHOLM, command};
    argv_strings.insert(argv_strings.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (std::string& s : argv_strings) argv.push_back(s.data());
    argv.push_back(nullptr);
    const pid_t pid = fork();
    if (pid == 0) {
        if (!freopen(err_file.c_str(), "w", stderr)) _exit(99);
        execv(argv[0], argv.data());
        _exit(98);
    }
    return pid;
}

Outcome wait_fredholm(pid_t pid) {
    int status = 0;
    waitpid(pid, &status, 0);
    Outcome run;
    run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    run.killed = WIFSIGNALED(status);
    const fs::path err_file = err_file_of(getpid());
    std::ifstream in(err_file);
    std::stringstream text;
    text << in.rdbuf();
    run.err = text.str();
    fs::remove(err_file);
    return run;
}

// Runs `fredholm render args...`; sends `signal_number` after `delay` if it is non-zero.
Outcome run_fredholm(const std::vector<std::string>& args, int signal_number = 0,
                 std::chrono::milliseconds delay = std::chrono::milliseconds(0)) {
    const pid_t pid = start_fredholm(args);
    if (signal_number != 0) {
        std::this_thread::sleep_for(delay);
        kill(pid, signal_number);
    }
    return wait_fredholm(pid);
}

// Whether `pid` has installed its SIGINT handler yet (bit SIGINT - 1 of SigCgt in /proc/PID/status).
bool catches_sigint(pid_t pid) {
    std::ifstream status("/proc/" + std::to_string(pid) + "/status");
    for (std::string line; std::getline(status, line);)
        if (line.rfind("SigCgt:", 0) == 0) return (std::stoull(line.substr(7), nullptr, 16) >> (SIGINT - 1)) & 1;
    return false;
}

// Whether `pid` has ended, leaving it to be waited for.
bool has_exited(pid_t pid) {
    siginfo_t info = {};
    return waitid(P_PID, id_t(pid), &info, WEXITED | WNOHANG | WNOWAIT) != 0 || info.si_pid != 0;
}

std::vector<std::string> with(std::vector<std::string> args, const std::vector<std::string>& more) {
    args.insert(args.end(), more.begin(), more.end());
    return args;
}

uint32_t spp_of(const fs::path& file) {
    fh::ImageMetadata metadata;
    fh::read_exr(file, &metadata);
    return uint32_t(std::stoul(metadata.at("fredholm:spp")));
}

// The error estimate's batches, variance layer and figures (render/error_estimate.h) are the same bits too.
void expect_identical_error_estimate(const fs::path& a, const fs::path& b) {
    fh::ImageMetadata ma, mb;
    fh::read_exr(a, &ma);
    fh::read_exr(b, &mb);
    for (const char* key : {"fredholm:batch_size", "fredholm:first_batch", "fredholm:error_batches",
                            "fredholm:relative_error"}) {
        ASSERT_TRUE(ma.count(key)) << a << " has no " << key;
        EXPECT_EQ(ma[key], mb[key]) << a << " and " << b << " differ in " << key;
    }
    std::vector<std::string> batches;
    for (int slot = 0; slot < 8; ++slot)
        for (int w = 0; w < 4; ++w) {
            const std::string name = "fredholm.batch." + std::to_string(slot) + "." + std::to_string(w);
            EXPECT_EQ(fh::exr_has_channel(a, name), fh::exr_has_channel(b, name)) << name;
            if (fh::exr_has_channel(a, name)) batches.push_back(name);
        }
    ASSERT_GE(batches.size(), 8u) << a << " has fewer than two batches";
    const fh::ExtraChannels ca = fh::read_exr_channels(a, batches), cb = fh::read_exr_channels(b, batches);
    for (const std::string& name : batches)
        EXPECT_EQ(ca.at(name), cb.at(name)) << a << " and " << b << " differ in " << name;
    const fh::FloatChannels va = fh::read_exr_float_channels(a, {"variance.Y"}),
                            vb = fh::read_exr_float_channels(b, {"variance.Y"});
    EXPECT_EQ(std::memcmp(va.at("variance.Y").data(), vb.at("variance.Y").data(), va.at("variance.Y").size() * 4), 0)
        << a << " and " << b << " differ in variance.Y";
}

// Same RGB bits and same raw film bits.
void expect_identical(const fs::path& a, const fs::path& b) {
    const fh::Image ia = fh::read_exr(a), ib = fh::read_exr(b);
    ASSERT_EQ(ia.rgb.size(), ib.rgb.size());
    EXPECT_EQ(std::memcmp(ia.rgb.data(), ib.rgb.data(), ia.rgb.size() * sizeof(float)), 0)
        << a << " and " << b << " differ in R, G, B";
    const fh::ExtraChannels fa = fh::read_exr_channels(a, FILM), fb = fh::read_exr_channels(b, FILM);
    for (const std::string& name : FILM)
        EXPECT_EQ(std::memcmp(fa.at(name).data(), fb.at(name).data(), fa.at(name).size() * sizeof(uint32_t)), 0)
            << a << " and " << b << " differ in " << name;
    expect_identical_error_estimate(a, b);
}

std::vector<fs::path> temp_files(const fs::path& dir) {
    std::vector<fs::path> found;
    for (const auto& entry : fs::directory_iterator(dir))
        if (entry.path().extension() == ".tmp") found.push_back(entry.path());
    return found;
}

TEST(Resume, ChunkedRenderEqualsStraightRender) {
    const fs::path dir = work_dir();
    const std::vector<std::string> settings = {"--width", "48", "--height", "40", "--seed", "3", "-q"};
    ASSERT_EQ(run_fredholm(with({CORNELL, "-o", (dir / "straight.exr").string(), "--spp", "8"}, settings)).exit_code, 0);
    const std::string chunked = (dir / "chunked.exr").string();
    ASSERT_EQ(run_fredholm(with({CORNELL, "-o", chunked, "--spp", "4"}, settings)).exit_code, 0);
    EXPECT_EQ(spp_of(chunked), 4u);
    // Resume in place, with a different wave size (chunks need not line up with waves).
    const Outcome resumed = run_fredholm(with({CORNELL, "-o", chunked, "--spp", "6", "--resume", "--wave-paths", "2048"}, settings));
    ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
    // Resume from another file into a new one.
    const std::string final_file = (dir / "final.exr").string();
    ASSERT_EQ(run_fredholm(with({CORNELL, "-o", final_file, "--spp", "8", "--resume", chunked}, settings)).exit_code, 0);
    EXPECT_EQ(spp_of(final_file), 8u);
    expect_identical(final_file, dir / "straight.exr");
}

// A thin-lens render resumes bit-exactly too (the lens and its focus, found by --focus-on, are the same each time).
TEST(Resume, LensRenderResumesBitExactly) {
    const fs::path dir = work_dir();
    const std::vector<std::string> settings = {"--width", "32", "--height", "32", "--aperture", "1.4", "--focus-on",
                                               "10,20", "--aperture-blades", "7", "-q"};
    ASSERT_EQ(run_fredholm(with({CORNELL, "-o", (dir / "straight.exr").string(), "--spp", "4"}, settings)).exit_code, 0);
    const std::string chunked = (dir / "chunked.exr").string();
    ASSERT_EQ(run_fredholm(with({CORNELL, "-o", chunked, "--spp", "2"}, settings)).exit_code, 0);
    const Outcome resumed = run_fredholm(with({CORNELL, "-o", chunked, "--spp", "4", "--resume"}, settings));
    ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
    expect_identical(chunked, dir / "straight.exr");
}

TEST(Resume, RejectsMismatchedSettingsWithOneLine) {
    const fs::path dir = work_dir();
    const std::string partial = (dir / "partial.exr").string();
    // --width W --spp S, then the remaining changes.
    auto args = [&](const std::string& width, const std::string& spp, const std::vector<std::string>& more) {
        return with({CORNELL, "-o", partial, "--width", width, "--height", "16", "--spp", spp, "-q"}, more);
    };
    ASSERT_EQ(run_fredholm(args("16", "2", {})).exit_code, 0);
    const auto before = fs::last_write_time(partial);
    struct Case {
        std::vector<std::string> args;
        std::string expected;
    };
    const std::vector<Case> cases = {
        {args("16", "4", {"--resume", "--seed", "9"}), "seed is 0 in the file but 9"},
        {args("16", "4", {"--resume", "--max-depth", "3"}), "max_depth is 0 in the file but 3"},
        {args("16", "4", {"--resume", "--nee", "off"}), "nee is on in the file but off"},
        {args("16", "4", {"--resume", "--filter", "gaussian"}), "filter is box in the file but gaussian"},
        {args("16", "4", {"--resume", "--aperture", "2", "--focus-distance", "3"}),
         "lens is pinhole in the file but f/2 sensor 24 mm, focus 3"},
        {args("16", "4", {"--resume", "--shutter", "0,0.01"}), "shutter is none in the file but 0,0.01"},
        {args("17", "4", {"--resume"}), "image_size is 16x16 in the file but 17x16 in this render"},
        {args("16", "4", {"--resume", "--crop", "0,0,8,8"}), "crop is none in the file but 0,0,8,8"},
        {args("16", "4", {"--resume", "--disable-technique", "exact-film"}), "disabled_techniques is none in the file"},
        {args("16", "1", {"--resume"}), "already has 2 spp, more than --spp 1"},
    };
    for (const Case& c : cases) {
        const Outcome run = run_fredholm(c.args);
        EXPECT_EQ(run.exit_code, 1) << run.err;
        EXPECT_NE(run.err.find(c.expected), std::string::npos) << run.err;
        EXPECT_NE(run.err.find(partial + ": cannot resume"), std::string::npos) << run.err;
        EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
    }
    EXPECT_EQ(fs::last_write_time(partial), before);
    // A file without the raw film (any other EXR) is refused naming the missing channel.
    fh::Image plain{16, 16, std::vector<float>(16 * 16 * 3, 0.5f)};
    fh::ImageMetadata metadata;
    fh::read_exr(partial, &metadata);
    const fs::path other = dir / "plain.exr";
    fh::write_exr(other, plain, metadata);
    const Outcome run = run_fredholm(args("16", "4", {"--resume", other.string()}));
    EXPECT_EQ(run.exit_code, 1) << run.err;
    EXPECT_NE(run.err.find("missing channel fredholm.sum"), std::string::npos) << run.err;
}

class Interrupt : public testing::TestWithParam<int> {};

TEST_P(Interrupt, WritesAResumablePartialImage) {
    const fs::path dir = work_dir();
    const std::string straight = (dir / "straight.exr").string();
    ASSERT_EQ(run_fredholm(with({CORNELL, "-o", straight, "-q"}, LONG_RENDER)).exit_code, 0);

    const std::string partial = (dir / "partial.exr").string();
    const Outcome stopped = run_fredholm(with({CORNELL, "-o", partial}, LONG_RENDER), GetParam(), std::chrono::seconds(1));
    EXPECT_EQ(stopped.exit_code, 130) << stopped.err;
    EXPECT_NE(stopped.err.find("interrupted: wrote " + partial), std::string::npos) << stopped.err;
    ASSERT_TRUE(fs::exists(partial));
    EXPECT_TRUE(temp_files(dir).empty()) << temp_files(dir).front();
    const uint32_t spp = spp_of(partial);
    EXPECT_GT(spp, 0u);
    EXPECT_LT(spp, 600u) << "the render finished before the signal: make LONG_RENDER longer";
    const fh::Image image = fh::read_exr(partial);
    for (float v : image.rgb) ASSERT_TRUE(std::isfinite(v));

    const Outcome resumed = run_fredholm(with({CORNELL, "-o", partial, "--resume", "-q"}, LONG_RENDER));
    ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
    EXPECT_EQ(spp_of(partial), 600u);
    expect_identical(partial, straight);
}

// An impatient Ctrl-C: once the first signal is pending, the next one exits at once (status 130) without
// waiting for the sample index to finish. At 1024 x 1024 a sample index takes over a second on lavapipe, so
// a normal stop would write the image long after the second signal; signals are re-sent every 50 ms because
// two sent together may merge into one.
TEST(ForcedExit, SecondSignalExitsAtOnce) {
    const fs::path dir = work_dir();
    const std::string image = (dir / "out.exr").string();
    const pid_t pid = start_fredholm({CORNELL, "-o", image, "--width", "1024", "--height", "1024", "--spp", "64"});
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    while (!catches_sigint(pid) && std::chrono::steady_clock::now() < deadline)
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    const auto first = std::chrono::steady_clock::now();
    for (int i = 0; i < 100 && !has_exited(pid); ++i) {
        kill(pid, SIGINT);
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    const Outcome run = wait_fredholm(pid);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - first).count();
    EXPECT_FALSE(run.killed) << "killed by the signal itself: the handler was not installed";
    EXPECT_EQ(run.exit_code, 130) << run.err;
    EXPECT_NE(run.err.find("fredholm: interrupted again: exiting at once"), std::string::npos) << run.err;
    EXPECT_EQ(run.err.find("interrupted: wrote"), std::string::npos) << run.err;
    EXPECT_LT(seconds, 1.0);
    EXPECT_FALSE(fs::exists(image));
}

INSTANTIATE_TEST_SUITE_P(Signals, Interrupt, testing::Values(SIGINT, SIGTERM),
                         [](const testing::TestParamInfo<int>& info) {
                             return std::string(info.param == SIGINT ? "SIGINT" : "SIGTERM");
                         });

// Parts of one render: sample ranges, and crops with their own sample ranges.
TEST(Merge, PartsEqualTheWholeRenderBitForBit) {
    const fs::path dir = work_dir();
    const std::vector<std::string> settings = {"--width", "24", "--height", "20", "--seed", "7", "-q"};
    auto render = [&](const std::string& name, const std::vector<std::string>& more) {
        const Outcome run = run_fredholm(with(with({CORNELL, "-o", (dir / name).string()}, settings), more));
        ASSERT_EQ(run.exit_code, 0) << run.err;
    };
    auto merge = [&](const std::string& out, const std::vector<std::string>& parts) {
        std::vector<std::string> args;
        for (const std::string& p : parts) args.push_back((dir / p).string());
        const Outcome run = wait_fredholm(start_fredholm(with(args, {"-o", (dir / out).string(), "-q"}), "merge"));
        ASSERT_EQ(run.exit_code, 0) << run.err;
    };
    render("whole.exr", {"--spp", "9"});
    render("s0.exr", {"--samples", "0:4"});
    render("s1.exr", {"--samples", "4:5"});
    render("s2.exr", {"--samples", "5:9"});
    merge("by_samples.exr", {"s2.exr", "s0.exr", "s1.exr"});  // any order
    expect_identical(dir / "by_samples.exr", dir / "whole.exr");
    render("top.exr", {"--crop", "0,0,24,7", "--spp", "9"});
    render("left.exr", {"--crop", "0,7,10,20", "--samples", "0:3"});
    render("left2.exr", {"--crop", "0,7,10,20", "--samples", "3:9"});
    render("right.exr", {"--crop", "10,7,24,20", "--spp", "9"});
    merge("by_crops.exr", {"right.exr", "left2.exr", "top.exr", "left.exr"});
    expect_identical(dir / "by_crops.exr", dir / "whole.exr");
    // A merged file is a render like any other: it continues with --resume as the whole render would.
    render("whole12.exr", {"--spp", "12"});
    render("by_samples.exr", {"--spp", "12", "--resume"});
    expect_identical(dir / "by_samples.exr", dir / "whole12.exr");
}

// What the fixed-point film buys: with plain float sums (--disable-technique exact-film) the same parts merge to other
// bits than the whole render, because float addition is not associative.
TEST(Merge, PlainFloatSumsDoNotMergeExactly) {
    const fs::path dir = work_dir();
    const std::vector<std::string> settings = {"--width", "16", "--height", "16", "-q", "--disable-technique", "exact-film"};
    for (const auto& [name, range] : {std::pair{"whole.exr", "0:40"}, {"a.exr", "0:13"}, {"b.exr", "13:40"}})
        ASSERT_EQ(run_fredholm(with({CORNELL, "-o", (dir / name).string(), "--samples", range}, settings)).exit_code, 0);
    const Outcome run = wait_fredholm(start_fredholm(
        {(dir / "a.exr").string(), (dir / "b.exr").string(), "-o", (dir / "merged.exr").string(), "-q"}, "merge"));
    ASSERT_EQ(run.exit_code, 0) << run.err;
    const fh::Image merged = fh::read_exr(dir / "merged.exr"), whole = fh::read_exr(dir / "whole.exr");
    ASSERT_EQ(merged.rgb.size(), whole.rgb.size());
    EXPECT_NE(std::memcmp(merged.rgb.data(), whole.rgb.data(), merged.rgb.size() * sizeof(float)), 0);
}

TEST(Merge, RefusesPartsThatDoNotBelongTogetherWithOneLine) {
    const fs::path dir = work_dir();
    auto render = [&](const std::string& name, const std::vector<std::string>& more) {
        const Outcome run = run_fredholm(with({CORNELL, "-o", (dir / name).string(), "--width", "16", "--height", "8",
                                               "-q"}, more));
        ASSERT_EQ(run.exit_code, 0) << run.err;
    };
    render("a.exr", {"--samples", "0:4"});
    render("b.exr", {"--samples", "4:8"});
    render("overlap.exr", {"--samples", "2:6"});
    render("late.exr", {"--samples", "6:8"});
    render("seed.exr", {"--samples", "4:8", "--seed", "1"});
    render("top.exr", {"--crop", "0,0,16,4", "--samples", "0:4"});
    render("bottom.exr", {"--crop", "0,3,16,8", "--samples", "0:4"});
    render("bottom_short.exr", {"--crop", "0,4,16,8", "--samples", "0:2"});
    // Parts whose metadata lies about their film: written here from a.exr with one key changed.
    auto forge = [&](const std::string& name, const std::string& key, const std::string& value) {
        fh::ImageMetadata metadata;
        const fh::Image image = fh::read_exr(dir / "a.exr", &metadata);
        metadata[key] = value;
        fh::write_exr(dir / name, image, metadata, fh::read_exr_channels(dir / "a.exr", FILM));
    };
    forge("more_spp.exr", "fredholm:spp", "6");
    forge("huge.exr", "fredholm:image_size", "100000x100000");
    forge("outside.exr", "fredholm:crop", "0,0,17,8");
    struct Case {
        std::vector<std::string> parts;
        std::string expected;
    };
    const std::vector<Case> cases = {
        {{"more_spp.exr", "b.exr"}, "more_spp.exr: cannot merge: pixel 0 holds 4 samples, not the 6 of its metadata"},
        {{"huge.exr"}, "huge.exr: cannot merge: fredholm:image_size is not WIDTHxHEIGHT (1 to 16384 each)"},
        {{"outside.exr"}, "outside.exr: cannot merge: fredholm:crop is not X0,Y0,X1,Y1 inside the image"},
        {{"a.exr", "overlap.exr"}, "a.exr and " + (dir / "overlap.exr").string() + " overlap: both hold samples 2:4"},
        {{"a.exr", "late.exr"}, "no part holds samples 4:6 of the whole image"},
        {{"a.exr", "seed.exr"}, "seed.exr: cannot merge: seed is 1 here but 0 in"},
        {{"top.exr", "bottom.exr"}, "overlap at pixel 0,3"},
        {{"top.exr"}, "no part covers pixel 0,4 of the 16x8 image"},
        {{"top.exr", "bottom_short.exr"}, "has samples 0:4 but crop 0,4,16,8 has 0:2"},
        {{"a.exr", "a.exr"}, "a.exr: cannot merge: given twice"},
    };
    for (const Case& c : cases) {
        std::vector<std::string> args;
        for (const std::string& p : c.parts) args.push_back((dir / p).string());
        const fs::path out = dir / "merged.exr";
        const Outcome run = wait_fredholm(start_fredholm(with(args, {"-o", out.string()}), "merge"));
        EXPECT_EQ(run.exit_code, 1) << run.err;
        EXPECT_NE(run.err.find(c.expected), std::string::npos) << run.err;
        EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
        EXPECT_FALSE(fs::exists(out));
    }
}

}  // namespace
