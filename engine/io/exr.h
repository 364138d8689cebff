// Reading and writing OpenEXR images: the renderer's lossless float output and the references' format.
#pragma once

#include <filesystem>

#include "io/image.h"

namespace fh {

// Writes channels R, G, B as FLOAT (32 bit) with lossless ZIP compression, and each metadata entry as a string
// attribute. Goes through write_file_atomically. Throws IoError (e.g. for a key that clashes with a standard
// EXR attribute such as "channels").
void write_exr(const std::filesystem::path& path, const Image& image, const ImageMetadata& metadata = {});

// Reads channels R, G and B of any pixel type (HALF, FLOAT, UINT) as float; other channels are ignored.
// A missing R, G or B channel is an IoError. If `metadata` is given it receives every string attribute.
Image read_exr(const std::filesystem::path& path, ImageMetadata* metadata = nullptr);

}  // namespace fh
