// The files `fredholm converge` writes into its report directory: convergence.csv, summary.json, report.md
// and plot.svg, each through write_file_atomically.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "app/converge/converge_metrics.h"

namespace fh {

// Where the error is measured against.
struct ReferenceInfo {
    enum Kind { file, rendered, two_seeds } kind = rendered;
    std::string source;          // the EXR given, or where the rendered reference was written
    uint32_t spp = 0;            // rendered: samples reached
    uint32_t spp_asked = 0;      // rendered: samples asked for
    double seconds = 0;          // rendered: render time
    double seconds_budget = 0;   // rendered: its time bound
    uint32_t seed = 0;
    double variance = 0;         // rendered: its own variance estimate (subtracted from the bias estimates)
};

struct ConvergeReport {
    std::string scene;
    std::string device;
    std::string command_line;
    uint32_t width = 0, height = 0;
    double max_seconds = 0;
    uint32_t max_spp = 0;
    ReferenceInfo reference;
    std::vector<ConvergeCurve> curves;  // curves[0] is the default configuration
    std::vector<CurveSummary> summaries;
};

// One-line description of a configuration's settings, e.g. "max-depth 0 (unlimited), nee on, mis on, rr on, box".
std::string describe_settings(const RenderSettings& s);

void write_convergence_csv(const std::filesystem::path& file, const ConvergeReport& report);
void write_summary_json(const std::filesystem::path& file, const ConvergeReport& report);
void write_report_markdown(const std::filesystem::path& file, const ConvergeReport& report);
// Log-log relMSE against cumulative seconds, one curve per configuration, a dashed slope -1 guide; plain SVG.
void write_plot_svg(const std::filesystem::path& file, const ConvergeReport& report);

}  // namespace fh
