// load_gltf's material inputs beyond factors: texture slots (samplers, texCoord, KHR_texture_transform),
// alphaMode, vertex attributes for textures (TEXCOORD_n, COLOR_0, TANGENT with mirroring), KHR_mesh_quantization
// (a quantized copy loads to exactly the same arrays), the KTX2 fallback, and the scene's effect set by value.
#include <gtest/gtest.h>

#include <cmath>

#include "gltf_builder.h"
#include "scene/effects.h"
#include "scene/scene.h"

namespace {
using fh::Scene;
using fh::test::GltfBuilder;
namespace gpu = fh::gpu;

const fh::LoadOptions WORLD_SPACE = [] {
    fh::LoadOptions o;
    o.rebase = false;
    return o;
}();

// One triangle with TEXCOORD_0/1, COLOR_0 and TANGENT; material 0 uses `material`.
GltfBuilder make_textured_triangle(const nlohmann::json& material) {
    GltfBuilder b;
    const std::vector<glm::vec3> p = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    const std::vector<float> uv0 = {0.0f, 0.0f, 1.0f, 0.0f, 0.0f, 1.0f}, uv1 = {0.5f, 0.5f, 0.25f, 0.5f, 0.5f, 0.25f};
    const std::vector<float> colors = {1, 0, 0, 1, 0, 1, 0, 0.5f, 0, 0, 1, 0.25f};
    const std::vector<float> tangents = {1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1};
    nlohmann::json attributes = {
        {"POSITION", b.add_vec3(p)},
        {"TEXCOORD_0", b.add_accessor(b.add_view(uv0.data(), 24), 5126, 3, "VEC2")},
        {"TEXCOORD_1", b.add_accessor(b.add_view(uv1.data(), 24), 5126, 3, "VEC2")},
        {"COLOR_0", b.add_accessor(b.add_view(colors.data(), 48), 5126, 3, "VEC4")},
        {"TANGENT", b.add_accessor(b.add_view(tangents.data(), 48), 5126, 3, "VEC4")}};
    b.add_material(material);
    b.add_mesh({{"attributes", attributes}, {"material", 0}});
    b.doc["images"] = {{{"uri", "data:image/png;base64," + fh::test::encode_base64(fh::test::png_2x1())}}};
    b.doc["samplers"] = {{{"wrapS", 33648}, {"wrapT", 33071}, {"magFilter", 9728}}};
    b.doc["textures"] = {{{"source", 0}, {"sampler", 0}}};
    return b;
}

// The scene of one textured triangle of `material`.
Scene load_textured_triangle(const nlohmann::json& material) {
    GltfBuilder b = make_textured_triangle(material);
    b.set_scene({b.add_node({{"mesh", 0}})});
    return fh::load_gltf(b.write_gltf(), WORLD_SPACE);
}

// The effect bits among `mask` that the analysis switches on for one triangle of `material`.
fh::EffectBits analysed_effects_of(const nlohmann::json& material, fh::EffectBits mask) {
    return fh::analyse_effects(load_textured_triangle(material), false).bits & mask;
}

TEST(GltfTextures, ReadsSlotsSamplersTransformsAndTheImage) {
    nlohmann::json transform = {{"offset", {0.5, 0.25}}, {"rotation", 0.5}, {"scale", {2, 3}}, {"texCoord", 1}};
    nlohmann::json material;
    material["pbrMetallicRoughness"]["baseColorTexture"] = {{"index", 0}};
    material["pbrMetallicRoughness"]["baseColorTexture"]["extensions"]["KHR_texture_transform"] = transform;
    material["pbrMetallicRoughness"]["metallicRoughnessTexture"] = {{"index", 0}};
    material["normalTexture"] = {{"index", 0}, {"scale", 0.5}};
    material["alphaMode"] = "MASK";
    material["alphaCutoff"] = 0.3;
    GltfBuilder b = make_textured_triangle(material);
    b.set_scene({b.add_node({{"mesh", 0}})});
    const Scene s = fh::load_gltf(b.write_gltf(), WORLD_SPACE);
    ASSERT_EQ(s.images.size(), 1u);
    EXPECT_EQ(s.images[0].width, 2u);
    ASSERT_EQ(s.images[0].texels.size(), 2u);
    EXPECT_EQ(s.images[0].texels[0], 0xff0000ffu);  // opaque red, r in the low byte
    const gpu::Material& m = s.materials[0];
    EXPECT_EQ(m.alpha_mode, gpu::ALPHA_MASK);
    EXPECT_FLOAT_EQ(m.alpha_cutoff, 0.3f);
    ASSERT_LT(m.base_color_texture, s.texture_slots.size());
    const gpu::TextureSlot& base = s.texture_slots[m.base_color_texture];
    EXPECT_EQ(base.addressing, gpu::WRAP_MIRRORED_REPEAT | gpu::WRAP_CLAMP_TO_EDGE << 2 | gpu::SAMPLER_NEAREST |
                                   gpu::SAMPLER_SRGB | gpu::SAMPLER_TEXCOORD_1);
    // KHR_texture_transform: T(0.5, 0.25) R(0.5) S(2, 3): row u = (cos 2, sin 3, 0.5), row v = (-sin 2, cos 3, 0.25).
    EXPECT_NEAR(base.transform_u.x, std::cos(0.5) * 2, 1e-6);
    EXPECT_NEAR(base.transform_u.y, std::sin(0.5) * 3, 1e-6);
    EXPECT_NEAR(base.transform_u.z, 0.5, 1e-6);
    EXPECT_NEAR(base.transform_v.x, -std::sin(0.5) * 2, 1e-6);
    EXPECT_NEAR(base.transform_v.y, std::cos(0.5) * 3, 1e-6);
    EXPECT_NEAR(base.transform_v.z, 0.25, 1e-6);
    const gpu::TextureSlot& mr = s.texture_slots[m.metallic_roughness_texture];
    EXPECT_EQ(mr.addressing & (gpu::SAMPLER_SRGB | gpu::SAMPLER_TEXCOORD_1), 0u);  // linear data, TEXCOORD_0
    EXPECT_FLOAT_EQ(s.texture_slots[m.normal_texture].scale, 0.5f);
    EXPECT_EQ(m.emissive_texture, gpu::INVALID_INDEX);

    ASSERT_EQ(s.texcoords1.size(), 3u);
    EXPECT_EQ(s.texcoords1[1], glm::vec2(0.25f, 0.5f));
    EXPECT_EQ(s.colors[1], glm::vec4(0, 1, 0, 0.5f));
    EXPECT_EQ(s.tangents[2], glm::vec4(1, 0, 0, 1));

    const fh::SceneEffects effects = fh::analyse_effects(s, false);
    EXPECT_EQ(effects.bits, gpu::EFFECT_BASE_COLOR_TEXTURE | gpu::EFFECT_METALLIC_ROUGHNESS_TEXTURE |
                                gpu::EFFECT_NORMAL_TEXTURE | gpu::EFFECT_VERTEX_COLORS | gpu::EFFECT_ALPHA |
                                gpu::EFFECT_SPECULAR |  // glTF's default material: metallic 1, roughness 1
                                gpu::EFFECT_GGX_MULTISCATTER);  // a rough metal
}

// Effects are decided by value: a normal texture of scale 0, an opaque BLEND, white vertex colours and an
// emissive texture under a black emissiveFactor switch nothing on.
TEST(GltfTextures, EffectsAreDecidedByValue) {
    GltfBuilder b = make_textured_triangle({{"normalTexture", {{"index", 0}, {"scale", 0.0}}},
                                            {"emissiveTexture", {{"index", 0}}},
                                            {"alphaMode", "BLEND"}});
    b.set_scene({b.add_node({{"mesh", 0}})});
    Scene s = fh::load_gltf(b.write_gltf(), WORLD_SPACE);
    for (glm::vec4& c : s.colors) c = glm::vec4(1.0f);
    s.materials[0].specular_color.w = 0.0f;  // KHR_materials_specular specularFactor 0 and no metal: Lambertian
    s.materials[0].metallic = 0.0f;
    EXPECT_EQ(fh::analyse_effects(s, false).bits, 0u) << fh::describe_effects(fh::analyse_effects(s, false).bits);
    s.materials[0].base_color.a = 0.5f;  // now BLEND matters
    EXPECT_EQ(fh::analyse_effects(s, true).bits, gpu::EFFECT_ALPHA | gpu::EFFECT_ENVIRONMENT);
}

// The base's GGX reflection is an effect by value: a Lambertian material (metallic 0, specularFactor 0) does not ask
// for it, a specular layer or any metal does, and an unlit material never does (it is never evaluated).
TEST(GltfTextures, SpecularLobeIsDecidedByValue) {
    Scene s = load_textured_triangle({{"pbrMetallicRoughness", {{"metallicFactor", 0.0}}}});
    const uint32_t specular = gpu::EFFECT_SPECULAR;
    EXPECT_EQ(fh::analyse_effects(s, false).bits & specular, specular);  // glTF's default: a 4% specular layer
    s.materials[0].specular_color.w = 0.0f;
    EXPECT_EQ(fh::analyse_effects(s, false).bits & specular, 0u);
    s.materials[0].metallic = 0.1f;
    EXPECT_EQ(fh::analyse_effects(s, false).bits & specular, specular);
    s.materials[0].flags |= gpu::MATERIAL_UNLIT;
    EXPECT_EQ(fh::analyse_effects(s, false).bits & specular, 0u);
}

// The multiple-scattering lobe (--microfacet compensated) is an effect by value too: a metal, a specular layer or a
// clear coat of roughness above 0, or an anisotropic metal, asks for it; roughness 0 (nothing lost), Lambert alone or an unlit material do not; --microfacet
// single switches it off.
TEST(GltfTextures, GgxMultiscatterIsDecidedByValue) {
    Scene s = load_textured_triangle({{"pbrMetallicRoughness", {{"metallicFactor", 1.0}, {"roughnessFactor", 0.5}}}});
    const uint32_t multiscatter = gpu::EFFECT_GGX_MULTISCATTER;
    fh::SceneEffects effects = fh::analyse_effects(s, false);
    EXPECT_EQ(effects.bits & multiscatter, multiscatter);
    fh::decide_microfacet_effects(effects, true);
    EXPECT_EQ(effects.bits & multiscatter, multiscatter);
    fh::decide_microfacet_effects(effects, false);
    EXPECT_EQ(effects.bits & multiscatter, 0u);
    s.materials[0].roughness = 0.0f;
    EXPECT_EQ(fh::analyse_effects(s, false).bits & multiscatter, 0u);
    s.materials[0].roughness = 0.5f;
    s.materials[0].metallic = 0.0f;  // a rough dielectric specular layer has the lobe too
    EXPECT_EQ(fh::analyse_effects(s, false).bits & multiscatter, multiscatter);
    s.materials[0].specular_color.w = 0.0f;  // no specular layer: Lambert alone
    EXPECT_EQ(fh::analyse_effects(s, false).bits & multiscatter, 0u);
    s.materials[0].specular_color.w = 1.0f;
    s.materials[0].metallic = 1.0f;
    s.materials[0].flags |= gpu::MATERIAL_UNLIT;
    EXPECT_EQ(fh::analyse_effects(s, false).bits & multiscatter, 0u);
    // A rough clear coat over a smooth Lambertian base asks for its own lobe; a smooth coat does not.
    Scene coated = load_textured_triangle(
        {{"pbrMetallicRoughness", {{"metallicFactor", 0.0}, {"roughnessFactor", 0.0}}},
         {"extensions", {{"KHR_materials_clearcoat", {{"clearcoatFactor", 1.0}, {"clearcoatRoughnessFactor", 0.4}}}}}});
    EXPECT_EQ(fh::analyse_effects(coated, false).bits & multiscatter, multiscatter);
    coated.material_layers[0].clearcoat_roughness = 0.0f;
    EXPECT_EQ(fh::analyse_effects(coated, false).bits & multiscatter, 0u);
    // An anisotropic lobe of roughness 0 is rough along its direction, a metal's or a dielectric's specular layer's;
    // a Lambertian material (no specular layer) has none.
    Scene stretched = load_textured_triangle(
        {{"pbrMetallicRoughness", {{"metallicFactor", 1.0}, {"roughnessFactor", 0.0}}},
         {"extensions", {{"KHR_materials_anisotropy", {{"anisotropyStrength", 0.5}}}}}});
    EXPECT_EQ(fh::analyse_effects(stretched, false).bits & multiscatter, multiscatter);
    stretched.materials[0].metallic = 0.0f;
    EXPECT_EQ(fh::analyse_effects(stretched, false).bits & multiscatter, multiscatter);
    stretched.materials[0].specular_color.w = 0.0f;
    EXPECT_EQ(fh::analyse_effects(stretched, false).bits & multiscatter, 0u);
}

// KHR_materials_specular's textures go through the texture path: specularTexture linear (its alpha is the factor),
// specularColorTexture sRGB; no warning. They are an effect where the dielectric's specular layer shows.
TEST(GltfTextures, ReadsSpecularTextures) {
    const nlohmann::json material = {
        {"pbrMetallicRoughness", {{"metallicFactor", 0.0}}},
        {"extensions", {{"KHR_materials_specular", {{"specularTexture", {{"index", 0}}},
                                                    {"specularColorTexture", {{"index", 0}, {"texCoord", 1}}}}}}}};
    Scene s = load_textured_triangle(material);
    EXPECT_TRUE(s.warnings.empty()) << s.warnings.front();
    const gpu::Material& m = s.materials[0];
    ASSERT_LT(m.specular_texture, s.texture_slots.size());
    ASSERT_LT(m.specular_color_texture, s.texture_slots.size());
    EXPECT_EQ(s.texture_slots[m.specular_texture].addressing & gpu::SAMPLER_SRGB, 0u);
    EXPECT_EQ(s.texture_slots[m.specular_color_texture].addressing & (gpu::SAMPLER_SRGB | gpu::SAMPLER_TEXCOORD_1),
              gpu::SAMPLER_SRGB | gpu::SAMPLER_TEXCOORD_1);
    EXPECT_EQ(s.texcoords1.size(), 3u);  // the colour texture reads TEXCOORD_1
    EXPECT_EQ(fh::analyse_effects(s, false).bits & fh::EFFECT_SPECULAR_TEXTURE, fh::EFFECT_SPECULAR_TEXTURE);
    EXPECT_EQ(fh::analyse_effects(s, false).bits & fh::EFFECT_GLOSSINESS_TEXTURE, 0u);
    s.materials[0].specular_color.w = 0.0f;  // no specular layer: nothing to texture
    EXPECT_EQ(fh::analyse_effects(s, false).bits & fh::EFFECT_SPECULAR_TEXTURE, 0u);
    s.materials[0].specular_color.w = 1.0f;
    s.materials[0].metallic = 1.0f;  // all metal: the dielectric's layer never shows
    EXPECT_EQ(fh::analyse_effects(s, false).bits & fh::EFFECT_SPECULAR_TEXTURE, 0u);
}

// KHR_materials_pbrSpecularGlossiness maps onto a dielectric: diffuse -> base colour, metallic 0, roughness =
// 1 - glossiness, f0 = the specular colour (ior 0 with KHR_materials_specular's colour), the diffuse texture as the
// base colour texture and the specular-glossiness texture as the (sRGB) specular colour texture with glossiness in
// its alpha. It may be required; the metallic-roughness fallback is not read.
TEST(GltfTextures, SpecularGlossinessMapsOntoTheDielectric) {
    nlohmann::json material = {
        {"pbrMetallicRoughness", {{"baseColorFactor", {1, 0, 0, 1}}, {"metallicFactor", 1.0}}},
        {"extensions", {{"KHR_materials_pbrSpecularGlossiness",
                         {{"diffuseFactor", {0.5, 0.25, 0.125, 0.75}}, {"specularFactor", {0.9, 0.6, 0.3}},
                          {"glossinessFactor", 0.8}, {"diffuseTexture", {{"index", 0}}},
                          {"specularGlossinessTexture", {{"index", 0}}}}}}}};
    GltfBuilder b = make_textured_triangle(material);
    b.doc["extensionsUsed"] = {"KHR_materials_pbrSpecularGlossiness"};
    b.doc["extensionsRequired"] = {"KHR_materials_pbrSpecularGlossiness"};
    b.set_scene({b.add_node({{"mesh", 0}})});
    Scene s = fh::load_gltf(b.write_gltf(), WORLD_SPACE);
    EXPECT_TRUE(s.warnings.empty()) << s.warnings.front();
    const gpu::Material& m = s.materials[0];
    EXPECT_EQ(m.base_color, glm::vec4(0.5f, 0.25f, 0.125f, 0.75f));
    EXPECT_EQ(m.metallic, 0.0f);
    EXPECT_NEAR(m.roughness, 0.2f, 1e-7);
    EXPECT_EQ(m.ior, 0.0f);
    EXPECT_EQ(m.specular_color, glm::vec4(0.9f, 0.6f, 0.3f, 1.0f));
    EXPECT_EQ(m.metallic_roughness_texture, gpu::INVALID_INDEX);
    EXPECT_EQ(m.specular_texture, gpu::INVALID_INDEX);
    ASSERT_LT(m.base_color_texture, s.texture_slots.size());
    ASSERT_LT(m.specular_color_texture, s.texture_slots.size());
    EXPECT_NE(s.texture_slots[m.specular_color_texture].addressing & gpu::SAMPLER_SRGB, 0u);
    EXPECT_EQ(m.flags & gpu::MATERIAL_GLOSSINESS_IN_ALPHA, gpu::MATERIAL_GLOSSINESS_IN_ALPHA);
    const fh::EffectBits texture_effects = fh::EFFECT_SPECULAR_TEXTURE | fh::EFFECT_GLOSSINESS_TEXTURE;
    EXPECT_EQ(fh::analyse_effects(s, false).bits & texture_effects, texture_effects);
    s.materials[0].roughness = 1.0f;  // glossinessFactor 0: the texture's alpha multiplies 0
    EXPECT_EQ(fh::analyse_effects(s, false).bits & texture_effects, fh::EFFECT_SPECULAR_TEXTURE);
}

TEST(GltfTextures, MirroringFlipsTheBitangentSign) {
    GltfBuilder b = make_textured_triangle({{"normalTexture", {{"index", 0}}}});
    b.set_scene({b.add_node({{"mesh", 0}, {"scale", {-1, 1, 1}}})});
    const Scene s = fh::load_gltf(b.write_gltf(), WORLD_SPACE);
    ASSERT_EQ(s.tangents.size(), 3u);
    EXPECT_EQ(s.tangents[0], glm::vec4(-1, 0, 0, -1));
}

TEST(GltfTextures, QuantizedMeshLoadsToTheSameArrays) {
    // Plain: float positions k / 256 and texture coordinates k / 65535. Quantized: SHORT positions k under a
    // node scale of 1/256 (exact), normalized UNSIGNED_SHORT texture coordinates, normalized BYTE normals.
    const std::vector<int16_t> qp = {0, 0, 0, 0, 512, 0, 0, 0, 0, 300, -7, 0};  // 4-byte aligned: stride 8
    const std::vector<uint16_t> quv = {0, 0, 65535, 1000, 12345, 65535};
    const std::vector<int8_t> qn = {0, 0, 127, 0, 0, 0, 127, 0, 0, 0, 127, 0};
    std::vector<glm::vec3> p;
    for (int i = 0; i < 3; ++i) p.push_back(glm::vec3(qp[4 * i], qp[4 * i + 1], qp[4 * i + 2]) / 256.0f);
    std::vector<float> uv;
    for (uint16_t q : quv) uv.push_back(float(q) / 65535.0f);
    const nlohmann::json material = {{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}};

    GltfBuilder plain = make_textured_triangle(material);
    plain.doc["meshes"] = nlohmann::json::array();
    plain.add_mesh({{"attributes", {{"POSITION", plain.add_vec3(p)},
                                    {"NORMAL", plain.add_vec3({{0, 0, 1}, {0, 0, 1}, {0, 0, 1}})},
                                    {"TEXCOORD_0", plain.add_accessor(plain.add_view(uv.data(), 24), 5126, 3, "VEC2")}}},
                    {"material", 0}});
    plain.set_scene({plain.add_node({{"mesh", 0}})});

    GltfBuilder quantized = make_textured_triangle(material);
    quantized.doc["meshes"] = nlohmann::json::array();
    quantized.doc["extensionsUsed"] = {"KHR_mesh_quantization"};
    quantized.doc["extensionsRequired"] = {"KHR_mesh_quantization"};
    const int pos = quantized.add_accessor(quantized.add_view(qp.data(), 24, 8), 5122, 3, "VEC3");
    const int nrm = quantized.add_accessor(quantized.add_view(qn.data(), 12, 4), 5120, 3, "VEC3");
    const int tex = quantized.add_accessor(quantized.add_view(quv.data(), 12), 5123, 3, "VEC2");
    quantized.doc["accessors"][size_t(nrm)]["normalized"] = true;
    quantized.doc["accessors"][size_t(tex)]["normalized"] = true;
    quantized.add_mesh({{"attributes", {{"POSITION", pos}, {"NORMAL", nrm}, {"TEXCOORD_0", tex}}}, {"material", 0}});
    quantized.set_scene({quantized.add_node({{"mesh", 0}, {"scale", {1.0 / 256, 1.0 / 256, 1.0 / 256}}})});

    const Scene a = fh::load_gltf(plain.write_gltf(), WORLD_SPACE);
    const Scene q = fh::load_gltf(quantized.write_glb(), WORLD_SPACE);
    EXPECT_EQ(a.positions, q.positions);
    EXPECT_EQ(a.normals, q.normals);
    EXPECT_EQ(a.texcoords0, q.texcoords0);
}

TEST(GltfTextures, Ktx2WithoutFallbackIsWarnedAndLeftOut) {
    GltfBuilder b = make_textured_triangle({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}});
    const std::vector<unsigned char> ktx2 = {0xab, 'K', 'T', 'X', ' ', '2', '0', 0xbb, '\r', '\n', 0x1a, '\n', 0, 0, 0, 0};
    b.doc["images"].push_back({{"bufferView", b.add_view(ktx2.data(), ktx2.size())}, {"mimeType", "image/ktx2"}});
    b.doc["textures"] = {{{"extensions", {{"KHR_texture_basisu", {{"source", 1}}}}}}};
    b.doc["extensionsUsed"] = {"KHR_texture_basisu"};
    b.set_scene({b.add_node({{"mesh", 0}})});
    const Scene s = fh::load_gltf(b.write_gltf(), WORLD_SPACE);
    EXPECT_EQ(s.materials[0].base_color_texture, gpu::INVALID_INDEX);
    bool warned = false;
    for (const std::string& w : s.warnings) warned = warned || w.find("KHR_texture_basisu") != std::string::npos;
    EXPECT_TRUE(warned);
    // With a PNG fallback in `source`, the fallback is used.
    b.doc["textures"][0]["source"] = 0;
    const Scene f = fh::load_gltf(b.write_gltf(), WORLD_SPACE);
    EXPECT_NE(f.materials[0].base_color_texture, gpu::INVALID_INDEX);
}

}  // namespace

