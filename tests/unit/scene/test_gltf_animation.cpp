// glTF animation, morph targets and skins: a scene posed at a time by load_gltf (LoadOptions::animate), checked on
// the bounds of a triangle moved by hand-computed amounts (the loader may rotate a triangle's vertex order).
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "gltf_builder.h"
#include "scene/scene.h"

namespace {
using fh::Scene;
using fh::test::GltfBuilder;
using nlohmann::json;

const std::vector<glm::vec3> UNIT_TRIANGLE = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};

fh::LoadOptions at_time(double time, const std::string& animation = "") {
    fh::LoadOptions o;
    o.rebase = false;
    o.animate = true;
    o.time = time;
    o.animation = animation;
    return o;
}
const fh::LoadOptions STATIC{.rebase = false};

int add_floats(GltfBuilder& b, const std::vector<float>& v, const std::string& type, size_t components) {
    return b.add_accessor(b.add_view(v.data(), v.size() * 4), 5126, v.size() / components, type);
}

// One animation with one channel on `node`.
void animate(GltfBuilder& b, int node, const std::string& path, const std::vector<float>& times,
             const std::vector<float>& values, const std::string& type, size_t components,
             const std::string& interpolation = "LINEAR", const std::string& name = "") {
    const int input = add_floats(b, times, "SCALAR", 1);
    const int output = add_floats(b, values, type, components);
    json animation = {{"samplers", {{{"input", input}, {"output", output}, {"interpolation", interpolation}}}},
                      {"channels", {{{"sampler", 0}, {"target", {{"node", node}, {"path", path}}}}}}};
    if (!name.empty()) animation["name"] = name;
    if (!b.doc.contains("animations")) b.doc["animations"] = json::array();
    b.doc["animations"].push_back(animation);
}

// A triangle node translated along x by keys (0, 0, 0) at t = 0 and (2, 0, 0) at t = 1.
std::filesystem::path translated_triangle(const std::string& interpolation) {
    GltfBuilder b;
    const int node = b.add_node({{"mesh", b.add_simple_mesh(UNIT_TRIANGLE)}});
    b.set_scene({node});
    animate(b, node, "translation", {0.0f, 1.0f}, {0, 0, 0, 2, 0, 0}, "VEC3", 3, interpolation, "slide");
    return b.write_gltf();
}

double min_x(const std::filesystem::path& file, const fh::LoadOptions& options) {
    return fh::load_gltf(file, options).bounds_min.x;
}

TEST(GltfAnimation, LinearInterpolatesAndClampsOutsideTheKeys) {
    const auto file = translated_triangle("LINEAR");
    EXPECT_NEAR(min_x(file, at_time(0.25)), 0.5, 1e-6);
    EXPECT_NEAR(min_x(file, at_time(-3.0)), 0.0, 1e-6);  // before the first key: its value
    EXPECT_NEAR(min_x(file, at_time(7.0)), 2.0, 1e-6);   // after the last: its value
    EXPECT_NEAR(min_x(file, at_time(0.25, "slide")), 0.5, 1e-6);
    EXPECT_NEAR(min_x(file, at_time(0.25, "0")), 0.5, 1e-6);
    const Scene s = fh::load_gltf(file, at_time(0.5));
    EXPECT_EQ(s.animation, "animation 0 'slide'");
    EXPECT_EQ(s.animation_start, 0.0);
    EXPECT_EQ(s.animation_end, 1.0);
    // Without --time the file's own transforms: no translation.
    EXPECT_NEAR(min_x(file, STATIC), 0.0, 1e-12);
}

TEST(GltfAnimation, StepHoldsEachKeyUntilTheNext) {
    const auto file = translated_triangle("STEP");
    EXPECT_NEAR(min_x(file, at_time(0.99)), 0.0, 1e-12);
    EXPECT_NEAR(min_x(file, at_time(1.0)), 2.0, 1e-6);
}

