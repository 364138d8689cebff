// Converts glTF materials (spec 3.9) and the KHR extensions emissive_strength, specular, ior, unlit,
// transmission, volume, clearcoat, sheen, diffuse_transmission, anisotropy, iridescence and dispersion, and the
// archived pbrSpecularGlossiness.
#include "scene/gltf/gltf_material.h"

#include <algorithm>
#include <cmath>

#include <tiny_gltf.h>

#include "scene/gltf/gltf_texture.h"

namespace fh::gltf {
namespace {

constexpr const char* SUPPORTED_EXTENSIONS[] = {
    "KHR_materials_emissive_strength",
    "KHR_materials_specular",
    "KHR_materials_ior",
    "KHR_materials_transmission",
    "KHR_materials_volume",
    "KHR_materials_clearcoat",
    "KHR_materials_unlit",
    "KHR_materials_sheen",
    "KHR_materials_diffuse_transmission",
    "KHR_materials_anisotropy",
    "KHR_materials_iridescence",
    "KHR_materials_dispersion",
    "KHR_lights_punctual",  // read by gltf_loader.cpp
    "KHR_texture_transform",  // gltf_texture.cpp
    "EXT_texture_webp",
    "KHR_texture_basisu",     // its fallback source is used; without one the texture is left out (warned)
    "KHR_mesh_quantization",  // gltf_loader.cpp: byte/short positions, normals, texture coordinates, ...
    "KHR_materials_variants", // gltf_loader.cpp: --variant NAME
    "EXT_meshopt_compression",  // gltf_meshopt.cpp
    "KHR_draco_mesh_compression",  // gltf_draco.cpp
    "EXT_mesh_gpu_instancing",     // gltf_loader.cpp: one instance per TRANSLATION/ROTATION/SCALE element
    "KHR_materials_pbrSpecularGlossiness",  // below: onto the dielectric with KHR_materials_specular's colour
    "KHR_node_visibility",         // gltf_flattener.cpp: a node with visible false is left out with its subtree
    "KHR_animation_pointer",       // gltf_animation_pointer.cpp: materials, lights, cameras, nodes at --time
    "KHR_xmp_json_ld",             // metadata (authors, licences): nothing to render
    "KHR_xmp",                     // its archived predecessor
};

// The object of extension `name` on `material`, or nullptr.
const tinygltf::Value* find_extension(const tinygltf::Material& material, const char* name) {
    const auto it = material.extensions.find(name);
    if (it == material.extensions.end() || !it->second.IsObject()) return nullptr;
    return &it->second;
}

double read_number(const tinygltf::Value* object, const char* key, double fallback) {
    if (object == nullptr || !object->Has(key)) return fallback;
    const tinygltf::Value& v = object->Get(key);
    return v.IsNumber() ? v.GetNumberAsDouble() : fallback;
}

glm::dvec3 read_color3(const tinygltf::Value* object, const char* key, glm::dvec3 fallback) {
    if (object == nullptr || !object->Has(key)) return fallback;
    const tinygltf::Value& v = object->Get(key);
    if (!v.IsArray() || v.ArrayLen() != 3) return fallback;
    glm::dvec3 out = fallback;
    for (int i = 0; i < 3; ++i)
        if (v.Get(i).IsNumber()) out[i] = v.Get(i).GetNumberAsDouble();
    return out;
}

// The slot of textureInfo `key` of extension object `extension` (INVALID_INDEX when absent).
uint32_t extension_slot(const tinygltf::Model& model, const tinygltf::Value* extension, const char* key, bool srgb,
                        const std::string& where, Scene& scene) {
    if (extension == nullptr || !extension->Has(key)) return gpu::INVALID_INDEX;
    const TextureReference texture = read_extension_texture(extension, key);
    if (texture.index < 0) throw SceneError(where + " " + key + " has no valid index");
    return add_texture_slot(model, texture, srgb, where + " " + key, scene);
}

// KHR_materials_pbrSpecularGlossiness (archived), which replaces pbrMetallicRoughness: the diffuse colour is the base
// colour of a dielectric (metallic 0) whose specular layer has f0 = the specular colour and f90 = 1 (ior 0 makes
// the ior's f0 1, which KHR_materials_specular's colour then scales) and roughness 1 - glossiness; the specular
// colour texture's alpha holds glossiness. shaders/lib/bsdf/README.md "Specular-glossiness" says where it departs.
void apply_specular_glossiness(const tinygltf::Model& model, const tinygltf::Value& gloss, const std::string& where,
                               gpu::Material& m, Scene& scene) {
    glm::dvec4 diffuse(1.0);
    if (gloss.Has("diffuseFactor") && gloss.Get("diffuseFactor").IsArray() && gloss.Get("diffuseFactor").ArrayLen() == 4)
        for (int i = 0; i < 4; ++i)
            if (gloss.Get("diffuseFactor").Get(i).IsNumber())
                diffuse[i] = gloss.Get("diffuseFactor").Get(i).GetNumberAsDouble();
    const glm::dvec3 specular = read_color3(&gloss, "specularFactor", glm::dvec3(1.0));
    const double glossiness = read_number(&gloss, "glossinessFactor", 1.0);
    for (double v : {diffuse.r, diffuse.g, diffuse.b, diffuse.a, specular.r, specular.g, specular.b, glossiness})
        if (!std::isfinite(v))
            throw SceneError(where + " has a non-finite KHR_materials_pbrSpecularGlossiness factor");
    m.base_color = gpu::vec4(glm::vec4(diffuse));
    m.metallic = 0.0f;
    m.roughness = float(1.0 - std::clamp(glossiness, 0.0, 1.0));
    m.specular_color = gpu::vec4(glm::vec3(glm::clamp(specular, 0.0, 1.0)), 1.0f);
    m.ior = 0.0f;
    m.base_color_texture = extension_slot(model, &gloss, "diffuseTexture", true, where, scene);
    m.metallic_roughness_texture = gpu::INVALID_INDEX;
    m.specular_texture = gpu::INVALID_INDEX;
    m.specular_color_texture = extension_slot(model, &gloss, "specularGlossinessTexture", true, where, scene);
    if (m.specular_color_texture != gpu::INVALID_INDEX) m.flags |= gpu::MATERIAL_GLOSSINESS_IN_ALPHA;
}

void clear_textures(gpu::Material& m) {
    m.base_color_texture = gpu::INVALID_INDEX;
    m.metallic_roughness_texture = gpu::INVALID_INDEX;
    m.normal_texture = gpu::INVALID_INDEX;
    m.emissive_texture = gpu::INVALID_INDEX;
    m.specular_texture = gpu::INVALID_INDEX;
    m.specular_color_texture = gpu::INVALID_INDEX;
}

}  // namespace

bool is_supported_extension(const std::string& name) {
    for (const char* supported : SUPPORTED_EXTENSIONS)
        if (name == supported) return true;
    return false;
}

gpu::Material make_default_material() {
    gpu::Material m{};
    m.base_color = gpu::vec4(1.0f);
    m.emission = gpu::vec4(0.0f);
    m.specular_color = gpu::vec4(1.0f);  // KHR_materials_specular defaults: color 1, factor 1
    m.metallic = 1.0f;
    m.roughness = 1.0f;
    m.ior = 1.5f;
    m.flags = 0u;
    m.alpha_mode = gpu::ALPHA_OPAQUE;
    m.alpha_cutoff = 0.5f;
    clear_textures(m);
    return m;
}

gpu::Material convert_material(const tinygltf::Model& model, int index, Scene& scene) {
    const tinygltf::Material& material = model.materials[size_t(index)];
    const std::string where = "material " + std::to_string(index);
    gpu::Material m = make_default_material();
    const auto& pbr = material.pbrMetallicRoughness;
    if (pbr.baseColorFactor.size() == 4)
        m.base_color = gpu::vec4(float(pbr.baseColorFactor[0]), float(pbr.baseColorFactor[1]),
                                 float(pbr.baseColorFactor[2]), float(pbr.baseColorFactor[3]));
    m.metallic = float(pbr.metallicFactor);
    m.roughness = float(pbr.roughnessFactor);

    glm::dvec3 emissive(0.0);
    if (material.emissiveFactor.size() == 3)
        emissive = glm::dvec3(material.emissiveFactor[0], material.emissiveFactor[1], material.emissiveFactor[2]);
    const double strength =
        read_number(find_extension(material, "KHR_materials_emissive_strength"), "emissiveStrength", 1.0);
    m.emission = gpu::vec4(glm::vec3(emissive * strength), 0.0f);

    const tinygltf::Value* specular = find_extension(material, "KHR_materials_specular");
    const glm::dvec3 specular_color = read_color3(specular, "specularColorFactor", glm::dvec3(1.0));
    m.specular_color = gpu::vec4(glm::vec3(specular_color), float(read_number(specular, "specularFactor", 1.0)));
    m.ior = float(read_number(find_extension(material, "KHR_materials_ior"), "ior", 1.5));
    m.flags = material.doubleSided ? gpu::MATERIAL_DOUBLE_SIDED : 0u;
    // KHR_materials_unlit: only the base colour counts (shade.comp shows it to camera rays); an emissiveFactor
    // beside it is not light.
    if (find_extension(material, "KHR_materials_unlit") != nullptr) {
        m.flags |= gpu::MATERIAL_UNLIT;
        m.emission = gpu::vec4(0.0f);
    }

    if (material.alphaMode == "MASK") m.alpha_mode = gpu::ALPHA_MASK;
    else if (material.alphaMode == "BLEND") m.alpha_mode = gpu::ALPHA_BLEND;
    else if (material.alphaMode == "OPAQUE" || material.alphaMode.empty()) m.alpha_mode = gpu::ALPHA_OPAQUE;
    else throw SceneError(where + " has unknown alphaMode '" + material.alphaMode + "'");
    m.alpha_cutoff = float(material.alphaCutoff);
    if (!(material.alphaCutoff >= 0.0) || !std::isfinite(material.alphaCutoff))
        throw SceneError(where + " has alphaCutoff " + std::to_string(material.alphaCutoff) + " (must be >= 0)");

    // occlusionTexture is a rasteriser's stand-in for the light a path tracer computes: not read.
    auto slot = [&](int texture, int tex_coord, double scale, const tinygltf::ExtensionMap& extensions, bool srgb,
                    const char* name) {
        return gltf::add_texture_slot(model, {texture, tex_coord, scale, &extensions}, srgb,
                                      where + " " + name, scene);
    };
    m.base_color_texture = slot(pbr.baseColorTexture.index, pbr.baseColorTexture.texCoord, 1.0,
                                pbr.baseColorTexture.extensions, true, "baseColorTexture");
    m.metallic_roughness_texture = slot(pbr.metallicRoughnessTexture.index, pbr.metallicRoughnessTexture.texCoord, 1.0,
                                        pbr.metallicRoughnessTexture.extensions, false, "metallicRoughnessTexture");
    m.normal_texture = slot(material.normalTexture.index, material.normalTexture.texCoord, material.normalTexture.scale,
                            material.normalTexture.extensions, false, "normalTexture");
    m.emissive_texture = slot(material.emissiveTexture.index, material.emissiveTexture.texCoord, 1.0,
                              material.emissiveTexture.extensions, true, "emissiveTexture");
    m.specular_texture = extension_slot(model, specular, "specularTexture", false, where, scene);
    m.specular_color_texture = extension_slot(model, specular, "specularColorTexture", true, where, scene);
    if (const tinygltf::Value* gloss = find_extension(material, "KHR_materials_pbrSpecularGlossiness"))
        apply_specular_glossiness(model, *gloss, where, m, scene);
    return m;
}

gpu::MaterialLayers make_default_layers() {
    gpu::MaterialLayers layers{};
    layers.attenuation = gpu::vec4(0.0f);
    layers.transmission = 0.0f;
    layers.transmission_texture = gpu::INVALID_INDEX;
    layers.flags = 0u;
    layers.clearcoat = 0.0f;
    layers.clearcoat_roughness = 0.0f;
    layers.clearcoat_texture = gpu::INVALID_INDEX;
    layers.clearcoat_roughness_texture = gpu::INVALID_INDEX;
    layers.clearcoat_normal_texture = gpu::INVALID_INDEX;
    layers.sheen = gpu::vec4(0.0f);
    layers.sheen_color_texture = gpu::INVALID_INDEX;
    layers.sheen_roughness_texture = gpu::INVALID_INDEX;
    layers.diffuse_transmission = gpu::vec4(1.0f, 1.0f, 1.0f, 0.0f);
    layers.diffuse_transmission_texture = gpu::INVALID_INDEX;
    layers.diffuse_transmission_color_texture = gpu::INVALID_INDEX;
    layers.anisotropy_strength = 0.0f;
    layers.anisotropy_cos = 1.0f;
    layers.anisotropy_sin = 0.0f;
    layers.anisotropy_texture = gpu::INVALID_INDEX;
    layers.iridescence = 0.0f;
    layers.iridescence_ior = 1.3f;
    layers.iridescence_thickness_min = 100.0f;
    layers.iridescence_thickness_max = 400.0f;
    layers.iridescence_texture = gpu::INVALID_INDEX;
    layers.iridescence_thickness_texture = gpu::INVALID_INDEX;
    layers.iridescence_albedo_f0 = 0.0f;
    layers.iridescence_albedo_f90 = 0.0f;
    layers.dispersion = 0.0f;
    return layers;
}

gpu::MaterialLayers convert_material_layers(const tinygltf::Model& model, int index, Scene& scene) {
    const tinygltf::Material& material = model.materials[size_t(index)];
    const std::string where = "material " + std::to_string(index);
    gpu::MaterialLayers layers = make_default_layers();

    auto layer_slot = [&](const tinygltf::Value* extension, const char* key, bool srgb = false) {
        return extension_slot(model, extension, key, srgb, where, scene);
    };

    // A specular-glossiness material has no index of refraction (ior 0 above): it refracts nothing.
    const bool specular_glossiness = find_extension(material, "KHR_materials_pbrSpecularGlossiness") != nullptr;
    if (specular_glossiness && (find_extension(material, "KHR_materials_transmission") != nullptr ||
                                find_extension(material, "KHR_materials_volume") != nullptr))
        scene.warnings.push_back(where + " has KHR_materials_pbrSpecularGlossiness, which defines no index of "
                                 "refraction: its KHR_materials_transmission and KHR_materials_volume are ignored");
    const tinygltf::Value* transmission =
        specular_glossiness ? nullptr : find_extension(material, "KHR_materials_transmission");
    layers.transmission = float(std::clamp(read_number(transmission, "transmissionFactor", 0.0), 0.0, 1.0));
    layers.transmission_texture = layer_slot(transmission, "transmissionTexture");

    const tinygltf::Value* clearcoat = find_extension(material, "KHR_materials_clearcoat");
    layers.clearcoat = float(std::clamp(read_number(clearcoat, "clearcoatFactor", 0.0), 0.0, 1.0));
    layers.clearcoat_roughness = float(std::clamp(read_number(clearcoat, "clearcoatRoughnessFactor", 0.0), 0.0, 1.0));
    layers.clearcoat_texture = layer_slot(clearcoat, "clearcoatTexture");
    layers.clearcoat_roughness_texture = layer_slot(clearcoat, "clearcoatRoughnessTexture");
    layers.clearcoat_normal_texture = layer_slot(clearcoat, "clearcoatNormalTexture");

    // KHR_materials_sheen: sheenColor (sRGB texture, RGB) and sheenRoughness (the texture's alpha).
    const tinygltf::Value* sheen = find_extension(material, "KHR_materials_sheen");
    const glm::dvec3 sheen_color = glm::clamp(read_color3(sheen, "sheenColorFactor", glm::dvec3(0.0)), 0.0, 1.0);
    layers.sheen = gpu::vec4(float(sheen_color.r), float(sheen_color.g), float(sheen_color.b),
                             float(std::clamp(read_number(sheen, "sheenRoughnessFactor", 0.0), 0.0, 1.0)));
    layers.sheen_color_texture = layer_slot(sheen, "sheenColorTexture", true);
    layers.sheen_roughness_texture = layer_slot(sheen, "sheenRoughnessTexture");

    // KHR_materials_diffuse_transmission: the factor (the texture's alpha) and colour (sRGB texture, RGB).
    const tinygltf::Value* diffuse = find_extension(material, "KHR_materials_diffuse_transmission");
    const glm::dvec3 diffuse_color =
        glm::clamp(read_color3(diffuse, "diffuseTransmissionColorFactor", glm::dvec3(1.0)), 0.0, 1.0);
    layers.diffuse_transmission =
        gpu::vec4(float(diffuse_color.r), float(diffuse_color.g), float(diffuse_color.b),
                  float(std::clamp(read_number(diffuse, "diffuseTransmissionFactor", 0.0), 0.0, 1.0)));
    layers.diffuse_transmission_texture = layer_slot(diffuse, "diffuseTransmissionTexture");
    layers.diffuse_transmission_color_texture = layer_slot(diffuse, "diffuseTransmissionColorTexture", true);

    // KHR_materials_anisotropy: strength, the rotation of the direction from the tangent, and the texture (RG: the
    // direction in tangent space, B: the strength; linear).
    const tinygltf::Value* anisotropy = find_extension(material, "KHR_materials_anisotropy");
    const double rotation = read_number(anisotropy, "anisotropyRotation", 0.0);
    layers.anisotropy_strength = float(std::clamp(read_number(anisotropy, "anisotropyStrength", 0.0), 0.0, 1.0));
    layers.anisotropy_cos = std::isfinite(rotation) ? float(std::cos(rotation)) : 1.0f;
    layers.anisotropy_sin = std::isfinite(rotation) ? float(std::sin(rotation)) : 0.0f;
    layers.anisotropy_texture = layer_slot(anisotropy, "anisotropyTexture");

    // KHR_materials_iridescence: the film's weight (R of its texture), index, and thickness in nm (G of the thickness
    // texture between the minimum and the maximum; the maximum without it). Its Fresnel bound is set by the loader
    // (bound_thin_film_albedo_f0), which also knows the base's f0.
    const tinygltf::Value* film = find_extension(material, "KHR_materials_iridescence");
    const double film_ior = read_number(film, "iridescenceIor", 1.3);
    const double thinnest = read_number(film, "iridescenceThicknessMinimum", 100.0);
    const double thickest = read_number(film, "iridescenceThicknessMaximum", 400.0);
    if (!(film_ior >= 1.0) || !std::isfinite(film_ior))
        throw SceneError(where + " has KHR_materials_iridescence iridescenceIor " + std::to_string(film_ior) +
                         " (must be >= 1)");
    for (double nm : {thinnest, thickest})
        if (!(nm >= 0.0) || !std::isfinite(nm))
            throw SceneError(where + " has a KHR_materials_iridescence thickness of " + std::to_string(nm) +
                             " nm (must be >= 0)");
    layers.iridescence = float(std::clamp(read_number(film, "iridescenceFactor", 0.0), 0.0, 1.0));
    layers.iridescence_ior = float(film_ior);
    layers.iridescence_thickness_min = float(thinnest);
    layers.iridescence_thickness_max = float(thickest);
    layers.iridescence_texture = layer_slot(film, "iridescenceTexture");
    layers.iridescence_thickness_texture = layer_slot(film, "iridescenceThicknessTexture");

    // KHR_materials_volume: thicknessFactor > 0 makes the mesh the boundary of a volume; its value (and the
    // thickness texture) is a rasteriser's stand-in for the geometry a path tracer has, so only its sign is read.
    const tinygltf::Value* volume = specular_glossiness ? nullptr : find_extension(material, "KHR_materials_volume");
    if (volume != nullptr && read_number(volume, "thicknessFactor", 0.0) > 0.0) layers.flags |= gpu::LAYERS_VOLUME;
    const double distance = read_number(volume, "attenuationDistance", HUGE_VAL);
    if (!(distance > 0.0))
        throw SceneError(where + " has KHR_materials_volume attenuationDistance " + std::to_string(distance) +
                         " (must be > 0)");
    const glm::dvec3 color = glm::clamp(read_color3(volume, "attenuationColor", glm::dvec3(1.0)), 0.0, 1.0);
    if (std::isfinite(distance) && (layers.flags & gpu::LAYERS_VOLUME)) {
        // sigma_a = -ln(c) / d per world unit (render space keeps world units); c = 0 absorbs everything.
        for (int i = 0; i < 3; ++i)
            layers.attenuation[i] = float(std::min(-std::log(std::max(color[i], 1e-300)) / distance, 1e30));
    }

    // KHR_materials_dispersion: 20 / Abbe number; it bends light by wavelength where the material bounds a volume.
    const tinygltf::Value* dispersion = find_extension(material, "KHR_materials_dispersion");
    const double strength = read_number(dispersion, "dispersion", 0.0);
    if (!(strength >= 0.0) || !std::isfinite(strength))
        throw SceneError(where + " has KHR_materials_dispersion dispersion " + std::to_string(strength) +
                         " (must be >= 0)");
    layers.dispersion = float(strength);
    return layers;
}

}  // namespace fh::gltf
