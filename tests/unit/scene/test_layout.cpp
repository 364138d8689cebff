// Checks that every host/device struct in shaders/shared/layout.h has the size and field offsets GLSL std430
// gives it (cross-checked once against glslangValidator -q reflection), so C++ arrays upload as-is.
#include <cstddef>
#include <type_traits>

#include <gtest/gtest.h>

#include "shared/layout.h"

namespace {
using namespace fh::gpu;

// std430: scalars align to 4, vec4 to 16; a struct aligns to its largest member and its size rounds up to
// that, which for C++ (glm::vec4 aligns to 4) means: vec4 offsets and the size of a struct holding one are
// multiples of 16.
#define FH_OFFSET(S, field, expected) static_assert(offsetof(S, field) == (expected), #S "." #field)
#define FH_SIZE(S, expected)                                                                        \
    static_assert(sizeof(S) == (expected), "sizeof " #S);                                           \
    static_assert(std::is_standard_layout_v<S> && std::is_trivially_copyable_v<S>, #S " layout")

FH_SIZE(BvhNode, 32);
FH_OFFSET(BvhNode, min_x, 0);
FH_OFFSET(BvhNode, child_or_first, 12);
FH_OFFSET(BvhNode, max_x, 16);
FH_OFFSET(BvhNode, count_and_axis, 28);

FH_SIZE(BvhWideNode, 48);
FH_OFFSET(BvhWideNode, origin_x, 0);
FH_OFFSET(BvhWideNode, exponents, 12);
FH_OFFSET(BvhWideNode, lo_x, 16);
FH_OFFSET(BvhWideNode, hi_x, 28);
FH_OFFSET(BvhWideNode, first_node, 40);
FH_OFFSET(BvhWideNode, first_leaf, 44);

// The scene arrays bound as texel buffers (layout.h TEXELS) are read as whole 16-byte RGBA32UI texels.
static_assert(sizeof(BvhWideNode) % TEXEL_BYTES == 0 && sizeof(TrianglePositions) % TEXEL_BYTES == 0 &&
                  sizeof(TriangleShading) % TEXEL_BYTES == 0 && sizeof(Material) % TEXEL_BYTES == 0 &&
                  sizeof(Emitter) % TEXEL_BYTES == 0 && sizeof(PunctualLight) % TEXEL_BYTES == 0 &&
                  sizeof(TriangleAttributes) % TEXEL_BYTES == 0 && sizeof(Instance) % TEXEL_BYTES == 0 &&
                  sizeof(MaterialLayers) % TEXEL_BYTES == 0,
              "texel-buffer structs are whole texels");

FH_SIZE(TrianglePositions, 48);
FH_OFFSET(TrianglePositions, source_index, 36);
FH_OFFSET(TrianglePositions, flags, 40);
FH_OFFSET(TrianglePositions, p1_x, 12);
FH_OFFSET(TrianglePositions, p2_z, 32);

FH_SIZE(TriangleShading, 48);
FH_OFFSET(TriangleShading, n1_x, 12);
FH_OFFSET(TriangleShading, n2_z, 32);
FH_OFFSET(TriangleShading, material, 36);
FH_OFFSET(TriangleShading, flags, 40);
FH_OFFSET(TriangleShading, light_pdf_area, 44);

FH_SIZE(Material, 96);
FH_OFFSET(Material, base_color, 0);
FH_OFFSET(Material, emission, 16);
FH_OFFSET(Material, specular_color, 32);
FH_OFFSET(Material, metallic, 48);
FH_OFFSET(Material, roughness, 52);
FH_OFFSET(Material, ior, 56);
FH_OFFSET(Material, flags, 60);
FH_OFFSET(Material, base_color_texture, 64);
FH_OFFSET(Material, metallic_roughness_texture, 68);
FH_OFFSET(Material, normal_texture, 72);
FH_OFFSET(Material, emissive_texture, 76);
FH_OFFSET(Material, alpha_mode, 80);
FH_OFFSET(Material, alpha_cutoff, 84);

FH_SIZE(TextureSlot, 48);
FH_OFFSET(TextureSlot, transform_u, 0);
FH_OFFSET(TextureSlot, transform_v, 16);
FH_OFFSET(TextureSlot, image, 32);
FH_OFFSET(TextureSlot, addressing, 36);
FH_OFFSET(TextureSlot, scale, 40);
FH_SIZE(TextureImage, 16);
FH_OFFSET(TextureImage, texel_offset, 0);
FH_OFFSET(TextureImage, width, 4);
FH_OFFSET(TextureImage, height, 8);
FH_SIZE(TriangleAttributes, 96);
FH_OFFSET(TriangleAttributes, uv0_c2_uv1_c0, 16);
FH_OFFSET(TriangleAttributes, uv1_c12, 32);
FH_OFFSET(TriangleAttributes, color0_rg, 48);
FH_OFFSET(TriangleAttributes, color2_ba, 68);
FH_OFFSET(TriangleAttributes, tangent0_xy, 72);
FH_OFFSET(TriangleAttributes, tangent2_zw, 92);

FH_SIZE(Emitter, 16);
FH_OFFSET(Emitter, light, 0);
FH_OFFSET(Emitter, alias_threshold, 4);
FH_OFFSET(Emitter, alias, 8);
FH_OFFSET(Emitter, pick_pdf, 12);
FH_SIZE(PunctualLight, 64);
FH_OFFSET(PunctualLight, position, 0);
FH_OFFSET(PunctualLight, direction, 16);
FH_OFFSET(PunctualLight, intensity, 32);
FH_OFFSET(PunctualLight, type, 48);
FH_OFFSET(PunctualLight, cos_inner, 52);
FH_OFFSET(PunctualLight, cos_outer, 56);

FH_SIZE(FrameParams, 272);
FH_OFFSET(FrameParams, camera_origin, 0);
FH_OFFSET(FrameParams, camera_right, 16);
FH_OFFSET(FrameParams, camera_up, 32);
FH_OFFSET(FrameParams, camera_forward, 48);
FH_OFFSET(FrameParams, scene_min, 64);
FH_OFFSET(FrameParams, scene_max, 80);
FH_OFFSET(FrameParams, width, 96);
FH_OFFSET(FrameParams, height, 100);
FH_OFFSET(FrameParams, max_depth, 104);
FH_OFFSET(FrameParams, seed, 108);
FH_OFFSET(FrameParams, camera_type, 112);
FH_OFFSET(FrameParams, filter_type, 116);
FH_OFFSET(FrameParams, filter_radius, 120);
FH_OFFSET(FrameParams, flags, 124);
FH_OFFSET(FrameParams, emitter_count, 128);
FH_OFFSET(FrameParams, rr_start_depth, 132);
FH_OFFSET(FrameParams, rr_survival_scale, 248);
FH_OFFSET(FrameParams, wave_capacity, 136);
FH_OFFSET(FrameParams, triangle_count, 140);
FH_OFFSET(FrameParams, env_width, 144);
FH_OFFSET(FrameParams, env_height, 148);
FH_OFFSET(FrameParams, env_rotation, 152);
FH_OFFSET(FrameParams, env_pick_pdf, 156);
FH_OFFSET(FrameParams, camera_motion_translation, 176);
FH_OFFSET(FrameParams, camera_motion_rotation, 192);
FH_OFFSET(FrameParams, motion_segments, 208);
FH_OFFSET(FrameParams, crop_x, 212);
FH_OFFSET(FrameParams, film_width, 220);
FH_OFFSET(FrameParams, film_height, 224);
FH_OFFSET(FrameParams, light_vertex_slots, 240);
FH_OFFSET(FrameParams, bdpt_strategy, 244);
FH_OFFSET(FrameParams, bdpt_depth, 256);
FH_OFFSET(FrameParams, merge_grid_cells, 260);

FH_SIZE(StagePush, 40);
FH_OFFSET(StagePush, depth, 0);
FH_OFFSET(StagePush, pixel_begin, 4);
FH_OFFSET(StagePush, pixel_count, 8);
FH_OFFSET(StagePush, sample_begin, 12);
FH_OFFSET(StagePush, sample_count, 16);
FH_OFFSET(StagePush, ray_order, 20);
FH_OFFSET(StagePush, bin_pushed_rays, 24);
FH_OFFSET(StagePush, count_handed_shadow_rays, 28);
FH_OFFSET(StagePush, count_escaped_rays, 32);
FH_OFFSET(StagePush, merge_radius, 36);

FH_SIZE(DispatchArgs, 12);

FH_SIZE(QueueCounters, 56);
FH_OFFSET(QueueCounters, ray_count, 0);
FH_OFFSET(QueueCounters, shadow_count, 8);
FH_OFFSET(QueueCounters, shadow_count_active, 12);
FH_OFFSET(QueueCounters, extend_args, 16);  // std430: a struct of uints aligns to 4, not 16
FH_OFFSET(QueueCounters, connect_args, 28);
FH_OFFSET(QueueCounters, nonfinite_samples, 40);
FH_OFFSET(QueueCounters, escaped_rays, 44);
FH_OFFSET(QueueCounters, traced_rays, 48);  // lib/core/queue.glsl reset_counters writes the 14 words by position
FH_OFFSET(QueueCounters, traced_shadow_rays, 52);

FH_SIZE(PathState, 32);
FH_OFFSET(PathState, bsdf_pdf, 12);
FH_OFFSET(PathState, radiance_r, 16);
FH_OFFSET(PathState, rng, 28);

FH_SIZE(MaterialLayers, 160);
FH_OFFSET(MaterialLayers, iridescence_albedo_f90, 140);
FH_OFFSET(MaterialLayers, dispersion, 144);

FH_SIZE(PathMis, 16);
FH_OFFSET(PathMis, dvc, 4);
FH_OFFSET(PathMis, light_vertices, 8);
FH_OFFSET(PathMis, flags, 12);

FH_SIZE(LightVertex, 64);
FH_OFFSET(LightVertex, dvcm, 12);
FH_OFFSET(LightVertex, dvc, 28);
FH_OFFSET(LightVertex, triangle, 32);
FH_OFFSET(LightVertex, instance, 44);
FH_OFFSET(LightVertex, eta_front, 48);

FH_SIZE(PathSpectrum, 16);
FH_OFFSET(PathSpectrum, throughput_3, 4);
FH_OFFSET(PathSpectrum, flags, 8);

FH_SIZE(RayItem, 32);
FH_OFFSET(RayItem, path, 12);
FH_OFFSET(RayItem, dir_x, 16);

FH_SIZE(HitItem, 32);  // whole texels (BINDING_HIT_TEXELS)
FH_OFFSET(HitItem, t, 0);
FH_OFFSET(HitItem, triangle, 4);
FH_OFFSET(HitItem, b1, 8);
FH_OFFSET(HitItem, b2, 12);
FH_OFFSET(HitItem, instance, 16);
FH_SIZE(Instance, 112);
FH_OFFSET(Instance, render_from_object_0, 48);
FH_OFFSET(Instance, root_node, 96);
FH_OFFSET(Instance, first_triangle, 100);
FH_OFFSET(Instance, motion, 108);
FH_OFFSET(Instance, material, 104);

FH_SIZE(ShadowRayItem, 48);
FH_OFFSET(ShadowRayItem, path, 12);
FH_OFFSET(ShadowRayItem, dir_x, 16);
FH_OFFSET(ShadowRayItem, t_max, 28);
FH_OFFSET(ShadowRayItem, contrib_r, 32);

FH_SIZE(FilmPixel, 52);
FH_OFFSET(FilmPixel, sum_g, 16);
FH_OFFSET(FilmPixel, sum_b, 32);
FH_OFFSET(FilmPixel, sample_count, 48);

// The general std430 rule for C++ structs built from 4-byte scalars and glm::vec4.
template <typename S>
constexpr bool has_std430_array_stride(bool holds_vec4) {
    return sizeof(S) % (holds_vec4 ? 16 : 4) == 0;
}

TEST(Layout, ArrayStridesFollowStd430) {
    static_assert(sizeof(vec4) == 16 && alignof(uint) == 4 && sizeof(float) == 4);
    EXPECT_TRUE(has_std430_array_stride<Material>(true));
    EXPECT_TRUE(has_std430_array_stride<MaterialLayers>(true));
    EXPECT_TRUE(has_std430_array_stride<FrameParams>(true));
    for (size_t size : {sizeof(BvhNode), sizeof(BvhWideNode), sizeof(TrianglePositions), sizeof(TriangleShading), sizeof(Emitter),
                        sizeof(QueueCounters), sizeof(PathState), sizeof(PathSpectrum), sizeof(RayItem), sizeof(HitItem),
                        sizeof(ShadowRayItem), sizeof(FilmPixel), sizeof(StagePush)})
        EXPECT_EQ(size % 4, 0u);
}

TEST(Layout, SizesMatchTheGpuStructs) {
    // Repeated as runtime checks so a failing build is not the only report.
    EXPECT_EQ(sizeof(BvhNode), 32u);
    EXPECT_EQ(sizeof(BvhWideNode), 48u);
    EXPECT_EQ(sizeof(TrianglePositions), 48u);
    EXPECT_EQ(sizeof(TriangleShading), 48u);
    EXPECT_EQ(sizeof(Material), 96u);
    EXPECT_EQ(sizeof(MaterialLayers), 160u);
    EXPECT_EQ(sizeof(TextureSlot), 48u);
    EXPECT_EQ(sizeof(TriangleAttributes), 96u);
    EXPECT_EQ(sizeof(Emitter), 16u);
    EXPECT_EQ(sizeof(FrameParams), 272u);
    EXPECT_EQ(sizeof(QueueCounters), 56u);
    EXPECT_EQ(sizeof(RayItem), 32u);
    EXPECT_EQ(sizeof(HitItem), 32u);
    EXPECT_EQ(sizeof(Instance), 112u);
    EXPECT_EQ(sizeof(ShadowRayItem), 48u);
    EXPECT_EQ(sizeof(PathState), 32u);
    EXPECT_EQ(sizeof(PathSpectrum), 16u);
    EXPECT_EQ(sizeof(PathMis), 16u);
    EXPECT_EQ(sizeof(LightVertex), 64u);
    EXPECT_EQ(sizeof(FilmPixel), 52u);
    EXPECT_EQ(sizeof(StagePush), 40u);
    EXPECT_EQ(BVH_LEAF_COUNT_BITS, 16u);
}

}  // namespace
