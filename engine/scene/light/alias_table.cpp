// Alias table construction (Vose 1991, "A linear algorithm for generating random numbers with a given
// distribution", IEEE TSE 17(9)), in double precision.
#include "scene/light/alias_table.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace fh {

std::vector<AliasEntry> build_alias_table(std::span<const double> weights) {
    const size_t n = weights.size();
    if (n == 0) throw std::invalid_argument("alias_table.cpp: no weights");
    double total = 0.0;
    for (size_t i = 0; i < n; ++i) {
        if (!(weights[i] >= 0.0) || !std::isfinite(weights[i]))
            throw std::invalid_argument("alias_table.cpp: weight " + std::to_string(i) + " is negative or not finite");
        total += weights[i];
    }
    if (!(total > 0.0)) throw std::invalid_argument("alias_table.cpp: the weights sum to zero");

    // Scaled probabilities q_i = n p_i; entries below 1 are "small" and get topped up by a "large" one.
    std::vector<double> q(n);
    std::vector<uint32_t> small, large;
    for (size_t i = 0; i < n; ++i) {
        q[i] = weights[i] * double(n) / total;
        (q[i] < 1.0 ? small : large).push_back(uint32_t(i));
    }
    std::vector<AliasEntry> table(n);
    while (!small.empty() && !large.empty()) {
        const uint32_t s = small.back();
        small.pop_back();
        const uint32_t l = large.back();
        large.pop_back();
        table[s] = {q[s], l};
        q[l] = (q[l] + q[s]) - 1.0;  // Vose's order of operations loses less precision than q[l] - (1 - q[s])
        (q[l] < 1.0 ? small : large).push_back(l);
    }
    // What is left is 1 up to rounding: such entries always keep themselves.
    for (uint32_t i : large) table[i] = {1.0, i};
    for (uint32_t i : small) table[i] = {1.0, i};
    return table;
}

}  // namespace fh