namespace {

TEST(GltfTextures, MaterialVariantsChooseThePrimitiveMaterial) {
    GltfBuilder b;
    b.add_material({{"pbrMetallicRoughness", {{"baseColorFactor", {1, 0, 0, 1}}}}});
    b.add_material({{"pbrMetallicRoughness", {{"baseColorFactor", {0, 1, 0, 1}}}}});
    b.add_material({{"pbrMetallicRoughness", {{"baseColorFactor", {0, 0, 1, 1}}}}});
    nlohmann::json prim = {{"attributes", {{"POSITION", b.add_vec3({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}})}}}, {"material", 0}};
    prim["extensions"]["KHR_materials_variants"]["mappings"] = {{{"material", 1}, {"variants", {0}}},
                                                                {{"material", 2}, {"variants", {1, 2}}}};
    b.add_mesh(prim);
    b.doc["extensions"]["KHR_materials_variants"]["variants"] = {{{"name", "green"}}, {{"name", "blue"}}, {{"name", "navy"}}};
    b.doc["extensionsUsed"] = {"KHR_materials_variants"};
    b.set_scene({b.add_node({{"mesh", 0}})});
    const auto path = b.write_gltf();
    auto load = [&](const std::string& variant) {
        fh::LoadOptions o = WORLD_SPACE;
        o.variant = variant;
        return fh::load_gltf(path, o);
    };
    EXPECT_EQ(load("").triangle_material[0], 0u);
    EXPECT_EQ(load("green").triangle_material[0], 1u);
    EXPECT_EQ(load("navy").triangle_material[0], 2u);
    EXPECT_EQ(load("").variants, (std::vector<std::string>{"green", "blue", "navy"}));
    try {
        load("red");
        ADD_FAILURE() << "an unknown variant loaded";
    } catch (const fh::SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("no material variant 'red' (KHR_materials_variants; the file has 'green', 'blue', 'navy')"),
                  std::string::npos) << e.what();
    }
}

}  // namespace

