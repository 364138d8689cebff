// Batch means of the film's luminance, exact and mergeable; see error_estimate.h.
#include "render/error_estimate.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace fh {
namespace {

constexpr ExactSum FIXED_NAN = ExactSum(gpu::FILM_NAN_TOP_WORD) << 96;  // layout.h
constexpr double LUMINANCE_SCALE = 1e4;                                  // the integer weights below sum to 10^4

ExactSum load_sum(const uint32_t (&w)[gpu::FILM_WORDS]) {
    static_assert(gpu::FILM_WORDS == 4, "a film sum is 128 bits");
    return ExactSum(w[0]) | ExactSum(w[1]) << 32 | ExactSum(w[2]) << 64 | ExactSum(w[3]) << 96;
}

// A luminance sum as a real number (radiance units), NaN for the NaN pattern.
double to_real(ExactSum value) {
    if (value == FIXED_NAN) return std::numeric_limits<double>::quiet_NaN();
    const bool negative = (value >> 127) != 0;
    const ExactSum magnitude = negative ? ExactSum(0) - value : value;
    const double real = std::ldexp(double(magnitude), -gpu::FILM_FRACTION_BITS) / LUMINANCE_SCALE;
    return negative ? -real : real;
}

ExactSum add_exact(ExactSum a, ExactSum b) { return a == FIXED_NAN || b == FIXED_NAN ? FIXED_NAN : a + b; }

bool is_power_of_two(uint32_t x) { return x != 0 && (x & (x - 1)) == 0; }

uint32_t touched_batches(uint64_t first, uint64_t end, uint64_t size) {
    return end <= first ? 0u : uint32_t((end - 1) / size - first / size + 1);
}

}  // namespace

ExactSum luminance_sum(const gpu::FilmPixel& pixel) {
    const ExactSum r = load_sum(pixel.sum_r), g = load_sum(pixel.sum_g), b = load_sum(pixel.sum_b);
    if (r == FIXED_NAN || g == FIXED_NAN || b == FIXED_NAN) return FIXED_NAN;
    return 2126 * r + 7152 * g + 722 * b;  // Rec.709 weights x 10^4, wrapping
}

ExactSum subtract_sums(ExactSum now, ExactSum before) {
    return now == FIXED_NAN || before == FIXED_NAN ? FIXED_NAN : now - before;
}

uint32_t ErrorBatches::slot_count() const { return touched_batches(first_sample, end_sample, batch_size); }

ErrorBatches make_error_batches(size_t pixels, uint32_t first_sample) {
    ErrorBatches b;
    b.first_batch = first_sample;
    b.first_sample = b.end_sample = first_sample;
    b.sums.assign(pixels * MAX_ERROR_BATCHES, 0);
    return b;
}

uint32_t batch_size_for(uint32_t first, uint32_t end) {
    uint64_t size = 1;
    while (touched_batches(first, end, size) > MAX_ERROR_BATCHES) size *= 2;
    return uint32_t(size);
}

void coarsen(ErrorBatches& b, uint32_t size) {
    if (!is_power_of_two(size) || size < b.batch_size)
        throw std::logic_error("coarsen: batch size " + std::to_string(size) + " is not a power of two above " +
                               std::to_string(b.batch_size));
    while (b.batch_size < size) {
        const uint32_t first = b.first_batch / 2, slots = b.slot_count();
        for (size_t p = 0; p < b.pixel_count(); ++p) {
            ExactSum* s = &b.sums[p * MAX_ERROR_BATCHES];
            ExactSum merged[MAX_ERROR_BATCHES] = {};
            for (uint32_t j = 0; j < slots; ++j) {
                ExactSum& into = merged[(b.first_batch + j) / 2 - first];
                into = add_exact(into, s[j]);
            }
            for (uint32_t j = 0; j < MAX_ERROR_BATCHES; ++j) s[j] = merged[j];
        }
        b.first_batch = first;
        b.batch_size *= 2;
    }
}

