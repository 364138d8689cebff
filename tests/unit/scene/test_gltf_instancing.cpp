// Instancing without copies: a mesh drawn by several nodes, or by EXT_mesh_gpu_instancing, is stored once and
// placed by instances (scene/instancing.h decides when); the two-level BVH over them (scene_bvh.h).
#include <gtest/gtest.h>

#include <filesystem>
#include <set>

#include <glm/gtc/matrix_transform.hpp>

#include "gltf_builder.h"
#include "scene/effects.h"
#include "scene/pack.h"
#include "scene/bvh/wide_bvh.h"
#include "scene/scene.h"
#include "scene/bvh/scene_bvh.h"

namespace {

using fh::Instancing;
using fh::Scene;
using fh::test::GltfBuilder;

const std::vector<glm::vec3> UNIT_TRIANGLE = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};

fh::LoadOptions options(Instancing instancing) {
    fh::LoadOptions o;
    o.rebase = false;
    o.instancing = instancing;
    return o;
}

// A mesh of UNIT_TRIANGLE drawn by nodes translated by (2 i, 0, 0), and a floor triangle of its own.
std::filesystem::path shared_mesh_scene(int nodes, int material = -1) {
    GltfBuilder b;
    const int mesh = b.add_simple_mesh(UNIT_TRIANGLE, {}, {}, 4, material);
    std::vector<int> roots{b.add_node({{"mesh", b.add_simple_mesh({{0, -1, 0}, {0, -1, 1}, {1, -1, 0}})}})};
    for (int i = 0; i < nodes; ++i) roots.push_back(b.add_node({{"mesh", mesh}, {"translation", {2.0 * i, 0.0, 0.0}}}));
    b.set_scene(roots);
    return b.write_gltf();
}

TEST(GltfInstancing, SharedMeshIsStoredOnceWithOneInstancePerNode) {
    const Scene s = fh::load_gltf(shared_mesh_scene(3), options(Instancing::always));
    EXPECT_EQ(s.world_triangle_count, 1u);
    EXPECT_EQ(s.triangle_count(), 2u);
    ASSERT_EQ(s.meshes.size(), 1u);
    EXPECT_EQ(s.meshes[0].first_triangle, 1u);
    EXPECT_EQ(s.meshes[0].triangle_count, 1u);
    ASSERT_EQ(s.instances.size(), 3u);
    EXPECT_EQ(s.rendered_triangle_count(), 4u);
    for (int i = 0; i < 3; ++i)  // render space = world space here (no rebase)
        EXPECT_EQ(s.instances[size_t(i)].render_from_object, glm::translate(glm::dmat4(1.0), glm::dvec3(2.0 * i, 0, 0)));
    EXPECT_EQ(s.positions[3], glm::vec3(0, 0, 0));  // the mesh in object space
    EXPECT_EQ(s.bounds_max, glm::dvec3(5, 1, 1));   // bounds cover every instance
    EXPECT_EQ(s.unique_triangle_count, 2u);

    const Scene flat = fh::load_gltf(shared_mesh_scene(3), options(Instancing::never));
    EXPECT_TRUE(flat.instances.empty());
    EXPECT_EQ(flat.triangle_count(), 4u);
    EXPECT_EQ(flat.rendered_triangle_count(), 4u);
    EXPECT_EQ(flat.positions[3 * 3], glm::vec3(4, 0, 0));
}

TEST(GltfInstancing, AutomaticInstancesOnlyWhenCopiesSaveEnoughTriangles) {
    EXPECT_TRUE(fh::load_gltf(shared_mesh_scene(3), options(Instancing::automatic)).instances.empty());
    // (uses - 1) x triangles >= MIN_TRIANGLES_SAVED_BY_INSTANCING: a mesh of 8192 triangles drawn 3 times.
    std::vector<glm::vec3> strip;
    for (int t = 0; t < 8192; ++t)
        for (const glm::vec3& p : UNIT_TRIANGLE) strip.push_back(p + glm::vec3(float(t), 0, 0));
    GltfBuilder b;
    const int mesh = b.add_simple_mesh(strip);
    b.set_scene({b.add_node({{"mesh", mesh}}), b.add_node({{"mesh", mesh}, {"translation", {0, 2, 0}}}),
                 b.add_node({{"mesh", mesh}, {"translation", {0, 4, 0}}})});
    const Scene s = fh::load_gltf(b.write_gltf(), options(Instancing::automatic));
    EXPECT_EQ(s.instances.size(), 3u);
    EXPECT_EQ(s.triangle_count(), 8192u);
    EXPECT_EQ(s.rendered_triangle_count(), 3u * 8192u);
}

