#include "nodes/align/offsets.h"

#include <Eigen/OrderingMethods>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>

namespace scanfill {

double offsets_cost(const std::vector<PairTerm>& terms, const std::vector<std::uint8_t>& is_free, double pull,
                    const std::vector<double>& d) {
  double sum = 0;
  for (const PairTerm& t : terms) sum += std::pow(t.w * (t.c + t.a * d[size_t(t.i)] + t.b * d[size_t(t.j)]), 2);
  for (size_t i = 0; i < d.size(); ++i)
    if (is_free[i]) sum += pull * d[i] * d[i];
  return 0.5 * sum;
}

SolverSummary solve_offsets(const std::vector<PairTerm>& terms, const std::vector<std::uint8_t>& is_free, double pull,
                            std::vector<double>& d) {
  std::vector<int> column(d.size(), -1);
  int unknowns = 0;
  for (size_t i = 0; i < d.size(); ++i)
    if (is_free[i]) column[i] = unknowns++;
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(3 * terms.size() + size_t(unknowns));
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(unknowns);
  for (const PairTerm& t : terms) {
    const int ci = column[size_t(t.i)], cj = column[size_t(t.j)];
    const double w2 = t.w * t.w;
    if (ci >= 0) entries.emplace_back(ci, ci, w2 * t.a * t.a), rhs(ci) -= w2 * t.c * t.a;
    if (cj >= 0) entries.emplace_back(cj, cj, w2 * t.b * t.b), rhs(cj) -= w2 * t.c * t.b;
    if (ci >= 0 && cj >= 0) entries.emplace_back(std::max(ci, cj), std::min(ci, cj), w2 * t.a * t.b);
  }
  for (int c = 0; c < unknowns; ++c) entries.emplace_back(c, c, pull);
  Eigen::SparseMatrix<double> normal(unknowns, unknowns);
  normal.setFromTriplets(entries.begin(), entries.end());  // duplicates are summed, in the entries' order
  SolverSummary summary{"CONVERGENCE", 1, offsets_cost(terms, is_free, pull, d), 0};
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower, Eigen::AMDOrdering<int>> ldlt(normal);
  if (ldlt.info() != Eigen::Success) {
    summary.termination = "FAILURE";
    summary.final_cost = summary.initial_cost;
    return summary;
  }
  const Eigen::VectorXd x = ldlt.solve(rhs);
  for (size_t i = 0; i < d.size(); ++i) d[i] = column[i] >= 0 ? x(column[i]) : 0.0;
  summary.final_cost = offsets_cost(terms, is_free, pull, d);
  return summary;
}

}  // namespace scanfill
