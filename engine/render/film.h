// The film's fixed-point sums on the host (layout.h FilmPixel, shaders/lib/film.glsl): adding films together and
// turning sums into the mean radiance image. Every step is integer arithmetic until the final division, so a film
// merged from parts equals the film of one uninterrupted render bit for bit.
#pragma once
#include <cstdint>
#include <vector>

#include "io/image.h"
#include "shared/layout.h"

namespace fh {

// A channel's sum as a real number (radiance units): exact to double rounding; NaN for the pixel a non-finite sample
// reached with the finite guard off.
double read_fixed_sum(const uint32_t (&words)[gpu::FILM_WORDS]);

// into += part: sums and sample counts (128-bit two's complement, wrapping like the device's).
void add_film_pixel(gpu::FilmPixel& into, const gpu::FilmPixel& part);

// into += part for the AOVs' sums (layout.h AovPixel), the same way.
void add_aov_pixel(gpu::AovPixel& into, const gpu::AovPixel& part);

// Mean radiance per pixel (sum / sample count; 0 where no sample landed), width x height pixels.
Image resolve_film(const std::vector<gpu::FilmPixel>& film, int width, int height);

}  // namespace fh
