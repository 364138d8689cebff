// Saving and reloading the raw film: the fixed-point sums and sample counts, bit for bit, so that a render continued
// from sample n, or merged from parts, holds the same film as one uninterrupted render (integer sums are associative).
#include "app/cli/resume.h"

#include <cstdio>
#include <fstream>
#include <stdexcept>

#include "app/cli/setting_table.h"

namespace fh {
namespace {

const char* const CHANNEL_LETTERS[3] = {"R", "G", "B"};
const char* const COUNT_NAME = "fredholm.count";
constexpr unsigned MAX_IMAGE_SIDE = 16384;  // as fredholm render --width/--height

uint32_t (&channel_words(gpu::FilmPixel& p, int c))[gpu::FILM_WORDS] { return c == 0 ? p.sum_r : c == 1 ? p.sum_g : p.sum_b; }
const uint32_t (&channel_words(const gpu::FilmPixel& p, int c))[gpu::FILM_WORDS] {
    return c == 0 ? p.sum_r : c == 1 ? p.sum_g : p.sum_b;
}

std::string batch_word_name(uint32_t slot, uint32_t w) {
    return "fredholm.batch." + std::to_string(slot) + "." + std::to_string(w);
}

std::string format_number(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.6g", value);
    return text;
}

std::string word_name(int c, uint32_t w) { return std::string("fredholm.sum.") + CHANNEL_LETTERS[c] + "." + std::to_string(w); }

std::string setting_name(const std::string& key) {
    const std::string prefix = "fredholm:";
    return key.rfind(prefix, 0) == 0 ? key.substr(prefix.size()) : key;
}

// A plain decimal number below 2^32, or -1.
int64_t parse_count(const std::string& text) {
    if (text.empty() || text.size() > 10) return -1;
    int64_t value = 0;
    for (char c : text) {
        if (c < '0' || c > '9') return -1;
        value = value * 10 + (c - '0');
    }
    return value <= int64_t(UINT32_MAX) ? value : -1;
}

const std::string& find_key(const ImageMetadata& m, const std::string& key, const std::string& prefix) {
    const auto it = m.find(key);
    if (it == m.end()) throw std::runtime_error(prefix + "it has no " + key + " metadata (not written by fredholm?)");
    return it->second;
}

uint32_t read_count(const ImageMetadata& m, const std::string& key, const std::string& prefix) {
    const int64_t value = parse_count(find_key(m, key, prefix));
    if (value < 0) throw std::runtime_error(prefix + "no valid " + key + " metadata");
    return uint32_t(value);
}

}  // namespace

const std::vector<std::string>& film_channel_names() {
    static const std::vector<std::string> names = [] {
        std::vector<std::string> n;
        for (int c = 0; c < 3; ++c)
            for (uint32_t w = 0; w < gpu::FILM_WORDS; ++w) n.push_back(word_name(c, w));
        n.push_back(COUNT_NAME);
        return n;
    }();
    return names;
}

const std::vector<std::string>& matching_film_keys() {
    static const std::vector<std::string> keys = [] {
        std::vector<std::string> k = {"fredholm:renderer", "fredholm:scene", "fredholm:scene_hash", "fredholm:image_size"};
        for (const SettingInfo& e : setting_table())
            if (e.must_match) k.push_back(e.metadata_key);
        return k;
    }();
    return keys;
}

std::string describe_crop(uint32_t x0, uint32_t y0, uint32_t x1, uint32_t y1) {
    if (x1 <= x0) return "none";
    return std::to_string(x0) + "," + std::to_string(y0) + "," + std::to_string(x1) + "," + std::to_string(y1);
}

ExtraChannels film_channels(const std::vector<gpu::FilmPixel>& film) {
    ExtraChannels channels;
    for (int c = 0; c < 3; ++c)
        for (uint32_t w = 0; w < gpu::FILM_WORDS; ++w) {
            std::vector<uint32_t>& values = channels[word_name(c, w)];
            values.resize(film.size());
            for (size_t i = 0; i < film.size(); ++i) values[i] = channel_words(film[i], c)[w];
        }
    std::vector<uint32_t>& counts = channels[COUNT_NAME];
    counts.resize(film.size());
    for (size_t i = 0; i < film.size(); ++i) counts[i] = film[i].sample_count;
    return channels;
}

void add_error_channels(const ErrorBatches& batches, const Image& image, ExtraChannels& channels, FloatChannels& floats,
                        ImageMetadata& metadata) {
    for (uint32_t slot = 0; slot < batches.slot_count(); ++slot)
        for (uint32_t w = 0; w < 4; ++w) {
            std::vector<uint32_t>& values = channels[batch_word_name(slot, w)];
            values.resize(batches.pixel_count());
            for (size_t p = 0; p < values.size(); ++p)
                values[p] = uint32_t(batches.sums[p * MAX_ERROR_BATCHES + slot] >> (32 * w));
        }
    metadata["fredholm:batch_size"] = std::to_string(batches.batch_size);
    metadata["fredholm:first_batch"] = std::to_string(batches.first_batch);
    const uint32_t complete = complete_batch_count(batches);
    metadata["fredholm:error_batches"] = std::to_string(complete) + " complete of " +
                                         std::to_string(batches.batch_size) + " samples";
    if (complete < 2) return;
    std::vector<float> variance = pixel_variance(batches);
    const double error = relative_error(image, variance);
    add_variance_layer(std::move(variance), error, floats, metadata);
}

void add_variance_layer(std::vector<float> variance, double relative_error, FloatChannels& floats,
                        ImageMetadata& metadata) {
    metadata["fredholm:relative_error"] = format_number(relative_error);
    floats["variance.Y"] = std::move(variance);
}

// The error batches of a film file, if it has them (fredholm:batch_size), checked against its samples.
void read_error_batches(const std::filesystem::path& file, FilmFile& f, const std::string& prefix) {
    if (!f.metadata.count("fredholm:batch_size")) return;
    const uint32_t size = read_count(f.metadata, "fredholm:batch_size", prefix);
    const uint32_t first_batch = read_count(f.metadata, "fredholm:first_batch", prefix);
    ErrorBatches& b = f.batches;
    b = make_error_batches(f.film.size(), f.first_sample);
    b.batch_size = size;
    b.first_batch = first_batch;
    b.end_sample = f.end_sample;
    if (size == 0 || (size & (size - 1)) != 0 || uint64_t(first_batch) * size > f.first_sample ||
        (uint64_t(first_batch) + 1) * size <= f.first_sample || b.slot_count() > MAX_ERROR_BATCHES)
        throw std::runtime_error(prefix + "fredholm:batch_size " + std::to_string(size) + " and fredholm:first_batch " +
                                 std::to_string(first_batch) + " do not fit its samples " +
                                 std::to_string(f.first_sample) + ":" + std::to_string(f.end_sample));
    std::vector<std::string> names;
    for (uint32_t slot = 0; slot < b.slot_count(); ++slot)
        for (uint32_t w = 0; w < 4; ++w) names.push_back(batch_word_name(slot, w));
    ExtraChannels channels;
    try {
        channels = read_exr_channels(file, names);
    } catch (const IoError& e) {
        throw std::runtime_error(prefix + "its error batches are incomplete (" + e.what() + ")");
    }
    for (uint32_t slot = 0; slot < b.slot_count(); ++slot)
        for (uint32_t w = 0; w < 4; ++w) {
            const std::vector<uint32_t>& values = channels[batch_word_name(slot, w)];
            for (size_t p = 0; p < values.size(); ++p)
                b.sums[p * MAX_ERROR_BATCHES + slot] |= ExactSum(values[p]) << (32 * w);
        }
    f.has_batches = true;
}

namespace {

// The AOV sums' channels, in AovPixel's order.
struct AovField {
    const char* name;
    uint32_t (gpu::AovPixel::*words)[gpu::FILM_WORDS];
};
constexpr AovField AOV_FIELDS[] = {{"albedo_r", &gpu::AovPixel::albedo_r}, {"albedo_g", &gpu::AovPixel::albedo_g},
                                   {"albedo_b", &gpu::AovPixel::albedo_b}, {"normal_x", &gpu::AovPixel::normal_x},
                                   {"normal_y", &gpu::AovPixel::normal_y}, {"normal_z", &gpu::AovPixel::normal_z},
                                   {"depth", &gpu::AovPixel::depth}};
const char* const AOV_HITS = "fredholm.aov.hits";

std::string aov_word_name(const AovField& f, uint32_t w) {
    return std::string("fredholm.aov.") + f.name + "." + std::to_string(w);
}

// The AOV sums of a film file that has them (channel fredholm.aov.hits).
void read_aov_sums(const std::filesystem::path& file, FilmFile& f, const std::string& prefix) {
    const auto aovs = f.metadata.find("fredholm:aovs");
    if (aovs != f.metadata.end()) f.aovs = aovs->second;
    if (!exr_has_channel(file, AOV_HITS)) return;
    std::vector<std::string> names = {AOV_HITS};
    for (const AovField& field : AOV_FIELDS)
        for (uint32_t w = 0; w < gpu::FILM_WORDS; ++w) names.push_back(aov_word_name(field, w));
    ExtraChannels channels;
    try {
        channels = read_exr_channels(file, names);
    } catch (const IoError& e) {
        throw std::runtime_error(prefix + "its AOV sums are incomplete (" + e.what() + ")");
    }
    f.aov_sums.assign(f.film.size(), gpu::AovPixel{});
    for (size_t p = 0; p < f.aov_sums.size(); ++p) {
        for (const AovField& field : AOV_FIELDS)
            for (uint32_t w = 0; w < gpu::FILM_WORDS; ++w) (f.aov_sums[p].*field.words)[w] = channels[aov_word_name(field, w)][p];
        f.aov_sums[p].hit_count = channels[AOV_HITS][p];
    }
    f.has_aov_sums = true;
}

}  // namespace

ExtraChannels aov_sum_channels(const std::vector<gpu::AovPixel>& aovs) {
    ExtraChannels channels;
    for (const AovField& field : AOV_FIELDS)
        for (uint32_t w = 0; w < gpu::FILM_WORDS; ++w) {
            std::vector<uint32_t>& values = channels[aov_word_name(field, w)];
            values.resize(aovs.size());
            for (size_t p = 0; p < aovs.size(); ++p) values[p] = (aovs[p].*field.words)[w];
        }
    std::vector<uint32_t>& hits = channels[AOV_HITS];
    hits.resize(aovs.size());
    for (size_t p = 0; p < aovs.size(); ++p) hits[p] = aovs[p].hit_count;
    return channels;
}

FilmFile read_film_file(const std::filesystem::path& file, const std::string& why) {
    const std::string prefix = file.string() + ": " + why + ": ";
    FilmFile f;
    const Image image = read_exr(file, &f.metadata);
    // A film written before a setting existed was rendered as that setting's value then (path tracing, all BDPT
    // strategies, NEE picking lights by power).
    for (const SettingInfo& e : setting_table())
        if (e.before_it_existed) f.metadata.emplace(e.metadata_key, e.before_it_existed);
    if (f.metadata.count("fredholm:adaptive"))
        throw std::runtime_error(prefix + "it is an adaptive render (--adaptive): its pixels hold different numbers "
                                          "of samples, so it cannot be continued or merged");
    f.end_sample = read_count(f.metadata, "fredholm:spp", prefix);
    f.first_sample = read_count(f.metadata, "fredholm:first_sample", prefix);
    if (f.first_sample > f.end_sample) throw std::runtime_error(prefix + "fredholm:first_sample is above fredholm:spp");
    const std::string& size = find_key(f.metadata, "fredholm:image_size", prefix);
    unsigned w = 0, h = 0, x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    char end = 0;
    if (std::sscanf(size.c_str(), "%ux%u%c", &w, &h, &end) != 2 || w == 0 || h == 0 || w > MAX_IMAGE_SIDE ||
        h > MAX_IMAGE_SIDE)
        throw std::runtime_error(prefix + "fredholm:image_size is not WIDTHxHEIGHT (1 to " +
                                 std::to_string(MAX_IMAGE_SIDE) + " each): " + size);
    f.image_width = w;
    f.image_height = h;
    const std::string& crop = find_key(f.metadata, "fredholm:crop", prefix);
    if (crop == "none") {
        x1 = w, y1 = h;
    } else if (std::sscanf(crop.c_str(), "%u,%u,%u,%u%c", &x0, &y0, &x1, &y1, &end) != 4 || x0 >= x1 || y0 >= y1 ||
               x1 > w || y1 > h) {
        throw std::runtime_error(prefix + "fredholm:crop is not X0,Y0,X1,Y1 inside the image: " + crop);
    }
    f.x0 = x0, f.y0 = y0, f.x1 = x1, f.y1 = y1;
    if (uint32_t(image.width) != x1 - x0 || uint32_t(image.height) != y1 - y0)
        throw std::runtime_error(prefix + "the image is " + std::to_string(image.width) + "x" +
                                 std::to_string(image.height) + " but its crop is " + crop);
    ExtraChannels channels;
    try {
        channels = read_exr_channels(file, film_channel_names());
    } catch (const IoError& e) {
        throw std::runtime_error(prefix + "no raw film (" + e.what() + ")");
    }
    f.film.resize(size_t(image.width) * image.height);
    const std::vector<uint32_t>& counts = channels[COUNT_NAME];
    for (size_t i = 0; i < f.film.size(); ++i) {
        gpu::FilmPixel& p = f.film[i];
        for (int c = 0; c < 3; ++c)
            for (uint32_t w = 0; w < gpu::FILM_WORDS; ++w) channel_words(p, c)[w] = channels[word_name(c, w)][i];
        p.sample_count = counts[i];
        // Every pixel holds the same samples: renders stop between sample indices.
        if (counts[i] != f.end_sample - f.first_sample)
            throw std::runtime_error(prefix + "pixel " + std::to_string(i) + " holds " + std::to_string(counts[i]) +
                                     " samples, not the " + std::to_string(f.end_sample - f.first_sample) +
                                     " of its metadata");
    }
    read_error_batches(file, f, prefix);
    read_aov_sums(file, f, prefix);
    return f;
}

FilmFile read_saved_film(const std::filesystem::path& file, const ImageMetadata& expected) {
    FilmFile saved = read_film_file(file, "cannot resume");
    const std::string prefix = file.string() + ": cannot resume: ";
    std::vector<std::string> keys = matching_film_keys();
    keys.insert(keys.end(), {"fredholm:first_sample", "fredholm:crop"});
    for (const std::string& key : keys) {
        const auto want = expected.find(key);
        const std::string& have = find_key(saved.metadata, key, prefix);
        if (want != expected.end() && want->second != have)
            throw std::runtime_error(prefix + setting_name(key) + " is " + have + " in the file but " + want->second +
                                     " in this render");
    }
    return saved;
}

std::string hash_file(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    if (!in) throw IoError(file.string() + ": cannot read the scene file to hash it");
    uint64_t hash = 14695981039346656037ull;
    char buffer[1 << 16];
    while (in.read(buffer, sizeof buffer) || in.gcount() > 0) {
        for (std::streamsize i = 0; i < in.gcount(); ++i) hash = (hash ^ uint8_t(buffer[i])) * 1099511628211ull;
        if (!in) break;
    }
    char text[17];
    std::snprintf(text, sizeof text, "%016llx", (unsigned long long)hash);
    return text;
}

}  // namespace fh
