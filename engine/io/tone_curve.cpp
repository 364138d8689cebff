// Exposure, tone curves and the sRGB OETF, one channel at a time.
#include "io/tone_curve.h"

#include <algorithm>
#include <cmath>

namespace fh {

float apply_tone_curve(float linear, ToneCurve curve) {
    if (!(linear > 0.0f)) return 0.0f;  // NaN, zero and negatives
    switch (curve) {
        case ToneCurve::clamp:
            return std::min(linear, 1.0f);
        case ToneCurve::aces: {
            // Narkowicz 2016; above ~1e4 the rational function is 2.51/2.43 > 1 anyway, and inf/inf is NaN.
            if (linear > 1e4f) return 1.0f;
            const float x = linear;
            return std::clamp(x * (2.51f * x + 0.03f) / (x * (2.43f * x + 0.59f) + 0.14f), 0.0f, 1.0f);
        }
    }
    return 0.0f;
}

float encode_srgb(float linear) {
    if (!(linear > 0.0f)) return 0.0f;  // NaN and negatives
    // In double, so that 1 encodes to exactly 1 (in float 1.055 - 0.055 is one ulp short).
    const double v = std::min(double(linear), 1.0);
    return float(v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1.0 / 2.4) - 0.055);
}

std::uint8_t encode_display_8bit(float linear, float exposure_ev, ToneCurve curve) {
    const float display = encode_srgb(apply_tone_curve(linear * std::exp2(exposure_ev), curve));
    return static_cast<std::uint8_t>(std::lround(std::clamp(display, 0.0f, 1.0f) * 255.0f));
}

}  // namespace fh
