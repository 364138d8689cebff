// Builds and checks shaders/lib/ggx_albedo_table.glsl, the GGX albedo table the energy-conserving BSDF
// needs. `test_ggx_albedo_table --write` regenerates the file (about two minutes, single-threaded); without
// it, the tests recompute spot checks of the committed table against the double-precision reference.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <fstream>
#include <random>
#include <string>

#include "ggx_albedo_reference.h"
#include "shared/layout.h"
#include "lib/cpp_compat.h"
namespace fh::glsl {
#include "lib/bsdf.glsl"
}  // namespace fh::glsl

namespace {
using namespace fh::glsl;
namespace ref = fh::test::ggx_albedo;

const int NX = GGX_ALBEDO_MU_SIZE, NY = GGX_ALBEDO_ALPHA_SIZE;
const int REFINE = 4;  // conservative raise: the interpolant is checked at 4x the table's resolution

double node_mu(double x) { return x * x * x / double((NX - 1) * (NX - 1) * (NX - 1)); }  // x in [0, NX - 1]
double node_alpha(double y) { return GGX_ALBEDO_ALPHA_MIN * std::pow(1.0 / GGX_ALBEDO_ALPHA_MIN, y / (NY - 1)); }

struct Table {
    std::vector<double> a, b, average_a, average_b;  // a[j * NX + i]: alpha row j, mu column i
};

double bilinear(const std::vector<double>& t, double x, double y) {
    const int i = std::min(int(x), NX - 2), j = std::min(int(y), NY - 2);
    const double fx = x - i, fy = y - j;
    return (1 - fy) * ((1 - fx) * t[j * NX + i] + fx * t[j * NX + i + 1]) +
           fy * ((1 - fx) * t[(j + 1) * NX + i] + fx * t[(j + 1) * NX + i + 1]);
}

// 2 int_0^1 mu T(mu) dmu for row j of a table piecewise linear in x = mu^(1/3) (NX - 1): with mu = s^3,
// 6 int s^5 T ds, a degree-6 polynomial per cell, so 4-point Gauss-Legendre is exact.
template <class Row>
double cosine_average(const Row& row) {
    const ref::Gauss g = ref::gauss_legendre(4);
    double sum = 0.0;
    for (int i = 0; i + 1 < NX; ++i)
        for (int k = 0; k < 4; ++k) {
            const double s = (i + g.x[k]) / (NX - 1);
            sum += 6.0 * std::pow(s, 5) * ((1 - g.x[k]) * row(i) + g.x[k] * row(i + 1)) * g.w[k] / (NX - 1);
        }
    return sum;
}

// Nodes are the reference albedos, then raised by the largest shortfall of the bilinear interpolant found in
// the cells around them (on a REFINE x finer grid) plus a margin for points between those samples: raising
// all four corners by d raises the whole cell by d, so the interpolant is an upper bound of A and B (and of
// f0 A + f90 B for f0, f90 >= 0), except where that would exceed 1 (below). Averages are then computed
// from the raised interpolant.
Table build_table(double margin) {
    const int FX = (NX - 1) * REFINE + 1, FY = (NY - 1) * REFINE + 1;
    std::vector<ref::Albedo> fine(FX * FY);
    for (int q = 0; q < FY; ++q) {
        for (int p = 0; p < FX; ++p) fine[q * FX + p] = ref::albedo(node_mu(double(p) / REFINE), node_alpha(double(q) / REFINE));
        if ((q + 1) % 25 == 0) std::fprintf(stderr, "reference albedo: row %d of %d\n", q + 1, FY);
    }
    Table t;
    t.a.resize(NX * NY);
    t.b.resize(NX * NY);
    for (int j = 0; j < NY; ++j)
        for (int i = 0; i < NX; ++i) {
            t.a[j * NX + i] = fine[j * REFINE * FX + i * REFINE].a;
            t.b[j * NX + i] = fine[j * REFINE * FX + i * REFINE].b;
        }
    for (auto [nodes, member] : {std::pair{&t.a, &ref::Albedo::a}, std::pair{&t.b, &ref::Albedo::b}}) {
        std::vector<double> raise_cell((NX - 1) * (NY - 1), 0.0);
        for (int q = 0; q < FY; ++q)
            for (int p = 0; p < FX; ++p) {
                const double x = double(p) / REFINE, y = double(q) / REFINE;
                const double shortfall = fine[q * FX + p].*member - bilinear(*nodes, x, y);
                for (int j = std::max(0, (q - 1) / REFINE); j <= std::min(NY - 2, q / REFINE); ++j)
                    for (int i = std::max(0, (p - 1) / REFINE); i <= std::min(NX - 2, p / REFINE); ++i)
                        raise_cell[j * (NX - 1) + i] = std::max(raise_cell[j * (NX - 1) + i], shortfall);
            }
        std::vector<double> raised = *nodes;
        for (int j = 0; j < NY; ++j)
            for (int i = 0; i < NX; ++i) {
                double r = 0.0;
                for (int cj = std::max(0, j - 1); cj <= std::min(NY - 2, j); ++cj)
                    for (int ci = std::max(0, i - 1); ci <= std::min(NX - 2, i); ++ci) r = std::max(r, raise_cell[cj * (NX - 1) + ci]);
                raised[j * NX + i] += r + margin;
            }
        *nodes = raised;
    }
    // A + B (the albedo of a white mirror, f0 = f90 = 1) is at most 1, and must stay so in the table: where
    // f0 A + f90 B > 1, 1 - E is clamped to 0 in bsdf.glsl, which no longer integrates to 1 - E_avg, and the
    // difference is amplified by 1 / (1 - E_avg) (large for f0 = f90 = 1 and small alpha). Where the raise
    // crossed 1 (small alpha, where A + B ~ 1 - alpha / (2 mu)), A gives the excess back: at most ~1e-3,
    // weighted by f0, so dielectrics (f0 ~ 0.04) stay conservative and only f0 ~ 1 ones can gain ~1e-3.
    for (int k = 0; k < NX * NY; ++k) {
        const double excess = double(float(t.a[k]) + float(t.b[k])) - 1.0;
        if (excess > 0.0) t.a[k] -= excess + 1e-7;
    }
    for (int j = 0; j < NY; ++j) {
        // Rounded to float first: the averages must integrate the table the shader reads.
        t.average_a.push_back(cosine_average([&](int i) { return double(float(t.a[j * NX + i])); }));
        t.average_b.push_back(cosine_average([&](int i) { return double(float(t.b[j * NX + i])); }));
    }
    return t;
}

void write_array(std::ofstream& out, const char* name, const std::vector<double>& v) {
    out << "const float " << name << "[" << v.size() << "] = {\n";
    for (size_t k = 0; k < v.size(); ++k) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "%.8ef", double(float(v[k])));
        out << (k % 8 == 0 ? "    " : " ") << buf << (k + 1 < v.size() ? "," : "") << (k % 8 == 7 || k + 1 == v.size() ? "\n" : "");
    }
    out << "};\n";
}

