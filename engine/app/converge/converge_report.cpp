// convergence.csv (one row per configuration and step), summary.json and report.md.
#include "app/converge/converge_report.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "io/atomic_write.h"
#include "io/image.h"

namespace fh {
namespace {

std::string fmt(const char* format, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, format, v);
    return buf;
}

void write_text(const std::filesystem::path& file, const std::string& text) {
    write_file_atomically(file, [&](const std::filesystem::path& temp) {
        std::ofstream out(temp, std::ios::binary);
        out << text;
        if (!out) throw IoError(temp.string() + ": cannot write");
    });
}

std::string reference_sentence(const ReferenceInfo& r) {
    switch (r.kind) {
    case ReferenceInfo::file:
        return "the given image `" + r.source + "`, taken as exact (its own noise, if any, is not subtracted).";
    case ReferenceInfo::two_seeds:
        return "none: each configuration is rendered twice with independent seeds and MSE = mean (a - b)^2 / 2, "
               "which estimates the **variance part only**; bias is invisible in this mode. Seconds count one of the two renders (the cost of one estimate).";
    case ReferenceInfo::rendered:
        break;
    }
    std::string s = "rendered by this command with the default configuration and an independent seed (" +
                    std::to_string(r.seed) + "): " + std::to_string(r.spp) + " spp in " + fmt("%.2f", r.seconds) +
                    " s";
    if (r.spp < r.spp_asked)
        s += " (" + std::to_string(r.spp_asked) + " spp asked; stopped by its time bound of " +
             fmt("%.0f", r.seconds_budget) + " s)";
    s += ", written to `" + r.source + "`. Its own variance (" + fmt("%.3g", r.variance) +
         " per channel, estimated from its half-spp film) is subtracted in the bias estimates; it still adds "
         "to every MSE, so curves flatten where they approach it.";
    return s;
}

std::string time_cell(const TargetTime& t) {
    switch (t.kind) {
    case TargetTime::reached: return fmt("%.3g s", t.seconds);
    case TargetTime::extrapolated: return "not reached in budget (extrapolated ~" + fmt("%.3g", t.seconds) + " s)";
    case TargetTime::never: break;
    }
    return "never (bias floor)";
}

// Speed-up at equal error: the default configuration's time to the target over this one's.
std::string speedup_cell(const TargetTime& def, const TargetTime& t) {
    if (def.kind == TargetTime::never || t.kind == TargetTime::never || !(t.seconds > 0)) return "-";
    const bool guess = def.kind == TargetTime::extrapolated || t.kind == TargetTime::extrapolated;
    return (guess ? "~" : "") + fmt("%.2fx", def.seconds / t.seconds);
}

nlohmann::json target_json(const TargetTime& t) {
    const char* kinds[] = {"reached", "extrapolated", "never"};
    nlohmann::json j{{"kind", kinds[t.kind]}};
    j["seconds"] = t.kind == TargetTime::never ? nlohmann::json(nullptr) : nlohmann::json(t.seconds);
    return j;
}

}  // namespace

std::string describe_settings(const RenderSettings& s) {
    return std::string("integrator ") + to_string(s.integrator) + ", max-depth " +
           (s.max_depth ? std::to_string(s.max_depth) : std::string("0 (unlimited)")) + ", nee " + (s.nee ? "on" : "off") + ", mis " + (s.mis ? "on" : "off") + ", rr " +
           (s.russian_roulette ? "on" : "off") + ", filter " + to_string(s.filter) + ", seed " +
           std::to_string(s.seed);
}

void write_convergence_csv(const std::filesystem::path& file, const ConvergeReport& report) {
    std::ostringstream out;
    out << "config,spp,seconds,samples_per_second,mse,rmse,relmse,mape,variance,bias2,bias2_stderr,rel_bias2,"
           "efficiency,nonfinite\n";
    for (const ConvergeCurve& c : report.curves)
        for (const ConvergeStep& st : c.steps) {
            const ImageErrors& e = st.errors;
            const double sps = st.seconds > 0 ? double(report.width) * report.height * st.spp / st.seconds : 0.0;
            const double eff = st.seconds > 0 && e.mse > 0 ? 1.0 / (e.mse * st.seconds) : 0.0;
            out << c.name << "," << st.spp << "," << fmt("%.9g", st.seconds) << "," << fmt("%.9g", sps) << ","
                << fmt("%.9g", e.mse) << "," << fmt("%.9g", std::sqrt(e.mse)) << "," << fmt("%.9g", e.relmse)
                << "," << fmt("%.9g", e.mape);
            if (e.has_variance)
                out << "," << fmt("%.9g", e.variance) << "," << fmt("%.9g", e.bias2) << ","
                    << fmt("%.9g", e.bias2_stderr) << "," << fmt("%.9g", e.rel_bias2);
            else
                out << ",,,,";
            out << "," << fmt("%.9g", eff) << "," << e.nonfinite << "\n";
        }
    write_text(file, out.str());
}

