// Image decoding with stb_image (PNG, JPEG; compiled here with static linkage, so it cannot clash with the copy
// inside libtinygltf) and libwebp.
#include "scene/gltf/image_decode.h"

#include <cstdio>
#include <algorithm>
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

// "image of W x H texels declared (G GiB as RGBA8), more than the limit of 16384 per side"
std::string too_large(int64_t width, int64_t height, const char* as, double bytes_per_texel) {
    char gib[32];
    std::snprintf(gib, sizeof gib, "%.1f", double(width) * double(height) * bytes_per_texel / double(1u << 30));
    return "image of " + std::to_string(width) + " x " + std::to_string(height) + " texels declared (" + gib +
           " GiB as " + as + "), more than the limit of " + std::to_string(MAX_IMAGE_SIDE) + " per side";
}

bool check_size(int64_t width, int64_t height, std::string& error) {
    if (width <= 0 || height <= 0) {
        error = "image of " + std::to_string(width) + " x " + std::to_string(height) + " texels";
        return false;
    }
    if (width > int64_t(MAX_IMAGE_SIDE) || height > int64_t(MAX_IMAGE_SIDE)) {
        error = too_large(width, height, "RGBA8", 4.0);
        return false;
    }
    return true;
}

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
        !check_size(declared_width, declared_height, error))
        return false;
    int width = 0, height = 0, channels = 0;
    if (!stbi_info_from_memory(bytes, int(size), &width, &height, &channels)) {
        error = std::string("corrupt or truncated image (") + stbi_failure_reason() + ")";
        return false;
    }
    if (!check_size(width, height, error)) return false;
    const size_t n = size_t(width) * size_t(height);
    out.width = uint32_t(width);
    out.height = uint32_t(height);
    // Allocated once stb's own buffer exists, so that at most two copies of the image are alive at once.
    if (stbi_is_16_bit_from_memory(bytes, int(size))) {
        stbi_us* data = stbi_load_16_from_memory(bytes, int(size), &width, &height, &channels, 4);
        if (data == nullptr) {
            error = std::string("corrupt or truncated image (") + stbi_failure_reason() + ")";
            return false;
        }
        auto to8 = [](stbi_us v) { return static_cast<unsigned char>((uint32_t(v) * 255u + 32767u) / 65535u); };
        out.rgba.resize(n * 4);
        for (size_t i = 0; i < n * 4; ++i) out.rgba[i] = to8(data[i]);
        stbi_image_free(data);
        return true;
    }
    stbi_uc* data = stbi_load_from_memory(bytes, int(size), &width, &height, &channels, 4);
    if (data == nullptr) {
        error = std::string("corrupt or truncated image (") + stbi_failure_reason() + ")";
        return false;
    }
    out.rgba.assign(data, data + n * 4);
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
    out.rgba.resize(size_t(width) * size_t(height) * 4);
    if (!WebPDecodeRGBAInto(bytes, size, out.rgba.data(), out.rgba.size(), width * 4)) {
        error = "corrupt or truncated WebP image";
        return false;
    }
    return true;
}

}  // namespace

bool read_image_size(const unsigned char* bytes, size_t size, uint32_t& width, uint32_t& height, std::string& error) {
    const ImageFormat format = detect_image_format(bytes, size);
    int64_t w = 0, h = 0;
    if (format == ImageFormat::webp) {
        int iw = 0, ih = 0;
        if (!WebPGetInfo(bytes, size, &iw, &ih)) {
            error = "corrupt or truncated WebP image";
            return false;
        }
        w = iw;
        h = ih;
    } else if (format == ImageFormat::png || format == ImageFormat::jpeg) {
        int iw = 0, ih = 0, channels = 0;
        if (!read_declared_size(bytes, size, w, h)) {
            if (size > size_t(1) << 31 || !stbi_info_from_memory(bytes, int(size), &iw, &ih, &channels)) {
                error = std::string("corrupt or truncated image (") + stbi_failure_reason() + ")";
                return false;
            }
            w = iw;
            h = ih;
        }
    } else {
        DecodedImage unused;
        return decode_image(bytes, size, unused, error);  // the format's own error (KTX2, unknown)
    }
    if (!check_size(w, h, error)) return false;
    width = uint32_t(w);
    height = uint32_t(h);
    return true;
}

bool read_radiance_hdr_size(const unsigned char* bytes, size_t size, int64_t& width, int64_t& height) {
    // "#?RADIANCE" (or "#?RGBE"), header lines, an empty line, then the resolution: "-Y H +X W" (stb reads only that
    // orientation; the others are sized the same way).
    const std::string text(reinterpret_cast<const char*>(bytes), std::min<size_t>(size, 64 * 1024));
    const size_t blank = text.find("\n\n");
    if (text.rfind("#?", 0) != 0 || blank == std::string::npos) return false;
    char y_axis[3] = {}, x_axis[3] = {};
    long long h = 0, w = 0;
    if (std::sscanf(text.c_str() + blank + 2, "%2s %lld %2s %lld", y_axis, &h, x_axis, &w) != 4) return false;
    height = h;
    width = w;
    return true;
}

bool decode_radiance_hdr(const unsigned char* bytes, size_t size, uint32_t& width, uint32_t& height,
                         std::vector<float>& rgb, std::string& error) {
    if (size > size_t(1) << 31 || !stbi_is_hdr_from_memory(bytes, int(size))) {
        error = "not a Radiance HDR image";
        return false;
    }
    int64_t declared_width = 0, declared_height = 0;
    if (read_radiance_hdr_size(bytes, size, declared_width, declared_height) &&
        (declared_width > int64_t(MAX_IMAGE_SIDE) || declared_height > int64_t(MAX_IMAGE_SIDE))) {
        error = too_large(declared_width, declared_height, "float RGB", 12.0);
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
