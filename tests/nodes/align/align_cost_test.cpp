// align's cost functors (issue 9): the hand-written Jacobians of eq. 10's terms against numeric differentiation at
// random configurations, and their residuals at known ones.
#include <gtest/gtest.h>

#include <array>
#include <memory>
#include <random>
#include <vector>

#include "gradient_check.h"
#include "nodes/align/linear_pair_cost.h"
#include "nodes/align/pull_cost.h"

namespace scanfill {
namespace {

TEST(LinearPairCost, JacobianMatchesNumericDifferentiation) {
  std::mt19937 rng(10);
  std::uniform_real_distribution<double> u(-1, 1), positive(0.1, 1);
  for (int trial = 0; trial < 8; ++trial) {
    // A seam pair at alpha = 0.02: w = sqrt(gap_weight) / alpha, c a gap of a few alpha, a and b cosines.
    const double w = 50 * positive(rng), c = 0.05 * u(rng), a = u(rng), b = -u(rng);
    const std::unique_ptr<ceres::CostFunction> cost(LinearPairCost::Create(w, c, a, b));
    const double di = 0.02 * u(rng), dj = 0.02 * u(rng);
    EXPECT_TRUE(test::jacobians_match(*cost, {&di, &dj}, 1e-7)) << "trial " << trial;
  }
}

TEST(LinearPairCost, ResidualIsTheWeightedGap) {
  const std::unique_ptr<ceres::CostFunction> cost(LinearPairCost::Create(2.0, 0.5, 3.0, -4.0));
  const double di = 0.25, dj = 0.125;
  const std::array<const double*, 2> x{&di, &dj};
  double r = 0;
  ASSERT_TRUE(cost->Evaluate(x.data(), &r, nullptr));
  EXPECT_DOUBLE_EQ(r, 2.0 * (0.5 + 3.0 * 0.25 - 4.0 * 0.125));
}

TEST(PullCost, JacobianMatchesNumericDifferentiation) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1), positive(0.1, 1);
  for (int trial = 0; trial < 8; ++trial) {
    const std::unique_ptr<ceres::CostFunction> cost(PullCost::Create(5 * positive(rng)));  // sqrt(0.01) / alpha
    const double d = 0.02 * u(rng);
    EXPECT_TRUE(test::jacobians_match(*cost, {&d}, 1e-7)) << "trial " << trial;
  }
}

TEST(PullCost, ResidualIsTheWeightedOffset) {
  const std::unique_ptr<ceres::CostFunction> cost(PullCost::Create(5.0));
  const double d = 0.125;
  const double* x = &d;
  double r = 0;
  ASSERT_TRUE(cost->Evaluate(&x, &r, nullptr));
  EXPECT_DOUBLE_EQ(r, 0.625);
}

}  // namespace
}  // namespace scanfill
