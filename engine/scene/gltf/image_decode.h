// Decoding of the image files glTF textures point to: PNG and JPEG (8 or 16 bit) and WebP (EXT_texture_webp);
// and of Radiance .hdr environment maps.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace fh {

// An image as the GPU stores it: RGBA8 texels, one uint each (r in the low byte), rows top to bottom.
struct DecodedImage {
    uint32_t width = 0, height = 0;
    std::vector<uint32_t> texels;
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

// Decodes a Radiance RGBE (.hdr) image into linear RGB floats (rows top to bottom).
bool decode_radiance_hdr(const unsigned char* bytes, size_t size, uint32_t& width, uint32_t& height,
                         std::vector<float>& rgb, std::string& error);

}  // namespace fh
