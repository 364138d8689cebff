// Means of the AOVs' fixed-point sums; see aov_image.h.
#include "render/aov_image.h"

#include <sstream>
#include <stdexcept>
#include <string>

#include "render/film.h"

namespace fh {

AovChoice parse_aovs(const std::string& list) {
    AovChoice c;
    std::stringstream in(list);
    std::string name;
    while (std::getline(in, name, ',')) {
        if (name == "albedo") c.albedo = true;
        else if (name == "normal") c.normal = true;
        else if (name == "depth") c.depth = true;
        else if (name == "spp") c.spp = true;
        else if (name != "variance")
            throw std::invalid_argument("'" + name + "' is not an AOV (albedo, normal, depth, variance, spp)");
    }
    return c;
}

FloatChannels aov_layers(const AovChoice& choice, const std::vector<gpu::AovPixel>& sums,
                         const std::vector<gpu::FilmPixel>& film) {
    FloatChannels layers;
    const size_t pixels = film.size();
    auto layer = [&](const char* name, auto value) {
        std::vector<float>& out = layers[name];
        out.resize(pixels);
        for (size_t p = 0; p < pixels; ++p) out[p] = float(value(p));
    };
    auto mean = [](const uint32_t (&words)[gpu::FILM_WORDS], uint32_t count) {
        return count > 0 ? read_fixed_sum(words) / double(count) : 0.0;
    };
    if (choice.albedo) {
        layer("albedo.R", [&](size_t p) { return mean(sums[p].albedo_r, film[p].sample_count); });
        layer("albedo.G", [&](size_t p) { return mean(sums[p].albedo_g, film[p].sample_count); });
        layer("albedo.B", [&](size_t p) { return mean(sums[p].albedo_b, film[p].sample_count); });
    }
    if (choice.normal) {
        layer("normal.X", [&](size_t p) { return mean(sums[p].normal_x, film[p].sample_count); });
        layer("normal.Y", [&](size_t p) { return mean(sums[p].normal_y, film[p].sample_count); });
        layer("normal.Z", [&](size_t p) { return mean(sums[p].normal_z, film[p].sample_count); });
    }
    if (choice.depth) layer("depth.Z", [&](size_t p) { return mean(sums[p].depth, sums[p].hit_count); });
    if (choice.spp) layer("spp.N", [&](size_t p) { return double(film[p].sample_count); });
    return layers;
}

}  // namespace fh