void write_summary_json(const std::filesystem::path& file, const ConvergeReport& report) {
    nlohmann::json j;
    j["scene"] = report.scene;
    j["device"] = report.device;
    j["command"] = report.command_line;
    j["width"] = report.width;
    j["height"] = report.height;
    j["max_seconds"] = report.max_seconds;
    j["max_spp"] = report.max_spp;
    j["rel_eps"] = REL_EPS;
    j["seconds_are_cumulative"] = true;
    const char* kinds[] = {"file", "rendered", "two-seeds"};
    j["reference"] = {{"kind", kinds[report.reference.kind]}, {"source", report.reference.source},
                      {"spp", report.reference.spp}, {"spp_asked", report.reference.spp_asked},
                      {"seconds", report.reference.seconds}, {"seed", report.reference.seed},
                      {"variance", report.reference.variance}};
    j["configurations"] = nlohmann::json::array();
    for (size_t i = 0; i < report.curves.size(); ++i) {
        const ConvergeCurve& c = report.curves[i];
        const CurveSummary& s = report.summaries[i];
        nlohmann::json steps = nlohmann::json::array();
        for (const ConvergeStep& st : c.steps) {
            nlohmann::json js{{"spp", st.spp}, {"seconds", st.seconds}, {"mse", st.errors.mse},
                              {"rmse", std::sqrt(st.errors.mse)}, {"relmse", st.errors.relmse},
                              {"mape", st.errors.mape}, {"nonfinite", st.errors.nonfinite}};
            if (st.errors.has_variance)
                js.update({{"variance", st.errors.variance}, {"bias2", st.errors.bias2},
                           {"bias2_stderr", st.errors.bias2_stderr}, {"rel_bias2", st.errors.rel_bias2}});
            steps.push_back(js);
        }
        nlohmann::json times;
        for (int k = 0; k < 3; ++k) times[fmt("%g", TARGET_RELMSE[k])] = target_json(s.time_to[k]);
        nlohmann::json jc{{"name", c.name}, {"settings", describe_settings(c.settings)},
                          {"stop_reason", c.stop_reason}, {"slope_mse_vs_spp", s.slope_mse_spp},
                          {"slope_mse_vs_seconds", s.slope_mse_seconds},
                          {"slope_relmse_vs_seconds", s.slope_relmse_seconds}, {"fit_steps", s.fit_steps},
                          {"samples_per_second", s.samples_per_second}, {"efficiency", s.efficiency},
                          {"time_to_relmse", times}, {"steps", steps}};
        if (s.has_bias)
            jc.update({{"bias2", s.bias2}, {"bias2_stderr", s.bias2_stderr}, {"rel_floor", s.rel_floor},
                       {"rel_floor_stderr", s.rel_floor_stderr}, {"floor_significant", s.floor_significant}});
        j["configurations"].push_back(jc);
    }
    write_text(file, j.dump(2) + "\n");
}

