// Reads the two images and their variance layers, runs the noise test, prints the verdict, draws the heatmap.
#include "app/compare/compare_command.h"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "app/cli/render_options.h"
#include "app/compare/noise_test.h"
#include "io/atomic_write.h"
#include "io/exr.h"
#include "io/png.h"
#include "render/error_estimate.h"

namespace fh {
namespace {

// An image and, when it has one, its variance layer and the degrees of freedom of its batches.
NoisyImage read_noisy(const std::filesystem::path& file, bool quiet) {
    NoisyImage n;
    ImageMetadata metadata;
    n.image = read_exr(file, &metadata);
    const auto batches = metadata.find("fredholm:error_batches");
    unsigned complete = 0;
    if (exr_has_channel(file, "variance.Y") && batches != metadata.end() &&
        std::sscanf(batches->second.c_str(), "%u complete", &complete) == 1 && complete >= 2) {
        n.variance = read_exr_float_channels(file, {"variance.Y"}).at("variance.Y");
        n.degrees_of_freedom = complete - 1;
        for (float v : n.variance)
            if (!std::isfinite(v) || v < 0)
                throw IoError(file.string() + ": its variance layer variance.Y holds a negative or non-finite value");
    } else if (!quiet) {
        std::fprintf(stderr, "fredholm compare: warning: %s has no variance layer (variance.Y with "
                             "fredholm:error_batches): comparing by a plain threshold instead\n", file.string().c_str());
    }
    return n;
}

std::string percent(double x) {
    char text[32];
    std::snprintf(text, sizeof text, "%.3g%%", 100 * x);
    return text;
}

std::string number(double x) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", x);
    return text;
}

std::string describe_tile(const TileVerdict& t) {
    char text[160];
    std::snprintf(text, sizeof text, "pixels %d,%d-%d,%d (mean %+.1f sigma, spread %.2f, score %.2f)", t.x0,
                  t.y0, t.x1 - 1, t.y1 - 1, t.mean_z, t.spread, t.score);
    return text;
}

// The first image dimmed to grey; per pixel red up to its |z| at the pixel limit, significant pixels full red;
// significant tiles outlined in yellow.
Image draw_heatmap(const Image& a, const CompareResult& r) {
    Image map = a;
    for (size_t p = 0; p < r.pixels; ++p) {
        const float y = pixel_luminance(a, p), grey = 0.3f * y / (1 + y);
        const float red = r.pixel_z.empty() ? 0.0f : std::min(1.0f, r.pixel_z[p] / float(r.pixel_limit));
        const bool hit = !r.pixel_significant.empty() && r.pixel_significant[p];
        map.rgb[3 * p] = hit ? 1.0f : std::max(grey, red);
        map.rgb[3 * p + 1] = hit ? 0.0f : grey * (1 - red);
        map.rgb[3 * p + 2] = hit ? 0.0f : grey * (1 - red);
    }
    for (const TileVerdict& t : r.tile_verdicts) {
        if (!t.significant) continue;
        for (int y = t.y0; y < t.y1; ++y)
            for (int x = t.x0; x < t.x1; ++x) {
                if (x != t.x0 && x != t.x1 - 1 && y != t.y0 && y != t.y1 - 1) continue;
                float* px = &map.rgb[3 * (size_t(y) * a.width + x)];
                px[0] = 1, px[1] = 1, px[2] = 0;
            }
    }
    return map;
}

}  // namespace

void add_compare_options(CLI::App& app, CompareCommand& c) {
    app.add_option("a", c.a, "an EXR written by fredholm render (or merge)")->required();
    app.add_option("b", c.b, "the EXR to compare it with, e.g. the golden image")->required();
    app.add_option("--alpha", c.alpha, "the chance that two renders of the same scene are called different "
                                       "(the false-alarm rate over the whole image; default 0.01)")
        ->check(CLI::Range(1e-9, 0.5));
    app.add_option("--tile", c.tile, "tile side in pixels for the tile tests (default 16)")->check(CLI::Range(2, 4096));
    app.add_option("--threshold", c.threshold, "without variance layers: the relative difference (relative RMSE of "
                                               "luminance) above which the images differ (default 0.02)")
        ->check(CLI::Range(0.0, 100.0));
    app.add_option("--heatmap", c.heatmap, "write a PNG of the differences: red by significance, significant pixels "
                                           "full red, significant tiles outlined in yellow");
    app.add_flag("-q,--quiet", c.quiet, "no warnings (the verdict line is still printed)");
}

int run_compare(const CompareCommand& c) {
    try {
        if (!c.heatmap.empty()) check_writable(c.heatmap);
        const NoisyImage a = read_noisy(c.a, c.quiet), b = read_noisy(c.b, c.quiet);
        CompareOptions options;
        options.alpha = c.alpha;
        options.tile = c.tile;
        options.threshold = c.threshold;
        CompareResult r;
        try {
            r = compare_images(a, b, options);
        } catch (const std::invalid_argument& e) {
            throw IoError(c.a.string() + " and " + c.b.string() + ": " + e.what());
        }
        std::string line = std::string(r.differs ? "differs" : "same within noise") + ": relative difference " +
                           percent(r.relative_difference);
        if (r.with_noise) {
            line += ", noise " + percent(r.relative_noise) + "; beyond noise at alpha " + number(c.alpha) +
                    ": " + std::to_string(r.significant_pixels) + " of " + std::to_string(r.pixels) + " pixels, " +
                    std::to_string(r.significant_tiles) + " of " + std::to_string(r.tiles) + " tiles";
            if (!r.worst.empty() && r.worst[0].score > 0) {
                line += "; worst tiles:";
                for (size_t i = 0; i < r.worst.size(); ++i) line += (i ? ", " : " ") + describe_tile(r.worst[i]);
            }
        } else {
            line += " against the plain threshold " + percent(c.threshold) + " (no variance layers)";
        }
        std::printf("fredholm compare: %s\n", line.c_str());
        if (!c.heatmap.empty()) write_png(c.heatmap, draw_heatmap(a.image, r), 0, ToneCurve::clamp);
        return r.differs ? 1 : 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "fredholm compare: error: %s\n", e.what());
        return 2;
    }
}

}  // namespace fh