// ---- KHR_materials_transmission and KHR_materials_volume ------------------------------------------------------
namespace {

nlohmann::json glass_material(double transmission, double thickness, const nlohmann::json& volume_extra = {},
                              double metallic = 0.0) {
    nlohmann::json volume = {{"thicknessFactor", thickness}};
    for (const auto& [key, value] : volume_extra.items()) volume[key] = value;
    return {{"pbrMetallicRoughness", {{"metallicFactor", metallic}}},
            {"extensions",
             {{"KHR_materials_transmission", {{"transmissionFactor", transmission}, {"transmissionTexture", {{"index", 0}}}}},
              {"KHR_materials_volume", volume}}}};
}

}  // namespace

TEST(GltfTransmission, ReadsTransmissionAndVolume) {
    GltfBuilder b = make_textured_triangle(
        glass_material(0.7, 0.1, {{"attenuationColor", {0.5, 1.0, 0.25}}, {"attenuationDistance", 2.0}}));
    b.set_scene({b.add_node({{"mesh", 0}})});
    const Scene s = fh::load_gltf(b.write_gltf(), WORLD_SPACE);
    ASSERT_EQ(s.material_layers.size(), 1u);
    const gpu::MaterialLayers& l = s.material_layers[0];
    EXPECT_FLOAT_EQ(l.transmission, 0.7f);
    ASSERT_NE(l.transmission_texture, gpu::INVALID_INDEX);
    EXPECT_EQ(s.texture_slots[l.transmission_texture].addressing & gpu::SAMPLER_SRGB, 0u);  // data, not colour
    EXPECT_EQ(l.flags & gpu::LAYERS_VOLUME, gpu::LAYERS_VOLUME);
    EXPECT_NEAR(l.attenuation.x, -std::log(0.5) / 2.0, 1e-6);  // Beer-Lambert: -ln(colour) / distance
    EXPECT_EQ(l.attenuation.y, 0.0f);
    EXPECT_NEAR(l.attenuation.z, -std::log(0.25) / 2.0, 1e-6);
    const fh::EffectBits bits = fh::analyse_effects(s, false).bits;
    const uint32_t glass = gpu::EFFECT_TRANSMISSION | gpu::EFFECT_TRANSMISSION_TEXTURE | gpu::EFFECT_VOLUME |
                           gpu::EFFECT_ABSORPTION;
    EXPECT_EQ(bits & glass, glass) << fh::describe_effects(bits);
}

