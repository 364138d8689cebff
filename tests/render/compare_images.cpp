// fh_compare: the command-line front end of the image checks, run by the render tests through ctest.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <stdexcept>
#include <string_view>
#include <vector>

#include "image_compare.h"
#include "io/exr.h"

namespace {

constexpr const char* USAGE = R"(usage:
  fh_compare TEST.exr --reference REF.exr [--block 16] [--max-block-rel 0.05] [--max-mean-rel 0.005]
                      [--alpha 0.01] [--diff-out DIFF.exr] [--z-out Z.exr]
  fh_compare TEST.exr --expect-constant VALUE|R,G,B [--tolerance 0.01] [--mean-tolerance TOLERANCE/10]
                      [--ignore-border 0] [--diff-out DIFF.exr]
  fh_compare TEST.exr --identical OTHER.exr [--diff-out DIFF.exr]
  fh_compare TEST.exr --finite [--diff-out DIFF.exr]
  fh_compare TEST.exr --elongated-along x|y [--min-ratio 2]
  fh_compare TEST.exr --dispersed-along x|-x|y|-y [--min-separation 1]
  fh_compare TEST.exr --blur-diameter SHARP.exr --expect-px D [--tolerance-px 1]
  fh_compare TEST.exr --smear-profile LEFT,WIDTH,TRAVEL --rows BEGIN,END [--tolerance 0.05]
  fh_compare T1.exr,T2.exr,... --same-distribution R1.exr,R2.exr,... [--alpha 0.01] [--diff-out DIFF.exr]
Exit status: 0 pass; 1 fail (one line per failing criterion, difference image written to --diff-out,
default TEST.diff.exr; --z-out adds each tile's z-score) or an unreadable image; 2 bad usage.
The exact pass/fail rules are documented in tests/render/image_compare.h.
)";

struct UsageError : std::runtime_error {
    using runtime_error::runtime_error;
};

// Which options each mode accepts, and what its difference image holds.
const std::map<std::string, std::vector<std::string>> MODE_OPTIONS = {
    {"--reference", {"--block", "--max-block-rel", "--max-mean-rel", "--alpha", "--diff-out", "--z-out"}},
    {"--expect-constant", {"--tolerance", "--mean-tolerance", "--ignore-border", "--diff-out"}},
    {"--identical", {"--diff-out"}},
    {"--finite", {"--diff-out"}},
    {"--elongated-along", {"--min-ratio"}},
    {"--dispersed-along", {"--min-separation"}},
    {"--blur-diameter", {"--expect-px", "--tolerance-px"}},
    {"--smear-profile", {"--rows", "--tolerance"}},
    {"--same-distribution", {"--alpha", "--diff-out"}},
};

const std::map<std::string, std::string> DIFFERENCE_CONTENT = {
    {"--reference", "test minus reference"},
    {"--expect-constant", "test minus expected constant"},
    {"--identical", "test minus other"},
    {"--finite", "1 where a value is NaN or infinite"},
    {"--elongated-along", "none"},
    {"--dispersed-along", "none"},
    {"--blur-diameter", "none"},
    {"--smear-profile", "none"},
    {"--same-distribution", "mean of test batches minus mean of reference batches"},
};

struct Arguments {
    std::filesystem::path test;
    std::string mode;
    std::map<std::string, std::string> options;  // option -> value ("" for --finite)

    bool has(const std::string& name) const { return options.count(name) != 0; }

    double number(const std::string& name, double fallback) const {
        if (!has(name)) return fallback;
        const std::string& text = options.at(name);
        std::size_t used = 0;
        double value = 0;
        try {
            value = std::stod(text, &used);
        } catch (const std::exception&) {
            used = 0;
        }
        if (used == 0 || used != text.size() || !std::isfinite(value))
            throw UsageError(name + " expects a number, got \"" + text + "\"");
        return value;
    }

