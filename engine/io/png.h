// Writing 8-bit sRGB PNG previews of linear renders (the EXR is the real output; the PNG is for eyes).
#pragma once

#include <filesystem>

#include "io/image.h"
#include "io/tone_curve.h"

namespace fh {

// Each channel: linear * 2^exposure_ev -> tone curve -> sRGB OETF -> 8 bit (NaN -> 0). Goes through
// write_file_atomically. Throws IoError.
void write_png(const std::filesystem::path& path, const Image& image, float exposure_ev = 0,
               ToneCurve curve = ToneCurve::aces);

}  // namespace fh
