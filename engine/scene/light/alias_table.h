// The alias method for sampling a discrete distribution in O(1) (Walker 1977), built as in Vose 1991.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

namespace fh {

struct AliasEntry {
    double threshold;  // keep this entry if u' < threshold, else take `alias`
    uint32_t alias;    // index of the other entry sharing this slot
};

// Entry i of the result is picked with probability weights[i] / sum(weights) by: i = floor(u * n),
// u' = u * n - i, keep i if u' < threshold else alias. Deterministic. Throws std::invalid_argument for
// no weights, a negative or non-finite weight, or a zero sum.
std::vector<AliasEntry> build_alias_table(std::span<const double> weights);

}  // namespace fh
