// PNG previews through stb_image_write (compiled here, with static linkage, so it clashes with no other copy).
#include "io/png.h"

#include <cstdint>
#include <string>
#include <vector>

#include "io/atomic_write.h"

#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#pragma GCC diagnostic ignored "-Wunused-function"
#endif
#include <stb_image_write.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

namespace fh {
namespace fs = std::filesystem;

void write_png(const fs::path& path, const Image& image, float exposure_ev, ToneCurve curve) {
    check_image_shape(image, path.string());
    std::vector<std::uint8_t> bytes(image.rgb.size());
    for (std::size_t i = 0; i < bytes.size(); ++i) bytes[i] = encode_display_8bit(image.rgb[i], exposure_ev, curve);
    write_file_atomically(path, [&](const fs::path& temp) {
        if (!stbi_write_png(temp.c_str(), image.width, image.height, 3, bytes.data(), 3 * image.width))
            throw IoError(path.string() + ": cannot write PNG");
    });
}

}  // namespace fh