TEST(GltfInstancing, EmissiveMeshesAreCopiedSoThatLightsStayInWorldSpace) {
    GltfBuilder b;
    const int light = b.add_material({{"emissiveFactor", {1.0, 1.0, 1.0}}});
    const int mesh = b.add_simple_mesh(UNIT_TRIANGLE, {}, {}, 4, light);
    b.set_scene({b.add_node({{"mesh", mesh}}), b.add_node({{"mesh", mesh}, {"translation", {2, 0, 0}}})});
    const Scene s = fh::load_gltf(b.write_gltf(), options(Instancing::always));
    EXPECT_TRUE(s.instances.empty());
    EXPECT_EQ(s.triangle_count(), 2u);
}

// One node drawing UNIT_TRIANGLE through EXT_mesh_gpu_instancing with `attributes` (accessor JSON built by `add`).
std::filesystem::path gpu_instanced(const std::function<nlohmann::json(GltfBuilder&)>& attributes) {
    GltfBuilder b;
    const int mesh = b.add_simple_mesh(UNIT_TRIANGLE);
    b.doc["extensionsUsed"] = {"EXT_mesh_gpu_instancing"};
    b.set_scene({b.add_node({{"mesh", mesh}, {"translation", {0, 0, 1}},
                             {"extensions", {{"EXT_mesh_gpu_instancing", {{"attributes", attributes(b)}}}}}})});
    return b.write_gltf();
}

TEST(GltfInstancing, GpuInstancingPlacesEveryElementUnderItsNode) {
    const auto file = gpu_instanced([](GltfBuilder& b) {
        const std::vector<glm::vec3> t{{0, 0, 0}, {10, 0, 0}, {20, 0, 0}, {30, 0, 0}};
        const std::vector<glm::vec3> s{{1, 1, 1}, {2, 2, 2}, {1, 1, 1}, {-1, 1, 1}};
        return nlohmann::json{{"TRANSLATION", b.add_vec3(t)}, {"SCALE", b.add_vec3(s)}};
    });
    const Scene s = fh::load_gltf(file, options(Instancing::always));
    ASSERT_EQ(s.instances.size(), 4u);
    EXPECT_EQ(s.triangle_count(), 1u);
    // node world (translation z 1) x instance (translation, scale)
    EXPECT_EQ(s.instances[1].render_from_object * glm::dvec4(1, 1, 0, 1), glm::dvec4(12, 2, 1, 1));
    const Scene flat = fh::load_gltf(file, options(Instancing::never));
    ASSERT_EQ(flat.triangle_count(), 4u);
    // The mirrored copy: triangles start at their lowest vertex in object space, (0, 0, 0).
    EXPECT_EQ(flat.positions[3 * 3], glm::vec3(30, 0, 1));
}

TEST(GltfInstancing, GpuInstancingRefusesInconsistentAttributes) {
    fh::test::expect_load_refused(gpu_instanced([](GltfBuilder& b) {
                       return nlohmann::json{{"TRANSLATION", b.add_vec3({{0, 0, 0}, {1, 0, 0}})},
                                             {"SCALE", b.add_vec3({{1, 1, 1}})}};
                   }),
                   "EXT_mesh_gpu_instancing of node 0: SCALE has 1 elements, the other attributes 2");
    fh::test::expect_load_refused(gpu_instanced([](GltfBuilder&) { return nlohmann::json::object(); }),
                   "EXT_mesh_gpu_instancing of node 0 has no");
    fh::test::expect_load_refused(gpu_instanced([](GltfBuilder& b) {
                       const std::vector<glm::vec4> q{{0, 0, 0, 0}};
                       return nlohmann::json{{"ROTATION", b.add_accessor(b.add_view(q.data(), 16), 5126, 1, "VEC4")}};
                   }),
                   "ROTATION 0 is not a rotation");
    fh::test::expect_load_refused(gpu_instanced([](GltfBuilder& b) { return nlohmann::json{{"TRANSLATION", b.add_accessor(-1, 5126, 1u << 30, "VEC3")}}; }),
                   "1073741824 instances take the scene past 4194304 node instances");
}

