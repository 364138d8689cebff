// load_gltf: the shipped Cornell box, node transforms, primitive modes, accessors, materials and errors.
#include <chrono>
#include <cmath>
#include <limits>
#include <string>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "gltf_builder.h"
#include "scene/gltf/json_limits.h"
#include "scene/scene.h"

namespace {
using fh::Scene;
using fh::SceneError;
using fh::test::GltfBuilder;
using nlohmann::json;

const std::vector<glm::vec3> UNIT_TRIANGLE = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
// Positions in world space (no render-space origin), for the tests that check transforms.
const fh::LoadOptions WORLD_SPACE{.rebase = false};

glm::vec3 geometric_normal(const Scene& s, size_t t) {
    const glm::vec3* p = &s.positions[3 * t];
    return glm::normalize(glm::cross(p[1] - p[0], p[2] - p[0]));
}

// The message of the SceneError thrown by loading `path` ("" when none is thrown).
std::string load_error(const std::filesystem::path& path) {
    try {
        fh::load_gltf(path);
    } catch (const SceneError& e) {
        return e.what();
    }
    return "";
}

void expect_near(const glm::vec3& a, const glm::vec3& b, float eps = 1e-5f) {
    EXPECT_NEAR(a.x, b.x, eps);
    EXPECT_NEAR(a.y, b.y, eps);
    EXPECT_NEAR(a.z, b.z, eps);
}

TEST(GltfLoader, LoadsTheCornellBox) {
    const Scene s = fh::load_gltf(std::filesystem::path(FH_SOURCE_DIR) / "scenes/cornell.gltf");
    // floor 2 + ceiling with a hole 8 + back 2 + walls 2 + 2 + light 2 + two boxes 2 * 12.
    EXPECT_EQ(s.triangle_count(), 42u);
    EXPECT_EQ(s.positions.size(), 3 * 42u);
    EXPECT_EQ(s.normals.size(), 3 * 42u);
    EXPECT_TRUE(s.warnings.empty()) << s.warnings.front();
    ASSERT_EQ(s.materials.size(), 4u);
    const fh::gpu::Material& light = s.materials[3];
    EXPECT_NEAR(light.emission.r, 18.387f * 1.0f, 1e-4f);
    EXPECT_NEAR(light.emission.g, 18.387f * 0.7607168107902321f, 1e-4f);
    EXPECT_NEAR(light.emission.b, 18.387f * 0.36730135421765375f, 1e-4f);
    EXPECT_EQ(light.specular_color.a, 0.0f);  // specularFactor 0
    EXPECT_EQ(light.specular_color.r, 1.0f);  // specularColorFactor default
    EXPECT_FLOAT_EQ(s.materials[1].base_color.r, 0.570068f);
    EXPECT_EQ(s.materials[0].metallic, 0.0f);
    EXPECT_EQ(s.materials[0].ior, 1.5f);
    EXPECT_EQ(s.materials[0].flags, 0u);
    EXPECT_EQ(s.materials[0].base_color_texture, fh::gpu::INVALID_INDEX);
    size_t light_triangles = 0;
    for (size_t t = 0; t < s.triangle_count(); ++t) {
        light_triangles += s.triangle_material[t] == 3;
        EXPECT_EQ(s.triangle_has_normals[t], 1);
        // The shipped normals agree with the winding (checks TRS of the boxes and normal transforms).
        EXPECT_GT(glm::dot(geometric_normal(s, t), s.normals[3 * t]), 0.99f) << "triangle " << t;
    }
    EXPECT_EQ(light_triangles, 2u);
    ASSERT_EQ(s.cameras.size(), 1u);
    EXPECT_FALSE(s.cameras[0].orthographic);
    EXPECT_NEAR(s.cameras[0].yfov, 0.6860487863861751, 1e-12);
    EXPECT_EQ(s.cameras[0].world_from_camera[3], glm::dvec4(0.0, 0.0, 3.9, 1.0));
    for (int k = 0; k < 3; ++k) {  // the large box pokes 0.01 through the floor (y = -0.4 - 0.61)
        EXPECT_NEAR(s.bounds_min[k], k == 1 ? -1.01 : -1.0, 1e-6);
        EXPECT_NEAR(s.bounds_max[k], 1.0, 1e-6);
    }
}

TEST(GltfLoader, ComposesTrsAndMatrixHierarchyInOrder) {
    GltfBuilder b;
    const int mesh = b.add_simple_mesh(UNIT_TRIANGLE, {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}});
    // child: matrix translating by +1 in x (column-major); parent: T (1,2,3) * R (90 deg about z) * S 2.
    const int child = b.add_node({{"mesh", mesh}, {"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 1, 0, 0, 1}}});
    const double h = std::sqrt(0.5);
    const int parent = b.add_node({{"children", {child}}, {"translation", {1, 2, 3}}, {"rotation", {0, 0, h, h}},
                                   {"scale", {2, 2, 2}}});
    b.set_scene({parent});
    const Scene s = fh::load_gltf(b.write_gltf(), WORLD_SPACE);
    ASSERT_EQ(s.triangle_count(), 1u);
    // (0,0,0) -> +x (1,0,0) -> *2 (2,0,0) -> rot z (0,2,0) -> + (1,2,3)
    expect_near(s.positions[0], {1, 4, 3});
    expect_near(s.positions[1], {1, 6, 3});   // (1,0,0) -> (2,0,0) -> (4,0,0) -> (0,4,0)
    expect_near(s.positions[2], {-1, 4, 3});  // (0,1,0) -> (1,1,0) -> (2,2,0) -> (-2,2,0)
    expect_near(s.normals[0], {0, 0, 1});
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(s.bounds_min[k], glm::dvec3(-1, 4, 3)[k], 1e-12);  // double world
}

TEST(GltfLoader, TransformsNormalsByTheInverseTranspose) {
    GltfBuilder b;
    const glm::vec3 n = glm::normalize(glm::vec3(1, 1, 0));
    const int mesh = b.add_simple_mesh({{0, 0, 0}, {0, 0, 1}, {1, -1, 0}}, {n, n, n});
    b.set_scene({b.add_node({{"mesh", mesh}, {"scale", {2, 1, 1}}})});
    const Scene s = fh::load_gltf(b.write_gltf(), WORLD_SPACE);
    ASSERT_EQ(s.triangle_count(), 1u);
    expect_near(s.normals[1], glm::normalize(glm::vec3(1, 2, 0)));  // plane x + 2y = 0 after scaling
    EXPECT_NEAR(std::abs(glm::dot(geometric_normal(s, 0), s.normals[0])), 1.0f, 1e-6f);
}

TEST(GltfLoader, MirroringTransformsFlipTheWinding) {
    GltfBuilder b;
    const int mesh = b.add_simple_mesh(UNIT_TRIANGLE, {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}});
    b.set_scene({b.add_node({{"mesh", mesh}, {"scale", {-1, 1, 1}}}), b.add_node({{"mesh", mesh}, {"scale", {1, 1, -3}}})});
    const Scene s = fh::load_gltf(b.write_gltf(), WORLD_SPACE);
    ASSERT_EQ(s.triangle_count(), 2u);
    for (size_t t = 0; t < 2; ++t)
        EXPECT_NEAR(glm::dot(geometric_normal(s, t), s.normals[3 * t]), 1.0f, 1e-6f) << "triangle " << t;
    expect_near(s.normals[3], {0, 0, -1});
}

// Whether triangle p lists a, b, c in this cyclic order (the loader starts each triangle at its lowest vertex, so
// that an encoder's rotation of a triangle does not change the image).
bool is_rotation_of(const glm::vec3* p, glm::vec3 a, glm::vec3 b, glm::vec3 c) {
    for (int k = 0; k < 3; ++k)
        if (p[k] == a && p[(k + 1) % 3] == b && p[(k + 2) % 3] == c) return true;
    return false;
}

TEST(GltfLoader, ConvertsStripsAndFansWithConsistentWinding) {
    GltfBuilder b;
    const int strip = b.add_simple_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0, 2, 0}}, {}, {}, 5);
    const int fan = b.add_simple_mesh({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {-1, 1, 0}}, {}, {0, 1, 2, 3, 4}, 6);
    b.set_scene({b.add_node({{"mesh", strip}}), b.add_node({{"mesh", fan}})});
    const Scene s = fh::load_gltf(b.write_gltf(), WORLD_SPACE);
    ASSERT_EQ(s.triangle_count(), 6u);
    for (size_t t = 0; t < 6; ++t) expect_near(geometric_normal(s, t), {0, 0, 1});
    // The fan covers the unit square and the triangle to its left: area 1.5.
    float fan_area = 0.0f;
    for (size_t t = 3; t < 6; ++t) {
        const glm::vec3* p = &s.positions[3 * t];
        fan_area += 0.5f * glm::length(glm::cross(p[1] - p[0], p[2] - p[0]));
        // spec 3.7.2.1: fan triangles are (v[i+1], v[i+2], v[0]) (each started at its lowest vertex)
        const glm::vec3 v[5] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {-1, 1, 0}};
        EXPECT_TRUE(is_rotation_of(p, v[t - 2], v[t - 1], v[0])) << "triangle " << t;
    }
    EXPECT_FLOAT_EQ(fan_area, 1.5f);
}

