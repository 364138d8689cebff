// Meshes as they ship: EXT_meshopt_compression (lossless and with KHR_mesh_quantization + filters) loads to the
// same arrays as the uncompressed copy; corrupt compressed streams are refused with the view named.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>

#include "gltf_builder.h"
#include "scene/scene.h"

namespace {

const std::filesystem::path MESHES = std::filesystem::path(FH_SOURCE_DIR) / "tests/unit/meshes";

fh::LoadOptions world_space() {
    fh::LoadOptions o;
    o.rebase = false;
    return o;
}

TEST(GltfCompression, MeshoptLoadsToTheSameArraysAsPlain) {
    const fh::Scene plain = fh::load_gltf(MESHES / "plain.glb", world_space());
    const fh::Scene packed = fh::load_gltf(MESHES / "meshopt.glb", world_space());
    ASSERT_EQ(plain.triangle_count(), 1280u);
    EXPECT_EQ(packed.positions, plain.positions);
    EXPECT_EQ(packed.normals, plain.normals);
    EXPECT_EQ(packed.triangle_material, plain.triangle_material);
}

TEST(GltfCompression, QuantizedMeshoptIsWithinItsQuantization) {
    const fh::Scene plain = fh::load_gltf(MESHES / "plain.glb", world_space());
    const fh::Scene packed = fh::load_gltf(MESHES / "meshopt_q.glb", world_space());
    ASSERT_EQ(packed.triangle_count(), plain.triangle_count());
    // Same triangles in the same order: positions within gltfpack's 14-bit grid over the unit sphere's box,
    // normals (octahedral, 8 bits) within a few degrees.
    for (size_t i = 0; i < plain.positions.size(); ++i) {
        EXPECT_NEAR(glm::length(packed.positions[i] - plain.positions[i]), 0.0f, 2e-3f) << "vertex " << i;
        EXPECT_GT(glm::dot(packed.normals[i], plain.normals[i]), 0.995f) << "vertex " << i;
    }
}

// A GLB whose JSON is changed by `edit` (written to the test's temp path).
std::filesystem::path edit_glb(const std::filesystem::path& source, const std::function<void(nlohmann::json&)>& edit) {
    std::ifstream in(source, std::ios::binary);
    std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    uint32_t json_length;
    std::memcpy(&json_length, bytes.data() + 12, 4);
    nlohmann::json doc = nlohmann::json::parse(bytes.begin() + 20, bytes.begin() + 20 + json_length);
    edit(doc);
    std::string json = doc.dump();
    while (json.size() % 4 != 0) json += ' ';
    std::vector<unsigned char> out(bytes.begin(), bytes.begin() + 12);
    const uint32_t length = uint32_t(json.size()), kind = 0x4E4F534Au;
    out.insert(out.end(), reinterpret_cast<const unsigned char*>(&length), reinterpret_cast<const unsigned char*>(&length) + 4);
    out.insert(out.end(), reinterpret_cast<const unsigned char*>(&kind), reinterpret_cast<const unsigned char*>(&kind) + 4);
    out.insert(out.end(), json.begin(), json.end());
    out.insert(out.end(), bytes.begin() + 20 + json_length, bytes.end());
    const uint32_t total = uint32_t(out.size());
    std::memcpy(out.data() + 8, &total, 4);
    const auto path = fh::test::temp_path(".glb");
    std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(out.data()), std::streamsize(out.size()));
    return path;
}

TEST(GltfCompression, CorruptMeshoptStreamsAreRefused) {
    auto ext = [](nlohmann::json& d) -> nlohmann::json& { return d["bufferViews"][0]["extensions"]["EXT_meshopt_compression"]; };
    fh::test::expect_load_refused(edit_glb(MESHES / "meshopt.glb", [&](nlohmann::json& d) { ext(d)["byteLength"] = 100; }),
                   "EXT_meshopt_compression of bufferView 0: the ATTRIBUTES stream cannot be decoded");
    fh::test::expect_load_refused(edit_glb(MESHES / "meshopt.glb", [&](nlohmann::json& d) { ext(d)["byteLength"] = 1u << 30; }),
                   "the compressed stream reaches past the end of buffer 0");
    fh::test::expect_load_refused(edit_glb(MESHES / "meshopt.glb", [&](nlohmann::json& d) { ext(d)["mode"] = "POINTS"; }),
                   "unknown mode 'POINTS'");
    fh::test::expect_load_refused(edit_glb(MESHES / "meshopt.glb", [&](nlohmann::json& d) { ext(d)["count"] = 100000; }),
                   "do not fit in the view");
    fh::test::expect_load_refused(edit_glb(MESHES / "meshopt.glb", [&](nlohmann::json& d) { d["buffers"][1]["byteLength"] = 1ull << 40; }),
                   "larger than the limit");
}

double total_area(const fh::Scene& s) {
    double area = 0.0;
    for (size_t t = 0; t < s.triangle_count(); ++t)
        area += 0.5 * glm::length(glm::cross(glm::dvec3(s.positions[3 * t + 1] - s.positions[3 * t]),
                                             glm::dvec3(s.positions[3 * t + 2] - s.positions[3 * t])));
    return area;
}

TEST(GltfCompression, LosslessDracoLoadsToTheSameArraysAsPlain) {
    const fh::Scene plain = fh::load_gltf(MESHES / "plain.glb", world_space());
    const fh::Scene packed = fh::load_gltf(MESHES / "draco_seq.glb", world_space());
    EXPECT_EQ(packed.positions, plain.positions);
    EXPECT_EQ(packed.normals, plain.normals);
}

TEST(GltfCompression, EdgebreakerDracoIsTheSameSurfaceWithinItsQuantization) {
    const fh::Scene plain = fh::load_gltf(MESHES / "plain.glb", world_space());
    const fh::Scene packed = fh::load_gltf(MESHES / "draco.glb", world_space());
    ASSERT_EQ(packed.triangle_count(), plain.triangle_count());  // reordered by Edgebreaker
    EXPECT_NEAR(total_area(packed), total_area(plain), 1e-3 * total_area(plain));
    for (const glm::vec3& p : packed.positions) EXPECT_NEAR(glm::length(p), 1.0f, 2e-3f);
}

TEST(GltfCompression, CorruptDracoStreamsAreRefused) {
    fh::test::expect_load_refused(edit_glb(MESHES / "draco.glb", [](nlohmann::json& d) { d["bufferViews"][0]["byteLength"] = 40; }),
                   "mesh 0 primitive 0: the Draco stream cannot be decoded");
    fh::test::expect_load_refused(edit_glb(MESHES / "draco.glb", [](nlohmann::json& d) {
                       d["meshes"][0]["primitives"][0]["extensions"]["KHR_draco_mesh_compression"]["attributes"]["NORMAL"] = 7;
                   }),
                   "the Draco stream has no attribute 7 (NORMAL)");
    fh::test::expect_load_refused(edit_glb(MESHES / "draco.glb", [](nlohmann::json& d) { d["accessors"][1]["count"] = 5; }),
                   "Draco attribute POSITION has 642 points, the accessor 5");
}

}  // namespace
