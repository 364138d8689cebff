// Which volume the camera stands in, from the first hits of its probe rays (render/camera_medium.h).
#include <gtest/gtest.h>

#include "render/camera_medium.h"

namespace {

// One triangle in the plane z = 1 whose winding faces +z (its geometric normal), material 0; `volume`: material 0
// bounds a volume.
fh::PackedScene plane_scene(bool volume) {
    fh::PackedScene scene;
    fh::gpu::TrianglePositions t{};
    t.p0_x = -1, t.p0_y = -1, t.p0_z = 1;
    t.p1_x = 1, t.p1_y = -1, t.p1_z = 1;
    t.p2_x = 0, t.p2_y = 1, t.p2_z = 1;
    scene.positions = {t};
    fh::gpu::TriangleShading shading{};
    shading.material = 0;
    scene.shading = {shading};
    scene.materials.resize(1);
    scene.material_layers.resize(1);
    scene.material_layers[0].flags = volume ? fh::gpu::LAYERS_VOLUME : 0u;
    return scene;
}

fh::gpu::HitItem hit_on(uint32_t triangle) { return {1.0f, triangle, 0.3f, 0.3f, fh::gpu::INVALID_INDEX}; }
const fh::gpu::HitItem MISS{0.0f, fh::gpu::INVALID_INDEX, 0.0f, 0.0f, fh::gpu::INVALID_INDEX};

TEST(CameraMedium, ProbesLeaveFromTheCameraAlongDistinctDirections) {
    const auto probes = fh::make_medium_probe_rays({1, 2, 3}, 14);
    ASSERT_EQ(probes.size(), 14u);
    for (const auto& p : probes) {
        EXPECT_EQ(p.origin_x, 1.0f);
        EXPECT_NEAR(p.dir_x * p.dir_x + p.dir_y * p.dir_y + p.dir_z * p.dir_z, 1.0f, 1e-6f);
    }
    EXPECT_EQ(fh::make_medium_probe_rays({0, 0, 0}, 1).size(), 1u);  // a one-path wave holds one probe
}

TEST(CameraMedium, ABackFaceOfAVolumeMeansInside) {
    const fh::PackedScene scene = plane_scene(true);
    const auto probes = fh::make_medium_probe_rays({0, 0, 0}, 6);  // +x -x +y -y +z -z
    // Only the +z probe (index 4) hits, from behind the triangle's winding: inside material 0, by 1 vote to 0 ...
    std::vector<fh::gpu::HitItem> hits(6, MISS);
    hits[4] = hit_on(0);
    // ... which loses to the five probes that escaped.
    EXPECT_EQ(fh::vote_camera_medium(scene, probes, hits), fh::gpu::INVALID_INDEX);
    // Every probe hits the back face (as inside a closed mesh): inside.
    std::vector<fh::gpu::HitItem> all(6, hit_on(0));
    auto up = probes;
    for (auto& p : up) p.dir_x = 0, p.dir_y = 0, p.dir_z = 1;
    EXPECT_EQ(fh::vote_camera_medium(scene, up, all), 0u);
    // The same hits from the front (rays going down onto the winding's side): outside.
    auto down = up;
    for (auto& p : down) p.dir_z = -1;
    EXPECT_EQ(fh::vote_camera_medium(scene, down, all), fh::gpu::INVALID_INDEX);
    // A back face of a surface without a volume (thin-walled): outside.
    EXPECT_EQ(fh::vote_camera_medium(plane_scene(false), up, all), fh::gpu::INVALID_INDEX);
}

// Probes that hit an opaque surface (or the front of a volume) abstain: a camera under water near the sea bed is
// still in the water when most probes see the bed.
TEST(CameraMedium, ProbesThatHitOtherSurfacesAbstain) {
    fh::PackedScene scene = plane_scene(true);
    scene.positions.push_back(scene.positions[0]);  // triangle 1: the same plane, material 1 without a volume
    scene.shading.push_back(scene.shading[0]);
    scene.shading[1].material = 1;
    scene.materials.resize(2);
    scene.material_layers.resize(2);
    auto probes = fh::make_medium_probe_rays({0, 0, 0}, 6);
    for (auto& p : probes) p.dir_x = 0, p.dir_y = 0, p.dir_z = 1;  // all from behind the winding
    std::vector<fh::gpu::HitItem> hits{hit_on(0), hit_on(0), hit_on(1), hit_on(1), hit_on(1), hit_on(1)};
    EXPECT_EQ(fh::vote_camera_medium(scene, probes, hits), 0u);  // 2 votes for the volume, 4 abstain
    hits[2] = hits[3] = hits[4] = MISS;                          // 3 escaped: outside wins 3 to 2
    EXPECT_EQ(fh::vote_camera_medium(scene, probes, hits), fh::gpu::INVALID_INDEX);
}

TEST(CameraMedium, AnInstanceMaterialAndItsMapDecide) {
    fh::PackedScene scene = plane_scene(false);
    scene.materials.resize(2);
    scene.material_layers.resize(2);
    scene.material_layers[1].flags = fh::gpu::LAYERS_VOLUME;
    fh::gpu::Instance inst{};
    // object_from_render mirrors z: a render-space ray going down goes up in object space, behind the winding.
    inst.object_from_render_0 = {1, 0, 0, 0};
    inst.object_from_render_1 = {0, 1, 0, 0};
    inst.object_from_render_2 = {0, 0, -1, 0};
    inst.material = 1;
    scene.instances = {inst};
    auto probes = fh::make_medium_probe_rays({0, 0, 0}, 3);
    for (auto& p : probes) p.dir_x = 0, p.dir_y = 0, p.dir_z = -1;
    std::vector<fh::gpu::HitItem> hits(3, hit_on(0));
    for (auto& h : hits) h.instance = 0;
    EXPECT_EQ(fh::vote_camera_medium(scene, probes, hits), 1u);
}

}  // namespace
