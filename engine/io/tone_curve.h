// Turning scene-linear values into display values: exposure, a tone curve, and the sRGB transfer function.
#pragma once

#include <cstdint>

namespace fh {

enum class ToneCurve {
    clamp,  // clip to [0, 1]: exact for values already in range, bright areas burn out to flat white
    aces,   // Narkowicz's fit of the ACES filmic curve (RRT+ODT), "ACES Filmic Tone Mapping Curve", blog post,
            // January 2016: x(2.51x + 0.03) / (x(2.43x + 0.59) + 0.14), clipped to [0, 1]; pre-exposed so
            // input 1 maps to about 0.8, highlights roll off smoothly instead of clipping
};

// Applies the curve to one linear channel value; NaN and negative values give 0, +infinity gives 1.
float apply_tone_curve(float linear, ToneCurve curve);

// sRGB opto-electronic transfer function (IEC 61966-2-1): 12.92 v below 0.0031308, else 1.055 v^(1/2.4) - 0.055.
// Input is clamped to [0, 1] first.
float encode_srgb(float linear);

// The whole display path for one channel: linear * 2^exposure_ev -> curve -> sRGB -> rounded 8-bit code.
std::uint8_t encode_display_8bit(float linear, float exposure_ev, ToneCurve curve);

}  // namespace fh
