// Eq. 10's least squares (align.h) in the samples' normal offsets d: pair terms linear in two offsets,
//   r = w (c + a d_i + b d_j)       (a seam gap, or a same-patch difference with c = 0, a = 1, b = -1)
// and a pull sum_i pull d_i^2 on the free samples; fixed samples (the scan's own) keep d_i = 0. The problem is linear,
// so its normal equations give the minimum in one sparse LDL^T solve (Eigen, AMD ordering).
#pragma once

#include <cstdint>
#include <vector>

#include "nodes/core/solver_summary.h"

namespace scanfill {

struct PairTerm {
  std::int32_t i, j;
  double w, c, a, b;
};

// 0.5 (sum of the pair terms' squares + pull sum of d_i^2 over the free samples), Ceres' cost convention.
double offsets_cost(const std::vector<PairTerm>& terms, const std::vector<std::uint8_t>& is_free, double pull,
                    const std::vector<double>& d);

// Sets d (one per sample) to the minimiser; the summary has the cost before (at the d given) and after.
SolverSummary solve_offsets(const std::vector<PairTerm>& terms, const std::vector<std::uint8_t>& is_free, double pull,
                            std::vector<double>& d);

}  // namespace scanfill
