// A hand-written Jacobian against Ceres' numeric differentiation (ceres::GradientChecker, central differences), as a
// gtest assertion that prints Ceres' error log on a mismatch.
#pragma once

#include <ceres/gradient_checker.h>
#include <ceres/manifold.h>
#include <ceres/numeric_diff_options.h>
#include <gtest/gtest.h>

#include <vector>

namespace scanfill::test {

// parameters: one pointer per parameter block of `cost`. Also fails when a Jacobian block the cost function wrote is
// all zero: every block of the functors tested here depends on its parameters, so a zero block would mean the
// hand-written Jacobian was never evaluated.
inline ::testing::AssertionResult jacobians_match(const ceres::CostFunction& cost,
                                                  const std::vector<const double*>& parameters,
                                                  double relative_precision) {
  const std::vector<const ceres::Manifold*>* euclidean = nullptr;
  const ceres::GradientChecker checker(&cost, euclidean, ceres::NumericDiffOptions());
  ceres::GradientChecker::ProbeResults results;
  if (!checker.Probe(parameters.data(), relative_precision, &results))
    return ::testing::AssertionFailure() << "Jacobian mismatch (max relative error " << results.maximum_relative_error
                                         << "):\n"
                                         << results.error_log;
  for (size_t i = 0; i < results.jacobians.size(); ++i)
    if (results.jacobians[i].isZero(0))
      return ::testing::AssertionFailure() << "the Jacobian of parameter block " << i << " is all zero";
  return ::testing::AssertionSuccess() << "max relative error " << results.maximum_relative_error;
}

}  // namespace scanfill::test