// Glass switches effects on by value: no transmission, all-metal, thickness 0 (thin-walled) and an infinite
// attenuationDistance (no absorption) each leave their effect off.
TEST(GltfTransmission, EffectsAreDecidedByValue) {
    const uint32_t glass = gpu::EFFECT_TRANSMISSION | gpu::EFFECT_TRANSMISSION_TEXTURE | gpu::EFFECT_VOLUME |
                           gpu::EFFECT_ABSORPTION;
    auto effects_of = [&](const nlohmann::json& material) { return analysed_effects_of(material, glass); };
    EXPECT_EQ(effects_of(glass_material(0.0, 1.0, {{"attenuationDistance", 1.0}})), 0u);
    EXPECT_EQ(effects_of(glass_material(1.0, 1.0, {{"attenuationDistance", 1.0}}, 1.0)), 0u);  // metal hides it
    EXPECT_EQ(effects_of(glass_material(1.0, 0.0, {{"attenuationDistance", 1.0}})),
              gpu::EFFECT_TRANSMISSION | gpu::EFFECT_TRANSMISSION_TEXTURE);  // thin-walled
    EXPECT_EQ(effects_of(glass_material(1.0, 1.0)),
              gpu::EFFECT_TRANSMISSION | gpu::EFFECT_TRANSMISSION_TEXTURE | gpu::EFFECT_VOLUME);  // clear volume
    // The forced/disabled selection touches material effects only.
    EXPECT_EQ(fh::select_effects(gpu::EFFECT_ENVIRONMENT, gpu::EFFECT_VOLUME, gpu::EFFECT_ENVIRONMENT),
              gpu::EFFECT_ENVIRONMENT | gpu::EFFECT_VOLUME);
}

