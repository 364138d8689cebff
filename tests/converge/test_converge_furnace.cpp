// `fredholm converge` on the closed furnace (every pixel 2.5 exactly): the default configuration converges at
// the Monte Carlo rate, max-depth 1 (expectation 0.5) shows a bias floor, and the CSV and JSON agree with the
// step images recomputed here against the analytic answer.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <sys/wait.h>
#include <string>
#include <vector>

#include "io/exr.h"

namespace {

namespace fs = std::filesystem;
constexpr double FURNACE = 2.5;  // 0.5 / (1 - 0.8): emission over one minus albedo
constexpr int SIZE = 32;

const fs::path OUT = fs::path(CONVERGE_OUT) / "furnace";

int run(const std::string& args) {
    const std::string line = std::string(FREDHOLM_EXE) + " converge " + args + " 2>>" + (OUT / "log.txt").string();
    std::printf("%s\n", line.c_str());
    const int status = std::system(line.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

struct Row {
    std::string config;
    std::map<std::string, double> values;
};

std::vector<Row> read_csv(const fs::path& file) {
    std::ifstream in(file);
    std::string line;
    std::vector<std::string> header;
    std::vector<Row> rows;
    auto split = [](const std::string& s) {
        std::vector<std::string> cells;
        std::stringstream ss(s);
        std::string cell;
        while (std::getline(ss, cell, ',')) cells.push_back(cell);
        if (!s.empty() && s.back() == ',') cells.push_back("");
        return cells;
    };
    if (std::getline(in, line)) header = split(line);
    while (std::getline(in, line)) {
        std::vector<std::string> cells = split(line);
        EXPECT_EQ(cells.size(), header.size()) << line;
        Row row{cells.at(0), {}};
        for (size_t i = 1; i < cells.size() && i < header.size(); ++i)
            if (!cells[i].empty()) row.values[header[i]] = std::stod(cells[i]);
        rows.push_back(row);
    }
    return rows;
}

double slope(const std::vector<double>& x, const std::vector<double>& y) {
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    const double n = double(x.size());
    for (size_t i = 0; i < x.size(); ++i) {
        const double lx = std::log(x[i]), ly = std::log(y[i]);
        sx += lx, sy += ly, sxx += lx * lx, sxy += lx * ly;
    }
    return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

// The last `count` steps of one configuration, as (spp, seconds, mse, relmse) columns.
struct Curve {
    std::vector<double> spp, seconds, mse, relmse;
};
Curve last_steps(const std::vector<Row>& rows, const std::string& config, size_t count) {
    Curve c;
    for (const Row& r : rows)
        if (r.config == config) {
            c.spp.push_back(r.values.at("spp")), c.seconds.push_back(r.values.at("seconds"));
            c.mse.push_back(r.values.at("mse")), c.relmse.push_back(r.values.at("relmse"));
        }
    auto tail = [&](std::vector<double>& v) {
        if (v.size() > count) v.erase(v.begin(), v.end() - long(count));
    };
    tail(c.spp), tail(c.seconds), tail(c.mse), tail(c.relmse);
    return c;
}

class ConvergeFurnace : public testing::Test {
protected:
    static void SetUpTestSuite() {
        fs::remove_all(OUT);
        fs::create_directories(OUT);
        fh::Image ref{SIZE, SIZE, std::vector<float>(size_t(3) * SIZE * SIZE, float(FURNACE))};
        fh::write_exr(OUT / "analytic.exr", ref);
        status_ = run(std::string(FURNACE_SCENE) + " -o " + (OUT / "report").string() + " --reference " +
                      (OUT / "analytic.exr").string() + " --width 32 --height 32 --max-spp 1024 --max-seconds 30" +
                      // Waves of 4 spp (4096 paths): render time then grows in proportion to the samples
                      // instead of being dominated by the fixed cost of one large wave per step.
                      " --wave-paths 4096" +
                      " --vary max-depth=1 --vary effect:transmission=on --keep-images");
        rows_ = read_csv(OUT / "report" / "convergence.csv");
        std::ifstream json(OUT / "report" / "summary.json");
        summary_ = nlohmann::json::parse(json, nullptr, false);
    }
    static nlohmann::json config(const std::string& name) {
        for (const auto& c : summary_["configurations"])
            if (c["name"] == name) return c;
        ADD_FAILURE() << "no configuration " << name << " in summary.json";
        return {};
    }
    static inline int status_ = -1;
    static inline std::vector<Row> rows_;
    static inline nlohmann::json summary_;
};

TEST_F(ConvergeFurnace, CommandSucceedsAndWritesTheReport) {
    ASSERT_EQ(status_, 0) << "see " << (OUT / "log.txt");
    for (const char* f : {"convergence.csv", "summary.json", "plot.svg", "report.md", "default.png"})
        EXPECT_TRUE(fs::exists(OUT / "report" / f)) << f;
    ASSERT_FALSE(summary_.is_discarded());
    EXPECT_EQ(summary_["configurations"].size(), 3u);
}

// Unbiased: MSE = Var / spp, so slope -1 against spp and (time proportional to spp) against seconds.
TEST_F(ConvergeFurnace, DefaultConvergesAtTheMonteCarloRate) {
    Curve c = last_steps(rows_, "default", 6);
    ASSERT_EQ(c.spp.size(), 6u);
    EXPECT_EQ(c.spp.back(), 1024);
    const double by_spp = slope(c.spp, c.mse), by_seconds = slope(c.seconds, c.mse);
    EXPECT_GE(by_spp, -1.2);
    EXPECT_LE(by_spp, -0.8);
    // Against seconds only loosely: step times jitter with the machine's load (ctest -j, other tenants), and
    // timing belongs to benchmarks; the rate itself is checked against spp above. The slope against seconds went
    // below -1.6 under ctest -j2 (-1.76: the first steps' times are the most disturbed), so the check is that the
    // seconds grow with the samples, by the samples' ratio within a factor of 8 either way, and the error falls.
    for (size_t i = 1; i < c.seconds.size(); ++i) EXPECT_GT(c.seconds[i], c.seconds[i - 1]);
    const double spp_ratio = c.spp.back() / c.spp.front(), seconds_ratio = c.seconds.back() / c.seconds.front();
    EXPECT_GT(seconds_ratio, spp_ratio / 8.0);
    EXPECT_LT(seconds_ratio, spp_ratio * 8.0);
    EXPECT_LT(by_seconds, -0.5);
    EXPECT_NEAR(config("default")["slope_mse_vs_spp"].get<double>(), by_spp, 1e-6);
    EXPECT_FALSE(config("default")["floor_significant"].get<bool>()) << "the default configuration is unbiased";
}

// max-depth 1 sees only the first wall's emission, 0.5: relMSE stays near (2 / 2.5)^2 and the floor is bias.
TEST_F(ConvergeFurnace, DepthOneShowsABiasFloor) {
    Curve c = last_steps(rows_, "max-depth=1", 6);
    ASSERT_GE(c.spp.size(), 3u);
    EXPECT_GT(slope(c.seconds, c.relmse), -0.3);
    const nlohmann::json d = config("max-depth=1");
    EXPECT_TRUE(d["floor_significant"].get<bool>());
    EXPECT_GT(d["bias2"].get<double>(), 3.5);  // (2.5 - 0.5)^2 = 4
    EXPECT_GT(d["bias2"].get<double>(), 10 * d["bias2_stderr"].get<double>());
    for (const auto& [target, t] : d["time_to_relmse"].items()) EXPECT_EQ(t["kind"], "never") << target;
}

// Every CSV row against its image, read back here and compared with the analytic 2.5; JSON against CSV.
TEST_F(ConvergeFurnace, CsvAndJsonAgreeWithTheStepImages) {
    ASSERT_FALSE(rows_.empty());
    std::map<std::string, size_t> step_of;
    for (const Row& r : rows_) {
        const std::string slug = r.config == "default"       ? "default"
                                 : r.config == "max-depth=1" ? "max-depth-1"
                                                             : "effect-transmission-on";
        char name[64];
        std::snprintf(name, sizeof name, "_spp%05d.exr", int(r.values.at("spp")));
        const fh::Image img = fh::read_exr(OUT / "report" / "images" / (slug + name));
        double sq = 0, rel = 0, abs_rel = 0;
        for (float v : img.rgb) {
            const double d = double(v) - FURNACE;
            sq += d * d, rel += d * d / (FURNACE * FURNACE + 1e-2), abs_rel += std::abs(d) / (FURNACE + 1e-2);
        }
        const double n = double(img.rgb.size());
        EXPECT_NEAR(r.values.at("mse"), sq / n, 1e-6 * sq / n) << r.config << " " << r.values.at("spp");
        EXPECT_NEAR(r.values.at("relmse"), rel / n, 1e-6 * rel / n);
        EXPECT_NEAR(r.values.at("mape"), abs_rel / n, 1e-6 * abs_rel / n);
        EXPECT_NEAR(r.values.at("rmse"), std::sqrt(sq / n), 1e-6 * std::sqrt(sq / n));

        const nlohmann::json js = config(r.config)["steps"][step_of[r.config]++];
        EXPECT_EQ(js["spp"].get<double>(), r.values.at("spp"));
        EXPECT_NEAR(js["mse"].get<double>(), r.values.at("mse"), 1e-6 * r.values.at("mse"));
        EXPECT_NEAR(js["seconds"].get<double>(), r.values.at("seconds"), 1e-6 * r.values.at("seconds"));
    }
    EXPECT_EQ(step_of["default"], config("default")["steps"].size());
}

// The furnace has no glass: forcing the transmission effect on compiles the glass lobe into every stage but
// must change no bit, so each step's error equals the default's exactly (the time may differ).
TEST_F(ConvergeFurnace, ForcingAnUnusedEffectChangesNoError) {
    const nlohmann::json d = config("default"), forced = config("effect:transmission=on");
    // Both stop at --max-spp unless the time budget runs out first (on a loaded machine): compare the steps
    // both reached.
    const size_t steps = std::min(forced["steps"].size(), d["steps"].size());
    ASSERT_GE(steps, 6u);
    for (size_t i = 0; i < steps; ++i) {
        EXPECT_EQ(forced["steps"][i]["spp"], d["steps"][i]["spp"]);
        EXPECT_EQ(forced["steps"][i]["mse"].get<double>(), d["steps"][i]["mse"].get<double>()) << "step " << i;
    }
    EXPECT_NE(summary_["command"].get<std::string>().find("effect:transmission=on"), std::string::npos);
}

TEST_F(ConvergeFurnace, BadUsageExitsWithTwoAndMissingSceneWithOne) {
    const std::string out = " -o " + (OUT / "bad").string();
    EXPECT_EQ(run(std::string(FURNACE_SCENE) + out + " --vary colour=red"), 2);
    EXPECT_EQ(run(std::string(FURNACE_SCENE) + out + " --vary nee=maybe"), 2);
    EXPECT_EQ(run(std::string(FURNACE_SCENE) + out + " --vary effect:sparkle=on"), 2);
    EXPECT_EQ(run(std::string(FURNACE_SCENE) + out + " --vary effect:transmission=yes"), 2);
    EXPECT_EQ(run(std::string(FURNACE_SCENE) + out + " --reference x.exr --two-seeds"), 2);
    EXPECT_EQ(run((OUT / "missing.gltf").string() + out), 1);
}

}  // namespace