void write_report_markdown(const std::filesystem::path& file, const ConvergeReport& report) {
    std::ostringstream md;
    md << "# Convergence: " << report.scene << "\n\n"
       << "`" << report.command_line << "`\n\n"
       << "- Film " << report.width << "x" << report.height << " on " << report.device << "; doubling spp up to "
       << report.max_spp << " or " << fmt("%g", report.max_seconds) << " s of render time per configuration.\n"
       << "- Reference: " << reference_sentence(report.reference) << "\n"
       << "- **Seconds are cumulative**: one film grows progressively (samples [prev, next) are added), and the "
          "time is the sum of the GPU wave loops so far (no loading, BVH or pipeline creation).\n"
       << "- relMSE = mean (x - r)^2 / (r^2 + " << REL_EPS << "), MAPE = mean |x - r| / (|r| + " << REL_EPS
       << "), over all pixels and channels.\n"
       << "- Bias: bias^2 = MSE - Var(x) - Var(reference), where Var(x) = mean (x_a - x)^2 * a / (n - a) from the "
          "same film at the previous step (a spp; its later n - a samples are independent). It is the floor the "
          "curve flattens to; a floor counts when it exceeds 3 standard errors (over pixels).\n"
       << "- Slopes are least-squares fits in log-log over the last " << FIT_STEPS
       << " steps; an unbiased estimator gives -1. Times to a target relMSE are interpolated in log-log between "
          "steps; past the budget they are extrapolated assuming relMSE - floor falls as 1/seconds.\n"
       << "- Speed-up: the default configuration's time to the same relMSE divided by this one's (~ when "
          "extrapolated).\n\n";

    const CurveSummary& def = report.summaries.front();
    md << "## Summary\n\n| configuration | spp | seconds | samples/s | relMSE | efficiency 1/(MSE s) | slope (relMSE vs s) "
          "| relMSE floor | t(1%) | t(0.5%) | t(0.1%) | speed-up at 1% / 0.5% / 0.1% |\n"
          "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (size_t i = 0; i < report.curves.size(); ++i) {
        const ConvergeCurve& c = report.curves[i];
        const CurveSummary& s = report.summaries[i];
        if (c.steps.empty()) continue;
        const ConvergeStep& last = c.steps.back();
        std::string floor = !s.has_bias ? "n/a"
                            : fmt("%.3g", s.rel_floor) + fmt(" ± %.2g", s.rel_floor_stderr) +
                                  (s.floor_significant ? " (bias)" : " (none)");
        md << "| " << c.name << " | " << last.spp << " | " << fmt("%.3g", last.seconds) << " | "
           << fmt("%.3g", s.samples_per_second) << " | " << fmt("%.3g", last.errors.relmse) << " | "
           << fmt("%.3g", s.efficiency) << " | " << fmt("%.2f", s.slope_relmse_seconds) << " | " << floor;
        for (int k = 0; k < 3; ++k) md << " | " << time_cell(s.time_to[k]);
        md << " | " << speedup_cell(def.time_to[0], s.time_to[0]) << " / " << speedup_cell(def.time_to[1], s.time_to[1])
           << " / " << speedup_cell(def.time_to[2], s.time_to[2]) << " |\n";
    }
    md << "\n![relMSE against seconds](plot.svg)\n";

    for (size_t i = 0; i < report.curves.size(); ++i) {
        const ConvergeCurve& c = report.curves[i];
        const CurveSummary& s = report.summaries[i];
        md << "\n## " << c.name << "\n\n" << describe_settings(c.settings) << "; stopped by " << c.stop_reason
           << ". Slopes: MSE vs spp " << fmt("%.2f", s.slope_mse_spp) << ", MSE vs seconds "
           << fmt("%.2f", s.slope_mse_seconds) << ".";
        if (s.has_bias)
            md << " bias^2 " << fmt("%.3g", s.bias2) << fmt(" ± %.2g", s.bias2_stderr) << " (RMS bias "
               << fmt("%.3g", std::sqrt(std::max(0.0, s.bias2))) << ").";
        md << "\n\n| spp | seconds | MSE | RMSE | relMSE | MAPE | Var(x) | bias^2 ± s.e. |\n|---|---|---|---|---|---|---|---|\n";
        for (const ConvergeStep& st : c.steps) {
            const ImageErrors& e = st.errors;
            md << "| " << st.spp << " | " << fmt("%.4g", st.seconds) << " | " << fmt("%.4g", e.mse) << " | "
               << fmt("%.4g", std::sqrt(e.mse)) << " | " << fmt("%.4g", e.relmse) << " | "
               << fmt("%.3g%%", 100 * e.mape) << " | "
               << (e.has_variance ? fmt("%.3g", e.variance) : std::string("-")) << " | "
               << (e.has_variance ? fmt("%.3g", e.bias2) + fmt(" ± %.2g", e.bias2_stderr) : std::string("-"))
               << " |\n";
        }
    }
    write_text(file, md.str());
}

}  // namespace fh
