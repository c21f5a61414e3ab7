// correspond's embedded deformation against Ceres (issues 9 and 13): the cost functors here are the reference model
// (DataCost's hand-written Jacobian against numeric differentiation, every functor's residuals at configurations with
// known answers), and solve_deformation, which assembles the normal equations itself, must reach the minimum Ceres
// reaches on the same problem.
#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <array>
#include <memory>
#include <random>
#include <vector>

#include "data_cost.h"
#include "gradient_check.h"
#include "nodes/core/kdtree.h"
#include "nodes/correspond/deformation_solve.h"
#include "rotation_cost.h"
#include "smooth_cost.h"

namespace scanfill {
namespace {

using NodeParams = std::array<double, 12>;

NodeParams identity_node() {
  NodeParams x{};
  x[0] = x[4] = x[8] = 1.0;
  return x;
}

// A data term as correspond builds one: a sample at spacing alpha = 0.02 among its 4 nodes, weights summing to 1.
struct DataTerm {
  Eigen::Vector3d p, q, n;
  std::array<Eigen::Vector3d, kNodesPerPoint> g;
  std::array<double, kNodesPerPoint> w;
  double inv_alpha = 50, sqrt_weight = 1;
};

DataTerm random_data_term(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1, 1), positive(0.1, 1);
  const auto vec = [&] { return Eigen::Vector3d(u(rng), u(rng), u(rng)); };
  DataTerm t;
  t.p = vec();
  t.q = t.p + 0.05 * vec();
  t.n = vec().normalized();
  double sum = 0;
  for (int i = 0; i < kNodesPerPoint; ++i) {
    t.g[size_t(i)] = t.p + 0.1 * vec();
    t.w[size_t(i)] = positive(rng);
    sum += t.w[size_t(i)];
  }
  for (auto& w : t.w) w /= sum;
  t.sqrt_weight = 1 + 2 * positive(rng);
  return t;
}

// A near-rigid node: A = I plus noise, a small translation.
NodeParams random_node(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  NodeParams x = identity_node();
  for (int k = 0; k < 9; ++k) x[size_t(k)] += 0.2 * u(rng);
  for (int k = 9; k < 12; ++k) x[size_t(k)] = 0.05 * u(rng);
  return x;
}

TEST(DataCost, JacobianMatchesNumericDifferentiation) {
  std::mt19937 rng(20140601);
  for (int trial = 0; trial < 8; ++trial) {
    const DataTerm t = random_data_term(rng);
    std::array<NodeParams, kNodesPerPoint> x;
    for (auto& xi : x) xi = random_node(rng);
    const std::vector<const double*> blocks{x[0].data(), x[1].data(), x[2].data(), x[3].data()};
    for (const double plane : {1.0, 0.0}) {  // a data term, a landmark (point-to-point only)
      const std::unique_ptr<ceres::CostFunction> cost(
          DataCost::Create(t.p, t.q, t.n, t.g, t.w, t.inv_alpha, t.sqrt_weight, plane));
      EXPECT_TRUE(test::jacobians_match(*cost, blocks, 1e-7)) << "trial " << trial << ", plane " << plane;
    }
  }
}

TEST(DataCost, UndeformedSampleGivesItsScaledOffset) {
  std::mt19937 rng(3);
  const DataTerm t = random_data_term(rng);
  const NodeParams id = identity_node();
  const std::array<const double*, kNodesPerPoint> x{id.data(), id.data(), id.data(), id.data()};
  const std::unique_ptr<ceres::CostFunction> cost(
      DataCost::Create(t.p, t.q, t.n, t.g, t.w, t.inv_alpha, t.sqrt_weight, 1.0));
  std::array<double, 4> r{};
  ASSERT_TRUE(cost->Evaluate(x.data(), r.data(), nullptr));
  // Identity nodes leave p in place (the weights sum to 1): r = (0.5 d, d . n), d = (p - q) sqrt(weight) / alpha.
  const Eigen::Vector3d d = (t.p - t.q) * t.inv_alpha * t.sqrt_weight;
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(r[size_t(c)], 0.5 * d(c), 1e-12);
  EXPECT_NEAR(r[3], d.dot(t.n), 1e-12);
}

TEST(RotationCost, VanishesOnARotationAndMeasuresAScaling) {
  const std::unique_ptr<ceres::CostFunction> cost(RotationCost::Create(3.0));
  NodeParams x{};
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, -2, 0.5).normalized()).toRotationMatrix();
  Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(x.data()) = R;
  const double* block = x.data();
  std::array<double, 6> r{};
  ASSERT_TRUE(cost->Evaluate(&block, r.data(), nullptr));
  for (double v : r) EXPECT_NEAR(v, 0, 1e-12);
  // A = 2 I: columns orthogonal, each of squared length 4: r = 3 (0, 0, 0, 3, 3, 3).
  Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(x.data()) = 2 * Eigen::Matrix3d::Identity();
  ASSERT_TRUE(cost->Evaluate(&block, r.data(), nullptr));
  const std::array<double, 6> expected{0, 0, 0, 9, 9, 9};
  for (size_t k = 0; k < 6; ++k) EXPECT_NEAR(r[k], expected[k], 1e-12) << k;
}