TEST(GltfLoader, ReadsNonIndexedTrianglesAndSmallIndexTypes) {
    GltfBuilder b;
    const std::vector<glm::vec3> quad = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    const int plain = b.add_simple_mesh(quad);
    const int bytes = b.add_mesh({{"attributes", {{"POSITION", b.add_vec3(UNIT_TRIANGLE)}}},
                                  {"indices", b.add_indices(std::vector<uint8_t>{0, 1, 2})}});
    const int shorts = b.add_mesh({{"attributes", {{"POSITION", b.add_vec3(UNIT_TRIANGLE)}}},
                                   {"indices", b.add_indices(std::vector<uint16_t>{2, 1, 0})}});
    b.set_scene({b.add_node({{"mesh", plain}}), b.add_node({{"mesh", bytes}}), b.add_node({{"mesh", shorts}})});
    const Scene s = fh::load_gltf(b.write_gltf(), WORLD_SPACE);
    ASSERT_EQ(s.triangle_count(), 4u);
    EXPECT_TRUE(is_rotation_of(&s.positions[3], {0, 0, 0}, {1, 1, 0}, {0, 1, 0}));
    EXPECT_TRUE(is_rotation_of(&s.positions[6], {0, 0, 0}, {1, 0, 0}, {0, 1, 0}));
    EXPECT_TRUE(is_rotation_of(&s.positions[9], {0, 1, 0}, {1, 0, 0}, {0, 0, 0}));  // indices 2, 1, 0
    for (size_t t = 0; t < 4; ++t)  // each starts at its lexicographically lowest vertex
        EXPECT_EQ(s.positions[3 * t], glm::vec3(0, 0, 0)) << "triangle " << t;
}

