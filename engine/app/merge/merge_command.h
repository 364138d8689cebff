// `fredholm merge PART.exr... -o OUT.exr`: joins parts of one render (sample ranges from `render --samples`, pixel
// regions from `render --crop`, or both) into the image one uninterrupted render of the same samples writes, bit for
// bit (the film's fixed-point sums are associative). No Vulkan device needed.
#pragma once
#include <filesystem>
#include <vector>

#include "io/tone_curve.h"

namespace CLI {
class App;
}

namespace fh {

struct MergeCommand {
    std::vector<std::filesystem::path> parts;
    std::filesystem::path output;
    std::filesystem::path png;
    float exposure_ev = 0.0f;
    ToneCurve tone_curve = ToneCurve::aces;
    bool quiet = false;
};

void add_merge_options(CLI::App& app, MergeCommand& command);
// Checks the parts belong together (same matching metadata; per pixel region, sample ranges that follow each other
// with no gap or overlap; regions that tile the image, all with the same samples) and writes the merged image
// atomically. Throws std::runtime_error with one line naming the file(s) and the problem.
int run_merge(const MergeCommand& command);

}  // namespace fh
