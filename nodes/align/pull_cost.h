// Eq. 10's pull towards the start (v = 0.01 of the paper; align.h): r = w d_i, w = sqrt(pull) / alpha, d_i a sample's
// normal offset. The Jacobian (w) is written out; align_cost_test checks it against numeric differentiation.
#pragma once

#include <ceres/sized_cost_function.h>

namespace scanfill {

class PullCost final : public ceres::SizedCostFunction<1, 1> {
 public:
  static ceres::CostFunction* Create(double w) { return new PullCost(w); }

  explicit PullCost(double w) : w_(w) {}

  bool Evaluate(double const* const* x, double* r, double** J) const override {
    r[0] = w_ * x[0][0];
    if (J && J[0]) J[0][0] = w_;
    return true;
  }

 private:
  double w_;
};

}  // namespace scanfill
