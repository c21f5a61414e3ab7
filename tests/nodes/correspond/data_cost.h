// Embedded deformation's data term (Sumner et al. 2007, E_con; paper eq. 1's distance): the exemplar sample p, moved
// by its kNodesPerPoint deformation nodes with weights w_i, v = sum_i w_i (A_i (p - g_i) + g_i + t_i), against its
// matched source sample q with normal n, in alpha units, times sqrt(weight):
//   r[0..2] = 0.5 (v - q) s,   r[3] = plane ((v - q) s) . n,   s = sqrt(weight) / alpha;
// half point-to-point plus point-to-plane (plane = 0 for a landmark: point-to-point only). v is linear in the 4 nodes'
// parameters, so the Jacobian is written out (autodiff of 48 parameters cost 5x more); data_cost_test checks it
// against numeric differentiation.
#pragma once

#include <ceres/sized_cost_function.h>

#include <Eigen/Core>
#include <array>
#include <cstddef>

#include "nodes/correspond/deformation_node.h"

namespace scanfill {

class DataCost final : public ceres::SizedCostFunction<4, 12, 12, 12, 12> {
 public:
  // p: the exemplar sample; q, n: its source sample and normal; g, w: its nodes' positions and weights.
  static ceres::CostFunction* Create(const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Eigen::Vector3d& n,
                                     const std::array<Eigen::Vector3d, kNodesPerPoint>& g,
                                     const std::array<double, kNodesPerPoint>& w, double inv_alpha, double sqrt_weight,
                                     double plane) {
    return new DataCost(p, q, n, g, w, inv_alpha, sqrt_weight, plane);
  }

  DataCost(const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Eigen::Vector3d& n,
           const std::array<Eigen::Vector3d, kNodesPerPoint>& g, const std::array<double, kNodesPerPoint>& w,
           double inv_alpha, double sqrt_weight, double plane)
      : p_(p), q_(q), n_(n), g_(g), w_(w), scale_(inv_alpha * sqrt_weight), plane_(plane) {}

  bool Evaluate(double const* const* x, double* r, double** J) const override {
    Eigen::Vector3d v = Eigen::Vector3d::Zero();
    for (int i = 0; i < kNodesPerPoint; ++i) v += w_[size_t(i)] * deform_by(x[i], p_, g_[size_t(i)]);
    const Eigen::Vector3d d = (v - q_) * scale_;
    for (int c = 0; c < 3; ++c) r[c] = 0.5 * d(c);
    r[3] = plane_ * d.dot(n_);
    if (!J) return true;
    for (int i = 0; i < kNodesPerPoint; ++i) {
      if (!J[i]) continue;
      // dv_c / dA[c][k] = w (p - g)_k, dv_c / dt_c = w; row-major 4 x 12.
      Eigen::Map<Eigen::Matrix<double, 4, 12, Eigen::RowMajor>> Ji(J[i]);
      Ji.setZero();
      const double ws = w_[size_t(i)] * scale_;
      const Eigen::Vector3d e = p_ - g_[size_t(i)];
      for (int c = 0; c < 3; ++c) {
        for (int k = 0; k < 3; ++k) {
          Ji(c, 3 * c + k) = 0.5 * ws * e(k);
          Ji(3, 3 * c + k) = plane_ * ws * e(k) * n_(c);
        }
        Ji(c, 9 + c) = 0.5 * ws;
        Ji(3, 9 + c) = plane_ * ws * n_(c);
      }
    }
    return true;
  }

 private:
  Eigen::Vector3d p_, q_, n_;
  std::array<Eigen::Vector3d, kNodesPerPoint> g_;
  std::array<double, kNodesPerPoint> w_;
  double scale_, plane_;
};

}  // namespace scanfill
