// `fredholm converge`: error against render time at doubling spp, for one or more configurations, as a report.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "render/settings.h"

namespace CLI {
class App;
}

namespace fh {

struct ConvergeCommand {
    std::filesystem::path scene;
    std::filesystem::path output_dir;
    std::filesystem::path reference;  // empty: render one (or --two-seeds)
    uint32_t reference_spp = 0;       // 0: min(16 * max_spp, 4096)
    double reference_seconds = 0;     // 0: 4 * max_seconds
    bool two_seeds = false;
    double max_seconds = 60;
    uint32_t max_spp = 1024;
    std::vector<std::string> vary;    // "KEY=V1,V2,..."
    bool keep_images = false;
    RenderSettings settings;          // the default configuration
    bool validation = false;
    std::string device;
    std::string command_line;
};

// The configurations to compare: the default first, then one per --vary value (relative to the default;
// values equal to the default are not repeated). Throws std::invalid_argument for an unknown key or value.
struct NamedSettings {
    std::string name;
    RenderSettings settings;
};
std::vector<NamedSettings> make_configurations(const RenderSettings& base, const std::vector<std::string>& vary);

void add_converge_options(CLI::App& app, ConvergeCommand& command);
// Returns the process exit code (0; 2 for a bad --vary; 130 when interrupted after writing a partial report).
int run_converge(const ConvergeCommand& command);

}  // namespace fh
