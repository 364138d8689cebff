// Light sampling pdfs integrate to 1: over area (sum of pdf_area x area over the emitter table), and over
// solid angle from a point enclosed by emitters (every direction sees exactly one emitter's front face).
#include <gtest/gtest.h>

#include <cmath>

#include "scene/bvh/bvh.h"
#include "scene/pack.h"
#include "scene/scene.h"
#include "test_meshes.h"

namespace fh {
namespace {

Scene make_emitter_scene(const test::Mesh& mesh, bool flip_inward) {
    std::vector<glm::vec3> positions = mesh.flatten();
    if (flip_inward)
        for (size_t t = 0; t < positions.size(); t += 3) std::swap(positions[t + 1], positions[t + 2]);
    gpu::Material m{};
    m.emission = glm::vec4(1.0f, 0.5f, 0.25f, 0.0f);
    m.roughness = 1.0f;
    m.ior = 1.5f;
    return test::make_single_material_scene(positions, m);
}

double triangle_area(const gpu::TrianglePositions& t) {
    glm::dvec3 p0(t.p0_x, t.p0_y, t.p0_z), p1(t.p1_x, t.p1_y, t.p1_z), p2(t.p2_x, t.p2_y, t.p2_z);
    return 0.5 * glm::length(glm::cross(p1 - p0, p2 - p0));
}

TEST(LightPdf, AreaPdfIntegratesToOne) {
    Scene scene = make_emitter_scene(test::make_sphere({1, 2, 3}, 0.7f, 12, 24), false);
    Bvh bvh = build_bvh(scene.positions);
    PackedScene packed = pack_scene(scene, bvh);
    double integral = 0, pick_total = 0;
    for (const gpu::Emitter& e : packed.emitters) {
        integral += double(packed.shading[e.light].light_pdf_area) * triangle_area(packed.positions[e.light]);
        pick_total += e.pick_pdf;
    }
    EXPECT_NEAR(pick_total, 1.0, 1e-6);
    EXPECT_NEAR(integral, 1.0, 1e-5);
}

// pdf_omega = pdf_area * dist^2 / |cos| (the conversion the shade stage uses), integrated over the sphere
// of directions by Monte Carlo from a point inside a closed sphere of inward-facing emitters.
TEST(LightPdf, SolidAnglePdfIntegratesToOneFromInside) {
    Scene scene = make_emitter_scene(test::make_sphere({0, 0, 0}, 2.0f, 16, 32), true);
    Bvh bvh = build_bvh(scene.positions);
    PackedScene packed = pack_scene(scene, bvh);
    const glm::dvec3 x(0.3, -0.4, 0.5);
    test::Rng rng(17);
    const int n = 200000;
    double sum = 0, sum2 = 0;
    for (int i = 0; i < n; ++i) {
        double z = 1.0 - 2.0 * rng.uniform(), phi = 2.0 * M_PI * rng.uniform(), r = std::sqrt(1.0 - z * z);
        glm::dvec3 d(r * std::cos(phi), r * std::sin(phi), z);
        double pdf = 0;
        for (size_t t = 0; t < packed.positions.size(); ++t) {  // the one triangle the direction hits
            const auto& tp = packed.positions[t];
            glm::dvec3 p0(tp.p0_x, tp.p0_y, tp.p0_z), e1 = glm::dvec3(tp.p1_x, tp.p1_y, tp.p1_z) - p0,
                e2 = glm::dvec3(tp.p2_x, tp.p2_y, tp.p2_z) - p0;
            glm::dvec3 q = glm::cross(d, e2);
            double det = glm::dot(e1, q);
            if (det == 0) continue;
            glm::dvec3 s = x - p0;
            double b1 = glm::dot(s, q) / det, b2 = glm::dot(d, glm::cross(s, e1)) / det;
            double dist = glm::dot(e2, glm::cross(s, e1)) / det;
            if (b1 < 0 || b2 < 0 || b1 + b2 > 1 || dist <= 0) continue;
            glm::dvec3 n_light = glm::normalize(glm::cross(e1, e2));
            double cos_light = -glm::dot(n_light, d);
            ASSERT_GT(cos_light, 0.0) << "emitters must face the point";
            pdf = packed.shading[t].light_pdf_area * dist * dist / cos_light;
            break;
        }
        double f = pdf * 4.0 * M_PI;  // estimator of the integral with uniform directions (pdf 1 / 4 pi)
        sum += f;
        sum2 += f * f;
    }
    double mean = sum / n, std_error = std::sqrt((sum2 / n - mean * mean) / n);
    EXPECT_NEAR(mean, 1.0, 5 * std_error + 1e-4) << "std error " << std_error;
}

}  // namespace
}  // namespace fh