// Hermite with tangents scaled by the interval: keys at t = 0 and 2, values 0 and 1, out-tangent 1 at the first key,
// in-tangent 0 at the second: at s = 1/2, p = h10 dt 1 + h01 1 = 0.125 x 2 + 0.5 = 0.75.
TEST(GltfAnimation, CubicSplineUsesTheScaledTangents) {
    GltfBuilder b;
    const int node = b.add_node({{"mesh", b.add_simple_mesh(UNIT_TRIANGLE)}});
    b.set_scene({node});
    animate(b, node, "translation", {0.0f, 2.0f},
            {9, 9, 9, 0, 0, 0, 1, 0, 0,    // key 0: in-tangent (unused), value, out-tangent
             0, 0, 0, 1, 0, 0, 9, 9, 9},   // key 1: in-tangent, value, out-tangent (unused)
            "VEC3", 3, "CUBICSPLINE");
    EXPECT_NEAR(min_x(b.write_gltf(), at_time(1.0)), 0.75, 1e-6);
}

// Identity to 90 degrees about z, the second key written as the negated quaternion (the same rotation): slerp takes
// the shorter arc, so half-way is 45 degrees and the vertex (1, 0, 0) lands at (cos 45, sin 45, 0).
TEST(GltfAnimation, RotationSlerpsAlongTheShorterArc) {
    GltfBuilder b;
    const int node = b.add_node({{"mesh", b.add_simple_mesh({{1, 0, 0}, {1, 0, 1}, {1, 0.001f, 0}})}});
    b.set_scene({node});
    const float h = float(std::sqrt(0.5));
    animate(b, node, "rotation", {0.0f, 1.0f}, {0, 0, 0, 1, 0, 0, -h, -h}, "VEC4", 4);
    const Scene s = fh::load_gltf(b.write_gltf(), at_time(0.5));
    const double c = std::cos(M_PI / 4);
    EXPECT_NEAR(s.bounds_max.x, c, 1e-5);
    EXPECT_NEAR(s.bounds_min.y, c, 1e-5);
}

// A morph target raising every vertex by 1 in z: the mesh's default weight, a node's override, and an animated weight.
TEST(GltfAnimation, MorphTargetsFollowTheirWeights) {
    auto make = [](const json& node_weights, bool animated) {
        GltfBuilder b;
        const std::vector<glm::vec3> up(3, glm::vec3(0, 0, 1));
        json prim = {{"attributes", {{"POSITION", b.add_vec3(UNIT_TRIANGLE)}}},
                     {"targets", {{{"POSITION", b.add_vec3(up)}}}}};
        const int mesh = b.add_mesh(prim);
        b.doc["meshes"][mesh]["weights"] = {0.25};
        json node = {{"mesh", mesh}};
        if (!node_weights.is_null()) node["weights"] = node_weights;
        const int n = b.add_node(node);
        b.set_scene({n});
        if (animated) animate(b, n, "weights", {0.0f, 1.0f}, {0.0f, 1.0f}, "SCALAR", 1);
        return b.write_gltf();
    };
    EXPECT_NEAR(fh::load_gltf(make(nullptr, false), STATIC).bounds_min.z, 0.25, 1e-6);
    EXPECT_NEAR(fh::load_gltf(make({0.5}, false), STATIC).bounds_min.z, 0.5, 1e-6);
    EXPECT_NEAR(fh::load_gltf(make({0.5}, true), at_time(0.8)).bounds_min.z, 0.8, 1e-6);
}

