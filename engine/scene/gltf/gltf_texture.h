// glTF textures (spec 3.8) as the GPU reads them: decoded images and the texture slots of materials, with
// samplers, texCoord and KHR_texture_transform; EXT_texture_webp and the KHR_texture_basisu fallback.
#pragma once
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "scene/memory_limit.h"
#include "scene/scene.h"
#include "shared/layout.h"

namespace tinygltf {
class Model;
class Value;
struct Image;
}  // namespace tinygltf

namespace fh::gltf {

// Images tinygltf has read but not decoded: their encoded bytes and the sizes their headers declare, so that what
// decoding takes is known (and a memory limit applied) before any image is decoded.
struct PendingImages {
    struct Entry {
        int index = -1;  // into Model::images
        uint32_t width = 0, height = 0;
        std::vector<unsigned char> encoded;
    };
    std::vector<Entry> images;
};

// tinygltf's image callback (tinygltf::LoadImageDataFunction; `pending`: a PendingImages): reads the size a PNG, JPEG
// or WebP header declares (refusing more than MAX_IMAGE_SIDE per side) and keeps the encoded bytes for
// decode_pending_images. KTX2 images are left empty (they are reported when a material uses them); anything else
// fails the load with the image named.
bool read_image_header(tinygltf::Image* image, int image_index, std::string* error, std::string* warning,
                       int requested_width, int requested_height, const unsigned char* bytes, int size, void* pending);

// What decoding the pending images will take on the host, one use per image (its RGBA8 copy and the packed one).
std::vector<MemoryUse> decoded_image_uses(const tinygltf::Model& model, const PendingImages& pending);

// Decodes each pending image into its Model::images entry as RGBA8. Throws SceneError naming an image that does not
// decode, or decodes to another size than its header declared.
void decode_pending_images(tinygltf::Model& model, PendingImages& pending);

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
