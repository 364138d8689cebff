// glTF textures (spec 3.8) as the GPU reads them: decoded images and the texture slots of materials, with
// samplers, texCoord and KHR_texture_transform; EXT_texture_webp and the KHR_texture_basisu fallback.
#pragma once
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "scene/scene.h"
#include "shared/layout.h"

namespace tinygltf {
class Model;
class Value;
struct Image;
}  // namespace tinygltf

namespace fh::gltf {

// tinygltf's image callback (tinygltf::LoadImageDataFunction): decodes PNG, JPEG and WebP into RGBA8. KTX2
// images are left empty (they are reported when a material uses them); anything else fails the load with the
// image named.
bool load_image_data(tinygltf::Image* image, int image_index, std::string* error, std::string* warning,
                     int requested_width, int requested_height, const unsigned char* bytes, int size, void*);

// The decoded images of `model` (moved out of it) in file order.
std::vector<SceneImage> take_images(tinygltf::Model& model);

// What a material's textureInfo says (textureInfo / normalTextureInfo / occlusionTextureInfo).
struct TextureReference {
    int index = -1;     // glTF texture; -1: none
    int tex_coord = 0;  // TEXCOORD_n
    double scale = 1.0; // normalTexture.scale
    const std::map<std::string, tinygltf::Value>* extensions = nullptr;  // the textureInfo's (ExtensionMap)
};

// The textureInfo object `key` of a material extension (tinygltf leaves extensions as JSON values): index (-1
// when absent or not an integer), texCoord, scale (normalTextureInfo) and the textureInfo's own extensions, which stay owned by `extension`.
TextureReference read_extension_texture(const tinygltf::Value* extension, const char* key);

// Adds the TextureSlot for `reference` to `scene.texture_slots` and returns its index; INVALID_INDEX when the
// reference is absent or its texture has no image we can decode (a KTX2 image without a fallback: warned
// once per texture in `scene.warnings`). Throws SceneError for a texture, image or sampler that does not
// exist, or a texCoord other than 0 and 1. `srgb`: the slot holds colour (baseColor, emissive).
uint32_t add_texture_slot(const tinygltf::Model& model, const TextureReference& reference, bool srgb,
                          const std::string& where, Scene& scene);

// Which TEXCOORD sets (bit 0: TEXCOORD_0, bit 1: TEXCOORD_1) the slots of `material` and its `layers` read.
uint32_t texcoord_sets_read(const gpu::Material& material, const gpu::MaterialLayers& layers,
                            const std::vector<gpu::TextureSlot>& slots);

}  // namespace fh::gltf