TEST(SmoothCost, ComparesNodeJsPredictionWithNodeKsTranslation) {
  const Eigen::Vector3d gj(0.1, 0.2, 0.3), gk(0.4, -0.1, 0.3);
  const double scale = 5.0;
  const std::unique_ptr<ceres::CostFunction> cost(SmoothCost::Create(gj, gk, scale));
  NodeParams xj = identity_node(), xk = identity_node();
  const std::array<const double*, 2> blocks{xj.data(), xk.data()};
  std::array<double, 3> r{};
  // Both translated alike: node j predicts node k exactly.
  for (NodeParams* x : {&xj, &xk}) {
    (*x)[9] = 0.3;
    (*x)[10] = -0.2;
    (*x)[11] = 0.1;
  }
  ASSERT_TRUE(cost->Evaluate(blocks.data(), r.data(), nullptr));
  for (double v : r) EXPECT_NEAR(v, 0, 1e-12);
  // Node k moves 0.1 further along x than j predicts: r = scale (-0.1, 0, 0).
  xk[9] += 0.1;
  ASSERT_TRUE(cost->Evaluate(blocks.data(), r.data(), nullptr));
  EXPECT_NEAR(r[0], -scale * 0.1, 1e-12);
  EXPECT_NEAR(r[1], 0, 1e-12);
  EXPECT_NEAR(r[2], 0, 1e-12);
}

// A bent sheet of 240 exemplar points bound to 12 nodes, its goals a smooth bend away with noise, some outliers beyond
// the Huber scale, a landmark, and smooth edges to each node's 4 nearest.
DeformationProblem random_problem(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  DeformationProblem pr;
  pr.nodes.resize(3, 12);
  for (Index j = 0; j < 12; ++j) pr.nodes.col(j) = Eigen::Vector3d(u(rng), u(rng), 0.2 * u(rng));
  KdTree tree;
  tree.build(pr.nodes);
  for (int i = 0; i < 240; ++i) {
    const Eigen::Vector3d p(u(rng), u(rng), 0.2 * u(rng));
    std::array<std::int32_t, kNodesPerPoint + 1> idx;
    std::array<double, kNodesPerPoint + 1> d2;
    tree.knn(p, kNodesPerPoint + 1, idx.data(), d2.data());
    DeformationDataTerm t;
    double sum = 0;
    for (int a = 0; a < kNodesPerPoint; ++a) {
      t.node[size_t(a)] = idx[size_t(a)];
      t.weight[size_t(a)] = std::pow(1 - std::sqrt(d2[size_t(a)] / d2[kNodesPerPoint]), 2) + 1e-9;
      sum += t.weight[size_t(a)];
    }
    for (auto& w : t.weight) w /= sum;
    t.p = p;
    t.q =
        p + Eigen::Vector3d(0.05 * p.y(), 0.02, 0.1 * p.x() * p.x()) + 0.005 * Eigen::Vector3d(u(rng), u(rng), u(rng));
    if (i % 40 == 0) t.q.z() += 0.3;  // an outlier, far beyond the Huber scale
    t.n = Eigen::Vector3d(0.1 * u(rng), 0.1 * u(rng), 1).normalized();
    t.scale = 1.0 / 0.02;
    t.plane = i == 0 ? 0.0 : 1.0;
    t.robust = i != 0;  // term 0 plays a landmark: point-to-point, no loss
    pr.data.push_back(t);
  }
  for (std::int32_t j = 0; j < 12; ++j) {
    std::array<std::int32_t, 5> idx;
    std::array<double, 5> d2;
    tree.knn(pr.nodes.col(j), 5, idx.data(), d2.data());
    for (int a = 1; a < 5; ++a) pr.edges.emplace_back(j, idx[size_t(a)]);
  }
  pr.rotation_scale = std::sqrt(20.0);
  pr.edge_scale = std::sqrt(5.0);
  pr.huber = 2.0;
  return pr;
}

