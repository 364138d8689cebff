// Saving and reloading the raw film: the Kahan sums and their compensations, bit for bit, so that continuing a
// render from sample index n adds samples n, n+1, ... in the same order an uninterrupted render would.
#include "app/resume.h"

#include <stdexcept>
#include <string>

namespace fh {
namespace {

const char* const SUM_NAMES[3] = {"fredholm.sum.R", "fredholm.sum.G", "fredholm.sum.B"};
const char* const COMP_NAMES[3] = {"fredholm.comp.R", "fredholm.comp.G", "fredholm.comp.B"};
// Metadata whose values must be equal for a render to continue another (besides the image size): the
// settings that decide each sample's value.
const char* const RESUME_KEYS[] = {"fredholm:renderer", "fredholm:scene", "fredholm:seed", "fredholm:max_depth",
                                   "fredholm:camera",   "fredholm:filter", "fredholm:filter_radius", "fredholm:sampler",
                                   "fredholm:nee",      "fredholm:mis",    "fredholm:rr",     "fredholm:rr_start_depth",
                                   "fredholm:environment", "fredholm:lens", "fredholm:animation", "fredholm:time", "fredholm:shutter", "fredholm:variant",
                                   "fredholm:disabled_effects"};

std::string setting_name(const std::string& key) {
    const std::string prefix = "fredholm:";
    return key.rfind(prefix, 0) == 0 ? key.substr(prefix.size()) : key;
}

// "fredholm:spp" as a sample count, or -1 when it is not a plain decimal number below 2^32.
int64_t parse_spp(const std::string& text) {
    if (text.empty() || text.size() > 10) return -1;
    int64_t value = 0;
    for (char c : text) {
        if (c < '0' || c > '9') return -1;
        value = value * 10 + (c - '0');
    }
    return value <= int64_t(UINT32_MAX) ? value : -1;
}

}  // namespace

ExtraChannels film_channels(const std::vector<gpu::FilmPixel>& film) {
    ExtraChannels channels;
    for (int c = 0; c < 3; ++c) {
        std::vector<float>& sum = channels[SUM_NAMES[c]];
        std::vector<float>& comp = channels[COMP_NAMES[c]];
        sum.resize(film.size());
        comp.resize(film.size());
        for (size_t i = 0; i < film.size(); ++i) {
            const gpu::FilmPixel& p = film[i];
            sum[i] = c == 0 ? p.sum_r : c == 1 ? p.sum_g : p.sum_b;
            comp[i] = c == 0 ? p.comp_r : c == 1 ? p.comp_g : p.comp_b;
        }
    }
    return channels;
}

SavedFilm read_saved_film(const std::filesystem::path& file, const ImageMetadata& expected, uint32_t width,
                          uint32_t height) {
    const std::string prefix = file.string() + ": cannot resume: ";
    ImageMetadata saved;
    const Image image = read_exr(file, &saved);
    if (uint32_t(image.width) != width || uint32_t(image.height) != height)
        throw std::runtime_error(prefix + "the image is " + std::to_string(image.width) + "x" +
                                 std::to_string(image.height) + " but this render is " + std::to_string(width) +
                                 "x" + std::to_string(height));
    for (const char* key : RESUME_KEYS) {
        const auto want = expected.find(key);
        const auto have = saved.find(key);
        if (have == saved.end())
            throw std::runtime_error(prefix + "it has no " + key + " metadata (not written by fredholm render?)");
        if (want != expected.end() && want->second != have->second)
            throw std::runtime_error(prefix + setting_name(key) + " is " + have->second + " in the file but " +
                                     want->second + " in this render");
    }
    const auto spp_text = saved.find("fredholm:spp");
    const int64_t spp = spp_text == saved.end() ? -1 : parse_spp(spp_text->second);
    if (spp < 0) throw std::runtime_error(prefix + "no valid fredholm:spp metadata");

    std::vector<std::string> names(std::begin(SUM_NAMES), std::end(SUM_NAMES));
    names.insert(names.end(), std::begin(COMP_NAMES), std::end(COMP_NAMES));
    ExtraChannels channels;
    try {
        channels = read_exr_channels(file, names);
    } catch (const IoError& e) {
        throw std::runtime_error(prefix + "no raw film (" + e.what() + ")");
    }
    SavedFilm saved_film;
    saved_film.spp = uint32_t(spp);
    saved_film.film.resize(size_t(width) * height);
    for (size_t i = 0; i < saved_film.film.size(); ++i) {
        gpu::FilmPixel& p = saved_film.film[i];
        p.sum_r = channels[SUM_NAMES[0]][i];
        p.sum_g = channels[SUM_NAMES[1]][i];
        p.sum_b = channels[SUM_NAMES[2]][i];
        p.comp_r = channels[COMP_NAMES[0]][i];
        p.comp_g = channels[COMP_NAMES[1]][i];
        p.comp_b = channels[COMP_NAMES[2]][i];
        p.sample_count = float(spp);  // every pixel holds the same samples: interruption stops between sample indices
        p.pad = 0.0f;
    }
    return saved_film;
}

}  // namespace fh