    int integer(const std::string& name, int fallback, int minimum) const {
        const double value = number(name, fallback);
        if (value != std::floor(value) || value < minimum || value > 1e6)
            throw UsageError(name + " expects an integer >= " + std::to_string(minimum) + ", got \"" +
                             options.at(name) + "\"");
        return int(value);
    }
};

Arguments parse_arguments(int argc, char** argv) {
    Arguments args;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        if (arg.rfind("--", 0) != 0) {
            if (!args.test.empty()) throw UsageError("more than one test image: " + args.test.string() + ", " + arg);
            args.test = arg;
            continue;
        }
        const bool is_mode = MODE_OPTIONS.count(arg) != 0;
        if (is_mode && !args.mode.empty()) throw UsageError("choose one of " + args.mode + " and " + arg);
        if (is_mode) args.mode = arg;
        if (args.options.count(arg)) throw UsageError(arg + " given twice");
        if (arg == "--finite") {
            args.options[arg] = "";
            continue;
        }
        if (i + 1 >= argc) throw UsageError(arg + " needs a value");
        args.options[arg] = argv[++i];
    }
    if (args.test.empty()) throw UsageError("no test image given");
    if (args.mode.empty())
        throw UsageError("choose one of --reference, --expect-constant, --identical, --finite, --same-distribution, "
                         "--elongated-along, --dispersed-along, --blur-diameter, --smear-profile");
    for (const auto& [name, value] : args.options) {
        if (name == args.mode) continue;
        bool known = false;
        for (const auto& [mode, allowed] : MODE_OPTIONS)
            known = known || std::find(allowed.begin(), allowed.end(), name) != allowed.end();
        const auto& allowed = MODE_OPTIONS.at(args.mode);
        if (!known) throw UsageError("unknown option " + name);
        if (std::find(allowed.begin(), allowed.end(), name) == allowed.end())
            throw UsageError(name + " is not an option of " + args.mode);
    }
    return args;
}

// The first file of a comma-separated list (where a difference image goes by default).
std::string read_first(const std::filesystem::path& list) {
    const std::string s = list.string();
    return s.substr(0, s.find(','));
}

std::vector<fh::Image> read_batches(const std::string& list) {
    std::vector<fh::Image> images;
    size_t begin = 0;
    while (begin <= list.size()) {
        const size_t end = std::min(list.find(',', begin), list.size());
        if (end > begin) images.push_back(fh::read_exr(list.substr(begin, end - begin)));
        begin = end + 1;
    }
    return images;
}

