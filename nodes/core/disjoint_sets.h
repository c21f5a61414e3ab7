// Union-find over the indices [0, n): the connected components of a graph given edge by edge (the symmetry node's
// smooth parts, the features node's spanning forest).
#pragma once

#include <cstdint>
#include <numeric>
#include <utility>
#include <vector>

namespace scanfill {

// Disjoint sets with path halving and union by size.
class DisjointSets {
 public:
  explicit DisjointSets(std::int64_t n) : parent_(static_cast<size_t>(n)), size_(static_cast<size_t>(n), 1) {
    std::iota(parent_.begin(), parent_.end(), 0);
  }
  // The representative of x's set.
  std::int32_t find(std::int32_t x) {
    while (parent_[size_t(x)] != x) x = parent_[size_t(x)] = parent_[size_t(parent_[size_t(x)])];
    return x;
  }
  // Joins the sets of a and b; false when they were one already.
  bool join(std::int32_t a, std::int32_t b) {
    a = find(a);
    b = find(b);
    if (a == b) return false;
    if (size_[size_t(a)] < size_[size_t(b)]) std::swap(a, b);
    parent_[size_t(b)] = a;
    size_[size_t(a)] += size_[size_t(b)];
    return true;
  }

 private:
  std::vector<std::int32_t> parent_;
  std::vector<std::int32_t> size_;
};

}  // namespace scanfill
