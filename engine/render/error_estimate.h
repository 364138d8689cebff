// The error estimate of a render: each pixel's variance of its mean from batch means over aligned blocks of its sample
// sequence, kept exact so that it resumes and merges bit for bit like the film (engine/render/README.md "Error estimate").
//
// The samples [first_sample, end_sample) of every pixel are cut into batches of `batch_size` (a power of two) sample
// indices, aligned to multiples of it; a render holds at most MAX_ERROR_BATCHES of them, and doubles the batch size
// (adding neighbours) when it would need more, so between 3 and 6 batches are complete once 6 samples are in. Per pixel
// and batch it keeps the exact sum of the samples' luminance, 2126 R + 7152 G + 722 B in the film's fixed point (so
// Rec.709 luminance x 10^4): integer arithmetic, so any split into waves, resumed runs or merged parts gives the same
// sums. The variance of the pixel's mean is then s^2 n / N, with s^2 the sample variance of the complete batches' means,
// n the batch size and N the pixel's samples.
#pragma once
#include <cstdint>
#include <vector>

#include "io/image.h"
#include "shared/layout.h"

namespace fh {

// A fixed-point sum, 128-bit two's complement, wrapping like the film's.
using ExactSum = unsigned __int128;

constexpr uint32_t MAX_ERROR_BATCHES = 6;

// The luminance of a film pixel's sums, exactly (see above); a pixel the non-finite guard let a NaN into gives the
// film's NaN pattern.
ExactSum luminance_sum(const gpu::FilmPixel& pixel);

// now - before, or the NaN pattern when either is NaN.
ExactSum subtract_sums(ExactSum now, ExactSum before);

struct ErrorBatches {
    uint32_t batch_size = 1;    // sample indices per batch, a power of two
    uint32_t first_batch = 0;   // the batch in slot 0: samples [first_batch * batch_size, ...)
    uint32_t first_sample = 0;  // the samples the sums hold: [first_sample, end_sample)
    uint32_t end_sample = 0;
    std::vector<ExactSum> sums;  // pixel * MAX_ERROR_BATCHES + slot

    size_t pixel_count() const { return sums.size() / MAX_ERROR_BATCHES; }
    // Batches that [first_sample, end_sample) touches (slots in use).
    uint32_t slot_count() const;
};

// Empty batches for `pixels` pixels that will hold samples from `first_sample` on.
ErrorBatches make_error_batches(size_t pixels, uint32_t first_sample);

// The smallest batch size (a power of two) at which samples [first, end) touch at most MAX_ERROR_BATCHES batches.
uint32_t batch_size_for(uint32_t first, uint32_t end);

// Doubles the batch size until it is `size` (a power of two, not below the current one), adding neighbouring sums.
void coarsen(ErrorBatches& batches, uint32_t size);

// Adds samples [sample_begin, sample_end) whose luminance sums per pixel are `added` (the film's luminance now minus
// before). They must follow end_sample and lie in one batch of the current size. Throws std::logic_error otherwise.
void add_samples(ErrorBatches& batches, uint32_t sample_begin, uint32_t sample_end, const std::vector<ExactSum>& added);

// The batches of a render joined from parts: samples [first, end) of `pixels` pixels at the batch size they need (or
// `at_least`, a part's: one interrupted early may hold larger batches than its samples need), all sums zero; add each
// part with add_part.
ErrorBatches make_joined_batches(size_t pixels, uint32_t first, uint32_t end, uint32_t at_least = 1);

// Adds `part`, whose samples lie inside into's, to `into`: part's pixel i to into's pixel into_pixel[i]. Throws
// std::logic_error when part's samples or batch size do not fit.
void add_part(ErrorBatches& into, ErrorBatches part, const std::vector<size_t>& into_pixel);

// The estimated variance of each pixel's mean luminance, or NaN where fewer than two batches are complete (or the
// pixel's sums are NaN).
std::vector<float> pixel_variance(const ErrorBatches& batches);

// Complete batches (those whose samples are all in).
uint32_t complete_batch_count(const ErrorBatches& batches);

// The image's relative error: sqrt(mean over pixels of var / (Y^2 + 0.01)), Y the pixel's luminance (the relMSE of
// pbrt and Mitsuba, on luminance, as an RMSE). NaN when any pixel's variance is unknown.
double relative_error(const Image& image, const std::vector<float>& variance);

// Rec.709 luminance of pixel i.
float pixel_luminance(const Image& image, size_t i);

}  // namespace fh