TEST(GltfLoader, MissingNormalsMeanFlatShading) {
    GltfBuilder b;
    b.set_scene({b.add_node({{"mesh", b.add_simple_mesh(UNIT_TRIANGLE)}})});
    const Scene s = fh::load_gltf(b.write_gltf(), WORLD_SPACE);
    ASSERT_EQ(s.triangle_count(), 1u);
    EXPECT_EQ(s.triangle_has_normals[0], 0);
    EXPECT_EQ(s.normals[0], glm::vec3(0.0f));
    // No material: the glTF default material is appended.
    ASSERT_EQ(s.materials.size(), 1u);
    EXPECT_EQ(s.triangle_material[0], 0u);
    EXPECT_EQ(s.materials[0].metallic, 1.0f);
    EXPECT_EQ(s.materials[0].base_color, glm::vec4(1.0f));
}

TEST(GltfLoader, ReadsInterleavedStridedAndSparseAccessors) {
    GltfBuilder b;
    // Interleaved position + normal, stride 24.
    const std::vector<float> interleaved = {0, 0, 0, 0, 0, 1, 1, 0, 0, 0, 0, 1, 0, 1, 0, 0, 0, 1};
    const int view = b.add_view(interleaved.data(), interleaved.size() * 4, 24);
    const int pos = b.add_accessor(view, 5126, 3, "VEC3", 0);
    const int nrm = b.add_accessor(view, 5126, 3, "VEC3", 12);
    // Sparse: replace vertex 2 of the positions by (0, 5, 0).
    const std::vector<uint16_t> sparse_index = {2};
    const std::vector<float> sparse_value = {0, 5, 0};
    const int si = b.add_view(sparse_index.data(), 2), sv = b.add_view(sparse_value.data(), 12);
    const int sparse = b.add_accessor(view, 5126, 3, "VEC3", 0);
    b.doc["accessors"][sparse]["sparse"] = {{"count", 1},
                                            {"indices", {{"bufferView", si}, {"componentType", 5123}}},
                                            {"values", {{"bufferView", sv}}}};
    const int m1 = b.add_mesh({{"attributes", {{"POSITION", pos}, {"NORMAL", nrm}}}});
    const int m2 = b.add_mesh({{"attributes", {{"POSITION", sparse}}}});
    b.set_scene({b.add_node({{"mesh", m1}}), b.add_node({{"mesh", m2}})});
    const Scene s = fh::load_gltf(b.write_gltf(), WORLD_SPACE);
    ASSERT_EQ(s.triangle_count(), 2u);
    EXPECT_EQ(s.positions[1], glm::vec3(1, 0, 0));
    EXPECT_EQ(s.normals[2], glm::vec3(0, 0, 1));
    EXPECT_EQ(s.triangle_has_normals[0], 1);
    EXPECT_EQ(s.positions[4], glm::vec3(1, 0, 0));
    EXPECT_EQ(s.positions[5], glm::vec3(0, 5, 0));
}