// A transmissionTexture on TEXCOORD_1 of a primitive without it is refused like a core slot's would be.
TEST(GltfTransmission, RefusesATransmissionTextureWithoutItsTexcoords) {
    nlohmann::json material = glass_material(1.0, 0.0);
    material["extensions"]["KHR_materials_transmission"]["transmissionTexture"]["texCoord"] = 1;
    GltfBuilder b = make_textured_triangle(material);
    b.doc["meshes"][0]["primitives"][0]["attributes"].erase("TEXCOORD_1");
    b.set_scene({b.add_node({{"mesh", 0}})});
    fh::test::expect_load_refused(b.write_gltf(), "reads TEXCOORD_1");
}

TEST(GltfTransmission, RefusesANonPositiveAttenuationDistance) {
    GltfBuilder b = make_textured_triangle(glass_material(1.0, 1.0, {{"attenuationDistance", 0.0}}));
    b.set_scene({b.add_node({{"mesh", 0}})});
    fh::test::expect_load_refused(b.write_gltf(), "attenuationDistance");
}

// ---- KHR_materials_clearcoat --------------------------------------------------------------------------------
namespace {

nlohmann::json coat_material(double clearcoat, double roughness, int roughness_tex_coord = 0) {
    return {{"pbrMetallicRoughness", {{"metallicFactor", 1.0}}},
            {"extensions",
             {{"KHR_materials_clearcoat",
               {{"clearcoatFactor", clearcoat},
                {"clearcoatTexture", {{"index", 0}}},
                {"clearcoatRoughnessFactor", roughness},
                {"clearcoatRoughnessTexture", {{"index", 0}, {"texCoord", roughness_tex_coord}}},
                {"clearcoatNormalTexture", {{"index", 0}, {"scale", 0.5}}}}}}}};
}

TEST(GltfClearcoat, ReadsFactorsAndTextures) {
    GltfBuilder b = make_textured_triangle(coat_material(0.75, 0.25, 1));
    b.set_scene({b.add_node({{"mesh", 0}})});
    const Scene s = fh::load_gltf(b.write_gltf(), WORLD_SPACE);
    ASSERT_EQ(s.material_layers.size(), 1u);
    const gpu::MaterialLayers& l = s.material_layers[0];
    EXPECT_FLOAT_EQ(l.clearcoat, 0.75f);
    EXPECT_FLOAT_EQ(l.clearcoat_roughness, 0.25f);
    for (uint32_t slot : {l.clearcoat_texture, l.clearcoat_roughness_texture, l.clearcoat_normal_texture}) {
        ASSERT_LT(slot, s.texture_slots.size());
        EXPECT_EQ(s.texture_slots[slot].addressing & gpu::SAMPLER_SRGB, 0u);  // data, not colour
    }
    EXPECT_EQ(s.texture_slots[l.clearcoat_roughness_texture].addressing & gpu::SAMPLER_TEXCOORD_1,
              gpu::SAMPLER_TEXCOORD_1);
    EXPECT_FLOAT_EQ(s.texture_slots[l.clearcoat_normal_texture].scale, 0.5f);
    // A coat covers metal too: all three effects are on.
    const uint32_t coat = gpu::EFFECT_CLEARCOAT | gpu::EFFECT_CLEARCOAT_TEXTURE | gpu::EFFECT_CLEARCOAT_NORMAL_TEXTURE;
    EXPECT_EQ(fh::analyse_effects(s, false).bits & coat, coat);
}

// By value: clearcoatFactor 0 switches nothing on, whatever textures it names; a roughness texture under a
// roughness factor of 0 is not a texture effect.
TEST(GltfClearcoat, EffectsAreDecidedByValue) {
    const uint32_t coat = gpu::EFFECT_CLEARCOAT | gpu::EFFECT_CLEARCOAT_TEXTURE | gpu::EFFECT_CLEARCOAT_NORMAL_TEXTURE;
    auto effects_of = [&](const nlohmann::json& material) { return analysed_effects_of(material, coat); };
    EXPECT_EQ(effects_of(coat_material(0.0, 0.5)), 0u);
    nlohmann::json plain = coat_material(1.0, 0.0);
    plain["extensions"]["KHR_materials_clearcoat"].erase("clearcoatTexture");
    plain["extensions"]["KHR_materials_clearcoat"].erase("clearcoatNormalTexture");
    EXPECT_EQ(effects_of(plain), gpu::EFFECT_CLEARCOAT);
}

TEST(GltfClearcoat, RefusesACoatTextureWithoutItsTexcoords) {
    GltfBuilder b = make_textured_triangle(coat_material(1.0, 0.5, 1));
    b.doc["meshes"][0]["primitives"][0]["attributes"].erase("TEXCOORD_1");
    b.set_scene({b.add_node({{"mesh", 0}})});
    fh::test::expect_load_refused(b.write_gltf(), "reads TEXCOORD_1");
}

}  // namespace

