// Multi-label energy minimisation by alpha-expansion with label costs (Boykov, Veksler, Zabih 2001; Delong, Osokin,
// Isack, Boykov 2012), written from the papers (GCO is research-only):
//
//   E(f) = sum_i D_i(f_i) + sum_(i,j) V_ij(f_i, f_j) + sum_l h_l [l is used by f]
//
// Labels are sparse: site i may take only the labels listed in its unary terms, so an expansion on label a involves
// only the sites where a is feasible. An expansion move is a binary energy solved by one minimum cut (binary_energy.h,
// on our Boykov-Kolmogorov max-flow, max_flow.h): x_i = 1 switches site i to a. Label costs (Delong et al., section
// 3.1): for a used label l != a whose every site may switch, an auxiliary variable y_l with h_l (1 - y_l) +
// sum_(i in P_l) h_l y_l (1 - x_i) pays h_l unless all of them switch. For an unused a, Delong et al. join an auxiliary
// z to every site (h_a once if any switches); that hub slows the max-flow several-fold, and it is not needed: the
// least of E(x) + h_a [x != 0] is min(E(0), h_a + min_x E(x)), so the move is solved without h_a and the acceptance
// test, which includes h_a, decides exactly. A move is accepted only if it lowers the true energy E, computed locally
// from the switching sites and their edges (V need not be a metric everywhere: non-submodular move terms are
// truncated, so a move can be suboptimal, never accepted if worse). All buffers, the flow graph's included, are
// reused from move to move. With two threads, the move on label a + 1 is computed beside the move on a, from the same
// labelling, and used only when a is rejected (most moves are, after the first sweep): the result is the sequential
// sweep's, bit for bit.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "nodes/core/point_set.h"

namespace scanfill {

struct LabelingProblem {
  Index sites = 0;
  int labels = 0;
  // Unary terms, CSR by site: site i may take unary_label[e] at cost unary_cost[e], e in [offset[i], offset[i + 1]).
  std::vector<std::int64_t> unary_offset{0};
  std::vector<std::int32_t> unary_label;
  std::vector<double> unary_cost;
  // MRF edges (i, j), i != j, each listed once.
  std::vector<std::pair<std::int32_t, std::int32_t>> edges;
  // V for edge e between labels a (of edges[e].first) and b; must be 0 when a == b.
  std::function<double(Index edge, int a, int b)> pairwise;
  // h_l, paid once when any site uses label l; size `labels` (or empty: no label costs).
  std::vector<double> label_cost;

  // Appends site i's feasible labels; sites must be added in order 0, 1, ...
  void add_site(const std::vector<std::pair<int, double>>& label_costs);
};

struct ExpansionOptions {
  int max_cycles = 20;  // sweeps over all labels; stops earlier when a sweep changes nothing; >= 1
};

struct ExpansionResult {
  std::vector<int> labeling;
  double energy_before = 0;          // E of the initial labelling
  double energy_after = 0;           // E of the result
  std::vector<double> energy_trace;  // E after each accepted move (non-increasing)
  int cycles = 0;
  Index moves_accepted = 0;
  Index truncated_terms = 0;  // non-submodular move terms that were truncated
  bool converged = false;     // a full sweep changed nothing
};

// E(f); +infinity if some site takes a label not listed for it.
double labeling_energy(const LabelingProblem& problem, const std::vector<int>& labeling);

// Minimises E from `initial`, which must be feasible (throws InvariantError otherwise).
ExpansionResult alpha_expansion(const LabelingProblem& problem, std::vector<int> initial,
                                const ExpansionOptions& options = {});

}  // namespace scanfill