TEST(GltfLoader, LoadsBinaryGlb) {
    GltfBuilder b;
    b.set_scene({b.add_node({{"mesh", b.add_simple_mesh(UNIT_TRIANGLE, {}, {0, 1, 2})}})});
    const Scene s = fh::load_gltf(b.write_glb(), WORLD_SPACE);
    ASSERT_EQ(s.triangle_count(), 1u);
    EXPECT_EQ(s.positions[2], glm::vec3(0, 1, 0));
}

TEST(GltfLoader, ReadsMaterialFactorsAndExtensions) {
    GltfBuilder b;
    const int mat = b.add_material(
        {{"pbrMetallicRoughness", {{"baseColorFactor", {0.1, 0.2, 0.3, 0.5}}, {"metallicFactor", 0.25}, {"roughnessFactor", 0.75}}},
         {"emissiveFactor", {1.0, 0.5, 0.25}},
         {"doubleSided", true},
         {"extensions",
          {{"KHR_materials_emissive_strength", {{"emissiveStrength", 4.0}}},
           {"KHR_materials_specular", {{"specularFactor", 0.5}, {"specularColorFactor", {0.2, 0.4, 0.6}}}},
           {"KHR_materials_ior", {{"ior", 1.33}}}}}});
    // Metadata (KHR_xmp_json_ld, and the archived KHR_xmp) has nothing to render: no warning.
    b.doc["extensionsUsed"] = {"KHR_materials_emissive_strength", "KHR_materials_specular", "KHR_materials_ior",
                               "EXT_something_new", "KHR_xmp_json_ld", "KHR_xmp"};
    b.set_scene({b.add_node({{"mesh", b.add_simple_mesh(UNIT_TRIANGLE, {}, {}, 4, mat)}})});
    const Scene s = fh::load_gltf(b.write_gltf(), WORLD_SPACE);
    ASSERT_EQ(s.materials.size(), 1u);
    const fh::gpu::Material& m = s.materials[0];
    EXPECT_EQ(m.base_color, glm::vec4(0.1f, 0.2f, 0.3f, 0.5f));
    EXPECT_EQ(m.metallic, 0.25f);
    EXPECT_EQ(m.roughness, 0.75f);
    EXPECT_EQ(m.emission, glm::vec4(4.0f, 2.0f, 1.0f, 0.0f));
    EXPECT_EQ(m.specular_color, glm::vec4(0.2f, 0.4f, 0.6f, 0.5f));
    EXPECT_EQ(m.ior, 1.33f);
    EXPECT_EQ(m.flags, fh::gpu::MATERIAL_DOUBLE_SIDED);
    ASSERT_EQ(s.warnings.size(), 1u);
    EXPECT_NE(s.warnings[0].find("EXT_something_new"), std::string::npos);
}

TEST(GltfLoader, ReadsCamerasFromTheirNodes) {
    GltfBuilder b;
    b.doc["cameras"] = {{{"type", "orthographic"}, {"name", "ortho"},
                         {"orthographic", {{"xmag", 2.0}, {"ymag", 1.5}, {"znear", 0.1}, {"zfar", 10.0}}}},
                        {{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 0.1}}}}};
    const int cam0 = b.add_node({{"camera", 0}, {"translation", {0, 0, 5}}});
    const int cam1 = b.add_node({{"camera", 1}, {"name", "eye"}, {"rotation", {0, 1, 0, 0}}});
    const int root = b.add_node({{"children", {cam0, cam1}}, {"translation", {1, 0, 0}}});
    b.set_scene({b.add_node({{"mesh", b.add_simple_mesh(UNIT_TRIANGLE)}}), root});
    const Scene s = fh::load_gltf(b.write_gltf(), WORLD_SPACE);
    ASSERT_EQ(s.cameras.size(), 2u);
    EXPECT_TRUE(s.cameras[0].orthographic);
    EXPECT_EQ(s.cameras[0].name, "ortho");
    EXPECT_EQ(s.cameras[0].xmag, 2.0);
    EXPECT_EQ(s.cameras[0].ymag, 1.5);
    EXPECT_EQ(s.cameras[0].world_from_camera[3], glm::dvec4(1, 0, 5, 1));
    EXPECT_FALSE(s.cameras[1].orthographic);
    EXPECT_EQ(s.cameras[1].name, "eye");
    EXPECT_EQ(s.cameras[1].yfov, 0.5);
    // Rotated 180 degrees about y: the camera's -Z looks down world +Z.
    const glm::dvec3 forward = -glm::dvec3(s.cameras[1].world_from_camera[2]);
    EXPECT_NEAR(forward.z, 1.0, 1e-12);
}