// Two joints; joint 1 moves up by 5 over a second. A triangle bound wholly to joint 1 follows it; one bound half to
// each moves half as far; the skinned node's own translation (100 in x) is ignored, as the spec says.
TEST(GltfAnimation, SkinsPlaceVerticesByTheirJoints) {
    auto make = [](float weight1) {
        GltfBuilder b;
        const std::vector<uint8_t> joints = {0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0};
        const std::vector<float> weights = {1 - weight1, weight1, 0, 0, 1 - weight1, weight1, 0, 0,
                                            1 - weight1, weight1, 0, 0};
        json prim = {{"attributes",
                      {{"POSITION", b.add_vec3(UNIT_TRIANGLE)},
                       {"JOINTS_0", b.add_accessor(b.add_view(joints.data(), joints.size()), 5121, 3, "VEC4")},
                       {"WEIGHTS_0", add_floats(b, weights, "VEC4", 4)}}}};
        const int mesh = b.add_mesh(prim);
        const int j0 = b.add_node(json::object());
        const int j1 = b.add_node(json::object());
        const int root = b.add_node({{"children", {j0, j1}}});
        const std::vector<float> identity = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
        std::vector<float> bind = identity;
        bind.insert(bind.end(), identity.begin(), identity.end());
        b.doc["skins"] = {{{"joints", {j0, j1}}, {"inverseBindMatrices", add_floats(b, bind, "MAT4", 16)}}};
        const int skinned = b.add_node({{"mesh", mesh}, {"skin", 0}, {"translation", {100, 0, 0}}});
        b.set_scene({root, skinned});
        animate(b, j1, "translation", {0.0f, 1.0f}, {0, 0, 0, 0, 5, 0}, "VEC3", 3);
        return b.write_gltf();
    };
    EXPECT_NEAR(fh::load_gltf(make(1.0f), at_time(1.0)).bounds_min.y, 5.0, 1e-5);
    EXPECT_NEAR(fh::load_gltf(make(0.5f), at_time(1.0)).bounds_min.y, 2.5, 1e-5);
    const Scene rest = fh::load_gltf(make(1.0f), STATIC);
    EXPECT_NEAR(rest.bounds_min.y, 0.0, 1e-6);
    EXPECT_NEAR(rest.bounds_min.x, 0.0, 1e-6);  // not at the node's x = 100
}

TEST(GltfAnimation, RefusesBadInputNamingTheProblem) {
    {
        GltfBuilder b;
        const int node = b.add_node({{"mesh", b.add_simple_mesh(UNIT_TRIANGLE)}});
        b.set_scene({node});
        animate(b, node, "translation", {1.0f, 0.5f}, {0, 0, 0, 1, 0, 0}, "VEC3", 3);
        fh::test::expect_load_refused_with(b.write_gltf(), at_time(0.2), "keyframe times do not increase");
    }
    {
        GltfBuilder b;
        const int node = b.add_node({{"mesh", b.add_simple_mesh(UNIT_TRIANGLE)}});
        b.set_scene({node});
        animate(b, node, "translation", {0.0f, 1.0f}, {0, 0, 0}, "VEC3", 3);
        fh::test::expect_load_refused_with(b.write_gltf(), at_time(0.2), "1 outputs for 2 keyframes");
    }
    fh::test::expect_load_refused_with(translated_triangle("LINEAR"), at_time(0.2, "walk"),
                                       "no animation 'walk' (the file has animation 0 'slide')");
    {
        GltfBuilder b;
        b.set_scene({b.add_node({{"mesh", b.add_simple_mesh(UNIT_TRIANGLE)}})});
        fh::test::expect_load_refused_with(b.write_gltf(), at_time(0.2), "--time: the file has no animations");
    }
}

}  // namespace

namespace {
fh::LoadOptions with_shutter(double time, double open, double close) {
    fh::LoadOptions o = at_time(time);
    o.shutter_open = open;
    o.shutter_close = close;
    return o;
}
}  // namespace

