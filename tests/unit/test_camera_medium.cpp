// Which volumes the camera stands in, from probe rays walking out through the volumes' surfaces
// (render/camera/camera_medium.h). The tracer is scripted: each call returns the next list of hits.
#include <gtest/gtest.h>

#include "render/camera/camera_medium.h"

namespace {

using fh::gpu::INVALID_INDEX;

// Triangles in the plane z = 1 (so a ray from the origin along +z meets them at t = 1): triangle i has material
// materials[i]; `faces_up[i]` its winding (geometric normal) faces +z, else -z. `volumes`: which materials bound a
// volume.
fh::PackedScene plane_scene(const std::vector<uint32_t>& materials, const std::vector<bool>& faces_up,
                            const std::vector<bool>& volumes) {
    fh::PackedScene scene;
    for (size_t i = 0; i < materials.size(); ++i) {
        fh::gpu::TrianglePositions t{};
        t.p0_x = -1, t.p0_y = -1, t.p0_z = 1;
        t.p1_x = 1, t.p1_y = -1, t.p1_z = 1;
        t.p2_x = 0, t.p2_y = 1, t.p2_z = 1;
        if (!faces_up[i]) std::swap(t.p1_x, t.p2_x), std::swap(t.p1_y, t.p2_y);
        scene.positions.push_back(t);
        fh::gpu::TriangleShading shading{};
        shading.material = materials[i];
        scene.shading.push_back(shading);
    }
    scene.materials.resize(volumes.size());
    scene.material_layers.resize(volumes.size());
    for (size_t m = 0; m < volumes.size(); ++m) scene.material_layers[m].flags = volumes[m] ? fh::gpu::LAYERS_VOLUME : 0u;
    return scene;
}

fh::gpu::HitItem hit_on(uint32_t triangle) { return {1.0f, triangle, 0.3f, 0.3f, INVALID_INDEX}; }
const fh::gpu::HitItem MISS{0.0f, INVALID_INDEX, 0.0f, 0.0f, INVALID_INDEX};

// A tracer that answers its n-th call with calls[n] (padded with misses), and records how many rays each call had.
struct ScriptedTracer {
    std::vector<std::vector<fh::gpu::HitItem>> calls;
    std::vector<size_t> ray_counts;
    fh::TraceProbes trace() {
        return [this](const std::vector<fh::gpu::RayItem>& rays) {
            std::vector<fh::gpu::HitItem> hits(rays.size(), MISS);
            const size_t n = ray_counts.size();
            for (size_t k = 0; n < calls.size() && k < rays.size() && k < calls[n].size(); ++k) hits[k] = calls[n][k];
            ray_counts.push_back(rays.size());
            return hits;
        };
    }
};

// Every probe goes up (+z): towards the planes' back faces when they face up.
std::vector<fh::gpu::RayItem> up_probes(uint32_t count) {
    auto probes = fh::make_medium_probe_rays({0, 0, 0}, count);
    for (auto& p : probes) p.dir_x = 0, p.dir_y = 0, p.dir_z = 1;
    return probes;
}

const fh::CameraMedia OUTSIDE = fh::NO_CAMERA_MEDIA;
fh::CameraMedia media(uint32_t a, uint32_t b = INVALID_INDEX, uint32_t c = INVALID_INDEX) { return {a, b, c}; }

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
    const fh::PackedScene scene = plane_scene({0}, {true}, {true});
    // Only the +z probe (index 4 of +x -x +y -y +z -z) hits, from behind the winding: inside material 0, by 1 vote
    // to the 5 that escaped: outside.
    ScriptedTracer one{{{MISS, MISS, MISS, MISS, hit_on(0), MISS}}};
    EXPECT_EQ(fh::find_camera_media(scene, fh::make_medium_probe_rays({0, 0, 0}, 6), one.trace()), OUTSIDE);
    EXPECT_EQ(one.ray_counts, (std::vector<size_t>{6, 1}));  // the one that hit walked on, and escaped
    // Every probe hits the back face (as inside a closed mesh): inside.
    ScriptedTracer all{{std::vector<fh::gpu::HitItem>(6, hit_on(0))}};
    EXPECT_EQ(fh::find_camera_media(scene, up_probes(6), all.trace()), media(0));
    // The same hits from the front (rays going down onto the winding's side): they enter it and escape: outside.
    auto down = up_probes(6);
    for (auto& p : down) p.dir_z = -1;
    ScriptedTracer front{{std::vector<fh::gpu::HitItem>(6, hit_on(0))}};
    EXPECT_EQ(fh::find_camera_media(scene, down, front.trace()), OUTSIDE);
    // A back face of a surface without a volume (thin-walled): every probe abstains: outside.
    ScriptedTracer thin{{std::vector<fh::gpu::HitItem>(6, hit_on(0))}};
    EXPECT_EQ(fh::find_camera_media(plane_scene({0}, {true}, {false}), up_probes(6), thin.trace()), OUTSIDE);
    EXPECT_EQ(thin.ray_counts, (std::vector<size_t>{6}));
}

