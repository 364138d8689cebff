// Builds and checks shaders/lib/tables/glass_albedo_table.glsl, the single-scattering energy of white rough glass that
// glass_multiscatter.glsl gives back. `test_glass_albedo_table --write` regenerates the file (a few minutes on two
// threads); without it, the tests recompute spot checks of the committed table with the shader's own glass lobe.
//
// E(mu) for light from one side of an interface of relative index eta: the mean, over the visible normals h of wo
// (a Q x Q midpoint grid of the sampler's inputs), of F(wo.h) w_r + (1 - F(wo.h)) w_t eta^2, where w = f cos / pdf
// of single scattering for the reflected and refracted direction: the energy it keeps (transmission counted
// without the radiance scaling 1 / eta^2).
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <fstream>
#include <random>
#include <string>
#include <thread>

#include "albedo_table_fit.h"
#include "ggx_albedo_reference.h"
#include "shared/layout.h"
#include "lib/core/cpp_compat.h"
namespace fh::glsl {
#include "lib/bsdf/bsdf.glsl"
}  // namespace fh::glsl

namespace {
using namespace fh::glsl;
namespace ref = fh::test::ggx_albedo;

// The table's shape; the committed table must have it (GlassAlbedoTable.CoordinatesMatchTheLookup). An odd NX puts
// the inside's critical angle on a column.
const int NX = 33, NY = 32, NZ = 16;
const int REFINE = 2;   // the interpolant is checked (and the nodes raised) at twice the table's resolution
const int QUADRATURE = 64;  // visible normals per axis
const double MARGIN = 2e-4;  // for the quadrature's error and points between the samples

// mu at column coordinate x in [0, NX - 1] (glass_table_mu_coordinate inverted; critical_mu < 0: outside) and its
// derivative.
double table_mu(double x, double critical_mu) {
    const double u = x / (NX - 1);
    if (critical_mu < 0.0) return u * u;
    return u <= 0.5 ? critical_mu * 4.0 * u * u : critical_mu + (2.0 * u - 1.0) * (1.0 - critical_mu);
}
double table_mu_derivative(double x, double critical_mu) {
    const double u = x / (NX - 1);
    if (critical_mu < 0.0) return 2.0 * u / (NX - 1);
    return (u <= 0.5 ? critical_mu * 8.0 * u : 2.0 * (1.0 - critical_mu)) / (NX - 1);
}
// Where a node's energy is computed: grazing just above 0, where wo would lie in the surface.
double node_mu(double x, double critical_mu) { return std::max(table_mu(x, critical_mu), 1e-4); }
double node_alpha(double y) { return std::max(y * y / double((NY - 1) * (NY - 1)), double(BSDF_MIN_ALPHA)); }
// The index ratio of eta coordinate z in [0, NZ - 1]: (n - 1) / (n + 1) = z / (NZ - 1) * GLASS_ALBEDO_ETA_COORD_MAX.
double node_eta(double z) {
    const double c = z / (NZ - 1) * GLASS_ALBEDO_ETA_COORD_MAX;
    return std::max((1.0 + c) / (1.0 - c), 1.0 + double(GLASS_MIN_ETA_OFFSET));
}

GlassParams make_white_glass(float alpha, float eta, bool thin) {
    GlassParams g;
    g.transmission_tint = vec3(1.0f);
    g.roughness = make_isotropic_roughness(alpha);
    g.specular_color = vec3(1.0f);
    g.specular = 1.0f;
    g.eta = thin ? eta : refraction_eta(eta);
    g.thin_walled = thin ? 1u : 0u;
    g.film = make_no_film();
    return g;
}

// Single scattering's energy albedo of white glass seen at cos theta = mu (see the top of the file).
double single_scattering_energy(double mu, float alpha, float eta, bool thin = false) {
    const GlassParams g = make_white_glass(alpha, eta, thin);
    const float m = float(mu);
    const vec3 wo(std::sqrt(std::max(0.0f, 1.0f - m * m)), 0.0f, m);
    const float scale = thin ? 1.0f : g.eta * g.eta;
    double sum = 0.0;
    for (int a = 0; a < QUADRATURE; ++a)
        for (int b = 0; b < QUADRATURE; ++b) {
            const float uy = (a + 0.5f) / QUADRATURE, uz = (b + 0.5f) / QUADRATURE;
            const vec3 h = sample_ggx_vndf_lobe(g.roughness, wo, vec2(uy, uz));
            const float cos_o = dot(wo, h);
            if (!(cos_o > 0.0f)) continue;
            const float f = fresnel_dielectric(cos_o, g.eta);
            for (bool reflect : {true, false}) {
                const float share = reflect ? f : 1.0f - f;
                if (!(share > 0.0f)) continue;
                const vec3 wi = sample_glass_single(g, wo, vec3(reflect ? 0.0f : 0.99999994f, uy, uz));
                if (wi == vec3(0.0f)) continue;
                const float pdf = pdf_glass_single(g, wo, wi);
                if (!(pdf > 0.0f)) continue;
                sum += share * eval_glass_single(g, wo, wi).y / pdf * (wi.z < 0.0f ? scale : 1.0f);
            }
        }
    return sum / (QUADRATURE * QUADRATURE);
}

// 2 int_0^1 F(mu) mu dmu of the smooth interface seen from outside (eta >= 1).
double average_fresnel(double eta) {
    const int n = 20000;
    double sum = 0.0;
    for (int i = 0; i < n; ++i) {
        const double mu = (i + 0.5) / n;
        sum += 2.0 * mu * fresnel_dielectric(float(mu), float(eta)) / n;
    }
    return sum;
}

// 2 int mu E dmu of a row linear in the column coordinate per cell: mu is sqrt-warped (outside, and inside below the
// critical angle, whose cosine sits on the middle column) or linear in it, so the integrand is a polynomial of degree
// at most 4 per cell and 4-point Gauss-Legendre is exact. critical_mu < 0: the outside's coordinate.
template <class Row>
double cosine_average(const Row& row, double critical_mu) {
    const ref::Gauss g = ref::gauss_legendre(4);
    double sum = 0.0;
    for (int i = 0; i + 1 < NX; ++i)
        for (int k = 0; k < 4; ++k) {
            const double x = i + g.x[k];
            sum += 2.0 * table_mu(x, critical_mu) * table_mu_derivative(x, critical_mu) *
                   ((1 - g.x[k]) * row(i) + g.x[k] * row(i + 1)) * g.w[k];
        }
    return sum;
}

struct Table {
    std::vector<double> e_out, e_in;           // [(k * NY + j) * NX + i]
    std::vector<double> average_out, average_in, k;  // [k * NY + j]
    std::vector<double> f_average;             // [k]
};

// The energies on the fine grid of both sides, two threads.
std::vector<double> fine_energies(bool inside) {
    const int FX = (NX - 1) * REFINE + 1, FY = (NY - 1) * REFINE + 1, FZ = (NZ - 1) * REFINE + 1;
    std::vector<double> fine(size_t(FX) * FY * FZ);
    auto work = [&](int first) {
        for (int r = first; r < FZ; r += 2) {
            const double eta = node_eta(double(r) / REFINE);
            for (int q = 0; q < FY; ++q)
                for (int p = 0; p < FX; ++p)
                    fine[(size_t(r) * FY + q) * FX + p] = single_scattering_energy(
                        node_mu(double(p) / REFINE, inside ? glass_critical_mu(float(eta)) : -1.0),
                        float(node_alpha(double(q) / REFINE)), float(inside ? 1.0 / eta : eta));
            std::fprintf(stderr, "glass energy (%s): eta slice %d of %d\n", inside ? "inside" : "outside", r + 1, FZ);
        }
    };
    std::thread other(work, 1);
    work(0);
    other.join();
    return fine;
}

Table build_table() {
    Table t;
    for (bool inside : {false, true}) {
        std::vector<double> nodes = fh::test::raise_to_upper_bound_3d(fine_energies(inside), NX, NY, NZ, REFINE, MARGIN);
        for (double& e : nodes) e = std::min(e, 1.0);  // white glass keeps at most all of it
        (inside ? t.e_in : t.e_out) = nodes;
    }
    for (int k = 0; k < NZ; ++k) {
        const double eta = node_eta(k);
        const double f_average = average_fresnel(eta);
        t.f_average.push_back(f_average);
        for (int j = 0; j < NY; ++j) {
            const size_t row = (size_t(k) * NY + j) * NX;
            // Rounded to float first: the averages must integrate the table the shader reads.
            const double average_out = cosine_average([&](int i) { return double(float(t.e_out[row + i])); }, -1.0);
            const double average_in = cosine_average([&](int i) { return double(float(t.e_in[row + i])); },
                                                     glass_critical_mu(float(eta)));
            t.average_out.push_back(average_out);
            t.average_in.push_back(average_in);
            // t_out = 1 - F_avg, unless that makes t_in = K pi (1 - E_avg_out) exceed 1 (glass_multiscatter.glsl).
            double k_value = 0.0;
            if (1.0 - average_in > double(GLASS_MIN_AVERAGE_LOSS) && 1.0 - average_out > double(GLASS_MIN_AVERAGE_LOSS)) {
                k_value = (1.0 - f_average) / (M_PI * eta * eta * (1.0 - average_in));
                k_value = std::min(k_value, 1.0 / (M_PI * (1.0 - average_out)));
            }
            t.k.push_back(k_value);
        }
    }
    return t;
}

void write_table(const std::string& path) {
    const Table t = build_table();
    const int n3 = NX * NY * NZ, n2 = NY * NZ;
    std::ofstream out(path);
    out << "// GENERATED by tests/unit/bsdf/test_glass_albedo_table.cpp (`test_glass_albedo_table --write`): do not edit.\n"
           "// Single-scattering energy albedo E(mu) of white rough glass (glass_multiscatter.glsl) from outside (OUT, index\n"
           "// ratio n >= 1) and from inside (IN, 1 / n), at mu = (i / " << NX - 1 << ")^2 (column i), alpha = (j / " << NY - 1
        << ")^2 (row j, at least\n// BSDF_MIN_ALPHA) and (n - 1) / (n + 1) = 0.5 k / " << NZ - 1
        << " (slice k); nodes raised so the trilinear interpolant bounds E\n"
           "// from above, at most 1. AVERAGE_* = 2 int mu E dmu of the interpolant per (k, j); K the transmitted part's\n"
           "// constant; F_AVERAGE = 2 int mu F dmu of the smooth interface from outside, per k.\n"
           "#ifndef FH_GLASS_ALBEDO_TABLE_GLSL\n#define FH_GLASS_ALBEDO_TABLE_GLSL\n\n"
           "// The values are C++ only: the host uploads them into a storage buffer (binding BINDING_GLASS_ALBEDO) that the\n"
           "// GLSL reads through glass_albedo_entry(). Order in the buffer: OUT, IN, AVERAGE_OUT, AVERAGE_IN, K, F_AVERAGE.\n"
           "const int GLASS_ALBEDO_MU_SIZE = " << NX << ";\nconst int GLASS_ALBEDO_ROUGHNESS_SIZE = " << NY << ";\n"
           "const int GLASS_ALBEDO_ETA_SIZE = " << NZ << ";\nconst float GLASS_ALBEDO_ETA_COORD_MAX = 0.5f;\n"
           "const int GLASS_ALBEDO_OUT_OFFSET = 0;\nconst int GLASS_ALBEDO_IN_OFFSET = " << n3 << ";\n"
           "const int GLASS_ALBEDO_AVERAGE_OUT_OFFSET = " << 2 * n3 << ";\n"
           "const int GLASS_ALBEDO_AVERAGE_IN_OFFSET = " << 2 * n3 + n2 << ";\n"
           "const int GLASS_ALBEDO_K_OFFSET = " << 2 * n3 + 2 * n2 << ";\n"
           "const int GLASS_ALBEDO_F_AVERAGE_OFFSET = " << 2 * n3 + 3 * n2 << ";\n"
           "const int GLASS_ALBEDO_TABLE_SIZE = " << 2 * n3 + 3 * n2 + NZ << ";\n\n#ifdef __cplusplus\n";
    fh::test::write_float_array(out, "GLASS_ALBEDO_OUT", t.e_out);
    fh::test::write_float_array(out, "GLASS_ALBEDO_IN", t.e_in);
    fh::test::write_float_array(out, "GLASS_ALBEDO_AVERAGE_OUT", t.average_out);
    fh::test::write_float_array(out, "GLASS_ALBEDO_AVERAGE_IN", t.average_in);
    fh::test::write_float_array(out, "GLASS_ALBEDO_K", t.k);
    fh::test::write_float_array(out, "GLASS_ALBEDO_F_AVERAGE", t.f_average);
    out << "#endif  // __cplusplus\n\n#endif\n";
    std::printf("wrote %s\n", path.c_str());
}

// ---- Checks of the committed table ------------------------------------------------------------------------------

// The table's node coordinates are those glass_table_cell reads.
TEST(GlassAlbedoTable, CoordinatesMatchTheLookup) {
    EXPECT_EQ(GLASS_SMOOTH_ALPHA, BSDF_MIN_ALPHA);
    ASSERT_EQ(GLASS_ALBEDO_MU_SIZE, NX);
    ASSERT_EQ(GLASS_ALBEDO_ROUGHNESS_SIZE, NY);
    ASSERT_EQ(GLASS_ALBEDO_ETA_SIZE, NZ);
    for (int k = 0; k < NZ; ++k)
        for (int j = 0; j < NY; ++j) {
            const GlassTableCell c = glass_table_cell(float(node_alpha(j)), float(node_eta(k)));
            const int jj = c.index % NY, kk = c.index / NY;
            EXPECT_NEAR(jj + c.frac.x, std::max(double(j), std::sqrt(double(BSDF_MIN_ALPHA)) * (NY - 1)), 1e-4) << j;
            if (k > 0) EXPECT_NEAR(kk + c.frac.y, k, 1e-4) << k;
            EXPECT_EQ(c.valid, 1u);
            // Both sides of an interface read the same cell.
            const GlassTableCell inside = glass_table_cell(float(node_alpha(j)), float(1.0 / node_eta(k)));
            EXPECT_EQ(inside.index % NY, c.index % NY);
            EXPECT_NEAR(inside.index / NY + inside.frac.y, kk + c.frac.y, 1e-4);
        }
    EXPECT_EQ(glass_table_cell(0.25f, 3.2f).valid, 0u);  // beyond the table: no compensation
}

// The interpolated table bounds the energy single scattering keeps from above (up to the quadrature's error),
// and not by much: at random points between the nodes, both sides.
TEST(GlassAlbedoTable, BoundsSingleScatteringFromAbove) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    double worst_under = 0.0, worst_over = 0.0;
    for (int n = 0; n < 24; ++n) {
        const double mu = 0.02 + 0.98 * uniform(rng), roughness = 0.1 + 0.9 * uniform(rng);
        const double eta = node_eta(uniform(rng) * (NZ - 1));
        const bool inside = n % 2 == 1;
        const float alpha = float(roughness * roughness), side_eta = float(inside ? 1.0 / eta : eta);
        const double reference = single_scattering_energy(mu, alpha, side_eta);
        const GlassTableCell c = glass_table_cell(alpha, side_eta);
        const double table = glass_table_energy(c, inside ? GLASS_ALBEDO_IN_OFFSET : GLASS_ALBEDO_OUT_OFFSET, float(mu),
                                                glass_critical_mu(side_eta));
        worst_under = std::max(worst_under, reference - table);
        worst_over = std::max(worst_over, table - reference);
        EXPECT_LE(table, 1.0);
    }
    std::printf("[table] worst shortfall %.2e, worst excess %.2e\n", worst_under, worst_over);
    EXPECT_LT(worst_under, 1e-3);
    EXPECT_LT(worst_over, 2e-2);
}

