// correspond's cost functors (issue 9): DataCost's hand-written Jacobian against numeric differentiation at random
// configurations, and every functor's residuals at configurations with known answers.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <array>
#include <memory>
#include <random>
#include <vector>

#include "gradient_check.h"
#include "nodes/correspond/data_cost.h"
#include "nodes/correspond/rotation_cost.h"
#include "nodes/correspond/smooth_cost.h"

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

}  // namespace
}  // namespace scanfill
