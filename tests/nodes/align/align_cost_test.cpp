// align's least squares against Ceres (issues 9 and 13): the cost functors here are the reference model of eq. 10's
// terms (hand-written Jacobians against numeric differentiation, residuals at known configurations), and
// solve_offsets, which solves the normal equations directly, must reach the minimum Ceres reaches.
#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include <array>
#include <memory>
#include <random>
#include <vector>

#include "gradient_check.h"
#include "linear_pair_cost.h"
#include "nodes/align/offsets.h"
#include "pull_cost.h"

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

// 300 samples in a chain with extra links, a third of them fixed; seam-like terms with gaps and keep-like differences.
std::vector<PairTerm> random_terms(std::mt19937& rng, std::vector<std::uint8_t>& is_free) {
  std::uniform_real_distribution<double> u(-1, 1);
  std::uniform_int_distribution<int> pick(0, 299);
  is_free.assign(300, 1);
  for (size_t i = 0; i < 300; i += 3) is_free[i] = 0;
  std::vector<PairTerm> terms;
  for (int i = 0; i + 1 < 300; ++i) terms.push_back({i, i + 1, 50, 0, 1, -1});
  for (int t = 0; t < 600; ++t) {
    const int i = pick(rng), j = pick(rng);
    if (i == j || (!is_free[size_t(i)] && !is_free[size_t(j)])) continue;
    terms.push_back({i, j, 50 * (0.5 + 0.5 * u(rng) * u(rng)), 0.04 * u(rng), 0.8 + 0.2 * u(rng), -0.8 - 0.2 * u(rng)});
  }
  return terms;
}

TEST(SolveOffsets, ReachesCeresMinimumAndKeepsFixedSamples) {
  std::mt19937 rng(12);
  for (int trial = 0; trial < 3; ++trial) {
    std::vector<std::uint8_t> is_free;
    const std::vector<PairTerm> terms = random_terms(rng, is_free);
    const double pull = 0.01 * 2500;  // v / alpha^2 at alpha = 0.02
    std::vector<double> ours(300, 0.0), theirs(300, 0.0);
    const SolverSummary s = solve_offsets(terms, is_free, pull, ours);
    ceres::Problem problem;
    for (auto& d : theirs) problem.AddParameterBlock(&d, 1);
    for (const PairTerm& t : terms)
      problem.AddResidualBlock(LinearPairCost::Create(t.w, t.c, t.a, t.b), nullptr, &theirs[size_t(t.i)],
                               &theirs[size_t(t.j)]);
    for (size_t i = 0; i < 300; ++i) {
      if (is_free[i])
        problem.AddResidualBlock(PullCost::Create(std::sqrt(pull)), nullptr, &theirs[i]);
      else
        problem.SetParameterBlockConstant(&theirs[i]);
    }
    ceres::Solver::Options so;
    so.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
    so.function_tolerance = so.parameter_tolerance = so.gradient_tolerance = 1e-15;
    ceres::Solver::Summary summary;
    ceres::Solve(so, &problem, &summary);
    EXPECT_EQ(s.termination, "CONVERGENCE");
    EXPECT_NEAR(s.initial_cost, summary.initial_cost, 1e-9 * summary.initial_cost);
    EXPECT_NEAR(s.final_cost, summary.final_cost, 1e-8 * summary.final_cost) << trial;
    EXPECT_LT(s.final_cost, 0.95 * s.initial_cost);  // the offsets do move
    for (size_t i = 0; i < 300; ++i) {
      EXPECT_NEAR(ours[i], theirs[i], 1e-7) << i;
      if (!is_free[i]) EXPECT_EQ(ours[i], 0.0) << i;
    }
  }
}

}  // namespace
}  // namespace scanfill
