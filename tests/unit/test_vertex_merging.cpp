// Vertex merging's schedule and sizes (engine/render/vertex_merging.h, light_tracing.h, memory_estimate.h).
#include <gtest/gtest.h>

#include <cmath>

#include "render/light_tracing.h"
#include "render/memory_estimate.h"
#include "render/renderer.h"
#include "render/vertex_merging.h"

namespace fh {
namespace {

RenderSettings vcm_settings() {
    RenderSettings s;
    s.integrator = Integrator::vcm;
    return s;
}

// r_n = r_1 n^((alpha - 1) / 2): the radius at sample index n - 1 over the first sample's, for alpha = 3/4.
TEST(VertexMerging, RadiusShrinksAsTheEighthRootOfTheSampleCount) {
    RenderSettings s = vcm_settings();
    s.merge_radius = 0.01f;
    EXPECT_FLOAT_EQ(merge_radius_at(s, 2.0, 0), 0.02f);
    EXPECT_NEAR(merge_radius_at(s, 2.0, 255) / merge_radius_at(s, 2.0, 0), std::pow(256.0, -0.125), 1e-6);
    EXPECT_LT(merge_radius_at(s, 2.0, 1), merge_radius_at(s, 2.0, 0));
}

TEST(VertexMerging, GridBucketsArePowersOfTwoNearAQuarterOfTheSlots) {
    EXPECT_EQ(count_merge_grid_cells(16, 1), 1024u);
    EXPECT_EQ(count_merge_grid_cells(65536, 15), 262144u);  // 983,040 slots / 4 -> 245,760 -> 2^18
    EXPECT_EQ(count_merge_grid_cells(1u << 30, 64), 1u << 24);
}

// A merge at the first camera vertex takes a light vertex one segment short of the path: one slot more than BDPT.
TEST(VertexMerging, StoresOneLightVertexMoreThanBdpt) {
    RenderSettings s = vcm_settings();
    EXPECT_EQ(count_light_vertex_slots(s), BDPT_DEFAULT_DEPTH - 1);
    s.max_depth = 6;
    EXPECT_EQ(count_light_vertex_slots(s), 5u);
    s.integrator = Integrator::bdpt;
    EXPECT_EQ(count_light_vertex_slots(s), 4u);
}

TEST(VertexMerging, BuffersOnlyForVcm) {
    RenderSettings s = vcm_settings();
    const PathStore vcm = make_path_store(s);
    EXPECT_TRUE(vcm.bdpt && vcm.vcm);
    EXPECT_EQ(merge_points_bytes(1000, vcm), 1000u * 15u * 16u);
    EXPECT_EQ(path_dvm_bytes(1000, vcm), 4000u);
    EXPECT_EQ(merge_grid_bytes(1000, vcm), (2u * 4096u + 15000u) * 4u);
    s.integrator = Integrator::bdpt;
    const PathStore bdpt = make_path_store(s);
    EXPECT_EQ(merge_points_bytes(1000, bdpt), 16u);
    EXPECT_EQ(path_dvm_bytes(1000, bdpt), 4u);
    EXPECT_EQ(merge_grid_bytes(1000, bdpt), 4u);
}

// With dispersion or motion blur a VCM wave holds one sample index (its wavelengths and time are shared by the wave):
// plan_waves given a capacity of the film's pixels then plans one sample per wave.
TEST(VertexMerging, WavesHoldOneSampleWithDispersionOrMotionBlur) {
    EXPECT_TRUE(waves_hold_one_sample(Integrator::vcm, gpu::EFFECT_SPECTRAL));
    EXPECT_TRUE(waves_hold_one_sample(Integrator::vcm, gpu::EFFECT_MOTION_BLUR | gpu::EFFECT_THIN_LENS));
    EXPECT_FALSE(waves_hold_one_sample(Integrator::vcm, gpu::EFFECT_THIN_LENS));
    EXPECT_FALSE(waves_hold_one_sample(Integrator::bdpt, gpu::EFFECT_SPECTRAL | gpu::EFFECT_MOTION_BLUR));
    for (const Wave& w : plan_waves(100, 0, 8, 100)) EXPECT_EQ(w.sample_count, 1u);
}

}  // namespace
}  // namespace fh
