// pack_scene and the emitter alias table: leaf-order packing, emitter powers and pdfs, and sampling
// frequencies that match pick_pdf.
#include <algorithm>
#include <cmath>
#include <numeric>

#include <glm/gtc/constants.hpp>
#include <gtest/gtest.h>

#include "scene/light/alias_table.h"
#include "scene/pack.h"
#include "scene/bvh/wide_bvh.h"
#include "test_meshes.h"

namespace {
using fh::gpu::Emitter;

fh::gpu::Material make_material(glm::vec3 emission, bool double_sided) {
    fh::gpu::Material m{};
    m.base_color = glm::vec4(0.5f);
    m.emission = glm::vec4(emission, 0.0f);
    m.flags = double_sided ? fh::gpu::MATERIAL_DOUBLE_SIDED : 0u;
    return m;
}

// A scene of random triangles; every third one emits, with one of three materials.
fh::Scene make_test_scene(size_t count) {
    fh::Scene s;
    s.positions = fh::test::make_random_soup(count, 31, 4.0f, 1.0f);
    s.materials = {make_material({0, 0, 0}, false), make_material({1, 2, 3}, false), make_material({5, 0, 0.5f}, true)};
    for (size_t t = 0; t < count; ++t) {
        const bool with_normals = t % 2 == 0;
        const glm::vec3 n = with_normals ? glm::vec3(0, 0, 1) : glm::vec3(0.0f);
        s.normals.insert(s.normals.end(), {n, n, n});
        s.triangle_has_normals.push_back(with_normals ? 1 : 0);
        s.triangle_material.push_back(t % 3 == 0 ? 0u : uint32_t(1 + t % 2));
    }
    // A zero-area emitter is not an emitter.
    s.positions[3] = s.positions[4] = s.positions[5];
    return s;
}

double area_of(const fh::gpu::TrianglePositions& p) {
    const glm::dvec3 a(p.p0_x, p.p0_y, p.p0_z), b(p.p1_x, p.p1_y, p.p1_z), c(p.p2_x, p.p2_y, p.p2_z);
    return 0.5 * glm::length(glm::cross(b - a, c - a));
}

// pi L A per emitting side, L the luminance of the material's (untextured) emission.
double expected_power(const fh::Scene& s, const fh::PackedScene& packed, uint32_t light) {
    const fh::gpu::Material& m = s.materials[packed.shading[light].material];
    const double lum = 0.2126 * m.emission.r + 0.7152 * m.emission.g + 0.0722 * m.emission.b;
    return lum * area_of(packed.positions[light]) * glm::pi<double>() *
           ((m.flags & fh::gpu::MATERIAL_DOUBLE_SIDED) ? 2.0 : 1.0);
}

// Probability that the alias table picks each entry, from its thresholds (exact up to rounding).
std::vector<double> implied_probabilities(const std::vector<fh::AliasEntry>& table) {
    std::vector<double> p(table.size(), 0.0);
    for (size_t i = 0; i < table.size(); ++i) {
        p[i] += table[i].threshold / double(table.size());
        p[table[i].alias] += (1.0 - table[i].threshold) / double(table.size());
    }
    return p;
}

TEST(AliasTable, ReproducesTheWeights) {
    const std::vector<double> weights = {0.0, 1.0, 2.0, 0.001, 100.0, 3.5, 0.0, 7.25, 1e-9};
    const auto table = fh::build_alias_table(weights);
    const double total = std::accumulate(weights.begin(), weights.end(), 0.0);
    const auto p = implied_probabilities(table);
    for (size_t i = 0; i < weights.size(); ++i) EXPECT_NEAR(p[i], weights[i] / total, 1e-15) << i;
    EXPECT_EQ(implied_probabilities(fh::build_alias_table(std::vector<double>{2.0}))[0], 1.0);
    EXPECT_THROW(fh::build_alias_table(std::vector<double>{}), std::invalid_argument);
    EXPECT_THROW(fh::build_alias_table(std::vector<double>{0.0, 0.0}), std::invalid_argument);
    EXPECT_THROW(fh::build_alias_table(std::vector<double>{1.0, -1.0}), std::invalid_argument);
}

TEST(Pack, StoresTrianglesInLeafOrder) {
    const fh::Scene s = make_test_scene(500);
    const fh::Bvh bvh = fh::build_bvh(s.positions);
    const fh::PackedScene packed = fh::pack_scene(s, bvh);
    ASSERT_EQ(packed.positions.size(), 500u);
    ASSERT_EQ(packed.shading.size(), 500u);
    const fh::WideBvh wide = fh::make_wide_nodes(bvh.nodes, bvh.max_leaf_size);
    EXPECT_EQ(packed.nodes.size(), wide.nodes.size());
    EXPECT_EQ(packed.materials.size(), 3u);
    for (size_t i = 0; i < 500; ++i) {
        const uint32_t t = bvh.triangle_order[wide.leaf_order[i]];
        EXPECT_EQ(packed.positions[i].p2_y, s.positions[3 * t + 2].y);
        EXPECT_EQ(packed.positions[i].p0_x, s.positions[3 * t].x);
        EXPECT_EQ(packed.shading[i].material, s.triangle_material[t]);
        EXPECT_EQ(packed.shading[i].flags, s.triangle_has_normals[t] ? fh::gpu::TRIANGLE_HAS_NORMALS : 0u);
        EXPECT_EQ(packed.shading[i].n1_z, s.normals[3 * t + 1].z);
    }
}

// Traversal leaves its loops to ask the material about coverage only on triangles flagged TRIANGLE_ALPHA_TESTED:
// exactly those whose material is MASK or BLEND.
TEST(Pack, FlagsTrianglesOfAlphaTestedMaterials) {
    fh::Scene s = make_test_scene(300);
    s.materials[1].alpha_mode = fh::gpu::ALPHA_MASK;
    s.materials[2].alpha_mode = fh::gpu::ALPHA_BLEND;
    const fh::Bvh bvh = fh::build_bvh(s.positions);
    const fh::PackedScene packed = fh::pack_scene(s, bvh);
    size_t flagged = 0;
    for (size_t i = 0; i < packed.positions.size(); ++i) {
        const uint32_t material = s.triangle_material[packed.positions[i].source_index];
        const uint32_t expected = material == 0 ? 0u : fh::gpu::TRIANGLE_ALPHA_TESTED;
        EXPECT_EQ(packed.positions[i].flags, expected) << i;
        flagged += expected != 0u;
    }
    EXPECT_EQ(flagged, 200u);  // materials 1 and 2: two triangles in three
}

TEST(Pack, WeighsEmittersByPower) {
    const fh::Scene s = make_test_scene(500);
    const fh::PackedScene packed = fh::pack_scene(s, fh::build_bvh(s.positions));
    double total = 0.0, pdf_sum = 0.0;
    std::vector<int> is_emitter(packed.shading.size(), 0);
    for (const Emitter& e : packed.emitters) {
        ASSERT_LT(e.light, packed.shading.size());
        ++is_emitter[e.light];
        const double area = area_of(packed.positions[e.light]);
        total += expected_power(s, packed, e.light);
        pdf_sum += e.pick_pdf;
        EXPECT_NEAR(packed.shading[e.light].light_pdf_area, e.pick_pdf / area, 1e-6 * e.pick_pdf / area);
        EXPECT_LT(e.alias, packed.emitters.size());
    }
    EXPECT_NEAR(packed.total_emitted_power, total, 1e-9 * total);
    EXPECT_NEAR(pdf_sum, 1.0, 1e-5);
    for (const Emitter& e : packed.emitters) {
        const double power = expected_power(s, packed, e.light);
        EXPECT_NEAR(e.pick_pdf, power / total, 1e-6 * power / total);
    }
    // Every emissive triangle with area is an emitter exactly once; the others have light_pdf_area 0.
    size_t expected = 0;
    for (size_t i = 0; i < packed.shading.size(); ++i) {
        const bool emissive = packed.shading[i].material != 0 && area_of(packed.positions[i]) > 0.0;
        expected += emissive;
        EXPECT_EQ(is_emitter[i], emissive ? 1 : 0) << i;
        if (!emissive) {
            EXPECT_EQ(packed.shading[i].light_pdf_area, 0.0f);
        }
    }
    EXPECT_EQ(packed.emitters.size(), expected);
    EXPECT_LT(expected, 334u);  // the zero-area emitter was left out
}

// Above 1024 triangles the emitters' luminance is measured on two threads (pack.cpp); every triangle still gets its own.
TEST(Pack, WeighsEveryEmitterOfALargeScene) {
    const fh::Scene s = make_test_scene(5000);
    const fh::PackedScene packed = fh::pack_scene(s, fh::build_bvh(s.positions));
    double total = 0.0;
    for (const Emitter& e : packed.emitters) total += expected_power(s, packed, e.light);
    EXPECT_NEAR(packed.total_emitted_power, total, 1e-9 * total);
    EXPECT_EQ(packed.emitters.size(), 3332u);  // 3333 of 5000 emit (t % 3 != 0), less the zero-area triangle 1
    for (const Emitter& e : packed.emitters) {
        const double power = expected_power(s, packed, e.light);
        EXPECT_NEAR(e.pick_pdf, power / total, 1e-6 * power / total) << e.light;
    }
}

TEST(Pack, AliasSamplingMatchesPickPdf) {
    const fh::Scene s = make_test_scene(60);
    const fh::PackedScene packed = fh::pack_scene(s, fh::build_bvh(s.positions));
    const size_t n = packed.emitters.size();
    ASSERT_GT(n, 10u);
    const size_t samples = 1000000;
    std::vector<size_t> counts(n, 0);
    fh::test::Rng rng(99);
    for (size_t i = 0; i < samples; ++i) ++counts[fh::sample_alias(packed.emitters, rng.uniform())];
    for (size_t e = 0; e < n; ++e) {
        const double p = packed.emitters[e].pick_pdf;
        const double sigma = std::sqrt(p * (1 - p) / double(samples));
        // 5 sigma per entry: with ~40 entries a false alarm has probability ~2e-5.
        EXPECT_NEAR(double(counts[e]) / double(samples), p, 5 * sigma + 1e-7) << "emitter " << e;
    }
    // The edges of [0, 1): u = 0 and the largest float below 1.
    EXPECT_LT(fh::sample_alias(packed.emitters, 0.0f), n);
    EXPECT_LT(fh::sample_alias(packed.emitters, 0x1.fffffep-1f), n);
}

TEST(Pack, CornellLightPower) {
    const fh::Scene s = fh::load_gltf(std::filesystem::path(FH_SOURCE_DIR) / "scenes/cornell.gltf");
    const fh::PackedScene packed = fh::pack_scene(s, fh::build_bvh(s.positions));
    ASSERT_EQ(packed.emitters.size(), 2u);
    const glm::dvec3 radiance = 18.387 * glm::dvec3(1.0, 0.7607168107902321, 0.36730135421765375);
    const double lum = 0.2126 * radiance.r + 0.7152 * radiance.g + 0.0722 * radiance.b;
    const double area = 0.46 * 0.38;  // x in [-0.23, 0.23], z in [-0.18, 0.2]
    EXPECT_NEAR(packed.total_emitted_power, lum * area * glm::pi<double>(), 1e-5 * packed.total_emitted_power);
    for (const Emitter& e : packed.emitters) EXPECT_NEAR(packed.shading[e.light].light_pdf_area, 1.0 / area, 1e-3);
}

TEST(Pack, SceneWithoutEmittersHasNoTable) {
    fh::Scene s = make_test_scene(30);
    s.materials[1].emission = s.materials[2].emission = glm::vec4(0.0f);
    const fh::PackedScene packed = fh::pack_scene(s, fh::build_bvh(s.positions));
    EXPECT_TRUE(packed.emitters.empty());
    EXPECT_EQ(packed.total_emitted_power, 0.0);
}

// The light effects follow the light table, by value: a black emitter, a zero-area one or a black light
// switches nothing on; an emitting triangle or a punctual light of non-zero power does.
TEST(Pack, LightEffectsFollowTheLightTable) {
    namespace gpu = fh::gpu;
    fh::Scene s = make_test_scene(30);
    s.materials[1].emission = s.materials[2].emission = glm::vec4(0.0f);
    fh::SceneLight black;
    black.intensity = glm::vec3(0.0f);
    s.lights = {black};
    EXPECT_EQ(fh::pack_scene(s, fh::build_bvh(s.positions)).effects.bits & gpu::EFFECT_LIGHTS, 0u);

    s.lights[0].intensity = glm::vec3(0.0f, 2.0f, 0.0f);
    fh::PackedScene packed = fh::pack_scene(s, fh::build_bvh(s.positions));
    EXPECT_EQ(packed.effects.bits & gpu::EFFECT_LIGHTS, gpu::EFFECT_PUNCTUAL_LIGHTS);

    s.lights.clear();
    s.materials[2].emission = glm::vec4(0.0f, 0.0f, 0.5f, 0.0f);
    packed = fh::pack_scene(s, fh::build_bvh(s.positions));
    EXPECT_EQ(packed.effects.bits & gpu::EFFECT_LIGHTS, gpu::EFFECT_EMISSIVE_TRIANGLES);
    // The table says why, in list_effects() order (emissive triangles before punctual lights before the environment).
    std::vector<std::string> names;
    for (const fh::EffectDecision& d : packed.effects.decisions) names.push_back(d.name);
    const auto at = [&](const char* name) { return std::find(names.begin(), names.end(), name) - names.begin(); };
    EXPECT_LT(at("emissive-triangles"), at("punctual-lights"));
    EXPECT_LT(at("punctual-lights"), at("environment"));
    EXPECT_EQ(names.size(), fh::list_effects().size());
    for (const fh::EffectDecision& d : packed.effects.decisions) {
        if (d.bit == gpu::EFFECT_EMISSIVE_TRIANGLES) {
            EXPECT_NE(d.why.find("material 2"), std::string::npos) << d.why;
        }
    }
}

}  // namespace
