// Merging render parts: check, add the fixed-point films, write one EXR (see merge_command.h).
#include "app/merge/merge_command.h"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <map>
#include <stdexcept>
#include <tuple>

#include "app/cli/render_options.h"
#include "app/cli/resume.h"
#include "io/atomic_write.h"
#include "io/exr.h"
#include "io/png.h"
#include "render/aov_image.h"
#include "render/film.h"

namespace fh {
namespace {

struct Part {
    std::filesystem::path file;
    FilmFile film;
};

using Region = std::tuple<uint32_t, uint32_t, uint32_t, uint32_t>;  // x0, y0, x1, y1

std::string name_region(const FilmFile& f) {
    if (f.x0 == 0 && f.y0 == 0 && f.x1 == f.image_width && f.y1 == f.image_height) return "the whole image";
    return "crop " + describe_crop(f.x0, f.y0, f.x1, f.y1);
}

std::string name_samples(uint32_t a, uint32_t b) { return std::to_string(a) + ":" + std::to_string(b); }

// `first` has been checked against itself, so its keys are all there.
void check_same_render(const Part& first, const Part& part) {
    for (const std::string& key : matching_film_keys()) {
        const auto have = part.film.metadata.find(key);
        const std::string setting = key.substr(key.find(':') + 1);
        if (have == part.film.metadata.end())
            throw std::runtime_error(part.file.string() + ": cannot merge: it has no " + key + " metadata");
        const auto want = first.film.metadata.find(key);
        if (want != first.film.metadata.end() && have->second != want->second)
            throw std::runtime_error(part.file.string() + ": cannot merge: " + setting + " is " + have->second +
                                     " here but " + want->second + " in " + first.file.string());
    }
}

// Within one region the parts' sample ranges must follow each other; returns the range they cover together.
std::pair<uint32_t, uint32_t> check_sample_ranges(std::vector<const Part*>& parts) {
    std::sort(parts.begin(), parts.end(), [](const Part* a, const Part* b) {
        return std::tie(a->film.first_sample, a->film.end_sample) < std::tie(b->film.first_sample, b->film.end_sample);
    });
    for (size_t i = 1; i < parts.size(); ++i) {
        const FilmFile &a = parts[i - 1]->film, &b = parts[i]->film;
        if (b.first_sample < a.end_sample)
            throw std::runtime_error("cannot merge: " + parts[i - 1]->file.string() + " and " + parts[i]->file.string() +
                                     " overlap: both hold samples " +
                                     name_samples(b.first_sample, std::min(a.end_sample, b.end_sample)) + " of " +
                                     name_region(a));
        if (b.first_sample > a.end_sample)
            throw std::runtime_error("cannot merge: no part holds samples " + name_samples(a.end_sample, b.first_sample) +
                                     " of " + name_region(a) + " (between " + parts[i - 1]->file.string() + " and " +
                                     parts[i]->file.string() + ")");
    }
    return {parts.front()->film.first_sample, parts.back()->film.end_sample};
}

// The regions must tile the image: no pixel in two regions, none in no region.
void check_regions_tile(const std::map<Region, std::vector<const Part*>>& regions, uint32_t width, uint32_t height) {
    std::vector<const Part*> owner(size_t(width) * height, nullptr);
    for (const auto& [region, parts] : regions) {
        const auto [x0, y0, x1, y1] = region;
        for (uint32_t y = y0; y < y1; ++y)
            for (uint32_t x = x0; x < x1; ++x) {
                const Part*& o = owner[size_t(y) * width + x];
                if (o)
                    throw std::runtime_error("cannot merge: " + o->file.string() + " (" + name_region(o->film) + ") and " +
                                             parts.front()->file.string() + " (" + name_region(parts.front()->film) +
                                             ") overlap at pixel " + std::to_string(x) + "," + std::to_string(y));
                o = parts.front();
            }
    }
    for (size_t i = 0; i < owner.size(); ++i)
        if (!owner[i])
            throw std::runtime_error("cannot merge: no part covers pixel " + std::to_string(i % width) + "," +
                                     std::to_string(i / width) + " of the " + std::to_string(width) + "x" +
                                     std::to_string(height) + " image");
}

// Where pixel i of a part (its crop, row by row) lies in the merged image of `width` pixels a row.
size_t image_pixel(const FilmFile& part, size_t i, uint32_t width) {
    const uint32_t part_width = part.x1 - part.x0;
    return (part.y0 + i / part_width) * size_t(width) + part.x0 + i % part_width;
}

// The parts' AOVs (`--aov`), joined like the film: every part must have been rendered with the same list.
void add_aov_layers(const std::vector<Part>& parts, const std::vector<gpu::FilmPixel>& film, ExtraChannels& channels,
                    FloatChannels& floats, ImageMetadata& metadata) {
    const FilmFile& first = parts.front().film;
    for (const Part& p : parts)
        if (p.film.aovs != first.aovs || p.film.has_aov_sums != first.has_aov_sums)
            throw std::runtime_error("cannot merge: " + p.file.string() + " has --aov '" + p.film.aovs + "' but " +
                                     parts.front().file.string() + " has '" + first.aovs + "'");
    if (first.aovs.empty()) return;
    std::vector<gpu::AovPixel> sums(film.size(), gpu::AovPixel{});
    const uint32_t width = first.image_width;
    if (first.has_aov_sums)
        for (const Part& p : parts) {
            for (size_t i = 0; i < p.film.aov_sums.size(); ++i)
                add_aov_pixel(sums[image_pixel(p.film, i, width)], p.film.aov_sums[i]);
        }
    const FloatChannels layers = aov_layers(parse_aovs(first.aovs), sums, film);
    floats.insert(layers.begin(), layers.end());
    if (first.has_aov_sums) {
        const ExtraChannels sum_channels = aov_sum_channels(sums);
        channels.insert(sum_channels.begin(), sum_channels.end());
    }
    metadata["fredholm:aovs"] = first.aovs;
}

}  // namespace

void add_merge_options(CLI::App& app, MergeCommand& c) {
    app.add_option("parts", c.parts, "EXR files written by fredholm render --samples / --crop (or by merge)")
        ->required()
        ->check(CLI::ExistingFile);
    app.add_option("-o,--output", c.output, "merged OpenEXR image")->required();
    app.add_option("--png", c.png, "also write a tone-mapped sRGB PNG preview");
    add_tone_options(app, c.exposure_ev, c.tone_curve, "PNG");
    app.add_flag("-q,--quiet", c.quiet, "no summary line");
}

int run_merge(const MergeCommand& c) {
    check_writable(c.output);
    if (!c.png.empty()) check_writable(c.png);
    std::vector<Part> parts;
    parts.reserve(c.parts.size());
    for (const std::filesystem::path& file : c.parts) {
        for (const Part& p : parts)
            if (std::filesystem::equivalent(p.file, file))
                throw std::runtime_error(file.string() + ": cannot merge: given twice");
        parts.push_back({file, read_film_file(file, "cannot merge")});
        check_same_render(parts.front(), parts.back());
    }
    const uint32_t width = parts.front().film.image_width, height = parts.front().film.image_height;

    std::map<Region, std::vector<const Part*>> regions;
    for (const Part& p : parts) regions[{p.film.x0, p.film.y0, p.film.x1, p.film.y1}].push_back(&p);
    std::pair<uint32_t, uint32_t> samples{0, 0};
    const Part* samples_from = nullptr;
    for (auto& [region, list] : regions) {
        const std::pair<uint32_t, uint32_t> covered = check_sample_ranges(list);
        if (samples_from && covered != samples)
            throw std::runtime_error("cannot merge: " + name_region(samples_from->film) + " has samples " +
                                     name_samples(samples.first, samples.second) + " but " +
                                     name_region(list.front()->film) + " has " +
                                     name_samples(covered.first, covered.second) + " (" + list.front()->file.string() +
                                     ")");
        samples = covered;
        samples_from = list.front();
    }
    check_regions_tile(regions, width, height);

    std::vector<gpu::FilmPixel> film(size_t(width) * height, gpu::FilmPixel{});
    for (const Part& p : parts) {
        for (size_t i = 0; i < p.film.film.size(); ++i) add_film_pixel(film[image_pixel(p.film, i, width)], p.film.film[i]);
    }
    ImageMetadata metadata = parts.front().film.metadata;
    // Only fredholm's own keys, less the error estimate's (written anew below): OpenEXR's standard attributes are
    // written anew.
    for (auto it = metadata.begin(); it != metadata.end();) {
        const bool error_key = it->first == "fredholm:relative_error" || it->first == "fredholm:error_batches" ||
                               it->first == "fredholm:batch_size" || it->first == "fredholm:first_batch";
        it = it->first.rfind("fredholm:", 0) == 0 && !error_key ? std::next(it) : metadata.erase(it);
    }
    metadata["fredholm:first_sample"] = std::to_string(samples.first);
    metadata["fredholm:spp"] = std::to_string(samples.second);
    metadata["fredholm:crop"] = "none";
    const Image image = resolve_film(film, int(width), int(height));
    ExtraChannels channels = film_channels(film);
    FloatChannels floats;
    const bool estimate = std::all_of(parts.begin(), parts.end(), [](const Part& p) { return p.film.has_batches; });
    if (estimate) {
        uint32_t largest = 1;
        for (const Part& p : parts) largest = std::max(largest, p.film.batches.batch_size);
        ErrorBatches batches = make_joined_batches(film.size(), samples.first, samples.second, largest);
        for (const Part& p : parts) {
            std::vector<size_t> into(p.film.film.size());
            for (size_t i = 0; i < into.size(); ++i) into[i] = image_pixel(p.film, i, width);
            add_part(batches, p.film.batches, into);
        }
        add_error_channels(batches, image, channels, floats, metadata);
    } else if (!c.quiet) {
        std::fprintf(stderr, "fredholm: note: a part has no error batches (written by an older fredholm), so the "
                             "merged image has no error estimate\n");
    }
    add_aov_layers(parts, film, channels, floats, metadata);
    write_exr(c.output, image, metadata, channels, {}, floats);
    if (!c.png.empty()) write_png(c.png, image, c.exposure_ev, c.tone_curve);
    if (!c.quiet)
        std::fprintf(stderr, "fredholm: %s: merged %zu part(s) in %zu region(s): %ux%u, samples %s\n",
                     c.output.string().c_str(), parts.size(), regions.size(), width, height,
                     name_samples(samples.first, samples.second).c_str());
    return 0;
}

}  // namespace fh