TEST(GltfInstancing, TwoLevelBvhReachesEveryTriangleThroughItsInstances) {
    const Scene s = fh::load_gltf(shared_mesh_scene(5), options(Instancing::always));
    const fh::SceneBvh bvh = fh::build_scene_bvh(s, fh::BvhOptions{});
    ASSERT_EQ(bvh.instances.size(), 6u);  // the world triangles' identity instance and five
    std::multiset<uint32_t> order(bvh.triangle_order.begin(), bvh.triangle_order.end());
    EXPECT_EQ(order, (std::multiset<uint32_t>{0, 1}));
    std::set<uint32_t> leaves;
    for (const fh::gpu::BvhWideNode& w : bvh.nodes)
        for (uint32_t k = 0; k < fh::gpu::BVH_WIDTH; ++k) {
            const fh::WideChild c = fh::read_wide_child(w, k);
            if (c.count == fh::gpu::WIDE_INSTANCE_COUNT) leaves.insert(c.index);
        }
    EXPECT_EQ(leaves, (std::set<uint32_t>{0, 1, 2, 3, 4, 5}));
    for (const fh::gpu::Instance& inst : bvh.instances) EXPECT_LT(inst.root_node, bvh.nodes.size());
    EXPECT_THROW(fh::pack_scene(s, fh::build_bvh(s.positions)), std::invalid_argument);
    EXPECT_EQ(fh::pack_scene(s, bvh).instances.size(), 6u);
}

// The memory criterion: MetalRoughSpheresNoTextures draws one sphere 98 times.
TEST(GltfInstancing, MetalRoughSpheresStoreAboutOneNinetyEighthOfTheTriangles) {
    const std::filesystem::path file = std::filesystem::path(FH_SOURCE_DIR) /
                                       "../shared/scenes-thirdparty/MetalRoughSpheresNoTextures/glTF/MetalRoughSpheresNoTextures.gltf";
    if (!std::filesystem::exists(file)) GTEST_SKIP() << file << " is not in this checkout";
    const Scene instanced = fh::load_gltf(file, options(Instancing::automatic));
    const Scene flat = fh::load_gltf(file, options(Instancing::never));
    EXPECT_EQ(instanced.rendered_triangle_count(), flat.triangle_count());
    EXPECT_GT(flat.triangle_count(), 1000000u);
    EXPECT_GE(instanced.instances.size(), 98u);
    const double ratio = double(instanced.triangle_count()) / double(flat.triangle_count());
    EXPECT_LT(ratio, 1.5 / 98.0) << instanced.triangle_count() << " of " << flat.triangle_count();
    const fh::PackedScene a = fh::pack_scene(instanced, fh::build_scene_bvh(instanced, {}));
    const fh::PackedScene b = fh::pack_scene(flat, fh::build_scene_bvh(flat, {}));
    const double bytes_a = double(a.positions.size() * sizeof(a.positions[0]) + a.shading.size() * sizeof(a.shading[0]) +
                                  a.nodes.size() * sizeof(a.nodes[0]) + a.instances.size() * sizeof(a.instances[0]));
    const double bytes_b = double(b.positions.size() * sizeof(b.positions[0]) + b.shading.size() * sizeof(b.shading[0]) +
                                  b.nodes.size() * sizeof(b.nodes[0]));
    EXPECT_LT(bytes_a / bytes_b, 1.5 / 98.0);
    std::printf("MetalRoughSpheresNoTextures: %zu stored of %zu rendered triangles; scene buffers %.2f MiB vs %.2f MiB "
                "flattened (%.4f)\n", instanced.triangle_count(), flat.triangle_count(), bytes_a / 1048576.0,
                bytes_b / 1048576.0, bytes_a / bytes_b);
}

}  // namespace

namespace {

// Instances of shared geometry may carry another material than the stored triangles: the effect analysis sees
// it (here a clear coat that only the instance's material has).
TEST(GltfInstancing, EffectsSeeTheMaterialsOfInstances) {
    GltfBuilder b;
    const int plain = b.add_material({{"pbrMetallicRoughness", {{"metallicFactor", 0.0}}}});
    const int coated = b.add_material(
        {{"extensions", {{"KHR_materials_clearcoat", {{"clearcoatFactor", 1.0}}}}}});
    const int mesh = b.add_simple_mesh(UNIT_TRIANGLE, {}, {}, 4, plain);
    nlohmann::json copy = b.doc["meshes"][size_t(mesh)];
    copy["primitives"][0]["material"] = coated;
    b.doc["meshes"].push_back(copy);
    std::vector<int> roots;
    for (int i = 0; i < 4; ++i)
        roots.push_back(b.add_node({{"mesh", i == 3 ? mesh + 1 : mesh}, {"translation", {2.0 * i, 0.0, 0.0}}}));
    b.set_scene(roots);
    const Scene s = fh::load_gltf(b.write_gltf(), options(Instancing::always));
    ASSERT_FALSE(s.instances.empty());
    EXPECT_NE(fh::analyse_effects(s, false).bits & fh::gpu::EFFECT_CLEARCOAT, 0u);
}

}  // namespace