// The same problem with the reference functors, solved by Ceres to tight tolerances.
double solve_with_ceres(const DeformationProblem& pr, std::vector<double>& x) {
  ceres::Problem problem;
  ceres::HuberLoss* huber = new ceres::HuberLoss(pr.huber);
  for (const DeformationDataTerm& t : pr.data) {
    std::array<Eigen::Vector3d, kNodesPerPoint> g;
    for (int i = 0; i < kNodesPerPoint; ++i) g[size_t(i)] = pr.nodes.col(t.node[size_t(i)]);
    problem.AddResidualBlock(DataCost::Create(t.p, t.q, t.n, g, t.weight, t.scale, 1.0, t.plane),
                             t.robust ? huber : nullptr, &x[size_t(t.node[0]) * 12], &x[size_t(t.node[1]) * 12],
                             &x[size_t(t.node[2]) * 12], &x[size_t(t.node[3]) * 12]);
  }
  for (Index j = 0; j < pr.nodes.cols(); ++j)
    problem.AddResidualBlock(RotationCost::Create(pr.rotation_scale), nullptr, &x[size_t(j) * 12]);
  for (const auto& [j, k] : pr.edges)
    problem.AddResidualBlock(SmoothCost::Create(pr.nodes.col(j), pr.nodes.col(k), pr.edge_scale), nullptr,
                             &x[size_t(j) * 12], &x[size_t(k) * 12]);
  ceres::Solver::Options so;
  so.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  so.max_num_iterations = 200;
  so.function_tolerance = 1e-14;
  so.parameter_tolerance = 1e-14;
  so.gradient_tolerance = 1e-14;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  return summary.final_cost;
}

std::vector<double> identity_params(Index nodes) {
  std::vector<double> x(size_t(nodes) * 12, 0.0);
  for (Index j = 0; j < nodes; ++j) x[size_t(j) * 12] = x[size_t(j) * 12 + 4] = x[size_t(j) * 12 + 8] = 1.0;
  return x;
}

TEST(SolveDeformation, ReachesCeresMinimumWithHuberLandmarkAndEdges) {
  std::mt19937 rng(13);
  for (int trial = 0; trial < 3; ++trial) {
    const DeformationProblem pr = random_problem(rng);
    std::vector<double> ours = identity_params(pr.nodes.cols()), theirs = ours;
    const double initial = deformation_cost(pr, ours);
    const SolverSummary s = solve_deformation(pr, ours, 50);
    const double reference = solve_with_ceres(pr, theirs);
    EXPECT_EQ(s.termination, "CONVERGENCE") << trial;
    EXPECT_NEAR(s.initial_cost, initial, 1e-9 * initial);
    EXPECT_NEAR(s.final_cost, deformation_cost(pr, ours), 1e-9 * initial);
    EXPECT_LT(reference, 0.5 * initial) << trial;  // the problem is not trivial
    EXPECT_NEAR(s.final_cost, reference, 1e-5 * reference) << trial;
    double largest = 0;
    for (size_t i = 0; i < ours.size(); ++i) largest = std::max(largest, std::abs(ours[i] - theirs[i]));
    EXPECT_LT(largest, 1e-3) << trial;
  }
}

TEST(SolveDeformation, CostOfIdentityIsTheDataOffsets) {
  std::mt19937 rng(5);
  DeformationProblem pr = random_problem(rng);
  pr.data.resize(3);
  for (auto& t : pr.data) t.robust = false;
  double expected = 0;
  for (const auto& t : pr.data) {
    const Eigen::Vector3d d = (t.p - t.q) * t.scale;
    expected += 0.5 * (0.25 * d.squaredNorm() + std::pow(t.plane * d.dot(t.n), 2));
  }
  // Identity nodes: rotation and smooth terms vanish, each data term is its undeformed offset.
  EXPECT_NEAR(deformation_cost(pr, identity_params(pr.nodes.cols())), expected, 1e-9 * expected);
}

}  // namespace
}  // namespace scanfill
