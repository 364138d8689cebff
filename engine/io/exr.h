// Reading and writing OpenEXR images: the renderer's lossless float output and the references' format.
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "io/image.h"

namespace fh {

// Further FLOAT channels by full EXR channel name (e.g. "fredholm.sum.R"), one value per pixel in the image's
// order (row-major, top row first). The renderer stores its raw film in them so a render can be resumed.
using ExtraChannels = std::map<std::string, std::vector<float>>;

// Writes channels R, G, B (and each extra channel) as FLOAT (32 bit) with lossless ZIP compression, and each
// metadata entry as a string attribute. Goes through write_file_atomically. Throws IoError (e.g. for a key that
// clashes with a standard EXR attribute such as "channels", or an extra channel of the wrong length).
void write_exr(const std::filesystem::path& path, const Image& image, const ImageMetadata& metadata = {},
               const ExtraChannels& extra = {});

// Reads channels R, G and B of any pixel type (HALF, FLOAT, UINT) as float; other channels are ignored.
// A missing R, G or B channel is an IoError. If `metadata` is given it receives every string attribute.
Image read_exr(const std::filesystem::path& path, ImageMetadata* metadata = nullptr);

// Reads the named channels (any pixel type, as float), width * height values each. A missing channel is an
// IoError naming it.
ExtraChannels read_exr_channels(const std::filesystem::path& path, const std::vector<std::string>& names);

}  // namespace fh
