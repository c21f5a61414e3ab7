// Embedded deformation's rigidity term (Sumner et al. 2007, E_rot): the columns c0, c1, c2 of a node's A orthonormal,
//   r = sqrt(weight) (c0.c1, c0.c2, c1.c2, c0.c0 - 1, c1.c1 - 1, c2.c2 - 1).
// Differentiated by Ceres' autodiff.
#pragma once

#include <ceres/autodiff_cost_function.h>

#include <Eigen/Core>

namespace scanfill {

class RotationCost {
 public:
  explicit RotationCost(double sqrt_weight) : sqrt_weight_(sqrt_weight) {}

  static ceres::CostFunction* Create(double sqrt_weight) {
    return new ceres::AutoDiffCostFunction<RotationCost, 6, 12>(new RotationCost(sqrt_weight));
  }

  // x: the node's 12 parameters (deformation_node.h).
  template <class T>
  bool operator()(const T* x, T* r) const {
    const Eigen::Matrix<T, 3, 1> c0(x[0], x[3], x[6]), c1(x[1], x[4], x[7]), c2(x[2], x[5], x[8]);
    const T w(sqrt_weight_);
    r[0] = w * c0.dot(c1);
    r[1] = w * c0.dot(c2);
    r[2] = w * c1.dot(c2);
    r[3] = w * (c0.dot(c0) - T(1));
    r[4] = w * (c1.dot(c1) - T(1));
    r[5] = w * (c2.dot(c2) - T(1));
    return true;
  }

 private:
  double sqrt_weight_;
};

}  // namespace scanfill
