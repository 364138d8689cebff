// The raw film in the output EXR (so any render can be continued or merged with others), and the checks before
// continuing one.
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "io/exr.h"
#include "render/error_estimate.h"
#include "shared/layout.h"

namespace fh {

// The EXR channels of the raw film: fredholm.sum.{R,G,B}.{0..3} (the fixed-point words, least significant first) and
// fredholm.count, all UINT.
const std::vector<std::string>& film_channel_names();
ExtraChannels film_channels(const std::vector<gpu::FilmPixel>& film);

// The error batches (render/error_estimate.h) in the EXR: channels fredholm.batch.<slot>.{0..3} (UINT, a slot's exact
// luminance sum, least significant word first) for the slots in use, metadata fredholm:batch_size and
// fredholm:first_batch; and what a reader wants: the variance layer variance.Y (the variance of each pixel's mean
// luminance, FLOAT) and fredholm:relative_error, fredholm:error_batches. Without two complete batches (a render of
// one sample) only the batches are written.
void add_error_channels(const ErrorBatches& batches, const Image& image, ExtraChannels& channels, FloatChannels& floats,
                        ImageMetadata& metadata);
// The reader's part alone: variance.Y and fredholm:relative_error (an adaptive render's, which has no batches).
void add_variance_layer(std::vector<float> variance, double relative_error, FloatChannels& floats,
                        ImageMetadata& metadata);

// The AOVs' exact sums (layout.h AovPixel, `--aov albedo,normal,depth`) in the EXR, so a render with AOVs resumes and
// merges like the film: UINT channels fredholm.aov.{albedo_r,albedo_g,albedo_b,normal_x,normal_y,normal_z,depth}.{0..3}
// and fredholm.aov.hits.
ExtraChannels aov_sum_channels(const std::vector<gpu::AovPixel>& aovs);

// Metadata whose values must be equal for films to continue or join each other: the settings that decide each
// sample's value, the scene file's hash and the image size.
const std::vector<std::string>& matching_film_keys();

// "X0,Y0,X1,Y1" of a crop; "none" for the whole image.
std::string describe_crop(uint32_t x0, uint32_t y0, uint32_t x1, uint32_t y1);

// A film written by `fredholm render` or `fredholm merge`: which samples of which pixels it holds, and its sums.
struct FilmFile {
    ImageMetadata metadata;
    std::vector<gpu::FilmPixel> film;
    uint32_t first_sample = 0, end_sample = 0;   // it holds samples [first_sample, end_sample) of each pixel
    uint32_t image_width = 0, image_height = 0;  // the whole image
    uint32_t x0 = 0, y0 = 0, x1 = 0, y1 = 0;     // the pixels it covers (the whole image unless cropped)
    bool has_batches = false;  // written before error batches existed: false
    ErrorBatches batches;      // over [first_sample, end_sample)
    std::string aovs;          // fredholm:aovs, the --aov list it was rendered with ("" none)
    bool has_aov_sums = false; // it holds the sums of albedo, normal and depth
    std::vector<gpu::AovPixel> aov_sums;
};

// Reads and checks a film file: throws std::runtime_error with one line "FILE: <why> ..." (`why`, e.g. "cannot
// resume") for a missing or malformed fredholm:spp, fredholm:first_sample, fredholm:crop or film channel, or a pixel
// whose sample count is not end_sample - first_sample, or error batches that do not fit its samples.
FilmFile read_film_file(const std::filesystem::path& file, const std::string& why);

// Reads a render to continue and checks it against this render: the image size, crop and every matching key of
// `expected` (plus fredholm:first_sample). Throws like read_film_file, "FILE: cannot resume: ...", naming the first
// setting that differs.
FilmFile read_saved_film(const std::filesystem::path& file, const ImageMetadata& expected);

// 64-bit FNV-1a of a file's bytes, as 16 hex digits (fredholm:scene_hash). Throws IoError if unreadable.
std::string hash_file(const std::filesystem::path& file);

}  // namespace fh