// Motion blur: a node that moves during the shutter becomes an instance placed halfway, keyed over the shutter (one
// segment: it does not turn), and the scene bounds hold it at both ends.
TEST(GltfMotion, AMovingNodeBecomesAnInstanceThatMovesOverTheShutter) {
    const auto file = translated_triangle("LINEAR");  // x from 0 at t = 0 to 2 at t = 1
    const Scene s = fh::load_gltf(file, with_shutter(0.5, -0.25, 0.25));
    ASSERT_EQ(s.instances.size(), 1u);
    EXPECT_EQ(s.moving_instances, 1u);
    const fh::SceneInstance& i = s.instances[0];
    EXPECT_TRUE(i.moves());
    EXPECT_EQ(s.motion_segments, 1u);
    ASSERT_EQ(i.keys.size(), 2u);
    EXPECT_NEAR(i.render_from_object[3].x, 1.0, 1e-9);  // halfway: t = 0.5
    EXPECT_NEAR(i.keys[0][3].x, 0.5, 1e-9);             // from x = 0.5 at t = 0.25 to 1.5 at 0.75
    EXPECT_NEAR(i.keys[1][3].x, 1.5, 1e-9);
    EXPECT_NEAR(i.render_from_object_at(0.25)[3].x, 0.75, 1e-9);
    EXPECT_NEAR(s.bounds_min.x, 0.5, 1e-6);
    EXPECT_NEAR(s.bounds_max.x, 2.5, 1e-6);
    // Without --time the shutter opens about t = 0; a shutter over which nothing moves makes no instance.
    EXPECT_EQ(fh::load_gltf(file, with_shutter(5.0, -0.1, 0.1)).moving_instances, 0u);
    fh::LoadOptions shutter_only = STATIC;
    shutter_only.shutter_close = 0.5;
    EXPECT_NEAR(fh::load_gltf(file, shutter_only).instances.at(0).keys.back()[3].x, 1.0, 1e-9);
}

// A node that turns a quarter turn over the shutter is keyed at 32 equal parts (5.6 degrees in 16 would be more than
// 5): the instance's keys are its poses there, so halfway it stands exactly where the file poses it, not on a chord.
TEST(GltfMotion, TurningNodesAreKeyedFinelyEnough) {
    GltfBuilder b;
    const int node = b.add_node({{"mesh", b.add_simple_mesh(UNIT_TRIANGLE)}});
    b.set_scene({node});
    const float h = std::sqrt(0.5f);  // 90 degrees about +Z at t = 1
    animate(b, node, "rotation", {0.0f, 1.0f}, {0, 0, 0, 1, 0, 0, h, h}, "VEC4", 4);
    const Scene s = fh::load_gltf(b.write_gltf(), with_shutter(0.0, 0.0, 1.0));
    EXPECT_EQ(s.motion_segments, 32u);
    ASSERT_EQ(s.instances.size(), 1u);
    const fh::SceneInstance& i = s.instances[0];
    ASSERT_EQ(i.keys.size(), 33u);
    // Halfway: 45 degrees; the unit x axis goes to (cos 45, sin 45), still of length 1.
    const glm::dvec3 x_axis(i.render_from_object_at(0.5)[0]);
    EXPECT_NEAR(x_axis.x, std::sqrt(0.5), 1e-6);
    EXPECT_NEAR(x_axis.y, std::sqrt(0.5), 1e-6);
    // Between two keys the chord shrinks it by at most 1 - cos(90 / 64 degrees) = 0.0003.
    EXPECT_GT(glm::length(glm::dvec3(i.render_from_object_at(0.5 + 0.5 / 32)[0])), 0.9996);
    // A sliding node needs one part.
    EXPECT_EQ(fh::load_gltf(translated_triangle("LINEAR"), with_shutter(0.0, 0.0, 1.0)).motion_segments, 1u);
}

// Only the moving node becomes an instance; its still sibling stays in world space.
TEST(GltfMotion, StillNodesStayInWorldSpace) {
    GltfBuilder b;
    const int moving = b.add_node({{"mesh", b.add_simple_mesh(UNIT_TRIANGLE)}});
    const int still = b.add_node({{"mesh", b.add_simple_mesh(UNIT_TRIANGLE)}, {"translation", {0, 5, 0}}});
    b.set_scene({moving, still});
    animate(b, moving, "translation", {0.0f, 1.0f}, {0, 0, 0, 2, 0, 0}, "VEC3", 3);
    const Scene s = fh::load_gltf(b.write_gltf(), with_shutter(0.5, -0.1, 0.1));
    EXPECT_EQ(s.instances.size(), 1u);
    EXPECT_EQ(s.world_triangle_count, 1u);
}

