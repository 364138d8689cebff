// glTF 2.0 metallic-roughness materials and the KHR material extensions we read, as gpu::Material.
#pragma once
#include <string>

#include "shared/layout.h"

#include "scene/scene.h"

namespace tinygltf {
class Model;
}

namespace fh::gltf {

// True for the extensions this loader implements (they may appear in extensionsRequired).
bool is_supported_extension(const std::string& name);

// Material `index` of `model`, with KHR_materials_emissive_strength, KHR_materials_specular and
// KHR_materials_ior applied, alphaMode and its texture slots (added to scene.texture_slots; scene.images must
// be filled already). Throws SceneError for an unknown alphaMode or a broken texture reference.
gpu::Material convert_material(const tinygltf::Model& model, int index, Scene& scene);

// What the KHR material extensions add to material `index` (layout.h MaterialLayers):
// KHR_materials_transmission, _volume, _clearcoat, _sheen, _diffuse_transmission, _anisotropy and _iridescence (its
// Fresnel bound left 0: thin_film_bound.h). Throws SceneError for an attenuationDistance <= 0, an iridescenceIor < 1
// or a negative film thickness.
gpu::MaterialLayers convert_material_layers(const tinygltf::Model& model, int index, Scene& scene);

// The material of primitives that name none: every property at its glTF default (spec 3.9.6).
gpu::Material make_default_material();
gpu::MaterialLayers make_default_layers();

}  // namespace fh::gltf