TEST(GltfLoader, SkipsPointsAndLinesAndNonFiniteTrianglesWithWarnings) {
    GltfBuilder b;
    const float nan = std::nanf("");
    const int lines = b.add_simple_mesh(UNIT_TRIANGLE, {}, {}, 1);
    const int points = b.add_simple_mesh(UNIT_TRIANGLE, {}, {}, 0);
    const int bad = b.add_simple_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {nan, 0, 0}, {1, 0, 0}, {0, 1, 0}});
    b.set_scene({b.add_node({{"mesh", lines}}), b.add_node({{"mesh", points}}), b.add_node({{"mesh", bad}})});
    const Scene s = fh::load_gltf(b.write_gltf(), WORLD_SPACE);
    EXPECT_EQ(s.triangle_count(), 1u);
    std::string all;
    for (const std::string& w : s.warnings) all += w + "\n";
    EXPECT_NE(all.find("LINES"), std::string::npos) << all;
    EXPECT_NE(all.find("POINTS"), std::string::npos) << all;
    EXPECT_NE(all.find("dropped 1 triangle"), std::string::npos) << all;
}

TEST(GltfLoader, RejectsAnOutOfRangeIndexNamingTheAccessor) {
    GltfBuilder b;
    b.set_scene({b.add_node({{"mesh", b.add_simple_mesh(UNIT_TRIANGLE, {}, {0, 1, 5})}})});
    const auto path = b.write_gltf();
    const std::string error = load_error(path);
    EXPECT_EQ(error.rfind(path.string() + ": ", 0), 0u) << error;
    EXPECT_NE(error.find("index 5"), std::string::npos) << error;
    EXPECT_NE(error.find("accessor 1"), std::string::npos) << error;
    EXPECT_NE(error.find("mesh 0"), std::string::npos) << error;
}

TEST(GltfLoader, RejectsAnAccessorOutsideItsBuffer) {
    GltfBuilder b;
    const int pos = b.add_vec3(UNIT_TRIANGLE);
    b.doc["accessors"][pos]["count"] = 4;
    b.set_scene({b.add_node({{"mesh", b.add_mesh({{"attributes", {{"POSITION", pos}}}})}})});
    const std::string error = load_error(b.write_gltf());
    EXPECT_NE(error.find("accessor 0"), std::string::npos) << error;
    EXPECT_NE(error.find("POSITION of mesh 0 primitive 0"), std::string::npos) << error;
}

TEST(GltfLoader, RejectsUnsupportedRequiredExtensions) {
    for (const char* name : {"EXT_fredholm_never_supported", "EXT_lights_image_based"}) {
        GltfBuilder b;
        b.doc["extensionsUsed"] = {name};
        b.doc["extensionsRequired"] = {name};
        b.set_scene({b.add_node({{"mesh", b.add_simple_mesh(UNIT_TRIANGLE)}})});
        const std::string error = load_error(b.write_gltf());
        EXPECT_NE(error.find(name), std::string::npos) << error;
    }
}

TEST(GltfLoader, RejectsCyclesNamingTheNode) {
    GltfBuilder b;
    const int mesh = b.add_simple_mesh(UNIT_TRIANGLE);
    b.add_node({{"name", "a"}, {"mesh", mesh}, {"children", {1}}});
    b.add_node({{"name", "b"}, {"children", {0}}});
    b.set_scene({0});
    const std::string error = load_error(b.write_gltf());
    EXPECT_NE(error.find("node 0 'a'"), std::string::npos) << error;
    EXPECT_NE(error.find("cycle"), std::string::npos) << error;
}

TEST(GltfLoader, RejectsMissingMalformedAndEmptyFiles) {
    const auto missing = fh::test::temp_path(".gltf");
    std::filesystem::remove(missing);
    EXPECT_NE(load_error(missing).find("not found"), std::string::npos);

    const auto broken = fh::test::temp_path("_broken.gltf");
    std::ofstream(broken) << "{ \"asset\": { \"version\": \"2.0\" }, \"nodes\": [ { \"mesh\": ";
    const std::string error = load_error(broken);
    EXPECT_NE(error.find("tinygltf"), std::string::npos) << error;
    EXPECT_EQ(error.find('\n'), std::string::npos) << error;

    GltfBuilder b;
    b.set_scene({b.add_node({{"name", "empty"}})});
    const std::string empty = load_error(b.write_gltf());
    EXPECT_NE(empty.find("no triangles"), std::string::npos) << empty;
}

