// Shape validation shared by every image writer.
#include "io/image.h"

namespace fh {

void check_image_shape(const Image& image, const std::string& path) {
    if (image.width <= 0 || image.height <= 0)
        throw IoError(path + ": image has no pixels (" + std::to_string(image.width) + " x " +
                      std::to_string(image.height) + ")");
    const std::size_t expected = std::size_t(3) * std::size_t(image.width) * std::size_t(image.height);
    if (image.rgb.size() != expected)
        throw IoError(path + ": image is " + std::to_string(image.width) + " x " + std::to_string(image.height) +
                      " so needs " + std::to_string(expected) + " floats, but holds " +
                      std::to_string(image.rgb.size()));
}

}  // namespace fh
