// Eq. 10's pair terms, both linear in two samples' normal offsets d_i, d_j (align.h):
//   r = w (c + a d_i + b d_j)
// a seam gap ((p_i + d_i n_i - p_j - d_j n_j) . m_ij: c = (p_i - p_j) . m_ij, a = n_i . m_ij, b = -n_j . m_ij, w =
// sqrt(gap_weight) / alpha) or a shape-keeping difference (c = 0, a = 1, b = -1, w = sqrt(keep_weight) / alpha). The
// Jacobian is written out (w a, w b); align_cost_test checks it against numeric differentiation.
#pragma once

#include <ceres/sized_cost_function.h>

namespace scanfill {

class LinearPairCost final : public ceres::SizedCostFunction<1, 1, 1> {
 public:
  static ceres::CostFunction* Create(double w, double c, double a, double b) { return new LinearPairCost(w, c, a, b); }

  LinearPairCost(double w, double c, double a, double b) : w_(w), c_(c), a_(a), b_(b) {}

  bool Evaluate(double const* const* x, double* r, double** J) const override {
    r[0] = w_ * (c_ + a_ * x[0][0] + b_ * x[1][0]);
    if (J) {
      if (J[0]) J[0][0] = w_ * a_;
      if (J[1]) J[1][0] = w_ * b_;
    }
    return true;
  }

 private:
  double w_, c_, a_, b_;
};

}  // namespace scanfill
