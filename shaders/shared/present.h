// Bindings and push constants of the present stage (film -> display pixels), shared by GLSL and C++.
// Same layout rules as shared/layout.h: 32-bit scalars only.
#ifndef FREDHOLM_SHARED_PRESENT_H
#define FREDHOLM_SHARED_PRESENT_H

#ifdef __cplusplus
#include <cstdint>
namespace fh::gpu {
using uint = std::uint32_t;
#define FH_CONST inline constexpr
#else
#define FH_CONST const
#endif

FH_CONST uint PRESENT_BINDING_FILM = 0u;    // FilmPixel[width * height] (read only)
FH_CONST uint PRESENT_BINDING_PIXELS = 1u;  // uint[width * height]: packed 8-bit texels, row-major, top row first
FH_CONST uint PRESENT_BINDING_COUNT = 2u;
FH_CONST uint PRESENT_WORKGROUP_SIZE = 64u;

FH_CONST uint PRESENT_TONE_CLAMP = 0u;
FH_CONST uint PRESENT_TONE_ACES = 1u;
FH_CONST uint PRESENT_BGRA = 1u;          // flags: byte order B, G, R, A (else R, G, B, A)
FH_CONST uint PRESENT_ENCODE_SRGB = 2u;   // flags: apply the sRGB OETF (off when the image format does it)

struct PresentPush {
    uint width;
    uint height;
    float exposure_scale;  // 2^EV
    uint tone_curve;       // PRESENT_TONE_*
    uint flags;            // PRESENT_BGRA | PRESENT_ENCODE_SRGB
};

#ifdef __cplusplus
}  // namespace fh::gpu
#endif
#undef FH_CONST
#endif