TEST(GltfLoader, RejectsHugeCountsBeforeAllocating) {
    GltfBuilder b;
    const int pos = b.add_vec3(UNIT_TRIANGLE);
    b.doc["accessors"][pos]["count"] = uint64_t(1) << 40;
    b.set_scene({b.add_node({{"mesh", b.add_mesh({{"attributes", {{"POSITION", pos}}}})}})});
    const std::string error = load_error(b.write_gltf());
    EXPECT_NE(error.find("count 1099511627776 exceeds the limit"), std::string::npos) << error;
    EXPECT_NE(error.find("accessor 0"), std::string::npos) << error;
}

TEST(GltfLoader, DrawsASharedNodeOncePerParentWithAWarning) {
    GltfBuilder b;
    const int shared = b.add_node({{"mesh", b.add_simple_mesh(UNIT_TRIANGLE)}});
    const int left = b.add_node({{"children", {shared}}, {"translation", {-2, 0, 0}}});
    const int right = b.add_node({{"children", {shared}}, {"translation", {2, 0, 0}}});
    b.set_scene({left, right});
    const Scene s = fh::load_gltf(b.write_gltf(), WORLD_SPACE);
    EXPECT_EQ(s.triangle_count(), 2u);
    EXPECT_EQ(s.bounds_min.x, -2.0);
    EXPECT_EQ(s.bounds_max.x, 3.0);
    std::string all;
    for (const std::string& w : s.warnings) all += w + "\n";
    EXPECT_NE(all.find("1 node(s) have several parents (first: node 0)"), std::string::npos) << all;
}

TEST(GltfLoader, StopsExponentiallySharedHierarchies) {
    GltfBuilder b;
    const int mesh = b.add_simple_mesh(UNIT_TRIANGLE);
    for (int i = 0; i < 40; ++i) b.add_node({{"children", {i + 1, i + 1}}});
    b.add_node({{"mesh", mesh}});
    b.set_scene({0});
    const auto start = std::chrono::steady_clock::now();
    const std::string error = load_error(b.write_gltf());
    EXPECT_NE(error.find("node instances"), std::string::npos) << error;
    EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(10));
}

TEST(GltfLoader, RejectsATransformThatOverflowsNamingTheNode) {
    GltfBuilder b;
    const int leaf = b.add_node({{"name", "leaf"}, {"mesh", b.add_simple_mesh(UNIT_TRIANGLE)}, {"scale", {1e200, 1, 1}}});
    b.set_scene({b.add_node({{"children", {leaf}}, {"scale", {1e200, 1, 1}}})});
    const std::string error = load_error(b.write_gltf());
    EXPECT_NE(error.find("world transform of node 0 'leaf' is not finite"), std::string::npos) << error;
}

TEST(GltfLoader, CountsTrianglesWithNonFiniteNormalsAsFlatShaded) {
    GltfBuilder b;
    const float inf = std::numeric_limits<float>::infinity();
    b.set_scene({b.add_node({{"mesh", b.add_simple_mesh(UNIT_TRIANGLE, {{0, 0, 1}, {0, 0, inf}, {0, 0, 1}})}})});
    const Scene s = fh::load_gltf(b.write_gltf(), WORLD_SPACE);
    ASSERT_EQ(s.triangle_count(), 1u);
    EXPECT_EQ(s.triangle_has_normals[0], 0);
    std::string all;
    for (const std::string& w : s.warnings) all += w + "\n";
    EXPECT_NE(all.find("shaded 1 triangle(s) flat"), std::string::npos) << all;
}

TEST(GltfLoader, DefaultCameraFramesTheBounds) {
    Scene s;
    s.bounds_min = glm::dvec3(-1, -2, -3);
    s.bounds_max = glm::dvec3(3, 2, 1);
    const fh::SceneCamera c = fh::make_default_camera(s);
    EXPECT_FALSE(c.orthographic);
    EXPECT_NEAR(c.yfov, glm::radians(45.0), 1e-12);
    const glm::dvec3 eye(c.world_from_camera[3]);
    EXPECT_EQ(eye.x, 1.0);
    EXPECT_EQ(eye.y, 0.0);
    EXPECT_GT(eye.z, s.bounds_max.z);
    // The bounding sphere subtends at most the vertical field of view.
    const double radius = glm::length(s.bounds_max - s.bounds_min) / 2;
    EXPECT_LE(std::asin(radius / (eye.z - -1.0)), c.yfov / 2 + 1e-12);
    EXPECT_EQ(glm::dmat3(c.world_from_camera), glm::dmat3(1.0));  // looks down -Z, +Y up
}

}  // namespace

