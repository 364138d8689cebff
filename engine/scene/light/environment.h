// The environment light's data: an equirectangular radiance map (from --env, or a constant --background) with
// the sampling distribution shaders/lib/light/environment.glsl draws from.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace fh {

struct EnvironmentMap {
    uint32_t width = 0, height = 0;
    // rgb: radiance; a: the texel's sampling density over the map's [0, 1)^2 (luminance x sin(theta) x
    // width x height / total weight), so the shader gets both with one load.
    std::vector<glm::vec4> texels;
    std::vector<float> cdf;     // marginal CDF over rows (height + 1), then each row's CDF (width + 1 each)
    float rotation = 0.0f;      // radians about +Y
    double luminance_integral = 0.0;  // integral of luminance over the sphere (W / m^2 for irradiance units)
    std::string source;         // the file, or "background R,G,B"
    size_t clamped_texels = 0;  // texels with a negative channel, set to 0 (warned)

    bool empty() const { return texels.empty(); }
};

// Largest environment accepted (--env): 16384 x 8192 texels.
constexpr uint32_t MAX_ENVIRONMENT_WIDTH = 16384;

// Builds the map from linear RGB (3 floats per texel, rows top to bottom), scaled by `intensity`. Throws
// std::invalid_argument for an empty image, a non-finite texel or intensity; negative channels become 0.
EnvironmentMap make_environment_map(uint32_t width, uint32_t height, const std::vector<float>& rgb, float intensity,
                                    float rotation_radians, const std::string& source);

// A constant environment of radiance `rgb` (a 64 x 32 map, so that rows are still sampled by sin(theta)).
EnvironmentMap make_constant_environment(glm::vec3 rgb);

}  // namespace fh
