// Sampling distribution of the environment map: piecewise constant over texels, weight luminance x sin(theta)
// (pbrt-v4 ImageInfiniteLight with PiecewiseConstant2D), CDFs accumulated in double and normalised.
#include "scene/light/environment.h"

#include <cmath>
#include <stdexcept>

#include <glm/gtc/constants.hpp>

namespace fh {
namespace {

double luminance(double r, double g, double b) { return 0.2126 * r + 0.7152 * g + 0.0722 * b; }

// Appends the normalised CDF of `weights` (n + 1 values from 0 to 1); uniform when they sum to 0.
double append_cdf(const std::vector<double>& weights, std::vector<float>& cdf) {
    double total = 0.0;
    for (double w : weights) total += w;
    double running = 0.0;
    const size_t n = weights.size();
    cdf.push_back(0.0f);
    for (size_t i = 0; i < n; ++i) {
        running += weights[i];
        cdf.push_back(i + 1 == n ? 1.0f : float(total > 0.0 ? running / total : double(i + 1) / double(n)));
    }
    return total;
}

}  // namespace

EnvironmentMap make_environment_map(uint32_t width, uint32_t height, const std::vector<float>& rgb, float intensity,
                                    float rotation_radians, const std::string& source) {
    if (width == 0 || height == 0 || rgb.size() != size_t(width) * height * 3)
        throw std::invalid_argument(source + ": empty environment image");
    if (width > MAX_ENVIRONMENT_WIDTH || height > MAX_ENVIRONMENT_WIDTH / 2)
        throw std::invalid_argument(source + ": environment of " + std::to_string(width) + " x " +
                                    std::to_string(height) + " texels is larger than " +
                                    std::to_string(MAX_ENVIRONMENT_WIDTH) + " x " +
                                    std::to_string(MAX_ENVIRONMENT_WIDTH / 2));
    if (!(intensity >= 0.0f) || !std::isfinite(intensity))
        throw std::invalid_argument(source + ": the environment intensity must be finite and >= 0");
    EnvironmentMap env;
    env.width = width;
    env.height = height;
    env.rotation = rotation_radians;
    env.source = source;
    env.texels.resize(size_t(width) * height);
    std::vector<double> weights(size_t(width) * height), row_weights(height);
    const double pi = glm::pi<double>();
    for (uint32_t y = 0; y < height; ++y) {
        const double sin_theta = std::sin(pi * (y + 0.5) / height);
        for (uint32_t x = 0; x < width; ++x) {
            const size_t i = size_t(y) * width + x;
            glm::vec3 c(rgb[3 * i], rgb[3 * i + 1], rgb[3 * i + 2]);
            if (!std::isfinite(c.r + c.g + c.b))
                throw std::invalid_argument(source + ": texel (" + std::to_string(x) + ", " + std::to_string(y) +
                                            ") is not finite");
            // Lossy EXR compression (DWAB) leaves small negative values near black: radiance cannot be negative.
            if (c.r < 0.0f || c.g < 0.0f || c.b < 0.0f) ++env.clamped_texels;
            c = glm::max(c, glm::vec3(0.0f));
            c *= intensity;
            env.texels[i] = glm::vec4(c, 0.0f);
            weights[i] = luminance(c.r, c.g, c.b) * sin_theta;
            row_weights[y] += weights[i];
            // Solid angle of the texel: (2 pi / width) (pi / height) sin(theta).
            env.luminance_integral += luminance(c.r, c.g, c.b) * sin_theta * 2.0 * pi * pi / (double(width) * height);
        }
    }
    const double total = append_cdf(row_weights, env.cdf);
    for (uint32_t y = 0; y < height; ++y)
        append_cdf(std::vector<double>(weights.begin() + ptrdiff_t(size_t(y) * width),
                                       weights.begin() + ptrdiff_t(size_t(y + 1) * width)),
                   env.cdf);
    // Density over [0, 1)^2: weight / total x texel count (0 everywhere for a black map: never sampled).
    const double scale = total > 0.0 ? double(width) * height / total : 0.0;
    for (size_t i = 0; i < env.texels.size(); ++i) env.texels[i].a = float(weights[i] * scale);
    return env;
}

EnvironmentMap make_constant_environment(glm::vec3 rgb) {
    const uint32_t w = 64, h = 32;
    std::vector<float> texels;
    texels.reserve(size_t(w) * h * 3);
    for (uint32_t i = 0; i < w * h; ++i) texels.insert(texels.end(), {rgb.r, rgb.g, rgb.b});
    char name[96];
    std::snprintf(name, sizeof name, "background %g,%g,%g", rgb.r, rgb.g, rgb.b);
    return make_environment_map(w, h, texels, 1.0f, 0.0f, name);
}

}  // namespace fh