// Runs the chosen check; writes the z-score image itself because only the reference mode has one.
fh::CheckResult run_check(const Arguments& args) {
    if (args.mode == "--same-distribution") {
        const double alpha = args.number("--alpha", 0.01);
        if (!(alpha > 0 && alpha < 1)) throw UsageError("--alpha must lie in (0, 1)");
        return fh::compare_distributions(read_batches(args.test.string()),
                                         read_batches(args.options.at("--same-distribution")), alpha);
    }
    const fh::Image test = fh::read_exr(args.test);
    if (args.mode == "--reference") {
        fh::ReferenceOptions options;
        options.block = args.integer("--block", options.block, 2);
        options.max_block_rel = args.number("--max-block-rel", options.max_block_rel);
        options.max_mean_rel = args.number("--max-mean-rel", options.max_mean_rel);
        options.alpha = args.number("--alpha", options.alpha);
        if (!(options.alpha > 0 && options.alpha < 1)) throw UsageError("--alpha must lie in (0, 1)");
        fh::ReferenceResult result = fh::compare_to_reference(test, fh::read_exr(args.options.at("--reference")), options);
        if (!result.passed() && args.has("--z-out") && !result.z_image.rgb.empty()) {
            fh::write_exr(args.options.at("--z-out"), result.z_image, {{"fredholm:content", "tile z-score"}});
            std::printf("fh_compare: wrote tile z-scores to %s\n", args.options.at("--z-out").c_str());
        }
        return result;
    }
    if (args.mode == "--expect-constant") {
        const double tolerance = args.number("--tolerance", 0.01);
        if (!(tolerance >= 0)) throw UsageError("--tolerance must not be negative");
        const double mean_tolerance = args.number("--mean-tolerance", tolerance / 10);
        if (!(mean_tolerance >= 0)) throw UsageError("--mean-tolerance must not be negative");
        const std::string text = args.options.at("--expect-constant");
        if (std::count(text.begin(), text.end(), ',') == 2) {
            std::array<double, 3> rgb{};
            std::size_t start = 0;
            for (int c = 0; c < 3; ++c) {
                const std::size_t end = c < 2 ? text.find(',', start) : text.size();
                const std::string part = text.substr(start, end - start);
                std::size_t used = 0;
                try {
                    rgb[c] = std::stod(part, &used);
                } catch (const std::exception&) {
                    used = 0;
                }
                if (used == 0 || used != part.size() || !std::isfinite(rgb[c]))
                    throw UsageError("--expect-constant expects a number or R,G,B, got \"" + text + "\"");
                start = end + 1;
            }
            return fh::check_constant(test, rgb, tolerance, args.integer("--ignore-border", 0, 0), mean_tolerance);
        }
        return fh::check_constant(test, args.number("--expect-constant", 0), tolerance,
                                  args.integer("--ignore-border", 0, 0), mean_tolerance);
    }
    if (args.mode == "--elongated-along") {
        const std::string axis = args.options.at("--elongated-along");
        if (axis != "x" && axis != "y") throw UsageError("--elongated-along takes x or y");
        const double min_ratio = args.number("--min-ratio", 2.0);
        if (!(min_ratio > 0)) throw UsageError("--min-ratio must be positive");
        return fh::check_elongation(test, axis[0], min_ratio);
    }
    if (args.mode == "--dispersed-along") {
        const std::string direction = args.options.at("--dispersed-along");
        if (direction != "x" && direction != "-x" && direction != "y" && direction != "-y")
            throw UsageError("--dispersed-along takes x, -x, y or -y");
        const double min_separation = args.number("--min-separation", 1.0);
        if (!(min_separation >= 0)) throw UsageError("--min-separation must not be negative");
        return fh::check_dispersion(test, direction, min_separation);
    }
    if (args.mode == "--blur-diameter") {
        if (!args.has("--expect-px")) throw UsageError("--blur-diameter needs --expect-px");
        const double expected = args.number("--expect-px", 0.0), tolerance = args.number("--tolerance-px", 1.0);
        if (!(expected >= 0) || !(tolerance >= 0)) throw UsageError("--expect-px and --tolerance-px must not be negative");
        return fh::check_blur_diameter(test, fh::read_exr(args.options.at("--blur-diameter")), expected, tolerance);
    }
    if (args.mode == "--smear-profile") {
        double bar[3];
        int rows[2];
        if (std::sscanf(args.options.at("--smear-profile").c_str(), "%lf,%lf,%lf", &bar[0], &bar[1], &bar[2]) != 3 ||
            !(bar[1] > 0) || !(bar[2] >= 0))
            throw UsageError("--smear-profile takes LEFT,WIDTH,TRAVEL in pixels (width above 0, travel not negative)");
        if (!args.has("--rows") || std::sscanf(args.options.at("--rows").c_str(), "%d,%d", &rows[0], &rows[1]) != 2)
            throw UsageError("--smear-profile needs --rows BEGIN,END");
        const double tolerance = args.number("--tolerance", 0.05);
        if (!(tolerance >= 0)) throw UsageError("--tolerance must not be negative");
        return fh::check_smear_profile(test, bar[0], bar[1], bar[2], rows[0], rows[1], tolerance);
    }
    if (args.mode == "--identical") return fh::check_identical(test, fh::read_exr(args.options.at("--identical")));
    return fh::check_finite(test);
}

}  // namespace

int main(int argc, char** argv) {
    if (argc == 2 && (std::string_view(argv[1]) == "--help" || std::string_view(argv[1]) == "-h")) {
        std::fputs(USAGE, stdout);
        return 0;
    }
    try {
        const Arguments args = parse_arguments(argc, argv);
        const fh::CheckResult result = run_check(args);
        if (result.passed()) {
            std::printf("fh_compare: %s: %s\n", args.test.c_str(), result.summary.c_str());
            return 0;
        }
        for (const std::string& failure : result.failures) std::printf("fh_compare: FAIL %s\n", failure.c_str());
        std::printf("fh_compare: %s: %s\n", args.test.c_str(), result.summary.c_str());
        if (!result.difference.rgb.empty()) {
            std::filesystem::path diff = args.has("--diff-out") ? std::filesystem::path(args.options.at("--diff-out"))
                                                                : std::filesystem::path(read_first(args.test)).replace_extension(".diff.exr");
            fh::write_exr(diff, result.difference, {{"fredholm:content", DIFFERENCE_CONTENT.at(args.mode)}});
            std::printf("fh_compare: wrote difference image %s\n", diff.c_str());
        }
        return 1;
    } catch (const UsageError& e) {
        std::fprintf(stderr, "fh_compare: %s\n%s", e.what(), USAGE);
        return 2;
    } catch (const std::exception& e) {
        std::printf("fh_compare: FAIL %s\n", e.what());
        return 1;
    }
}
