// glTF textures: image decoding callback, samplers, texCoord and KHR_texture_transform into gpu::TextureSlot.
#include "scene/gltf/gltf_texture.h"

#include <cmath>
#include <cstring>

#include <tiny_gltf.h>

#include "scene/gltf/gltf_accessor.h"
#include "scene/gltf/image_decode.h"

namespace fh::gltf {
namespace {

uint32_t wrap_bits(int gl_wrap) {
    switch (gl_wrap) {
        case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE: return gpu::WRAP_CLAMP_TO_EDGE;
        case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT: return gpu::WRAP_MIRRORED_REPEAT;
        default: return gpu::WRAP_REPEAT;  // 10497 and unknown values: the spec's default
    }
}

double read_number(const tinygltf::Value& object, const char* key, double fallback) {
    if (!object.IsObject() || !object.Has(key)) return fallback;
    const tinygltf::Value& v = object.Get(key);
    return v.IsNumber() || v.IsInt() ? v.GetNumberAsDouble() : fallback;
}

glm::dvec2 read_pair(const tinygltf::Value& object, const char* key, glm::dvec2 fallback) {
    if (!object.IsObject() || !object.Has(key)) return fallback;
    const tinygltf::Value& v = object.Get(key);
    if (!v.IsArray() || v.ArrayLen() != 2) return fallback;
    for (int i = 0; i < 2; ++i)
        if (v.Get(i).IsNumber() || v.Get(i).IsInt()) fallback[i] = v.Get(i).GetNumberAsDouble();
    return fallback;
}

const tinygltf::Value* find(const std::map<std::string, tinygltf::Value>* extensions, const char* name) {
    if (extensions == nullptr) return nullptr;
    const auto it = extensions->find(name);
    return it != extensions->end() && it->second.IsObject() ? &it->second : nullptr;
}

// The image a texture shows: EXT_texture_webp's source (we decode WebP), else `source`, else nothing
// (KHR_texture_basisu without a fallback). -1 when there is none.
int texture_image(const tinygltf::Texture& texture, int texture_index, size_t image_count) {
    int image = texture.source;
    if (const tinygltf::Value* webp = find(&texture.extensions, "EXT_texture_webp")) {
        const int source = webp->Has("source") ? read_json_index(webp->Get("source")) : -1;
        if (source >= 0) image = source;
    }
    if (image >= 0 && size_t(image) >= image_count)
        throw SceneError("texture " + std::to_string(texture_index) + " uses image " + std::to_string(image) +
                         ", which does not exist");
    return image;
}

}  // namespace

namespace {
std::string image_label(const tinygltf::Image& image, int index) {
    const std::string name = image.uri.empty() || image.uri.rfind("data:", 0) == 0 ? image.name : image.uri;
    return "image " + std::to_string(index) + (name.empty() ? "" : " '" + name + "'");
}
}  // namespace

bool read_image_header(tinygltf::Image* image, int image_index, std::string* error, std::string*, int, int,
                       const unsigned char* bytes, int size, void* pending) {
    if (size <= 0 || bytes == nullptr) {
        *error += "image " + std::to_string(image_index) + " is empty";
        return false;
    }
    if (detect_image_format(bytes, size_t(size)) == ImageFormat::ktx2) {  // left empty: see the header
        image->width = image->height = image->component = 0;
        return true;
    }
    uint32_t width = 0, height = 0;
    std::string problem;
    if (!read_image_size(bytes, size_t(size), width, height, problem)) {
        *error += image_label(*image, image_index) + ": " + problem;
        return false;
    }
    image->width = int(width);
    image->height = int(height);
    image->component = 4;
    image->bits = 8;
    image->pixel_type = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
    static_cast<PendingImages*>(pending)->images.push_back(
        {image_index, width, height, std::vector<unsigned char>(bytes, bytes + size)});
    return true;
}

void decode_pending_images(tinygltf::Model& model, PendingImages& pending) {
    for (PendingImages::Entry& entry : pending.images) {
        tinygltf::Image& image = model.images.at(size_t(entry.index));
        DecodedImage decoded;
        std::string problem;
        if (!decode_image(entry.encoded.data(), entry.encoded.size(), decoded, problem))
            throw SceneError(image_label(image, entry.index) + ": " + problem);
        std::vector<unsigned char>().swap(entry.encoded);
        if (decoded.width != entry.width || decoded.height != entry.height)
            throw SceneError(image_label(image, entry.index) + ": decoded as " + std::to_string(decoded.width) + " x " +
                             std::to_string(decoded.height) + " texels, not the " + std::to_string(entry.width) +
                             " x " + std::to_string(entry.height) + " its header declares");
        image.image = std::move(decoded.rgba);
    }
}

std::vector<MemoryUse> decoded_image_uses(const tinygltf::Model& model, const PendingImages& pending) {
    std::vector<MemoryUse> uses;
    for (const PendingImages::Entry& e : pending.images)
        uses.push_back({image_label(model.images.at(size_t(e.index)), e.index) + " (" + std::to_string(e.width) +
                            " x " + std::to_string(e.height) + ", decoded and packed)",
                        2 * uint64_t(e.width) * e.height * 4});
    return uses;
}

std::vector<SceneImage> take_images(tinygltf::Model& model) {
    std::vector<SceneImage> images(model.images.size());
    for (size_t i = 0; i < model.images.size(); ++i) {
        tinygltf::Image& source = model.images[i];
        SceneImage& image = images[i];
        image.name = "image " + std::to_string(i) + (source.name.empty() ? "" : " '" + source.name + "'");
        // tinygltf only warns when an image file cannot be read, and never calls the decoder: its fields keep
        // their defaults (-1). A KTX2 image was seen and left empty on purpose (component 0).
        if (source.component == -1)
            throw SceneError(image.name + (source.uri.empty() || source.uri.rfind("data:", 0) == 0 ? "" : " ('" + source.uri + "')") +
                             " could not be read (missing or unreadable file)");
        if (source.image.empty() || source.component != 4 || source.bits != 8) continue;
        image.width = uint32_t(source.width);
        image.height = uint32_t(source.height);
        image.texels.resize(source.image.size() / 4);
        std::memcpy(image.texels.data(), source.image.data(), image.texels.size() * 4);
        std::vector<unsigned char>().swap(source.image);
    }
    return images;
}

uint32_t add_texture_slot(const tinygltf::Model& model, const TextureReference& reference, bool srgb,
                          const std::string& where, Scene& scene) {
    if (reference.index < 0) return gpu::INVALID_INDEX;
    if (size_t(reference.index) >= model.textures.size())
        throw SceneError("texture " + std::to_string(reference.index) + " does not exist (" + where + ")");
    const tinygltf::Texture& texture = model.textures[size_t(reference.index)];
    const int image = texture_image(texture, reference.index, scene.images.size());
    if (image < 0 || scene.images[size_t(image)].texels.empty()) {
        const std::string message = "texture " + std::to_string(reference.index) +
                                    " has no image that can be decoded (KHR_texture_basisu/KTX2 without a PNG, "
                                    "JPEG or WebP fallback): rendered without it";
        bool seen = false;
        for (const std::string& w : scene.warnings) seen = seen || w == message;
        if (!seen) scene.warnings.push_back(message);
        return gpu::INVALID_INDEX;
    }

    gpu::TextureSlot slot{};
    slot.image = uint32_t(image);
    slot.scale = float(reference.scale);
    int tex_coord = reference.tex_coord;
    glm::dvec2 offset(0.0), scale(1.0);
    double rotation = 0.0;
    if (const tinygltf::Value* transform = find(reference.extensions, "KHR_texture_transform")) {
        offset = read_pair(*transform, "offset", offset);
        scale = read_pair(*transform, "scale", scale);
        rotation = read_number(*transform, "rotation", 0.0);
        // A real of any size may stand here (a fuzzer finding: int(3.5e38) is undefined); 0 and 1 are the sets read.
        const double set = read_number(*transform, "texCoord", double(tex_coord));
        tex_coord = set == 0.0 || set == 1.0 ? int(set) : (set >= 0.0 && set < 1e9 ? int(set) : -1);
    }
    if (tex_coord != 0 && tex_coord != 1)
        throw SceneError("texCoord " + std::to_string(tex_coord) + " is not supported, only TEXCOORD_0 and " +
                         "TEXCOORD_1 (" + where + ")");
    if (!std::isfinite(offset.x + offset.y + scale.x + scale.y + rotation))
        throw SceneError("KHR_texture_transform has a non-finite value (" + where + ")");
    // KHR_texture_transform: uv' = T(offset) R(rotation) S(scale) (u, v, 1), R = [cos sin; -sin cos].
    const double c = std::cos(rotation), s = std::sin(rotation);
    slot.transform_u = gpu::vec4(float(c * scale.x), float(s * scale.y), float(offset.x), 0.0f);
    slot.transform_v = gpu::vec4(float(-s * scale.x), float(c * scale.y), float(offset.y), 0.0f);

    uint32_t sampler = srgb ? gpu::SAMPLER_SRGB : 0u;
    if (tex_coord == 1) sampler |= gpu::SAMPLER_TEXCOORD_1;
    if (texture.sampler >= 0) {
        if (size_t(texture.sampler) >= model.samplers.size())
            throw SceneError("texture " + std::to_string(reference.index) + " uses sampler " +
                             std::to_string(texture.sampler) + ", which does not exist");
        const tinygltf::Sampler& s = model.samplers[size_t(texture.sampler)];
        sampler |= wrap_bits(s.wrapS) | wrap_bits(s.wrapT) << 2;
        // Magnification decides: a path tracer supersamples the pixel, so minification needs no filter of
        // its own (engine/scene/gltf/README.md "Textures").
        if (s.magFilter == TINYGLTF_TEXTURE_FILTER_NEAREST) sampler |= gpu::SAMPLER_NEAREST;
    }
    slot.addressing = sampler;
    scene.texture_slots.push_back(slot);
    return uint32_t(scene.texture_slots.size() - 1);
}

TextureReference read_extension_texture(const tinygltf::Value* extension, const char* key) {
    TextureReference reference;
    if (extension == nullptr || !extension->Has(key)) return reference;
    const tinygltf::Value& info = extension->Get(key);
    if (info.Has("index") && info.Get("index").IsInt()) reference.index = info.Get("index").GetNumberAsInt();
    if (info.Has("texCoord") && info.Get("texCoord").IsInt())
        reference.tex_coord = info.Get("texCoord").GetNumberAsInt();
    if (info.Has("scale") && info.Get("scale").IsNumber()) reference.scale = info.Get("scale").GetNumberAsDouble();
    if (info.Has("extensions") && info.Get("extensions").IsObject())
        reference.extensions = &info.Get("extensions").Get<tinygltf::Value::Object>();
    return reference;
}

uint32_t texcoord_sets_read(const gpu::Material& material, const gpu::MaterialLayers& layers,
                            const std::vector<gpu::TextureSlot>& slots) {
    uint32_t sets = 0;
    for (uint32_t index : {material.base_color_texture, material.metallic_roughness_texture, material.normal_texture,
                           material.emissive_texture, material.specular_texture, material.specular_color_texture,
                           layers.transmission_texture, layers.clearcoat_texture,
                           layers.clearcoat_roughness_texture, layers.clearcoat_normal_texture, layers.sheen_color_texture,
                           layers.sheen_roughness_texture, layers.diffuse_transmission_texture,
                           layers.diffuse_transmission_color_texture, layers.anisotropy_texture,
                           layers.iridescence_texture, layers.iridescence_thickness_texture})
        if (index != gpu::INVALID_INDEX && index < slots.size())
            sets |= (slots[index].addressing & gpu::SAMPLER_TEXCOORD_1) ? 2u : 1u;
    return sets;
}

}  // namespace fh::gltf