namespace {

// A unit triangle at `offset` (node translation), and its scene loaded with and without rebasing.
Scene load_translated_triangle(const glm::dvec3& offset, bool rebase) {
    GltfBuilder b;
    const int mesh = b.add_simple_mesh({{0.1f, 0.2f, 0.3f}, {1.3f, 0.2f, 0.3f}, {0.1f, 1.7f, 0.3f}});
    b.set_scene({b.add_node({{"mesh", mesh}, {"translation", {offset.x, offset.y, offset.z}}})});
    return fh::load_gltf(b.write_gltf(), fh::LoadOptions{.rebase = rebase});
}

}  // namespace

// Composed in double and rebased before rounding: a triangle moved far away keeps its float coordinates
// relative to the scene centre exactly, where world-space floats lose them.
TEST(GltfLoader, RebasingKeepsPrecisionFarFromTheOrigin) {
    const Scene near = load_translated_triangle({0, 0, 0}, true);
    const Scene far = load_translated_triangle({148376, 1234, -223423}, true);
    ASSERT_EQ(far.triangle_count(), 1u);
    for (int k = 0; k < 3; ++k) EXPECT_EQ(far.positions[k], near.positions[k]) << "vertex " << k;
    EXPECT_NEAR(far.origin.x - near.origin.x, 148376.0, 1e-9);
    EXPECT_NEAR(far.bounds_min.x, 148376.1, 1e-6);  // bounds stay in world space
    const Scene world = load_translated_triangle({148376, 1234, -223423}, false);
    EXPECT_EQ(world.origin, glm::dvec3(0.0));
    EXPECT_GT(std::abs((world.positions[1].x - world.positions[0].x) - 1.2f), 1e-3f);  // float ulp at 1.5e5 is 1/64
}

TEST(GltfLoader, DropsTrianglesWithoutAreaAndCountsThem) {
    GltfBuilder b;
    const std::vector<glm::vec3> positions = {
        {0, 0, 0}, {1, 0, 0}, {0, 1, 0},   // kept
        {0, 0, 0}, {1, 1, 1}, {2, 2, 2},   // collinear
        {3, 3, 3}, {3, 3, 3}, {4, 5, 6},   // repeated vertex
        {5, 5, 5}, {5, 5, 5}, {5, 5, 5}};  // a point
    b.set_scene({b.add_node({{"mesh", b.add_simple_mesh(positions)}})});
    const Scene s = fh::load_gltf(b.write_gltf());
    EXPECT_EQ(s.triangle_count(), 1u);
    bool warned = false;
    for (const std::string& w : s.warnings) warned = warned || w.find("dropped 3 triangle(s) without area") != std::string::npos;
    EXPECT_TRUE(warned);
}