// ---- KHR_materials_unlit ------------------------------------------------------------------------------------
namespace {

// Unlit keeps the base colour (and its texture) and drops emission, which would otherwise become a light.
TEST(GltfUnlit, FlagsTheMaterialAndDropsItsEmission) {
    GltfBuilder b = make_textured_triangle({{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}},
                                            {"emissiveFactor", {1.0, 0.5, 0.25}},
                                            {"emissiveTexture", {{"index", 0}}},
                                            {"extensions", {{"KHR_materials_unlit", nlohmann::json::object()}}}});
    b.set_scene({b.add_node({{"mesh", 0}})});
    const Scene s = fh::load_gltf(b.write_gltf(), WORLD_SPACE);
    ASSERT_EQ(s.materials.size(), 1u);
    EXPECT_EQ(s.materials[0].flags & gpu::MATERIAL_UNLIT, gpu::MATERIAL_UNLIT);
    EXPECT_EQ(s.materials[0].emission.x, 0.0f);
    EXPECT_NE(s.materials[0].base_color_texture, gpu::INVALID_INDEX);
    const fh::EffectBits bits = fh::analyse_effects(s, false).bits;
    EXPECT_NE(bits & gpu::EFFECT_UNLIT, 0u);
    EXPECT_EQ(bits & gpu::EFFECT_EMISSIVE_TEXTURE, 0u);
}

// An unlit material's layers are never evaluated, so they switch nothing on.
TEST(GltfUnlit, LayersOfAnUnlitMaterialSwitchNothingOn) {
    const uint32_t layers = gpu::EFFECT_CLEARCOAT | gpu::EFFECT_SHEEN | gpu::EFFECT_TRANSMISSION;
    const nlohmann::json extensions = {{"KHR_materials_clearcoat", {{"clearcoatFactor", 1.0}}},
                                       {"KHR_materials_sheen", {{"sheenColorFactor", {1.0, 1.0, 1.0}}}},
                                       {"KHR_materials_transmission", {{"transmissionFactor", 1.0}}}};
    nlohmann::json lit = {{"pbrMetallicRoughness", {{"metallicFactor", 0.0}}}, {"extensions", extensions}};
    EXPECT_EQ(analysed_effects_of(lit, layers), layers);
    lit["extensions"]["KHR_materials_unlit"] = nlohmann::json::object();
    EXPECT_EQ(analysed_effects_of(lit, layers), 0u);
}

}  // namespace

