// A submodular binary energy E(x) = constant + sum_v U_v(x_v) + sum_uv P_uv(x_u, x_v), x in {0, 1}, minimised exactly
// by one s-t minimum cut (Kolmogorov and Zabih 2004), with our Boykov-Kolmogorov max-flow (max_flow.h). This is the
// move solver of the alpha-expansion in expansion.h.
//
// Costly set-up becomes a class with build-then-solve (CONVENTIONS): reset() keeps the term buffers' and the flow
// graph's capacity across the many expansion moves of one labelling.
#pragma once

#include <cstdint>
#include <vector>

#include "nodes/core/point_set.h"
#include "nodes/graphcut/max_flow.h"

namespace scanfill {

class BinaryEnergy {
 public:
  // Clears all terms; keeps allocated storage.
  void reset();
  // Adds a variable and returns its index (0, 1, ...).
  Index add_variable();
  Index variables() const { return Index(unary_.size()); }
  void add_constant(double c) { constant_ += c; }
  // U_v(0) = e0, U_v(1) = e1.
  void add_unary(Index v, double e0, double e1);
  // P_uv with the table (e00, e01, e10, e11), first index x_u. A term that is not submodular (e00 + e11 > e01 + e10)
  // has its mixed entries raised until it is (Rother et al. 2005, "truncation"); the return value says whether it
  // was, and truncated() counts such terms since reset().
  bool add_pairwise(Index u, Index v, double e00, double e01, double e10, double e11);
  Index truncated() const { return truncated_; }

  // Minimises; returns the minimum of the (truncated) energy. value(v) is then the optimal x_v.
  double minimize();
  bool value(Index v) const { return value_[size_t(v)] != 0; }

 private:
  double constant_ = 0;
  std::vector<double> unary_;          // U_v(1) - U_v(0)
  std::vector<MaxFlow::Arc> edges_;    // capacity u -> v is paid when x_u = 0, x_v = 1
  std::vector<double> source_, sink_;  // terminal capacities (scratch of minimize())
  MaxFlow flow_;
  std::vector<std::uint8_t> value_;
  Index truncated_ = 0;
};

}  // namespace scanfill
