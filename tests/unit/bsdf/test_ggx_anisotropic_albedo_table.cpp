// Builds and checks shaders/lib/tables/ggx_anisotropic_albedo_table.glsl, the single-scattering albedo of the white
// anisotropic GGX lobe that the metal's multiple-scattering lobe gives back (ggx_anisotropic_albedo.glsl).
// `test_ggx_anisotropic_albedo_table --write` regenerates the file (about a minute on two threads); without it, the
// tests recompute spot checks of the committed table.
//
// E(wo) of the white lobe: the mean, over the visible normals h of wo (a Q x Q midpoint grid of the sampler's
// inputs), of f cos / pdf = G2(wo, wi) / G1(wo) for wi = wo reflected about h (0 below the surface).
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <fstream>
#include <random>
#include <string>
#include <thread>

#include "albedo_table_fit.h"
#define BSDF_HAS_GGX_MULTISCATTER false  // the reference check reads the single-scattering lobe
#include "bsdf_test_setup.h"
#include "ggx_albedo_reference.h"

namespace {
using namespace fh::test;
namespace ref = fh::test::ggx_albedo;

// The table's shape; the committed table must have it (AnisotropicAlbedoTable.CoordinatesMatchTheLookup).
const int NX = 16, NY = 9, NZ = 16, NW = 9;  // mu^(1/3), azimuth, log alpha, stretch
const int REFINE = 2;       // the interpolant is checked (and the nodes raised) at twice the table's resolution
const int QUADRATURE = 64;  // visible normals per axis
const double MARGIN = 5e-4; // for the quadrature's error and points between the samples

double table_mu(double x) {
    const double u = x / (NX - 1);
    return u * u * u;
}
double node_mu(double x) { return std::max(table_mu(x), 1e-4); }  // grazing just above 0
double node_phi(double y) { return y / (NY - 1) * 0.5 * M_PI; }
double node_alpha(double z) { return GGX_ALBEDO_ALPHA_MIN * std::pow(1.0 / GGX_ALBEDO_ALPHA_MIN, z / (NZ - 1)); }
double node_alpha_t(double alpha, double w) { return alpha + w / (NW - 1) * (1.0 - alpha); }

struct Dir {
    double x, y, z;
};

// cos theta sqrt(1 + alpha(phi)^2 tan^2 theta) (ggx_lambda_term_lobe), alpha_t along x.
double lambda_term(const Dir& w, double alpha, double alpha_t) {
    return std::sqrt(w.z * w.z + alpha_t * alpha_t * w.x * w.x + alpha * alpha * w.y * w.y);
}

// sample_ggx_vndf_stretched in double.
Dir sample_visible_normal(const Dir& wo, double alpha, double alpha_t, double u1, double u2) {
    Dir s{alpha_t * wo.x, alpha * wo.y, wo.z};
    const double len = std::sqrt(s.x * s.x + s.y * s.y + s.z * s.z);
    s = {s.x / len, s.y / len, s.z / len};
    const double phi = 2.0 * M_PI * u1, z = (1.0 - u2) * (1.0 + s.z) - s.z;
    const double sin_theta = std::sqrt(std::clamp(1.0 - z * z, 0.0, 1.0));
    Dir h{alpha_t * (sin_theta * std::cos(phi) + s.x), alpha * (sin_theta * std::sin(phi) + s.y), std::max(z + s.z, 0.0)};
    const double hl = std::sqrt(h.x * h.x + h.y * h.y + h.z * h.z);
    return hl > 1e-300 ? Dir{h.x / hl, h.y / hl, h.z / hl} : Dir{0, 0, 0};
}

// E(wo) of the white lobe (see the top of the file), wo at cos theta = mu and azimuth phi from alpha_t's axis.
double white_albedo(double mu, double phi, double alpha, double alpha_t, int quadrature = QUADRATURE) {
    const double sin_theta = std::sqrt(std::max(0.0, 1.0 - mu * mu));
    const Dir wo{sin_theta * std::cos(phi), sin_theta * std::sin(phi), mu};
    const double lo = lambda_term(wo, alpha, alpha_t);
    double sum = 0.0;
    for (int a = 0; a < quadrature; ++a)
        for (int b = 0; b < quadrature; ++b) {
            const Dir h = sample_visible_normal(wo, alpha, alpha_t, (a + 0.5) / quadrature, (b + 0.5) / quadrature);
            const double d = wo.x * h.x + wo.y * h.y + wo.z * h.z;
            const Dir wi{2.0 * d * h.x - wo.x, 2.0 * d * h.y - wo.y, 2.0 * d * h.z - wo.z};
            if (!(wi.z > 0.0)) continue;
            const double li = lambda_term(wi, alpha, alpha_t);
            sum += (wo.z + lo) * wi.z / (lo * wi.z + wo.z * li);
        }
    return sum / (double(quadrature) * quadrature);
}

struct Table {
    std::vector<double> albedo;   // [((w * NZ + z) * NY + y) * NX + x]
    std::vector<double> average;  // [w * NZ + z]
};

// The albedos on the fine grid, two threads.
std::vector<double> fine_albedos() {
    const int FX = (NX - 1) * REFINE + 1, FY = (NY - 1) * REFINE + 1, FZ = (NZ - 1) * REFINE + 1, FW = (NW - 1) * REFINE + 1;
    std::vector<double> fine(size_t(FX) * FY * FZ * FW);
    auto work = [&](int first) {
        for (int l = first; l < FW; l += 2) {
            for (int k = 0; k < FZ; ++k) {
                const double alpha = node_alpha(double(k) / REFINE), alpha_t = node_alpha_t(alpha, double(l) / REFINE);
                for (int j = 0; j < FY; ++j)
                    for (int i = 0; i < FX; ++i)
                        fine[((size_t(l) * FZ + k) * FY + j) * FX + i] =
                            white_albedo(node_mu(double(i) / REFINE), node_phi(double(j) / REFINE), alpha, alpha_t);
            }
            std::fprintf(stderr, "anisotropic albedo: stretch slice %d of %d\n", l + 1, FW);
        }
    };
    std::thread other(work, 1);
    work(0);
    other.join();
    return fine;
}

// E_avg of slice (z, w) of the interpolant: the azimuths' mean (trapezoidal: linear between the nodes) of
// 2 int E mu dmu, whose integrand is a polynomial of degree 6 in the column coordinate per cell (mu = x^3), so
// 4-point Gauss-Legendre is exact.
template <class Entry>
double slice_average(const Entry& entry) {
    const ref::Gauss g = ref::gauss_legendre(4);
    double mean = 0.0;
    for (int j = 0; j < NY; ++j) {
        double row = 0.0;
        for (int i = 0; i + 1 < NX; ++i)
            for (int k = 0; k < 4; ++k) {
                const double x = i + g.x[k], u = x / (NX - 1);
                const double dmu = 3.0 * u * u / (NX - 1);
                row += 2.0 * table_mu(x) * dmu * ((1 - g.x[k]) * entry(i, j) + g.x[k] * entry(i + 1, j)) * g.w[k];
            }
        mean += row * (j == 0 || j == NY - 1 ? 0.5 : 1.0) / (NY - 1);
    }
    return mean;
}

Table build_table() {
    Table t;
    t.albedo = fh::test::raise_to_upper_bound_nd(fine_albedos(), {NX, NY, NZ, NW}, REFINE, MARGIN);
    for (double& e : t.albedo) e = std::min(e, 1.0);  // a white lobe keeps at most all of it
    for (int l = 0; l < NW; ++l)
        for (int k = 0; k < NZ; ++k) {
            const size_t slice = (size_t(l) * NZ + k) * NY * NX;
            // Rounded to float first: the averages must integrate the table the shader reads.
            t.average.push_back(slice_average([&](int i, int j) { return double(float(t.albedo[slice + j * NX + i])); }));
        }
    return t;
}

void write_table(const std::string& path) {
    const Table t = build_table();
    const int n4 = NX * NY * NZ * NW;
    std::ofstream out(path);
    out << "// GENERATED by tests/unit/bsdf/test_ggx_anisotropic_albedo_table.cpp (`test_ggx_anisotropic_albedo_table --write`):\n"
           "// do not edit. Directional albedo E of the white anisotropic GGX lobe (height-correlated Smith; alpha_t along the\n"
           "// direction, alpha across) at mu = (i / " << NX - 1 << ")^3 (column i), azimuth from the direction pi/2 j / " << NY - 1
        << " (row j), alpha =\n// 1e-3 * 1000^(k / " << NZ - 1 << ") (slice k) and stretch (alpha_t - alpha) / (1 - alpha) = l / " << NW - 1
        << " (block l); nodes raised so the\n// quadrilinear interpolant bounds E from above, at most 1. AVERAGE = (1 / pi) int E cos dw of the "
           "interpolant per\n// (k, l).\n"
           "#ifndef FH_GGX_ANISOTROPIC_ALBEDO_TABLE_GLSL\n#define FH_GGX_ANISOTROPIC_ALBEDO_TABLE_GLSL\n\n"
           "// The values are C++ only: the host uploads them into a storage buffer (binding BINDING_ANISOTROPIC_ALBEDO) that\n"
           "// the GLSL reads through ggx_anisotropic_albedo_entry(). Order in the buffer: ALBEDO, AVERAGE.\n"
           "const int GGX_ANISOTROPIC_ALBEDO_MU_SIZE = " << NX << ";\n"
           "const int GGX_ANISOTROPIC_ALBEDO_AZIMUTH_SIZE = " << NY << ";\n"
           "const int GGX_ANISOTROPIC_ALBEDO_ALPHA_SIZE = " << NZ << ";\n"
           "const int GGX_ANISOTROPIC_ALBEDO_STRETCH_SIZE = " << NW << ";\n"
           "const int GGX_ANISOTROPIC_ALBEDO_AVERAGE_OFFSET = " << n4 << ";\n"
           "const int GGX_ANISOTROPIC_ALBEDO_TABLE_SIZE = " << n4 + NZ * NW << ";\n\n#ifdef __cplusplus\n";
    fh::test::write_float_array(out, "GGX_ANISOTROPIC_ALBEDO", t.albedo);
    fh::test::write_float_array(out, "GGX_ANISOTROPIC_ALBEDO_AVERAGE", t.average);
    out << "#endif  // __cplusplus\n\n#endif\n";
    std::printf("wrote %s\n", path.c_str());
}

// ---- Checks of the committed table ------------------------------------------------------------------------------

// The lookup reads each node exactly where the generator put it.
TEST(AnisotropicAlbedoTable, CoordinatesMatchTheLookup) {
    ASSERT_EQ(GGX_ANISOTROPIC_ALBEDO_MU_SIZE, NX);
    ASSERT_EQ(GGX_ANISOTROPIC_ALBEDO_AZIMUTH_SIZE, NY);
    ASSERT_EQ(GGX_ANISOTROPIC_ALBEDO_ALPHA_SIZE, NZ);
    ASSERT_EQ(GGX_ANISOTROPIC_ALBEDO_STRETCH_SIZE, NW);
    for (int l = 0; l < NW; l += 4)
        for (int k = 0; k < NZ; k += 5)
            for (int j = 0; j < NY; j += 2)
                for (int i = 1; i < NX; i += 3) {
                    const double alpha = node_alpha(k), alpha_t = node_alpha_t(alpha, l);
                    if (alpha >= 1.0) continue;
                    const GgxAnisotropicCell c = ggx_anisotropic_cell(float(alpha), float(alpha_t));
                    const double mu = table_mu(i), phi = node_phi(j), s = std::sqrt(1.0 - mu * mu);
                    const float e = ggx_anisotropic_white_albedo(c, vec3(float(s * std::cos(phi)), float(s * std::sin(phi)), float(mu)));
                    EXPECT_NEAR(e, GGX_ANISOTROPIC_ALBEDO[((l * NZ + k) * NY + j) * NX + i], 2e-4) << i << " " << j << " " << k << " " << l;
                }
}

// The interpolated table bounds the white lobe's albedo from above (up to the quadrature's error), and not by much,
// at random points between the nodes; the reference is the shader's own lobe (checked against eval_bsdf here).
TEST(AnisotropicAlbedoTable, BoundsSingleScatteringFromAbove) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    double worst_under = 0.0, worst_over = 0.0;
    for (int n = 0; n < 40; ++n) {
        const double mu = 0.02 + 0.98 * uniform(rng), phi = 0.5 * M_PI * uniform(rng);
        const double roughness = 0.03 + 0.97 * uniform(rng), strength = uniform(rng);
        const double alpha = std::max(roughness * roughness, 1e-3), alpha_t = alpha + strength * strength * (1.0 - alpha);
        const double reference = white_albedo(mu, phi, alpha, alpha_t, 128);
        const double s = std::sqrt(1.0 - mu * mu);
        const double table = ggx_anisotropic_white_albedo(ggx_anisotropic_cell(float(alpha), float(alpha_t)),
                                                          vec3(float(s * std::cos(phi)), float(s * std::sin(phi)), float(mu)));
        worst_under = std::max(worst_under, reference - table);
        worst_over = std::max(worst_over, table - reference);
        EXPECT_LE(table, 1.0);
    }
    std::printf("[table] worst shortfall %.2e, worst excess %.2e\n", worst_under, worst_over);
    EXPECT_LT(worst_under, 1e-3);
    EXPECT_LT(worst_over, 3e-2);
    // The reference is the BSDF's single-scattering lobe: a white metal stretched by the extension.
    for (float roughness : {0.1f, 0.5f})
        for (float degrees : {0.0f, 70.0f}) {
            const BsdfParams p = with_anisotropy(make_bsdf_params(make_material(vec3(1.0f), 1.0f, roughness)), 0.8f,
                                                 vec2(1.0f, 0.0f));
            const vec3 wo = outgoing(degrees);
            const double quadrature = integrate_hemisphere(wo, [&](vec3 wi) { return eval_bsdf(p, wo, wi).x; });
            EXPECT_NEAR(white_albedo(wo.z, std::atan2(wo.y, wo.x), p.roughness.alpha, p.roughness.alpha_t, 128), quadrature, 2e-3)
                << roughness << " " << degrees;
        }
}

// The averages integrate the committed interpolant (so the lobe's (1 - E(w_i)) / (1 - E_avg) integrates to 1).
TEST(AnisotropicAlbedoTable, AveragesIntegrateTheInterpolant) {
    for (int l = 0; l < NW; ++l)
        for (int k = 0; k < NZ; ++k) {
            const int slice = (l * NZ + k) * NY * NX;
            const double average = slice_average([&](int i, int j) { return double(GGX_ANISOTROPIC_ALBEDO[slice + j * NX + i]); });
            EXPECT_NEAR(GGX_ANISOTROPIC_ALBEDO_AVERAGE[l * NZ + k], average, 2e-7) << k << " " << l;
        }
}

}  // namespace

int main(int argc, char** argv) {
    if (argc >= 2 && std::strcmp(argv[1], "--write") == 0) {
        write_table(argc >= 3 ? argv[2] : FH_SOURCE_DIR "/shaders/lib/tables/ggx_anisotropic_albedo_table.glsl");
        return 0;
    }
    ::testing::InitGoogleTest(&argc, argv);
    return RUN_ALL_TESTS();
}