// ---- KHR_materials_sheen ------------------------------------------------------------------------------------
namespace {

nlohmann::json sheen_material(nlohmann::json color, double roughness, bool textured) {
    nlohmann::json sheen = {{"sheenColorFactor", color}, {"sheenRoughnessFactor", roughness}};
    if (textured) {
        sheen["sheenColorTexture"] = {{"index", 0}};
        sheen["sheenRoughnessTexture"] = {{"index", 0}};
    }
    return {{"extensions", {{"KHR_materials_sheen", sheen}}}};
}

// The factors land in MaterialLayers.sheen; the colour texture is sRGB (a colour), the roughness one is data.
TEST(GltfSheen, ReadsFactorsAndTextures) {
    const Scene s = load_textured_triangle(sheen_material({1.0, 0.5, 0.25}, 0.8, true));
    ASSERT_EQ(s.material_layers.size(), 1u);
    const gpu::MaterialLayers& l = s.material_layers[0];
    EXPECT_FLOAT_EQ(l.sheen.x, 1.0f);
    EXPECT_FLOAT_EQ(l.sheen.y, 0.5f);
    EXPECT_FLOAT_EQ(l.sheen.z, 0.25f);
    EXPECT_FLOAT_EQ(l.sheen.w, 0.8f);
    ASSERT_LT(l.sheen_color_texture, s.texture_slots.size());
    ASSERT_LT(l.sheen_roughness_texture, s.texture_slots.size());
    EXPECT_EQ(s.texture_slots[l.sheen_color_texture].addressing & gpu::SAMPLER_SRGB, gpu::SAMPLER_SRGB);
    EXPECT_EQ(s.texture_slots[l.sheen_roughness_texture].addressing & gpu::SAMPLER_SRGB, 0u);
    const uint32_t sheen = gpu::EFFECT_SHEEN | gpu::EFFECT_SHEEN_TEXTURE;
    EXPECT_EQ(fh::analyse_effects(s, false).bits & sheen, sheen);
}

// By value: a black sheenColorFactor switches nothing on, whatever textures it names.
TEST(GltfSheen, EffectsAreDecidedByValue) {
    const uint32_t sheen = gpu::EFFECT_SHEEN | gpu::EFFECT_SHEEN_TEXTURE;
    auto effects_of = [&](const nlohmann::json& material) { return analysed_effects_of(material, sheen); };
    EXPECT_EQ(effects_of(sheen_material({0.0, 0.0, 0.0}, 0.5, true)), 0u);
    EXPECT_EQ(effects_of(sheen_material({0.0, 0.1, 0.0}, 0.5, false)), gpu::EFFECT_SHEEN);
}

}  // namespace

// ---- KHR_materials_diffuse_transmission ---------------------------------------------------------------------
namespace {

nlohmann::json diffuse_material(double factor, bool textured, double metallic = 0.0) {
    nlohmann::json ext = {{"diffuseTransmissionFactor", factor}, {"diffuseTransmissionColorFactor", {0.5, 0.25, 1.0}}};
    if (textured) {
        ext["diffuseTransmissionTexture"] = {{"index", 0}};
        ext["diffuseTransmissionColorTexture"] = {{"index", 0}};
    }
    return {{"pbrMetallicRoughness", {{"metallicFactor", metallic}}},
            {"extensions", {{"KHR_materials_diffuse_transmission", ext}}}};
}

// The factor and colour land in MaterialLayers.diffuse_transmission; the colour texture is sRGB, the factor's data.
TEST(GltfDiffuseTransmission, ReadsFactorsAndTextures) {
    const Scene s = load_textured_triangle(diffuse_material(0.75, true));
    ASSERT_EQ(s.material_layers.size(), 1u);
    const gpu::MaterialLayers& l = s.material_layers[0];
    EXPECT_FLOAT_EQ(l.diffuse_transmission.w, 0.75f);
    EXPECT_FLOAT_EQ(l.diffuse_transmission.x, 0.5f);
    EXPECT_FLOAT_EQ(l.diffuse_transmission.y, 0.25f);
    EXPECT_FLOAT_EQ(l.diffuse_transmission.z, 1.0f);
    ASSERT_LT(l.diffuse_transmission_texture, s.texture_slots.size());
    ASSERT_LT(l.diffuse_transmission_color_texture, s.texture_slots.size());
    EXPECT_EQ(s.texture_slots[l.diffuse_transmission_texture].addressing & gpu::SAMPLER_SRGB, 0u);
    EXPECT_EQ(s.texture_slots[l.diffuse_transmission_color_texture].addressing & gpu::SAMPLER_SRGB, gpu::SAMPLER_SRGB);
    const uint32_t bits = gpu::EFFECT_DIFFUSE_TRANSMISSION | gpu::EFFECT_DIFFUSE_TRANSMISSION_TEXTURE;
    EXPECT_EQ(fh::analyse_effects(s, false).bits & bits, bits);
}

// By value: a factor of 0, or metal (which has no diffuse lobe), switches nothing on.
TEST(GltfDiffuseTransmission, EffectsAreDecidedByValue) {
    const uint32_t bits = gpu::EFFECT_DIFFUSE_TRANSMISSION | gpu::EFFECT_DIFFUSE_TRANSMISSION_TEXTURE;
    auto effects_of = [&](const nlohmann::json& material) { return analysed_effects_of(material, bits); };
    EXPECT_EQ(effects_of(diffuse_material(0.0, true)), 0u);
    EXPECT_EQ(effects_of(diffuse_material(1.0, false, 1.0)), 0u);
    EXPECT_EQ(effects_of(diffuse_material(1.0, false)), gpu::EFFECT_DIFFUSE_TRANSMISSION);
}

}  // namespace

// ---- KHR_materials_anisotropy -----------------------------------------------------------------------------
namespace {

nlohmann::json anisotropy_material(double strength, double rotation, bool textured, double roughness = 0.5) {
    nlohmann::json ext = {{"anisotropyStrength", strength}, {"anisotropyRotation", rotation}};
    if (textured) ext["anisotropyTexture"] = {{"index", 0}};
    return {{"pbrMetallicRoughness", {{"roughnessFactor", roughness}}},
            {"extensions", {{"KHR_materials_anisotropy", ext}}}};
}

// Strength and rotation (as its cosine and sine) land in MaterialLayers; the texture is data (linear).
TEST(GltfAnisotropy, ReadsFactorsAndTexture) {
    const Scene s = load_textured_triangle(anisotropy_material(0.6, 0.5, true));
    ASSERT_EQ(s.material_layers.size(), 1u);
    const gpu::MaterialLayers& l = s.material_layers[0];
    EXPECT_FLOAT_EQ(l.anisotropy_strength, 0.6f);
    EXPECT_FLOAT_EQ(l.anisotropy_cos, std::cos(0.5f));
    EXPECT_FLOAT_EQ(l.anisotropy_sin, std::sin(0.5f));
    ASSERT_LT(l.anisotropy_texture, s.texture_slots.size());
    EXPECT_EQ(s.texture_slots[l.anisotropy_texture].addressing & gpu::SAMPLER_SRGB, 0u);
    const uint32_t bits = gpu::EFFECT_ANISOTROPY | gpu::EFFECT_ANISOTROPY_TEXTURE;
    EXPECT_EQ(fh::analyse_effects(s, false).bits & bits, bits);
}

// By value: strength 0, or roughness 1 (alpha 1 stretched towards 1 stays isotropic), switches nothing on.
TEST(GltfAnisotropy, EffectsAreDecidedByValue) {
    const uint32_t bits = gpu::EFFECT_ANISOTROPY | gpu::EFFECT_ANISOTROPY_TEXTURE;
    auto effects_of = [&](const nlohmann::json& material) { return analysed_effects_of(material, bits); };
    EXPECT_EQ(effects_of(anisotropy_material(0.0, 0.0, true)), 0u);
    EXPECT_EQ(effects_of(anisotropy_material(1.0, 0.0, true, 1.0)), 0u);
    EXPECT_EQ(effects_of(anisotropy_material(0.5, 1.0, false)), gpu::EFFECT_ANISOTROPY);
}

}  // namespace