// A moving camera: the pose halfway, the translation and the turn (about +Y here) over the shutter.
TEST(GltfMotion, AMovingCameraCarriesItsMotion) {
    GltfBuilder b;
    const int mesh = b.add_node({{"mesh", b.add_simple_mesh(UNIT_TRIANGLE)}});
    b.doc["cameras"] = json::array({{{"type", "perspective"}, {"perspective", {{"yfov", 0.7}, {"znear", 0.01}}}}});
    const int camera = b.add_node({{"camera", 0}, {"translation", {0, 0, 4}}});
    b.set_scene({mesh, camera});
    const float s = std::sin(0.25f), c = std::cos(0.25f);  // 0.5 rad about +Y at t = 1
    const int input = add_floats(b, {0.0f, 1.0f}, "SCALAR", 1);
    const int slide = add_floats(b, {0, 0, 4, 2, 0, 4}, "VEC3", 3);
    const int turn = add_floats(b, {0, 0, 0, 1, 0, s, 0, c}, "VEC4", 4);
    b.doc["animations"] = json::array({{{"samplers", {{{"input", input}, {"output", slide}}, {{"input", input}, {"output", turn}}}},
                                        {"channels", {{{"sampler", 0}, {"target", {{"node", camera}, {"path", "translation"}}}},
                                                      {{"sampler", 1}, {"target", {{"node", camera}, {"path", "rotation"}}}}}}}});
    const Scene scene = fh::load_gltf(b.write_gltf(), with_shutter(0.5, -0.5, 0.5));
    ASSERT_EQ(scene.cameras.size(), 1u);
    const fh::SceneCamera& cam = scene.cameras[0];
    EXPECT_TRUE(cam.moves);
    EXPECT_NEAR(cam.motion_translation.x, 2.0, 1e-9);
    EXPECT_NEAR(cam.motion_angle, 0.5, 1e-6);  // keys in float
    EXPECT_NEAR(cam.motion_axis.y, 1.0, 1e-9);
    EXPECT_NEAR(cam.world_from_camera[3].x, 1.0, 1e-9);  // halfway
    EXPECT_NEAR(std::atan2(cam.world_from_camera[2].x, cam.world_from_camera[2].z), 0.25, 1e-6);  // turned 0.25 rad
    EXPECT_EQ(scene.moving_instances, 0u);  // the mesh stands still
}

// ---- KHR_animation_pointer ----

// Adds a channel with `pointer` to the file's first animation (made when missing).
void animate_pointer(GltfBuilder& b, const std::string& pointer, const std::vector<float>& times, int output,
                     const std::string& interpolation = "LINEAR") {
    if (!b.doc.contains("animations")) b.doc["animations"] = {{{"samplers", json::array()}, {"channels", json::array()}}};
    json& animation = b.doc["animations"][0];
    const int sampler = int(animation["samplers"].size());
    animation["samplers"].push_back(
        {{"input", add_floats(b, times, "SCALAR", 1)}, {"output", output}, {"interpolation", interpolation}});
    animation["channels"].push_back(
        {{"sampler", sampler},
         {"target", {{"path", "pointer"}, {"extensions", {{"KHR_animation_pointer", {{"pointer", pointer}}}}}}}});
}