const double MARGIN = 2e-5;

void write_table(const std::string& path) {
    const Table t = build_table(MARGIN);
    std::ofstream out(path);
    out << "// GENERATED by tests/unit/test_ggx_albedo_table.cpp (`test_ggx_albedo_table --write`): do not edit.\n"
           "// GGX (height-correlated Smith) directional albedo split by Schlick's weight s = (1 - v.h)^5:\n"
           "// A = int D V cos (1 - s) dwi, B = int D V cos s dwi, at mu = (i / 31)^3 (column i) and\n"
           "// alpha = 1e-3 * 1000^(j / 31) (row j); nodes raised so the bilinear interpolant bounds A and B from\n"
           "// above (see ggx_albedo.glsl); AVERAGE_* = 2 int mu X(mu) dmu of the interpolant per row.\n"
           "#ifndef FREDHOLM_LIB_GGX_ALBEDO_TABLE_GLSL\n#define FREDHOLM_LIB_GGX_ALBEDO_TABLE_GLSL\n\n"
           "// The values are C++ only: the host uploads them into a uniform buffer (binding BINDING_GGX_ALBEDO_UNIFORM)\n"
           "// that the GLSL reads through ggx_albedo_entry(); lavapipe cannot compile large constant arrays indexed at\n"
           "// run time. Order in the buffer: A, B, AVERAGE_A, AVERAGE_B.\n"
           "const int GGX_ALBEDO_MU_SIZE = " << NX << ";\nconst int GGX_ALBEDO_ALPHA_SIZE = " << NY << ";\n"
           "const float GGX_ALBEDO_ALPHA_MIN = 1.0e-3f;\n"
           "const float GGX_ALBEDO_INV_LOG_ALPHA_RANGE = 0.144764827f;  // 1 / ln(1 / GGX_ALBEDO_ALPHA_MIN)\n"
           "const int GGX_ALBEDO_A_OFFSET = 0;\nconst int GGX_ALBEDO_B_OFFSET = " << NX * NY << ";\n"
           "const int GGX_ALBEDO_AVERAGE_A_OFFSET = " << 2 * NX * NY << ";\n"
           "const int GGX_ALBEDO_AVERAGE_B_OFFSET = " << 2 * NX * NY + NY << ";\n"
           "const int GGX_ALBEDO_TABLE_SIZE = " << 2 * NX * NY + 2 * NY << ";  // floats; a multiple of 4 (std140 vec4 packing)\n\n"
           "#ifdef __cplusplus\n";
    write_array(out, "GGX_ALBEDO_A", t.a);
    write_array(out, "GGX_ALBEDO_B", t.b);
    write_array(out, "GGX_ALBEDO_AVERAGE_A", t.average_a);
    write_array(out, "GGX_ALBEDO_AVERAGE_B", t.average_b);
    out << "#endif  // __cplusplus\n\n#endif\n";
    std::printf("wrote %s\n", path.c_str());
}