void add_samples(ErrorBatches& b, uint32_t sample_begin, uint32_t sample_end, const std::vector<ExactSum>& added) {
    const uint32_t batch = sample_begin / b.batch_size;
    if (sample_begin != b.end_sample || sample_end <= sample_begin || (sample_end - 1) / b.batch_size != batch ||
        batch - b.first_batch >= MAX_ERROR_BATCHES || added.size() != b.pixel_count())
        throw std::logic_error("add_samples: samples " + std::to_string(sample_begin) + ":" +
                               std::to_string(sample_end) + " do not continue the batches of size " +
                               std::to_string(b.batch_size) + " at sample " + std::to_string(b.end_sample));
    const uint32_t slot = batch - b.first_batch;
    for (size_t p = 0; p < added.size(); ++p) {
        ExactSum& s = b.sums[p * MAX_ERROR_BATCHES + slot];
        s = add_exact(s, added[p]);
    }
    b.end_sample = sample_end;
}

ErrorBatches make_joined_batches(size_t pixels, uint32_t first, uint32_t end, uint32_t at_least) {
    ErrorBatches b = make_error_batches(pixels, first);
    b.batch_size = std::max(batch_size_for(first, end), at_least);
    b.first_batch = first / b.batch_size;
    b.end_sample = end;
    return b;
}

void add_part(ErrorBatches& into, ErrorBatches part, const std::vector<size_t>& into_pixel) {
    if (part.first_sample < into.first_sample || part.end_sample > into.end_sample ||
        part.batch_size > into.batch_size || into_pixel.size() != part.pixel_count())
        throw std::logic_error("add_part: a part's samples or batches do not fit the joined render");
    coarsen(part, into.batch_size);
    const uint32_t offset = part.first_batch - into.first_batch, slots = part.slot_count();
    for (size_t p = 0; p < into_pixel.size(); ++p)
        for (uint32_t j = 0; j < slots; ++j) {
            ExactSum& s = into.sums[into_pixel[p] * MAX_ERROR_BATCHES + offset + j];
            s = add_exact(s, part.sums[p * MAX_ERROR_BATCHES + j]);
        }
}

uint32_t complete_batch_count(const ErrorBatches& b) {
    uint32_t complete = 0;
    for (uint32_t j = 0; j < b.slot_count(); ++j) {
        const uint64_t begin = uint64_t(b.first_batch + j) * b.batch_size, end = begin + b.batch_size;
        complete += begin >= b.first_sample && end <= b.end_sample;
    }
    return complete;
}

std::vector<float> pixel_variance(const ErrorBatches& b) {
    std::vector<float> variance(b.pixel_count(), std::numeric_limits<float>::quiet_NaN());
    uint32_t complete[MAX_ERROR_BATCHES], k = 0;
    for (uint32_t j = 0; j < b.slot_count(); ++j) {
        const uint64_t begin = uint64_t(b.first_batch + j) * b.batch_size, end = begin + b.batch_size;
        if (begin >= b.first_sample && end <= b.end_sample) complete[k++] = j;
    }
    if (k < 2) return variance;
    const double samples = double(b.end_sample - b.first_sample), n = double(b.batch_size);
    for (size_t p = 0; p < variance.size(); ++p) {
        double means[MAX_ERROR_BATCHES], mean = 0;
        for (uint32_t i = 0; i < k; ++i) mean += means[i] = to_real(b.sums[p * MAX_ERROR_BATCHES + complete[i]]) / n;
        mean /= k;
        double squares = 0;
        for (uint32_t i = 0; i < k; ++i) squares += (means[i] - mean) * (means[i] - mean);
        // Variance of a batch mean, then of the mean of all the pixel's samples (n / samples batches' worth).
        variance[p] = float(squares / (k - 1) * n / samples);
    }
    return variance;
}

float pixel_luminance(const Image& image, size_t i) {
    return 0.2126f * image.rgb[3 * i] + 0.7152f * image.rgb[3 * i + 1] + 0.0722f * image.rgb[3 * i + 2];
}

double relative_error(const Image& image, const std::vector<float>& variance) {
    if (variance.empty()) return std::numeric_limits<double>::quiet_NaN();
    double sum = 0;
    for (size_t i = 0; i < variance.size(); ++i) {
        const double y = pixel_luminance(image, i);
        sum += double(variance[i]) / (y * y + 0.01);
    }
    return std::sqrt(sum / double(variance.size()));
}

}  // namespace fh
