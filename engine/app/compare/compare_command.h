// `fredholm compare A.exr B.exr`: a verdict for CI on whether two renders differ beyond their Monte Carlo noise, from
// their variance layers (app/compare/noise_test.h); exit 0 the same within noise, 1 different, 2 bad usage or
// unreadable files. No Vulkan device needed.
#pragma once
#include <filesystem>

namespace CLI {
class App;
}

namespace fh {

struct CompareCommand {
    std::filesystem::path a, b;
    std::filesystem::path heatmap;  // PNG of the significant differences
    double alpha = 0.01;
    int tile = 16;
    double threshold = 0.02;
    bool quiet = false;
};

void add_compare_options(CLI::App& app, CompareCommand& command);
// Prints one verdict line (stdout) and returns the exit code; every error is one line on stderr and exit 2.
int run_compare(const CompareCommand& command);

}  // namespace fh
