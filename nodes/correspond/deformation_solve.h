// Embedded deformation's least squares (Sumner, Schmid, Pauly 2007) as correspond solves it: Levenberg-Marquardt on
// normal equations we assemble ourselves. Node j's 12 parameters (deformation_node.h) enter
//   data      r = s M (v - q),  v = sum_i w_i (A_i (p - g_i) + g_i + t_i),  M = [0.5 I; plane n^T]   (Huber when
//   robust) rotation  r = w (c0.c1, c0.c2, c1.c2, c0.c0 - 1, c1.c1 - 1, c2.c2 - 1), c_m the columns of A_j smooth    r
//   = s (A_j (g_k - g_j) + g_j + t_j - (g_k + t_k))
// The data and smooth terms are linear in the parameters, so each of their Gauss-Newton blocks is a Kronecker product
// P (x) (a b^T) of a 3 x 3 weight and two homogeneous offsets (a = (p - g_i, 1)). The normal matrix is block sparse,
// a 12 x 12 block per pair of nodes that share a term; each block row is summed by one task in a fixed order, so the
// result is the same bytes on any number of threads. It is factorised by Eigen's sparse LDL^T (AMD ordering, the
// pattern analysed once per solve). The Huber loss enters as iteratively reweighted least squares (Ceres does the same
// for a loss whose second derivative is not positive), and the step control follows Ceres' Levenberg-Marquardt:
// D = diag(J^T J) clamped to [1e-6, 1e32], trust radius 1e4, stopped on a relative cost change below 1e-6.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include "nodes/core/solver_summary.h"
#include "nodes/correspond/deformation_node.h"

namespace scanfill {

// One data term: the exemplar point p bound to kNodesPerPoint nodes, its goal q with normal n.
struct DeformationDataTerm {
  Eigen::Vector3d p, q, n;
  std::array<std::int32_t, kNodesPerPoint> node;
  std::array<double, kNodesPerPoint> weight;
  double scale = 1;  // s: sqrt(term weight) / alpha
  double plane = 1;  // 1: half point-to-point plus point-to-plane; 0: point-to-point (a landmark)
  bool robust = true;
};

struct DeformationProblem {
  Eigen::Matrix3Xd nodes;                                    // g_j
  std::vector<DeformationDataTerm> data;                     //
  std::vector<std::pair<std::int32_t, std::int32_t>> edges;  // smooth terms (j predicts k)
  double rotation_scale = 1;                                 // w of the rotation terms
  double edge_scale = 1;                                     // s of the smooth terms
  double huber = 1;                                          // Huber scale of the robust data terms (residual units)
};

// Minimises the problem's cost from params (12 per node, updated in place) in at most max_iterations steps.
SolverSummary solve_deformation(const DeformationProblem& problem, std::vector<double>& params, int max_iterations);

// The cost 0.5 sum rho(|r|^2) at params (Ceres' definition), for tests and reports.
double deformation_cost(const DeformationProblem& problem, const std::vector<double>& params);

}  // namespace scanfill
