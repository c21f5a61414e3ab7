// ceres::Solver::Summary reduced to the plain SolverSummary a node's Result carries. Included only by the .cpp of a
// node that solves with Ceres, never by a public node header.
#pragma once

#include <ceres/solver.h>
#include <ceres/types.h>

#include "nodes/core/solver_summary.h"

namespace scanfill {

// iterations: num_successful_steps + num_unsuccessful_steps, as Ceres' FullReport counts them. Ceres counts the
// evaluation at the start (iteration 0) as a successful step, so this equals Summary::iterations.size() and a solve
// stopped by max_num_iterations = 10 reports 11.
inline SolverSummary summarize(const ceres::Solver::Summary& summary) {
  SolverSummary s;
  s.termination = ceres::TerminationTypeToString(summary.termination_type);
  s.iterations = summary.num_successful_steps + summary.num_unsuccessful_steps;
  s.initial_cost = summary.initial_cost;
  s.final_cost = summary.final_cost;
  return s;
}

}  // namespace scanfill
