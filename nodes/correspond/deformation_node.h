// Embedded deformation (Sumner, Schmid, Pauly 2007) as correspond solves it: node j has an affine map A_j and a
// translation t_j, packed as 12 doubles (A_j row-major, then t_j); it moves a point p to A_j (p - g_j) + g_j + t_j,
// g_j the node's position. Shared by the cost functors and the deformation that applies the solved parameters.
#pragma once

#include <Eigen/Core>

namespace scanfill {

inline constexpr int kNodesPerPoint = 4;  // deformation nodes influencing a point (Sumner et al. use k + 1 = 5)

// Node parameters x (12) applied to p, the node at g: A (p - g) + g + t.
template <class T>
Eigen::Matrix<T, 3, 1> deform_by(const T* x, const Eigen::Vector3d& p, const Eigen::Vector3d& g) {
  const Eigen::Matrix<T, 3, 1> d = (p - g).cast<T>();
  Eigen::Matrix<T, 3, 1> out;
  for (int r = 0; r < 3; ++r) out(r) = x[3 * r] * d(0) + x[3 * r + 1] * d(1) + x[3 * r + 2] * d(2) + T(g(r)) + x[9 + r];
  return out;
}

}  // namespace scanfill