// A triangle of material 0 (emissive, with KHR_materials_emissive_strength), a second triangle, a point light and a
// perspective camera, whose properties pointers animate between t = 0 and 1.
GltfBuilder pointer_scene() {
    GltfBuilder b;
    b.add_material({{"emissiveFactor", {1, 1, 1}},
                    {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 1.0}}}}}});
    b.doc["extensionsUsed"] = {"KHR_animation_pointer", "KHR_lights_punctual", "KHR_node_visibility",
                               "KHR_materials_emissive_strength"};
    b.doc["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "point"}, {"intensity", 1.0}}};
    b.doc["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"znear", 0.1}}}}};
    const int mesh = b.add_simple_mesh(UNIT_TRIANGLE, {}, {}, 4, 0);
    b.set_scene({b.add_node({{"mesh", mesh}}), b.add_node({{"mesh", b.add_simple_mesh(UNIT_TRIANGLE)}}),
                 b.add_node({{"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}}),
                 b.add_node({{"camera", 0}})});
    return b;
}

TEST(GltfAnimationPointer, AnimatesMaterialsLightsCamerasNodesAndVisibility) {
    GltfBuilder b = pointer_scene();
    const std::vector<float> t01 = {0.0f, 1.0f};
    animate_pointer(b, "/materials/0/pbrMetallicRoughness/baseColorFactor", t01,
                    add_floats(b, {0, 0, 0, 1, 1, 0.5f, 0.25f, 1}, "VEC4", 4));
    animate_pointer(b, "/materials/0/pbrMetallicRoughness/roughnessFactor", t01, add_floats(b, {0, 1}, "SCALAR", 1));
    animate_pointer(b, "/materials/0/extensions/KHR_materials_emissive_strength/emissiveStrength", t01,
                    add_floats(b, {0, 4}, "SCALAR", 1));
    animate_pointer(b, "/extensions/KHR_lights_punctual/lights/0/intensity", t01, add_floats(b, {0, 10}, "SCALAR", 1));
    animate_pointer(b, "/cameras/0/perspective/yfov", t01, add_floats(b, {0.2f, 0.6f}, "SCALAR", 1));
    animate_pointer(b, "/nodes/1/translation", t01, add_floats(b, {0, 0, 0, 0, 0, 4}, "VEC3", 3));
    const std::vector<unsigned char> shown_hidden = {1, 0};
    animate_pointer(b, "/nodes/0/extensions/KHR_node_visibility/visible", t01,
                    b.add_accessor(b.add_view(shown_hidden.data(), 2), 5121, 2, "SCALAR"), "STEP");
    animate_pointer(b, "/materials/0/occlusionTexture/strength", t01, add_floats(b, {0, 1}, "SCALAR", 1));
    const auto file = b.write_gltf();

    const Scene s = fh::load_gltf(file, at_time(0.5));
    EXPECT_EQ(s.materials[0].base_color, glm::vec4(0.5f, 0.25f, 0.125f, 1.0f));
    EXPECT_FLOAT_EQ(s.materials[0].roughness, 0.5f);
    EXPECT_FLOAT_EQ(s.materials[0].emission.x, 2.0f);
    ASSERT_EQ(s.lights.size(), 1u);
    EXPECT_FLOAT_EQ(s.lights[0].intensity.x, 5.0f);
    ASSERT_EQ(s.cameras.size(), 1u);
    EXPECT_NEAR(s.cameras[0].yfov, 0.4, 1e-6);
    EXPECT_NEAR(s.bounds_max.z, 2.0, 1e-6);  // node 1 halfway along +z
    EXPECT_EQ(s.triangle_count(), 2u);       // node 0 still visible (STEP: 1 until t = 1)
    bool warned = false;
    for (const std::string& w : s.warnings) warned = warned || w.find("occlusionTexture is not read") != std::string::npos;
    EXPECT_TRUE(warned);

    const Scene hidden = fh::load_gltf(file, at_time(1.0));
    EXPECT_EQ(hidden.triangle_count(), 1u);  // node 0 hidden from t = 1
    EXPECT_FLOAT_EQ(hidden.lights[0].intensity.x, 10.0f);
    // Without --time the file's own values.
    const Scene still = fh::load_gltf(file, STATIC);
    EXPECT_EQ(still.materials[0].base_color, glm::vec4(1.0f));
    EXPECT_NEAR(still.cameras[0].yfov, 0.5, 1e-12);
}

// A core texture slot's KHR_texture_transform, named by a pointer through the slot (two tokens for
// pbrMetallicRoughness/baseColorTexture, one for emissiveTexture): the loader's table of slots must outlive the
// lookup (a dangling initializer_list here was a fuzzer finding under ASan).
TEST(GltfAnimationPointer, AnimatesACoreTexturesTransform) {
    GltfBuilder b = pointer_scene();
    const nlohmann::json slot = {{"index", 0}, {"extensions", {{"KHR_texture_transform", {{"offset", {0, 0}}}}}}};
    b.doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = slot;
    b.doc["materials"][0]["emissiveTexture"] = slot;
    b.doc["extensionsUsed"].push_back("KHR_texture_transform");
    b.doc["images"] = {{{"uri", "data:image/png;base64," + fh::test::encode_base64(fh::test::png_2x1())}}};
    b.doc["textures"] = {{{"source", 0}}};
    b.doc["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = add_floats(b, {0, 0, 1, 0, 0, 1}, "VEC2", 2);
    const std::vector<float> t01 = {0.0f, 1.0f};
    animate_pointer(b, "/materials/0/pbrMetallicRoughness/baseColorTexture/extensions/KHR_texture_transform/offset",
                    t01, add_floats(b, {0, 0, 1, 0.5f}, "VEC2", 2));
    animate_pointer(b, "/materials/0/emissiveTexture/extensions/KHR_texture_transform/offset", t01,
                    add_floats(b, {0, 0, 0.25f, 2}, "VEC2", 2));
    const Scene s = fh::load_gltf(b.write_gltf(), at_time(0.5));
    const fh::gpu::Material& m = s.materials[0];
    ASSERT_LT(m.base_color_texture, s.texture_slots.size());
    ASSERT_LT(m.emissive_texture, s.texture_slots.size());
    const fh::gpu::TextureSlot& base = s.texture_slots[m.base_color_texture];
    EXPECT_NEAR(base.transform_u.z, 0.5, 1e-6);
    EXPECT_NEAR(base.transform_v.z, 0.25, 1e-6);
    const fh::gpu::TextureSlot& emissive = s.texture_slots[m.emissive_texture];
    EXPECT_NEAR(emissive.transform_u.z, 0.125, 1e-6);
    EXPECT_NEAR(emissive.transform_v.z, 1.0, 1e-6);
}

TEST(GltfAnimationPointer, RefusesBadPointersNamingThem) {
    auto refused = [](const std::string& pointer, const std::string& interpolation, const std::string& expected) {
        GltfBuilder b = pointer_scene();
        animate_pointer(b, pointer, {0.0f, 1.0f}, add_floats(b, {0, 1}, "SCALAR", 1), interpolation);
        fh::test::expect_load_refused_with(b.write_gltf(), at_time(0.5), expected);
    };
    refused("/materials/7/pbrMetallicRoughness/metallicFactor", "LINEAR", "material '7' does not exist");
    refused("/extensions/KHR_lights_punctual/lights/3/intensity", "LINEAR", "light '3' does not exist");
    refused("materials/0/alphaCutoff", "LINEAR", "does not start with '/'");
    refused("/nodes/0/extensions/KHR_node_visibility/visible", "LINEAR", "requires STEP");
    refused("/materials/0/pbrMetallicRoughness/baseColorFactor", "LINEAR", "expected a VEC4 accessor");
    refused("/nodes/0/extensions/KHR_node_visibility/visible", "STEP", "needs unsigned byte outputs");  // floats
    refused("/materials/0/extensions/KHR_materials_sheen/sheenRoughnessFactor", "LINEAR", "has no KHR_materials_sheen");
    refused("/cameras/0/orthographic/xmag", "LINEAR", "camera 0 is perspective, not orthographic");
}
