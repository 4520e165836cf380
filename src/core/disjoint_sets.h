#pragma once
// Disjoint sets over 0 .. n-1 (union-find with path halving): which elements a set of pairwise
// joins has connected. find() gives each set's representative, its smallest element.
#include <algorithm>
#include <cstdint>
#include <numeric>
#include <vector>

namespace daisy {

class DisjointSets {
public:
    explicit DisjointSets(std::size_t n) : parent_(n) {
        std::iota(parent_.begin(), parent_.end(), 0u);
    }
    uint32_t find(uint32_t i) {
        while (parent_[i] != i)
            i = parent_[i] = parent_[parent_[i]];
        return i;
    }
    void join(uint32_t a, uint32_t b) {
        a = find(a), b = find(b);
        if (a != b) parent_[std::max(a, b)] = std::min(a, b);
    }

private:
    std::vector<uint32_t> parent_;
};

}  // namespace daisy
