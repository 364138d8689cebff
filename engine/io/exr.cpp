// OpenEXR reading and writing through the Imf scanline API (OpenEXR 3.1).
#include "io/exr.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfStdIO.h>
#include <ImfStringAttribute.h>
#include <ImfVersion.h>

#include <cstdio>
#include <exception>
#include <stdexcept>
#include <string>

#include "io/atomic_write.h"

namespace fh {
namespace fs = std::filesystem;

namespace {

constexpr const char* CHANNEL_NAMES[3] = {"R", "G", "B"};

// Attribute names OpenEXR sets itself when it writes a file; a user string under one of them corrupts the file.
constexpr const char* RESERVED_NAMES[] = {"type", "name", "version", "chunkCount", "tiles", "view", "multiView"};

// One FLOAT slice per channel over the interleaved rgb array, placed at the data window (which need not
// start at 0,0). Reading converts HALF and UINT channels to float.
Imf::FrameBuffer make_frame_buffer(const float* rgb, const Imath::Box2i& window) {
    Imf::FrameBuffer frame;
    const std::size_t x_stride = 3 * sizeof(float);
    const std::size_t y_stride = x_stride * std::size_t(window.max.x - window.min.x + 1);
    for (int c = 0; c < 3; ++c)
        frame.insert(CHANNEL_NAMES[c],
                     Imf::Slice::Make(Imf::FLOAT, rgb + c, window, x_stride, y_stride));
    return frame;
}

// One UINT slice over a plain array of one value per pixel.
Imf::Slice make_single_slice(const uint32_t* values, const Imath::Box2i& window) {
    return Imf::Slice::Make(Imf::UINT, values, window, sizeof(uint32_t),
                            sizeof(uint32_t) * std::size_t(window.max.x - window.min.x + 1));
}
Imf::Slice make_single_slice(const float* values, const Imath::Box2i& window) {
    return Imf::Slice::Make(Imf::FLOAT, values, window, sizeof(float),
                            sizeof(float) * std::size_t(window.max.x - window.min.x + 1));
}

// Refuses an image larger than MAX_EXR_SIDE per side from its header, before OpenEXR or this file allocates for it
// (OpenEXR sizes its line offsets by the declared height when the file is opened); OpenEXR's own limit is set to
// the same as a second guard.
void check_exr_size(const fs::path& path) {
    Imf::Header::setMaxImageSize(MAX_EXR_SIDE, MAX_EXR_SIDE);
    const ImageSize size = read_exr_size(path);
    if (size.width > 0 && size.height > 0 && size.width <= MAX_EXR_SIDE && size.height <= MAX_EXR_SIDE) return;
    char gib[32];
    std::snprintf(gib, sizeof gib, "%.1f", double(size.width) * double(size.height) * 12.0 / double(1u << 30));
    throw IoError(path.string() + ": EXR image of " + std::to_string(size.width) + " x " + std::to_string(size.height) +
                  " pixels declared (" + gib + " GiB as float RGB), more than the limit of " +
                  std::to_string(MAX_EXR_SIDE) + " per side");
}

template <typename Channels>
void check_channel_shapes(const fs::path& path, const Image& image, const Channels& channels) {
    for (const auto& [name, values] : channels) {
        bool clashes = false;
        for (const char* rgb : CHANNEL_NAMES) clashes = clashes || name == rgb;
        if (clashes || name.empty())
            throw IoError(path.string() + ": extra channel name \"" + name + "\" is empty or clashes with R, G, B");
        if (values.size() != std::size_t(image.width) * std::size_t(image.height))
            throw IoError(path.string() + ": extra channel " + name + " has " + std::to_string(values.size()) +
                          " values for " + std::to_string(image.width) + " x " + std::to_string(image.height) +
                          " pixels");
    }
}

template <typename Channels, typename Value>
Channels read_channels(const fs::path& path, const std::vector<std::string>& names, bool need_uint) {
    try {
        check_exr_size(path);
        Imf::InputFile in(path.c_str());
        const Imath::Box2i window = in.header().dataWindow();
        const std::size_t pixels =
            std::size_t(window.max.x - window.min.x + 1) * std::size_t(window.max.y - window.min.y + 1);
        Channels channels;
        Imf::FrameBuffer frame;
        for (const std::string& name : names) {
            const Imf::Channel* channel = in.header().channels().findChannel(name);
            if (!channel) throw IoError(path.string() + ": missing channel " + name);
            if (need_uint && channel->type != Imf::UINT) throw IoError(path.string() + ": channel " + name + " is not UINT");
            std::vector<Value>& values = channels[name];
            values.assign(pixels, Value(0));
            frame.insert(name, make_single_slice(values.data(), window));
        }
        in.setFrameBuffer(frame);
        in.readPixels(window.min.y, window.max.y);
        return channels;
    } catch (const IoError&) {
        throw;
    } catch (const std::exception& e) {
        throw IoError(path.string() + ": cannot read EXR: " + e.what());
    }
}

void write_exr_file(const fs::path& file, const Image& image, const ImageMetadata& metadata,
                    const ExtraChannels& extra, const ImageWindow& window, const FloatChannels& floats) {
    Imf::Header header(image.width, image.height);
    if (window.full_width > 0) {
        header.displayWindow() = Imath::Box2i({0, 0}, {window.full_width - 1, window.full_height - 1});
        header.dataWindow() = Imath::Box2i({window.x, window.y}, {window.x + image.width - 1, window.y + image.height - 1});
    }
    header.compression() = Imf::ZIP_COMPRESSION;
    for (const char* name : CHANNEL_NAMES) header.channels().insert(name, Imf::Channel(Imf::FLOAT));
    for (const auto& [name, values] : extra) header.channels().insert(name, Imf::Channel(Imf::UINT));
    for (const auto& [name, values] : floats) header.channels().insert(name, Imf::Channel(Imf::FLOAT));
    for (const auto& [key, value] : metadata) {
        bool reserved = header.find(key) != header.end();
        for (const char* name : RESERVED_NAMES) reserved = reserved || key == name;
        if (reserved) throw std::invalid_argument("metadata key \"" + key + "\" clashes with a standard EXR attribute");
        header.insert(key, Imf::StringAttribute(value));
    }
    Imf::OutputFile out(file.c_str(), header);
    Imf::FrameBuffer frame = make_frame_buffer(image.rgb.data(), header.dataWindow());
    for (const auto& [name, values] : extra) frame.insert(name, make_single_slice(values.data(), header.dataWindow()));
    for (const auto& [name, values] : floats) frame.insert(name, make_single_slice(values.data(), header.dataWindow()));
    out.setFrameBuffer(frame);
    out.writePixels(image.height);
}

}  // namespace

void write_exr(const fs::path& path, const Image& image, const ImageMetadata& metadata, const ExtraChannels& extra,
               const ImageWindow& window, const FloatChannels& floats) {
    check_image_shape(image, path.string());
    check_channel_shapes(path, image, extra);
    check_channel_shapes(path, image, floats);
    for (const auto& [name, values] : floats)
        if (extra.count(name)) throw IoError(path.string() + ": channel " + name + " given twice");
    try {
        write_file_atomically(path, [&](const fs::path& temp) { write_exr_file(temp, image, metadata, extra, window, floats); });
    } catch (const IoError&) {
        throw;
    } catch (const std::exception& e) {
        throw IoError(path.string() + ": cannot write EXR: " + e.what());
    }
}

ImageSize read_exr_size(const fs::path& path) {
    try {
        Imf::StdIFStream in(path.c_str());
        char magic_and_version[8] = {};
        in.read(magic_and_version, 8);
        if (!Imf::isImfMagic(magic_and_version)) throw IoError(path.string() + ": not an OpenEXR file");
        int version = 0;
        for (int i = 3; i >= 0; --i) version = version << 8 | static_cast<unsigned char>(magic_and_version[4 + i]);
        Imf::Header header;
        header.readFrom(in, version);
        const Imath::Box2i window = header.dataWindow();
        return {int64_t(window.max.x) - window.min.x + 1, int64_t(window.max.y) - window.min.y + 1};
    } catch (const IoError&) {
        throw;
    } catch (const std::exception& e) {
        throw IoError(path.string() + ": cannot read EXR: " + e.what());
    }
}

Image read_exr(const fs::path& path, ImageMetadata* metadata) {
    try {
        check_exr_size(path);
        Imf::InputFile in(path.c_str());
        const Imf::Header& header = in.header();
        for (const char* name : CHANNEL_NAMES) {
            if (header.channels().findChannel(name)) continue;
            std::string present;
            for (auto it = header.channels().begin(); it != header.channels().end(); ++it)
                present += std::string(present.empty() ? "" : ", ") + it.name();
            throw IoError(path.string() + ": missing channel " + name + " (channels present: " +
                          (present.empty() ? "none" : present) + ")");
        }
        const Imath::Box2i window = header.dataWindow();
        Image image;
        image.width = window.max.x - window.min.x + 1;
        image.height = window.max.y - window.min.y + 1;
        image.rgb.assign(std::size_t(3) * std::size_t(image.width) * std::size_t(image.height), 0.0f);
        in.setFrameBuffer(make_frame_buffer(image.rgb.data(), window));
        in.readPixels(window.min.y, window.max.y);
        if (metadata) {
            metadata->clear();
            for (auto it = header.begin(); it != header.end(); ++it)
                if (auto* text = dynamic_cast<const Imf::StringAttribute*>(&it.attribute()))
                    (*metadata)[it.name()] = text->value();
        }
        return image;
    } catch (const IoError&) {
        throw;
    } catch (const std::exception& e) {
        throw IoError(path.string() + ": cannot read EXR: " + e.what());
    }
}

ExtraChannels read_exr_channels(const fs::path& path, const std::vector<std::string>& names) {
    return read_channels<ExtraChannels, uint32_t>(path, names, true);
}

FloatChannels read_exr_float_channels(const fs::path& path, const std::vector<std::string>& names) {
    return read_channels<FloatChannels, float>(path, names, false);
}

bool exr_has_channel(const fs::path& path, const std::string& name) {
    try {
        Imf::InputFile in(path.c_str());
        return in.header().channels().findChannel(name) != nullptr;
    } catch (const std::exception&) {
        return false;
    }
}

}  // namespace fh
