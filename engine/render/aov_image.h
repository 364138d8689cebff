// The AOV layers of an EXR (`--aov`) from the AOVs' exact sums per pixel (layout.h AovPixel, lib/core/aov.glsl).
#pragma once
#include <cstdint>
#include <vector>

#include "io/exr.h"
#include "shared/layout.h"

namespace fh {

struct AovChoice {
    bool albedo = false, normal = false, depth = false;  // recorded by the stages (RenderSettings::aovs)
    bool spp = false;                                     // from the film's sample counts
    bool any_recorded() const { return albedo || normal || depth; }
};

// Parses "albedo,normal,depth,variance,spp" (any of them, in any order; variance is always written and is accepted
// for completeness). Throws std::invalid_argument naming an unknown one.
AovChoice parse_aovs(const std::string& list);

// The layers: albedo.R/G/B and normal.X/Y/Z, means over each pixel's `samples` samples (a path that escaped first adds
// zero); depth.Z, the mean distance over the samples whose camera ray hit a surface (0 where none did); spp.N, the
// film's samples per pixel.
FloatChannels aov_layers(const AovChoice& choice, const std::vector<gpu::AovPixel>& sums,
                         const std::vector<gpu::FilmPixel>& film);

}  // namespace fh