// ---- Checks of the committed table ------------------------------------------------------------------------
TEST(GgxAlbedoTable, ConstantsMatchTheBsdf) {
    EXPECT_EQ(GGX_ALBEDO_ALPHA_MIN, BSDF_MIN_ALPHA);  // below it the table clamps to its first row
    EXPECT_NEAR(GGX_ALBEDO_INV_LOG_ALPHA_RANGE, 1.0 / std::log(1.0 / GGX_ALBEDO_ALPHA_MIN), 1e-7);
}

// Every node is its reference albedo raised by at most a few 1e-3 (the interpolation error it covers).
TEST(GgxAlbedoTable, NodesMatchTheReference) {
    std::mt19937 rng(21);
    double max_raise = 0.0;
    for (int n = 0; n < 64; ++n) {
        const int i = n < 8 ? (n % 2) * (NX - 1) : int(rng() % NX), j = n < 8 ? (n / 2 % 4) * (NY - 1) / 3 : int(rng() % NY);
        const ref::Albedo r = ref::albedo(node_mu(i), node_alpha(j));
        const double da = GGX_ALBEDO_A[j * NX + i] - r.a, db = GGX_ALBEDO_B[j * NX + i] - r.b;
        EXPECT_GE(da, -3e-3) << "A at node " << i << ", " << j;  // A may give back the excess over A + B = 1
        EXPECT_GE(db, 0.0) << "B at node " << i << ", " << j;
        EXPECT_LT(std::max(da, db), 1e-2) << "node " << i << ", " << j;
        max_raise = std::max({max_raise, da, db});
    }
    std::printf("[table] largest raise of a sampled node above the reference: %.2e\n", max_raise);
}

