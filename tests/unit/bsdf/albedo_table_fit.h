// Shared by the generators of the BSDF's albedo tables (test_ggx_albedo_table, test_sheen_albedo_table): a table
// of nx x ny nodes read by bilinear interpolation, raised so that the interpolant bounds the reference from above
// (the energy-conserving layerings need E_table >= E_true), and written as a C++ array for the .glsl file.
#pragma once
#include <algorithm>
#include <cstdio>
#include <ostream>
#include <vector>

namespace fh::test {

// t[j * nx + i] (row j, column i) at x in [0, nx - 1], y in [0, ny - 1].
inline double interpolate_bilinear(const std::vector<double>& t, int nx, int ny, double x, double y) {
    const int i = std::min(int(x), nx - 2), j = std::min(int(y), ny - 2);
    const double fx = x - i, fy = y - j;
    return (1 - fy) * ((1 - fx) * t[j * nx + i] + fx * t[j * nx + i + 1]) +
           fy * ((1 - fx) * t[(j + 1) * nx + i] + fx * t[(j + 1) * nx + i + 1]);
}

// Nodes are the reference values (every `refine`-th sample of `fine`, a grid (nx - 1) refine + 1 wide), raised by
// the largest shortfall of the interpolant found in the cells around them plus `margin` for points between the
// samples: raising all four corners of a cell by d raises the whole cell by d.
inline std::vector<double> raise_to_upper_bound(const std::vector<double>& fine, int nx, int ny, int refine, double margin) {
    const int fx = (nx - 1) * refine + 1, fy = (ny - 1) * refine + 1;
    std::vector<double> nodes(size_t(nx) * ny);
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) nodes[j * nx + i] = fine[j * refine * fx + i * refine];
    std::vector<double> raise_cell(size_t(nx - 1) * (ny - 1), 0.0);
    for (int q = 0; q < fy; ++q)
        for (int p = 0; p < fx; ++p) {
            const double shortfall = fine[q * fx + p] - interpolate_bilinear(nodes, nx, ny, double(p) / refine, double(q) / refine);
            for (int j = std::max(0, (q - 1) / refine); j <= std::min(ny - 2, q / refine); ++j)
                for (int i = std::max(0, (p - 1) / refine); i <= std::min(nx - 2, p / refine); ++i)
                    raise_cell[j * (nx - 1) + i] = std::max(raise_cell[j * (nx - 1) + i], shortfall);
        }
    std::vector<double> raised = nodes;
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            double r = 0.0;
            for (int cj = std::max(0, j - 1); cj <= std::min(ny - 2, j); ++cj)
                for (int ci = std::max(0, i - 1); ci <= std::min(nx - 2, i); ++ci) r = std::max(r, raise_cell[cj * (nx - 1) + ci]);
            raised[j * nx + i] += r + margin;
        }
    return raised;
}

// raise_to_upper_bound in any number of dimensions, tighter: `fine` holds ((n_d - 1) refine + 1) samples along each
// dimension d of `sizes` (the first fastest). Nodes start at the samples they sit on; then, sweep after sweep, each
// sample the multilinear interpolant falls short of by d raises the 2^D corners of its cell by d w_n / sum(w^2) (w_n
// their interpolation weights: the smallest change that lifts the interpolant there by exactly d, Kaczmarz's
// projection), until no sample is short by more than 1e-7; then every node gets `margin` for points between the
// samples. Nodes only rise, so a sample met once stays met except through its neighbours' cells, which the sweeps
// revisit.
inline std::vector<double> raise_to_upper_bound_nd(const std::vector<double>& fine, const std::vector<int>& sizes,
                                                   int refine, double margin) {
    const int dims = int(sizes.size()), corners = 1 << dims;
    std::vector<size_t> fine_stride(dims), node_stride(dims);
    size_t fine_count = 1, node_count = 1;
    for (int d = 0; d < dims; ++d) {
        fine_stride[d] = fine_count;
        node_stride[d] = node_count;
        fine_count *= size_t(sizes[d] - 1) * refine + 1;
        node_count *= size_t(sizes[d]);
    }
    std::vector<double> nodes(node_count);
    for (size_t n = 0; n < node_count; ++n) {
        size_t f = 0;
        for (int d = 0; d < dims; ++d) f += (n / node_stride[d] % sizes[d]) * refine * fine_stride[d];
        nodes[n] = fine[f];
    }
    std::vector<size_t> index(corners);
    std::vector<double> weight(corners);
    std::vector<int> cell(dims);
    std::vector<double> frac(dims);
    for (int sweep = 0; sweep < 1000; ++sweep) {
        double worst = 0.0;
        for (size_t f = 0; f < fine_count; ++f) {
            for (int d = 0; d < dims; ++d) {
                const int p = int(f / fine_stride[d] % (size_t(sizes[d] - 1) * refine + 1));
                cell[d] = std::min(p / refine, sizes[d] - 2);
                frac[d] = double(p) / refine - cell[d];
            }
            double value = 0.0, norm = 0.0;
            for (int c = 0; c < corners; ++c) {
                size_t at = 0;
                double w = 1.0;
                for (int d = 0; d < dims; ++d) {
                    const int up = (c >> d) & 1;
                    at += size_t(cell[d] + up) * node_stride[d];
                    w *= up ? frac[d] : 1 - frac[d];
                }
                index[c] = at;
                weight[c] = w;
                value += w * nodes[at];
                norm += w * w;
            }
            const double shortfall = fine[f] - value;
            if (shortfall <= 1e-7) continue;
            worst = std::max(worst, shortfall);
            for (int c = 0; c < corners; ++c) nodes[index[c]] += shortfall * weight[c] / norm;
        }
        if (worst <= 1e-7) break;
    }
    for (double& n : nodes) n += margin;
    return nodes;
}

// raise_to_upper_bound_nd over ((nz - 1) refine + 1) slices of ((ny - 1) refine + 1) rows of ((nx - 1) refine + 1)
// samples.
inline std::vector<double> raise_to_upper_bound_3d(const std::vector<double>& fine, int nx, int ny, int nz, int refine,
                                                   double margin) {
    return raise_to_upper_bound_nd(fine, {nx, ny, nz}, refine, margin);
}

// `const float NAME[n] = {...};`, eight floats a line, each rounded to float as the shader reads it.
inline void write_float_array(std::ostream& out, const char* name, const std::vector<double>& v) {
    out << "const float " << name << "[" << v.size() << "] = {\n";
    for (size_t k = 0; k < v.size(); ++k) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "%.8ef", double(float(v[k])));
        out << (k % 8 == 0 ? "    " : " ") << buf << (k + 1 < v.size() ? "," : "") << (k % 8 == 7 || k + 1 == v.size() ? "\n" : "");
    }
    out << "};\n";
}

}  // namespace fh::test
