// What one Ceres solve of a node reports, as plain data: a node's Result carries it to the engine, which logs it and
// writes it into report.json. No Ceres type here (Ceres' headers are heavy and stay out of public node headers);
// nodes/core/ceres_summary.h fills it from a ceres::Solver::Summary.
#pragma once

#include <string>

namespace scanfill {

struct SolverSummary {
  std::string termination;  // Ceres' TerminationType by name: "CONVERGENCE", "NO_CONVERGENCE", "FAILURE", ...
  int iterations = 0;       // Ceres' iteration count (ceres_summary.h): with max_num_iterations 10, at most 11
  double initial_cost = 0;  // Ceres' cost before the solve: 0.5 x the sum of the (robustified) squared residuals
  double final_cost = 0;    // the same after it
};

}  // namespace scanfill
