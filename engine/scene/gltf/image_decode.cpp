// Image decoding with stb_image (PNG, JPEG; compiled here with static linkage, so it cannot clash with the copy
// inside libtinygltf) and libwebp.
#include "scene/gltf/image_decode.h"

#include <cstdio>
#include <cstring>

#include <webp/decode.h>

#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#define STBI_ONLY_PNG
#define STBI_ONLY_JPEG
#define STBI_ONLY_HDR
#define STBI_NO_STDIO
#define STBI_MAX_DIMENSIONS 16384
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wunused-but-set-variable"
#endif
#include <stb_image.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

namespace fh {
namespace {

bool starts_with(const unsigned char* bytes, size_t size, const char* magic, size_t n, size_t at = 0) {
    return size >= at + n && std::memcmp(bytes + at, magic, n) == 0;
}

bool check_size(int width, int height, std::string& error) {
    if (width <= 0 || height <= 0 || uint32_t(width) > MAX_IMAGE_SIDE || uint32_t(height) > MAX_IMAGE_SIDE) {
        error = "image of " + std::to_string(width) + " x " + std::to_string(height) + " texels (at most " +
                std::to_string(MAX_IMAGE_SIDE) + " per side)";
        return false;
    }
    return true;
}

uint32_t pack_rgba8(uint32_t r, uint32_t g, uint32_t b, uint32_t a) { return r | g << 8 | b << 16 | a << 24; }

uint32_t load_be16(const unsigned char* p) { return uint32_t(p[0]) << 8 | p[1]; }
uint32_t load_be32(const unsigned char* p) { return load_be16(p) << 16 | load_be16(p + 2); }

// The size a PNG (IHDR) or JPEG (its first SOF marker) declares, read before stb_image sees the file: stb refuses a
// side above STBI_MAX_DIMENSIONS while it looks for the format, and then reports "unknown image type". False where
// the header does not say (stb then reports what is wrong).
bool read_declared_size(const unsigned char* bytes, size_t size, int64_t& width, int64_t& height) {
    if (starts_with(bytes, size, "\x89PNG\r\n\x1a\n", 8) && starts_with(bytes, size, "IHDR", 4, 12) && size >= 24) {
        width = load_be32(bytes + 16);
        height = load_be32(bytes + 20);
        return true;
    }
    if (!starts_with(bytes, size, "\xff\xd8", 2)) return false;
    for (size_t at = 2; at + 9 <= size;) {
        if (bytes[at] != 0xff) return false;
        const unsigned marker = bytes[at + 1];
        if (marker == 0xff) {  // fill byte
            ++at;
            continue;
        }
        const bool frame = marker >= 0xc0 && marker <= 0xcf && marker != 0xc4 && marker != 0xc8 && marker != 0xcc;
        if (frame) {
            height = load_be16(bytes + at + 5);
            width = load_be16(bytes + at + 7);
            return true;
        }
        if (marker == 0xd9 || marker == 0xda) return false;  // end of image, or scan data before any frame header
        at += 2 + load_be16(bytes + at + 2);
    }
    return false;
}

bool decode_with_stb(const unsigned char* bytes, size_t size, DecodedImage& out, std::string& error) {
    if (size > size_t(1) << 31) {
        error = "image file larger than 2 GiB";
        return false;
    }
    int64_t declared_width = 0, declared_height = 0;
    if (read_declared_size(bytes, size, declared_width, declared_height) &&
        (declared_width > int64_t(MAX_IMAGE_SIDE) || declared_height > int64_t(MAX_IMAGE_SIDE))) {
        char gib[32];
        std::snprintf(gib, sizeof gib, "%.1f", double(declared_width) * double(declared_height) * 4.0 / double(1u << 30));
        error = "image of " + std::to_string(declared_width) + " x " + std::to_string(declared_height) +
                " texels declared (" + gib + " GiB as RGBA8), more than the limit of " + std::to_string(MAX_IMAGE_SIDE) +
                " per side";
        return false;
    }
    int width = 0, height = 0, channels = 0;
    if (!stbi_info_from_memory(bytes, int(size), &width, &height, &channels)) {
        error = std::string("corrupt or truncated image (") + stbi_failure_reason() + ")";
        return false;
    }
    if (!check_size(width, height, error)) return false;
    const size_t n = size_t(width) * size_t(height);
    out.width = uint32_t(width);
    out.height = uint32_t(height);
    out.texels.resize(n);
    if (stbi_is_16_bit_from_memory(bytes, int(size))) {
        stbi_us* data = stbi_load_16_from_memory(bytes, int(size), &width, &height, &channels, 4);
        if (data == nullptr) {
            error = std::string("corrupt or truncated image (") + stbi_failure_reason() + ")";
            return false;
        }
        auto to8 = [](stbi_us v) { return uint32_t((uint32_t(v) * 255u + 32767u) / 65535u); };
        for (size_t i = 0; i < n; ++i)
            out.texels[i] = pack_rgba8(to8(data[4 * i]), to8(data[4 * i + 1]), to8(data[4 * i + 2]), to8(data[4 * i + 3]));
        stbi_image_free(data);
        return true;
    }
    stbi_uc* data = stbi_load_from_memory(bytes, int(size), &width, &height, &channels, 4);
    if (data == nullptr) {
        error = std::string("corrupt or truncated image (") + stbi_failure_reason() + ")";
        return false;
    }
    std::memcpy(out.texels.data(), data, n * 4);  // RGBA bytes = little-endian r | g << 8 | ...
    stbi_image_free(data);
    return true;
}

bool decode_webp(const unsigned char* bytes, size_t size, DecodedImage& out, std::string& error) {
    int width = 0, height = 0;
    if (!WebPGetInfo(bytes, size, &width, &height)) {
        error = "corrupt or truncated WebP image";
        return false;
    }
    if (!check_size(width, height, error)) return false;
    out.width = uint32_t(width);
    out.height = uint32_t(height);
    out.texels.resize(size_t(width) * size_t(height));
    if (!WebPDecodeRGBAInto(bytes, size, reinterpret_cast<uint8_t*>(out.texels.data()), out.texels.size() * 4,
                            width * 4)) {
        error = "corrupt or truncated WebP image";
        return false;
    }
    return true;
}

}  // namespace

bool decode_radiance_hdr(const unsigned char* bytes, size_t size, uint32_t& width, uint32_t& height,
                         std::vector<float>& rgb, std::string& error) {
    if (size > size_t(1) << 31 || !stbi_is_hdr_from_memory(bytes, int(size))) {
        error = "not a Radiance HDR image";
        return false;
    }
    int w = 0, h = 0, channels = 0;
    float* data = stbi_loadf_from_memory(bytes, int(size), &w, &h, &channels, 3);
    if (data == nullptr) {
        error = std::string("corrupt or truncated Radiance HDR image (") + stbi_failure_reason() + ")";
        return false;
    }
    width = uint32_t(w);
    height = uint32_t(h);
    rgb.assign(data, data + size_t(w) * size_t(h) * 3);
    stbi_image_free(data);
    return true;
}

ImageFormat detect_image_format(const unsigned char* bytes, size_t size) {
    if (starts_with(bytes, size, "\x89PNG\r\n\x1a\n", 8)) return ImageFormat::png;
    if (starts_with(bytes, size, "\xff\xd8\xff", 3)) return ImageFormat::jpeg;
    if (starts_with(bytes, size, "RIFF", 4) && starts_with(bytes, size, "WEBP", 4, 8)) return ImageFormat::webp;
    if (starts_with(bytes, size, "\xabKTX 20\xbb\r\n\x1a\n", 12)) return ImageFormat::ktx2;
    return ImageFormat::unknown;
}

const char* to_string(ImageFormat format) {
    switch (format) {
        case ImageFormat::png: return "PNG";
        case ImageFormat::jpeg: return "JPEG";
        case ImageFormat::webp: return "WebP";
        case ImageFormat::ktx2: return "KTX2";
        default: return "unknown";
    }
}

bool decode_image(const unsigned char* bytes, size_t size, DecodedImage& out, std::string& error) {
    switch (detect_image_format(bytes, size)) {
        case ImageFormat::png:
        case ImageFormat::jpeg: return decode_with_stb(bytes, size, out, error);
        case ImageFormat::webp: return decode_webp(bytes, size, out, error);
        case ImageFormat::ktx2:
            error = "KTX2 (KHR_texture_basisu) images cannot be decoded: no Basis Universal decoder";
            return false;
        default:
            error = "not a PNG, JPEG or WebP image";
            return false;
    }
}

}  // namespace fh