// ---- KHR_materials_iridescence --------------------------------------------------------------------------------
namespace {

nlohmann::json film_material(double factor, double thickest, bool textured, double thinnest = 100.0) {
    nlohmann::json ext = {{"iridescenceFactor", factor}, {"iridescenceIor", 1.7},
                          {"iridescenceThicknessMinimum", thinnest}, {"iridescenceThicknessMaximum", thickest}};
    if (textured) ext["iridescenceThicknessTexture"] = {{"index", 0}};
    return {{"extensions", {{"KHR_materials_iridescence", ext}}}};
}

// Factor, index, thicknesses and the texture land in MaterialLayers, with the host's bound of the film's Fresnel.
TEST(GltfIridescence, ReadsFactorsTextureAndBound) {
    const Scene s = load_textured_triangle(film_material(0.8, 450.0, true));
    ASSERT_EQ(s.material_layers.size(), 1u);
    const gpu::MaterialLayers& l = s.material_layers[0];
    EXPECT_FLOAT_EQ(l.iridescence, 0.8f);
    EXPECT_FLOAT_EQ(l.iridescence_ior, 1.7f);
    EXPECT_FLOAT_EQ(l.iridescence_thickness_min, 100.0f);
    EXPECT_FLOAT_EQ(l.iridescence_thickness_max, 450.0f);
    EXPECT_EQ(l.iridescence_texture, gpu::INVALID_INDEX);
    ASSERT_LT(l.iridescence_thickness_texture, s.texture_slots.size());
    EXPECT_EQ(s.texture_slots[l.iridescence_thickness_texture].addressing & gpu::SAMPLER_SRGB, 0u);
    EXPECT_GT(l.iridescence_albedo_f0, 0.0f);
    EXPECT_GE(l.iridescence_albedo_f90, 1.0f);
    const uint32_t bits = gpu::EFFECT_IRIDESCENCE | gpu::EFFECT_IRIDESCENCE_TEXTURE;
    EXPECT_EQ(fh::analyse_effects(s, false).bits & bits, bits);
}

// By value: factor 0, or a film of no thickness, switches nothing on.
TEST(GltfIridescence, EffectsAreDecidedByValue) {
    const uint32_t bits = gpu::EFFECT_IRIDESCENCE | gpu::EFFECT_IRIDESCENCE_TEXTURE;
    auto effects_of = [&](const nlohmann::json& material) { return analysed_effects_of(material, bits); };
    EXPECT_EQ(effects_of(film_material(0.0, 400.0, true)), 0u);
    EXPECT_EQ(effects_of(film_material(1.0, 0.0, false)), 0u);
    EXPECT_EQ(effects_of(film_material(1.0, 0.0, true, 0.0)), 0u);
    EXPECT_EQ(effects_of(film_material(1.0, 400.0, false)), gpu::EFFECT_IRIDESCENCE);
    EXPECT_EQ(effects_of(film_material(1.0, 0.0, true, 100.0)), bits);  // thin where the texture is 1, not where 0
}

// An index below 1 or a negative thickness is an error naming the material.
TEST(GltfIridescence, RejectsImpossibleFilms) {
    nlohmann::json bad_ior = film_material(1.0, 400.0, false);
    bad_ior["extensions"]["KHR_materials_iridescence"]["iridescenceIor"] = 0.5;
    EXPECT_THROW(load_textured_triangle(bad_ior), fh::SceneError);
    EXPECT_THROW(load_textured_triangle(film_material(1.0, -5.0, false)), fh::SceneError);
}

}  // namespace

namespace {

nlohmann::json dispersive_material(double dispersion, double transmission = 1.0, double thickness = 1.0) {
    nlohmann::json m = glass_material(transmission, thickness);
    m["extensions"]["KHR_materials_dispersion"] = {{"dispersion", dispersion}};
    return m;
}

// KHR_materials_dispersion is read, and switches the spectral path on only where it can bend light: a visible volume.
TEST(GltfDispersion, ReadsDispersionAndGoesSpectralOnlyForVolumes) {
    const Scene s = load_textured_triangle(dispersive_material(0.6));
    ASSERT_EQ(s.material_layers.size(), 1u);
    EXPECT_FLOAT_EQ(s.material_layers[0].dispersion, 0.6f);
    auto effects_of = [&](const nlohmann::json& material) { return analysed_effects_of(material, gpu::EFFECT_SPECTRAL); };
    EXPECT_EQ(effects_of(dispersive_material(0.6)), gpu::EFFECT_SPECTRAL);
    EXPECT_EQ(effects_of(dispersive_material(0.0)), 0u);            // no dispersion
    EXPECT_EQ(effects_of(dispersive_material(0.6, 0.0)), 0u);       // no glass
    EXPECT_EQ(effects_of(dispersive_material(0.6, 1.0, 0.0)), 0u);  // thin-walled: nothing bends
    EXPECT_EQ(effects_of(glass_material(1.0, 1.0)), 0u);
}

TEST(GltfDispersion, RejectsNegativeDispersion) {
    EXPECT_THROW(load_textured_triangle(dispersive_material(-0.1)), fh::SceneError);
}

}  // namespace
