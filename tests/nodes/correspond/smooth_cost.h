// Embedded deformation's smoothness term (Sumner et al. 2007, E_reg): node j's map predicts where neighbour node k
// goes, and k's translation says where it does go,
//   r = s (A_j (g_k - g_j) + g_j + t_j - (g_k + t_k)),   s = sqrt(weight) / node spacing.
// Differentiated by Ceres' autodiff.
#pragma once

#include <ceres/autodiff_cost_function.h>

#include <Eigen/Core>

#include "nodes/correspond/deformation_node.h"

namespace scanfill {

class SmoothCost {
 public:
  // gj, gk: the two nodes' positions; scale: sqrt(weight) / node spacing.
  SmoothCost(const Eigen::Vector3d& gj, const Eigen::Vector3d& gk, double scale) : gj_(gj), gk_(gk), scale_(scale) {}

  static ceres::CostFunction* Create(const Eigen::Vector3d& gj, const Eigen::Vector3d& gk, double scale) {
    return new ceres::AutoDiffCostFunction<SmoothCost, 3, 12, 12>(new SmoothCost(gj, gk, scale));
  }

  // xj, xk: the nodes' 12 parameters each (deformation_node.h).
  template <class T>
  bool operator()(const T* xj, const T* xk, T* r) const {
    const Eigen::Matrix<T, 3, 1> d =
        deform_by(xj, gk_, gj_) - (gk_.cast<T>() + Eigen::Matrix<T, 3, 1>(xk[9], xk[10], xk[11]));
    for (int c = 0; c < 3; ++c) r[c] = T(scale_) * d(c);
    return true;
  }

 private:
  Eigen::Vector3d gj_, gk_;
  double scale_;
};

}  // namespace scanfill