// The averages integrate the interpolant (so the lobes' (1 - E(mu_i)) / (1 - E_avg) integrate to exactly 1) and
// K keeps both sides' transmitted shares in [0, 1], light from outside passing in 1 - F_avg where it can.
TEST(GlassAlbedoTable, AveragesAndSharesAreConsistent) {
    for (int k = 0; k < NZ; ++k) {
        EXPECT_NEAR(GLASS_ALBEDO_F_AVERAGE[k], average_fresnel(node_eta(k)), 1e-5);
        for (int j = 0; j < NY; ++j) {
            const int row = (k * NY + j) * NX, cell = k * NY + j;
            const double eta = node_eta(k);
            EXPECT_NEAR(GLASS_ALBEDO_AVERAGE_OUT[cell], cosine_average([&](int i) { return double(GLASS_ALBEDO_OUT[row + i]); }, -1.0), 2e-7);
            EXPECT_NEAR(GLASS_ALBEDO_AVERAGE_IN[cell], cosine_average([&](int i) { return double(GLASS_ALBEDO_IN[row + i]); },
                                                                      glass_critical_mu(float(eta))), 2e-7);
            const double t_out = eta * eta * GLASS_ALBEDO_K[cell] * M_PI * (1.0 - GLASS_ALBEDO_AVERAGE_IN[cell]);
            const double t_in = GLASS_ALBEDO_K[cell] * M_PI * (1.0 - GLASS_ALBEDO_AVERAGE_OUT[cell]);
            EXPECT_GE(GLASS_ALBEDO_K[cell], 0.0f);
            // Float rounding of 1 - E_avg where it is ~1e-5 moves t by a few 1e-3 (the shader clamps t at 1).
            if (1.0 - GLASS_ALBEDO_AVERAGE_IN[cell] < 1e-3 || 1.0 - GLASS_ALBEDO_AVERAGE_OUT[cell] < 1e-3) continue;
            EXPECT_LE(t_out, 1.0 + 1e-4);  // float rounding of K and E_avg
            EXPECT_LE(t_in, 1.0 + 1e-4);
            if (t_in < 0.999 && GLASS_ALBEDO_K[cell] > 0.0f) EXPECT_NEAR(t_out, 1.0 - GLASS_ALBEDO_F_AVERAGE[k], 1e-4);
        }
    }
}

}  // namespace

int main(int argc, char** argv) {
    if (argc >= 2 && std::strcmp(argv[1], "--write") == 0) {
        write_table(argc >= 3 ? argv[2] : FH_SOURCE_DIR "/shaders/lib/tables/glass_albedo_table.glsl");
        return 0;
    }
    if (argc >= 2 && std::strcmp(argv[1], "--probe") == 0) {
        const float alpha = float(std::atof(argv[2])), eta = float(std::atof(argv[3]));
        for (int i = 0; i <= 40; ++i) {
            const double mu = std::max(i / 40.0, 1e-3);
            const GlassTableCell c = glass_table_cell(alpha, eta);
            const double table = glass_table_energy(c, eta >= 1.0f ? GLASS_ALBEDO_OUT_OFFSET : GLASS_ALBEDO_IN_OFFSET, float(mu),
                                                    glass_critical_mu(eta));
            std::printf("mu %.3f ref %.5f table %.5f excess %.5f\n", mu, single_scattering_energy(mu, alpha, eta), table,
                        table - single_scattering_energy(mu, alpha, eta));
        }
        return 0;
    }
    ::testing::InitGoogleTest(&argc, argv);
    return RUN_ALL_TESTS();
}
