// glTF 2.0 metallic-roughness materials and the KHR material extensions we read, as gpu::Material.
#pragma once
#include <string>

#include "shared/layout.h"

namespace tinygltf {
struct Material;
}

namespace fh::gltf {

// True for the extensions this loader implements (they may appear in extensionsRequired).
bool is_supported_extension(const std::string& name);

// Factors of a glTF material, with KHR_materials_emissive_strength, KHR_materials_specular and
// KHR_materials_ior applied; texture slots are INVALID_INDEX (textures are not read yet).
gpu::Material convert_material(const tinygltf::Material& material);

// The material of primitives that name none: every property at its glTF default (spec 3.9.6).
gpu::Material make_default_material();

}  // namespace fh::gltf