// The shader's interpolation never underestimates A or B (up to float rounding and the cap A + B <= 1), and
// overestimates by little.
TEST(GgxAlbedoTable, InterpolationBoundsTheReferenceFromAbove) {
    std::mt19937 rng(22);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    double worst_under = 0.0, worst_under_a = 0.0, worst_over = 0.0;
    for (int n = 0; n < 300; ++n) {
        const double mu = n % 2 ? std::pow(uniform(rng), 3.0) : std::cos(glm::radians(80.0 + 9.9 * uniform(rng)));
        const double alpha = GGX_ALBEDO_ALPHA_MIN * std::pow(1.0 / GGX_ALBEDO_ALPHA_MIN, uniform(rng));
        const ref::Albedo r = ref::albedo(mu, alpha);
        const vec2 t = ggx_albedo(float(mu), float(alpha));
        worst_under_a = std::max(worst_under_a, r.a - t.x);
        worst_under = std::max(worst_under, r.b - t.y);
        worst_over = std::max({worst_over, t.x - r.a, t.y - r.b});
    }
    std::printf("[table] interpolant vs reference: B under by at most %.2e, A under by at most %.2e (cap), over by at most %.2e\n",
                worst_under, worst_under_a, worst_over);
    EXPECT_LT(worst_under, 2e-6);
    EXPECT_LT(worst_under_a, 1.5e-3);  // only where A + B is capped at 1
    EXPECT_LT(worst_over, 1.5e-2);
}

// f0 A + f90 B <= 1 for every f0, f90 <= 1, so 1 - E is never clamped (see build_table).
TEST(GgxAlbedoTable, WhiteMirrorAlbedoIsAtMostOne) {
    for (int k = 0; k < NX * NY; ++k) EXPECT_LE(GGX_ALBEDO_A[k] + GGX_ALBEDO_B[k], 1.0f) << k;
}

// The averages are the exact cosine-weighted means of the interpolant, at nodes and between them, so that
// the diffuse lobe's (1 - E(mu_i)) / (1 - E_avg) integrates to exactly 1.
TEST(GgxAlbedoTable, AveragesIntegrateTheInterpolant) {
    for (int j = 0; j < NY; ++j) {
        EXPECT_NEAR(GGX_ALBEDO_AVERAGE_A[j], cosine_average([&](int i) { return double(GGX_ALBEDO_A[j * NX + i]); }), 2e-7);
        EXPECT_NEAR(GGX_ALBEDO_AVERAGE_B[j], cosine_average([&](int i) { return double(GGX_ALBEDO_B[j * NX + i]); }), 2e-7);
    }
    const ref::Gauss g = ref::gauss_legendre(16);
    for (float alpha : {1e-3f, 2e-3f, 0.013f, 0.2f, 0.77f, 1.0f}) {
        double a = 0.0, b = 0.0;  // 2 int mu E dmu = 6 int s^5 E ds with mu = s^3, per cell of the table
        for (int i = 0; i + 1 < NX; ++i)
            for (int k = 0; k < 16; ++k) {
                const double s = (i + g.x[k]) / (NX - 1), w = 6.0 * std::pow(s, 5) * g.w[k] / (NX - 1);
                const vec2 e = ggx_albedo(float(s * s * s), alpha);
                a += w * e.x;
                b += w * e.y;
            }
        EXPECT_NEAR(ggx_albedo_average(alpha).x, a, 1e-5) << alpha;
        EXPECT_NEAR(ggx_albedo_average(alpha).y, b, 1e-5) << alpha;
    }
}

}  // namespace

int main(int argc, char** argv) {
    if (argc >= 2 && std::strcmp(argv[1], "--write") == 0) {
        write_table(argc >= 3 ? argv[2] : FH_SOURCE_DIR "/shaders/lib/ggx_albedo_table.glsl");
        return 0;
    }
    ::testing::InitGoogleTest(&argc, argv);
    return RUN_ALL_TESTS();
}
