// The bound of a KHR_materials_iridescence film's Fresnel that the BSDF's albedo scaling needs (shaders/lib/bsdf/bsdf.glsl).
#pragma once
#include "shared/layout.h"

namespace fh {

// F_film(c) <= a (1 - w(c)) + b w(c), w(c) = (1 - c)^5, in every channel, for every cos theta c in (0, 1] and every
// thickness the material's film can take (its maximum, or the range between minimum and maximum where it has a
// thickness texture), over the material's dielectric base (f0 from ior, specularFactor and specularColorFactor, as
// make_bsdf_params). With the GGX albedo terms (A, B) the film's albedo is then at most a A + b B.
struct FilmFresnelBound {
    float a = 0.0f;
    float b = 0.0f;
};

// Of the (a, b) that bound the film, one with a small a A_avg + b B_avg (the diffuse lobe keeps the rest) for a
// mirror's averages (A_avg : B_avg = 20 : 1): b searched over [1, 4], each b's least a found on a grid of angles and
// thicknesses, both plus a small margin. (0, 0) for a material without a film.
FilmFresnelBound bound_thin_film_fresnel(const gpu::Material& material, const gpu::MaterialLayers& layers);

// F_film(c) - (a (1 - w) + b w) at its largest over the same angles and thicknesses, on a grid `refine` times finer
// than bound_thin_film_fresnel's (tests: the bound holds off its grid).
float measure_thin_film_excess(const gpu::Material& material, const gpu::MaterialLayers& layers, FilmFresnelBound bound,
                               int refine);

}  // namespace fh
