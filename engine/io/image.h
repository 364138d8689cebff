// The in-memory image every file format reads and writes: linear RGB float, plus string metadata and the I/O error.
#pragma once

#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace fh {

// Scene-linear RGB, 3 floats per pixel, row-major, top row first.
struct Image {
    int width = 0, height = 0;
    std::vector<float> rgb;
};

// Free-form key/value pairs stored as string attributes in EXR headers (e.g. "fredholm:spp" -> "1024").
using ImageMetadata = std::map<std::string, std::string>;

// Every problem reading or writing a file; the message reads "FILE: problem".
struct IoError : std::runtime_error {
    using runtime_error::runtime_error;
};

// Throws IoError naming `path` unless the image has positive size and exactly 3 * width * height floats.
void check_image_shape(const Image& image, const std::string& path);

}  // namespace fh
