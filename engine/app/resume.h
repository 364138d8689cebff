// The raw film in the output EXR (so any render can be continued), and the checks before continuing one.
#pragma once
#include <cstdint>
#include <filesystem>
#include <vector>

#include "io/exr.h"
#include "shared/layout.h"

namespace fh {

// The film's compensated sums as EXR channels fredholm.sum.R/G/B and fredholm.comp.R/G/B (float32, exact).
ExtraChannels film_channels(const std::vector<gpu::FilmPixel>& film);

struct SavedFilm {
    std::vector<gpu::FilmPixel> film;
    uint32_t spp = 0;  // samples per pixel already in the film ("fredholm:spp")
};

// Reads a render written by `fredholm render` and checks it can continue a render of width x height whose
// metadata is `expected`: throws std::runtime_error with one line "FILE: cannot resume: ..." naming the first
// setting that differs, a missing film channel or a missing "fredholm:spp".
SavedFilm read_saved_film(const std::filesystem::path& file, const ImageMetadata& expected, uint32_t width,
                          uint32_t height);

}  // namespace fh
