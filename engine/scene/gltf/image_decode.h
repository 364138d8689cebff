// Decoding of the image files glTF textures point to: PNG and JPEG (8 or 16 bit) and WebP (EXT_texture_webp);
// and of Radiance .hdr environment maps.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace fh {

// A decoded image: RGBA8, four bytes a texel (r first: as a little-endian uint, r in the low byte, as the GPU stores
// it), rows top to bottom.
struct DecodedImage {
    uint32_t width = 0, height = 0;
    std::vector<unsigned char> rgba;
};

// Images larger than this per side are refused (a texture of 16384^2 already takes 1 GiB as RGBA8).
constexpr uint32_t MAX_IMAGE_SIDE = 16384;

enum class ImageFormat { png, jpeg, webp, ktx2, unknown };

// The format by its magic bytes (the file's own word; a mimeType or extension may lie).
ImageFormat detect_image_format(const unsigned char* bytes, size_t size);
const char* to_string(ImageFormat format);

// Decodes PNG, JPEG or WebP; 16-bit PNG channels are rounded to 8 bits, grey and grey-alpha are expanded, a
// missing alpha is 255. Returns false with `error` set for corrupt, truncated, oversized or unsupported data
// (KTX2/Basis Universal has no decoder here).
bool decode_image(const unsigned char* bytes, size_t size, DecodedImage& out, std::string& error);

// The size a PNG, JPEG or WebP declares, read from its header without decoding; false with `error` set where the
// header is unreadable or the size breaks MAX_IMAGE_SIDE (the error then gives the size and the bytes it would take).
bool read_image_size(const unsigned char* bytes, size_t size, uint32_t& width, uint32_t& height, std::string& error);

// The size a Radiance .hdr header declares (its resolution line); false where there is no readable header.
bool read_radiance_hdr_size(const unsigned char* bytes, size_t size, int64_t& width, int64_t& height);

// Decodes a Radiance RGBE (.hdr) image into linear RGB floats (rows top to bottom).
// A declared side above MAX_IMAGE_SIDE is refused before decoding, with the size and the bytes it would take.
bool decode_radiance_hdr(const unsigned char* bytes, size_t size, uint32_t& width, uint32_t& height,
                         std::vector<float>& rgb, std::string& error);

}  // namespace fh
