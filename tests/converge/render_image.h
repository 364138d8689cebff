// Runs `fredholm render` for the converge tests that score images themselves, and reads the image back.
#pragma once
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <sys/wait.h>

#include "io/exr.h"

namespace fh::test {

// FREDHOLM_EXE render SCENE -o DIR/NAME.exr ARGS, its messages appended to DIR/log.txt; a failed render fails the test.
inline Image render_image(const std::string& fredholm, const std::string& scene, const std::filesystem::path& dir,
                          const std::string& name, const std::string& args) {
    std::filesystem::create_directories(dir);
    const std::filesystem::path file = dir / (name + ".exr");
    const std::string line =
        fredholm + " render " + scene + " -o " + file.string() + " " + args + " 2>>" + (dir / "log.txt").string();
    std::printf("%s\n", line.c_str());
    const int status = std::system(line.c_str());
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << line;
    return read_exr(file);
}

// The arguments of a size x size render at `spp` samples, paths of at most max_depth bounces, seeded with `seed`.
inline std::string square_render_args(int size, int spp, int max_depth, unsigned seed) {
    return "--width " + std::to_string(size) + " --height " + std::to_string(size) + " --spp " + std::to_string(spp) +
           " --max-depth " + std::to_string(max_depth) + " --seed " + std::to_string(seed);
}

}  // namespace fh::test
