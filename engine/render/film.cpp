// Host side of the fixed-point film; see film.h.
#include "render/film.h"

#include <cmath>
#include <limits>

namespace fh {
namespace {

using Fixed = unsigned __int128;

Fixed load_fixed(const uint32_t (&w)[gpu::FILM_WORDS]) {
    return Fixed(w[0]) | Fixed(w[1]) << 32 | Fixed(w[2]) << 64 | Fixed(w[3]) << 96;
}

void store_fixed(uint32_t (&w)[gpu::FILM_WORDS], Fixed value) {
    for (uint32_t i = 0; i < gpu::FILM_WORDS; ++i) w[i] = uint32_t(value >> (32 * i));
}

constexpr Fixed FIXED_NAN = Fixed(gpu::FILM_NAN_TOP_WORD) << 96;  // layout.h

void add_fixed(uint32_t (&into)[gpu::FILM_WORDS], const uint32_t (&part)[gpu::FILM_WORDS]) {
    const Fixed a = load_fixed(into), b = load_fixed(part);
    store_fixed(into, a == FIXED_NAN || b == FIXED_NAN ? FIXED_NAN : a + b);
}

}  // namespace

double read_fixed_sum(const uint32_t (&words)[gpu::FILM_WORDS]) {
    static_assert(gpu::FILM_WORDS == 4, "a film sum is 128 bits");
    const Fixed value = load_fixed(words);
    if (value == FIXED_NAN) return std::numeric_limits<double>::quiet_NaN();
    const bool negative = (value >> 127) != 0;
    const Fixed magnitude = negative ? Fixed(0) - value : value;
    const double real = std::ldexp(double(magnitude), -gpu::FILM_FRACTION_BITS);  // one rounding, to double
    return negative ? -real : real;
}

void add_film_pixel(gpu::FilmPixel& into, const gpu::FilmPixel& part) {
    add_fixed(into.sum_r, part.sum_r);
    add_fixed(into.sum_g, part.sum_g);
    add_fixed(into.sum_b, part.sum_b);
    into.sample_count += part.sample_count;
}

void add_aov_pixel(gpu::AovPixel& into, const gpu::AovPixel& part) {
    add_fixed(into.albedo_r, part.albedo_r);
    add_fixed(into.albedo_g, part.albedo_g);
    add_fixed(into.albedo_b, part.albedo_b);
    add_fixed(into.normal_x, part.normal_x);
    add_fixed(into.normal_y, part.normal_y);
    add_fixed(into.normal_z, part.normal_z);
    add_fixed(into.depth, part.depth);
    into.hit_count += part.hit_count;
}

Image resolve_film(const std::vector<gpu::FilmPixel>& film, int width, int height) {
    Image image;
    image.width = width;
    image.height = height;
    image.rgb.resize(film.size() * 3);
    for (size_t i = 0; i < film.size(); ++i) {
        const double n = film[i].sample_count > 0 ? double(film[i].sample_count) : 1.0;
        image.rgb[3 * i + 0] = float(read_fixed_sum(film[i].sum_r) / n);
        image.rgb[3 * i + 1] = float(read_fixed_sum(film[i].sum_g) / n);
        image.rgb[3 * i + 2] = float(read_fixed_sum(film[i].sum_b) / n);
    }
    return image;
}

}  // namespace fh