// Probes that hit an opaque surface first abstain: a camera under water near the sea bed is still in the water when
// most probes see the bed.
TEST(CameraMedium, ProbesThatHitOtherSurfacesFirstAbstain) {
    const fh::PackedScene scene = plane_scene({0, 1}, {true, true}, {true, false});  // triangle 1: opaque
    ScriptedTracer bed{{{hit_on(0), hit_on(0), hit_on(1), hit_on(1), hit_on(1), hit_on(1)}}};
    EXPECT_EQ(fh::find_camera_media(scene, up_probes(6), bed.trace()), media(0));  // 2 votes, 4 abstain
    ScriptedTracer open{{{hit_on(0), hit_on(0), MISS, MISS, MISS, hit_on(1)}}};
    EXPECT_EQ(fh::find_camera_media(scene, up_probes(6), open.trace()), OUTSIDE);  // 3 escaped: outside wins 3 to 2
}

// Water (material 0) in a glass (material 1): a probe leaves the water, then the glass; the camera starts in both.
TEST(CameraMedium, NestedVolumesAreFoundInnermostFirst) {
    const fh::PackedScene scene = plane_scene({0, 1}, {true, true}, {true, true});
    ScriptedTracer nested{{std::vector<fh::gpu::HitItem>(4, hit_on(0)), std::vector<fh::gpu::HitItem>(4, hit_on(1))}};
    EXPECT_EQ(fh::find_camera_media(scene, up_probes(4), nested.trace()), media(0, 1));
    EXPECT_EQ(nested.ray_counts, (std::vector<size_t>{4, 4, 4}));
    // A probe that meets an opaque wall after leaving the water still knows the camera is in the water.
    const fh::PackedScene walled = plane_scene({0, 1}, {true, true}, {true, false});
    ScriptedTracer wall{{std::vector<fh::gpu::HitItem>(4, hit_on(0)), std::vector<fh::gpu::HitItem>(4, hit_on(1))}};
    EXPECT_EQ(fh::find_camera_media(walled, up_probes(4), wall.trace()), media(0));
}

// A volume entered and left on the way (a glass marble in the water: its front face, then its back face) says
// nothing about the camera; the water's back face after it does.
TEST(CameraMedium, VolumesEnteredOnTheWayAreNotTheCameras) {
    // Triangle 0: the water's surface (back face from below); 1: the marble's far side (back face); 2: its near side
    // (faces down: a front face from below).
    const fh::PackedScene scene = plane_scene({0, 1, 1}, {true, true, false}, {true, true});
    ScriptedTracer marble{{std::vector<fh::gpu::HitItem>(4, hit_on(2)), std::vector<fh::gpu::HitItem>(4, hit_on(1)),
                           std::vector<fh::gpu::HitItem>(4, hit_on(0))}};
    EXPECT_EQ(fh::find_camera_media(scene, up_probes(4), marble.trace()), media(0));
    EXPECT_EQ(marble.ray_counts, (std::vector<size_t>{4, 4, 4, 4}));
}

// A probe still walking after MEDIUM_PROBE_STEPS surfaces stops: here it has only entered volumes, so it abstains.
TEST(CameraMedium, AWalkEndsAfterItsStepsAndFindsFourVolumesAtMost) {
    const fh::PackedScene scene = plane_scene({1, 0, 1, 2, 3}, {false, true, true, true, true}, {true, true, true, true});
    ScriptedTracer endless{std::vector<std::vector<fh::gpu::HitItem>>(20, std::vector<fh::gpu::HitItem>(2, hit_on(0)))};
    EXPECT_EQ(fh::find_camera_media(scene, up_probes(2), endless.trace()), OUTSIDE);
    EXPECT_EQ(endless.ray_counts.size(), size_t(fh::MEDIUM_PROBE_STEPS));
    // Four volumes around the camera: the walk stops at the third, which is all FrameParams holds.
    ScriptedTracer deep{{std::vector<fh::gpu::HitItem>(2, hit_on(1)), std::vector<fh::gpu::HitItem>(2, hit_on(2)),
                         std::vector<fh::gpu::HitItem>(2, hit_on(3)), std::vector<fh::gpu::HitItem>(2, hit_on(4))}};
    EXPECT_EQ(fh::find_camera_media(scene, up_probes(2), deep.trace()), media(0, 1, 2));
    EXPECT_EQ(deep.ray_counts.size(), 3u);
}

TEST(CameraMedium, AnInstanceMaterialAndItsMapDecide) {
    fh::PackedScene scene = plane_scene({0}, {true}, {false, true});
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
    ScriptedTracer instanced{{hits}};
    EXPECT_EQ(fh::find_camera_media(scene, probes, instanced.trace()), media(1));
}

}  // namespace