TEST(GltfLoader, ReadsPunctualLightsWithTheirNodeTransforms) {
    GltfBuilder b;
    const int mesh = b.add_simple_mesh(UNIT_TRIANGLE);
    b.doc["extensionsUsed"] = {"KHR_lights_punctual"};
    b.doc["extensions"]["KHR_lights_punctual"]["lights"] = {
        {{"type", "point"}, {"color", {1.0, 0.5, 0.25}}, {"intensity", 8.0}},
        {{"type", "spot"}, {"intensity", 2.0}, {"spot", {{"innerConeAngle", 0.2}, {"outerConeAngle", 0.5}}}},
        {{"type", "directional"}, {"intensity", 3.0}}};
    const double h = std::sqrt(0.5);  // 90 degrees about x: local -Z becomes +Y... (0,0,-1) -> (0,1,0)
    b.set_scene({b.add_node({{"mesh", mesh}}),
                 b.add_node({{"translation", {1, 2, 3}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}}),
                 b.add_node({{"rotation", {h, 0, 0, h}}, {"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}}),
                 b.add_node({{"extensions", {{"KHR_lights_punctual", {{"light", 2}}}}}})});
    const Scene s = fh::load_gltf(b.write_gltf(), WORLD_SPACE);
    ASSERT_EQ(s.lights.size(), 3u);
    EXPECT_EQ(s.lights[0].type, fh::gpu::LIGHT_POINT);
    EXPECT_EQ(s.lights[0].position, glm::dvec3(1, 2, 3));
    EXPECT_EQ(s.lights[0].intensity, glm::vec3(8.0f, 4.0f, 2.0f));
    EXPECT_EQ(s.lights[1].type, fh::gpu::LIGHT_SPOT);
    EXPECT_NEAR(s.lights[1].direction.y, 1.0, 1e-12);
    EXPECT_FLOAT_EQ(s.lights[1].outer_cone, 0.5f);
    EXPECT_EQ(s.lights[2].type, fh::gpu::LIGHT_DIRECTIONAL);
    EXPECT_EQ(s.lights[2].direction, glm::dvec3(0, 0, -1));
}

// KHR_node_visibility: visible false hides the node's meshes and lights and its descendants', even one marked
// visible; cameras stay. A visible node and a node without the extension draw.
TEST(GltfLoader, NodeVisibilityHidesMeshesAndLightsOfASubtree) {
    GltfBuilder b;
    const int mesh = b.add_simple_mesh(UNIT_TRIANGLE);
    b.doc["extensionsUsed"] = {"KHR_lights_punctual", "KHR_node_visibility"};
    b.doc["extensionsRequired"] = {"KHR_node_visibility"};
    b.doc["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "point"}, {"intensity", 1.0}}};
    b.doc["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 0.1}}}}};
    const nlohmann::json hidden = {{"KHR_node_visibility", {{"visible", false}}}};
    const nlohmann::json shown = {{"KHR_node_visibility", {{"visible", true}}}};
    const int child_mesh = b.add_node({{"mesh", mesh}, {"extensions", shown}});
    const int child_light = b.add_node({{"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
    const int child_camera = b.add_node({{"camera", 0}});
    const int hidden_root = b.add_node({{"mesh", mesh}, {"extensions", hidden},
                                        {"children", {child_mesh, child_light, child_camera}}});
    b.set_scene({hidden_root, b.add_node({{"mesh", mesh}})});  // a scene with nothing to draw is refused
    Scene s = fh::load_gltf(b.write_gltf(), WORLD_SPACE);
    EXPECT_EQ(s.triangle_count(), 1u);
    EXPECT_TRUE(s.lights.empty());
    EXPECT_EQ(s.cameras.size(), 1u);
    EXPECT_TRUE(s.warnings.empty()) << s.warnings.front();
    b.doc["nodes"][size_t(hidden_root)]["extensions"] = shown;
    s = fh::load_gltf(b.write_gltf(), WORLD_SPACE);
    EXPECT_EQ(s.triangle_count(), 3u);
    EXPECT_EQ(s.lights.size(), 1u);
    b.doc["nodes"][size_t(hidden_root)].erase("extensions");
    s = fh::load_gltf(b.write_gltf(), WORLD_SPACE);
    EXPECT_EQ(s.triangle_count(), 3u);
    b.doc["nodes"][size_t(hidden_root)]["extensions"] = {{"KHR_node_visibility", {{"visible", 3}}}};
    const std::string error = load_error(b.write_gltf());
    EXPECT_NE(error.find("KHR_node_visibility visible is not true or false"), std::string::npos) << error;
}

TEST(GltfLoader, RejectsAMissingLightWithItsNode) {
    GltfBuilder b;
    const int mesh = b.add_simple_mesh(UNIT_TRIANGLE);
    b.set_scene({b.add_node({{"mesh", mesh}, {"extensions", {{"KHR_lights_punctual", {{"light", 4}}}}}})});
    const std::string error = load_error(b.write_gltf());
    EXPECT_NE(error.find("node 0: KHR_lights_punctual light 4"), std::string::npos) << error;
}

// The nesting count the loader checks before tinygltf parses (a 30,000-level file overflowed its stack).
TEST(JsonLimits, CountsNestingOutsideStringsOnly) {
    EXPECT_EQ(fh::json_nesting_depth(R"({"a": [1, {"b": []}]})"), 4u);
    EXPECT_EQ(fh::json_nesting_depth(R"({"a": "[[[[{{{{", "b": "\\"})"), 1u);  // brackets in strings, escaped backslash
    EXPECT_EQ(fh::json_nesting_depth(R"(["\"[[[["])"), 1u);                     // an escaped quote stays in the string
    EXPECT_EQ(fh::json_nesting_depth("]]]][[]"), 2u);                              // stray closers do not go below zero
    const std::string deep = std::string(5000, '[') + std::string(5000, ']');
    EXPECT_EQ(fh::json_nesting_depth(deep, 100), 101u);  // stops counting past the limit
    EXPECT_NO_THROW(fh::check_json_nesting(std::string(fh::MAX_JSON_DEPTH, '['), "x"));
    EXPECT_THROW(fh::check_json_nesting(std::string(fh::MAX_JSON_DEPTH + 1, '{'), "x"), fh::SceneError);
}
