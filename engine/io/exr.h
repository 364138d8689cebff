// Reading and writing OpenEXR images: the renderer's lossless float output and the references' format.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "io/image.h"

namespace fh {

// Further UINT (32-bit integer) channels by full EXR channel name (e.g. "fredholm.sum.R.0"), one value per pixel
// in the image's order (row-major, top row first). The renderer stores its raw film in them so a render can be
// resumed or merged.
using ExtraChannels = std::map<std::string, std::vector<uint32_t>>;
// Further FLOAT channels by full EXR channel name (OpenEXR's layer convention, e.g. "variance.Y"), the same shape.
using FloatChannels = std::map<std::string, std::vector<float>>;

// Where the image lies in a larger one (EXR data window inside the display window): a crop of a render.
struct ImageWindow {
    int x = 0, y = 0;                        // the image's top-left pixel in the full image
    int full_width = 0, full_height = 0;     // 0: the image is the full image
};

// Writes channels R, G, B and each float channel as FLOAT (32 bit) and each extra channel as UINT, with lossless ZIP
// compression, and each metadata entry as a string attribute; `window` places a crop in its full image. Goes through
// write_file_atomically. Throws IoError (e.g. for a key that clashes with a standard EXR attribute such as
// "channels", or a channel of the wrong length or a name given twice).
void write_exr(const std::filesystem::path& path, const Image& image, const ImageMetadata& metadata = {},
               const ExtraChannels& extra = {}, const ImageWindow& window = {}, const FloatChannels& floats = {});

// The largest EXR read, per side (fredholm render's --width/--height limit; environment maps keep theirs).
constexpr int64_t MAX_EXR_SIDE = 16384;

struct ImageSize {
    int64_t width = 0, height = 0;
};
// The data window's size as the file's header declares it, read without opening the image. IoError for a file that
// is not OpenEXR or whose header does not parse.
ImageSize read_exr_size(const std::filesystem::path& path);

// The readers below refuse an image of more than MAX_EXR_SIDE pixels per side (IoError giving the declared size, the
// bytes it would take and the limit) before anything is allocated for it.

// Reads channels R, G and B of any pixel type (HALF, FLOAT, UINT) as float; other channels are ignored.
// A missing R, G or B channel is an IoError. If `metadata` is given it receives every string attribute.
Image read_exr(const std::filesystem::path& path, ImageMetadata* metadata = nullptr);

// Reads the named UINT channels, width * height values each (of the data window). A missing channel, or one of
// another type, is an IoError naming it.
ExtraChannels read_exr_channels(const std::filesystem::path& path, const std::vector<std::string>& names);

// Reads the named channels (any pixel type) as float, like read_exr_channels.
FloatChannels read_exr_float_channels(const std::filesystem::path& path, const std::vector<std::string>& names);

// Whether the file has a channel of this name (false for an unreadable file).
bool exr_has_channel(const std::filesystem::path& path, const std::string& name);

}  // namespace fh
