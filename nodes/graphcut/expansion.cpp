#include "nodes/graphcut/expansion.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "nodes/core/errors.h"
#include "nodes/graphcut/binary_energy.h"

namespace scanfill {
namespace {

constexpr double kInfeasible = std::numeric_limits<double>::infinity();

double unary(const LabelingProblem& p, Index i, int label) {
  for (std::int64_t e = p.unary_offset[size_t(i)]; e < p.unary_offset[size_t(i) + 1]; ++e)
    if (p.unary_label[size_t(e)] == label) return p.unary_cost[size_t(e)];
  return kInfeasible;
}

}  // namespace

void LabelingProblem::add_site(const std::vector<std::pair<int, double>>& label_costs) {
  for (const auto& [label, cost] : label_costs) {
    unary_label.push_back(label);
    unary_cost.push_back(cost);
  }
  unary_offset.push_back(std::int64_t(unary_label.size()));
  ++sites;
}

double labeling_energy(const LabelingProblem& p, const std::vector<int>& f) {
  if (Index(f.size()) != p.sites) throw InvariantError("labelling has the wrong number of sites");
  double e = 0;
  std::vector<std::uint8_t> used(size_t(p.labels), 0);
  for (Index i = 0; i < p.sites; ++i) {
    e += unary(p, i, f[size_t(i)]);
    used[size_t(f[size_t(i)])] = 1;
  }
  for (size_t k = 0; k < p.edges.size(); ++k) {
    const auto [i, j] = p.edges[k];
    if (f[size_t(i)] != f[size_t(j)]) e += p.pairwise(Index(k), f[size_t(i)], f[size_t(j)]);
  }
  if (!p.label_cost.empty())
    for (int l = 0; l < p.labels; ++l)
      if (used[size_t(l)]) e += p.label_cost[size_t(l)];
  return e;
}

ExpansionResult alpha_expansion(const LabelingProblem& p, std::vector<int> f, const ExpansionOptions& options) {
  if (Index(p.unary_offset.size()) != p.sites + 1)
    throw InvariantError("labelling problem: unary offsets do not match");
  ExpansionResult result;
  result.energy_before = labeling_energy(p, f);
  if (!std::isfinite(result.energy_before))
    throw InvariantError("alpha expansion: the initial labelling is infeasible");
  // Incidence lists: the edges of each site.
  std::vector<std::int64_t> inc_offset(size_t(p.sites) + 1, 0);
  for (const auto& [i, j] : p.edges) {
    ++inc_offset[size_t(i) + 1];
    ++inc_offset[size_t(j) + 1];
  }
  for (Index i = 0; i < p.sites; ++i) inc_offset[size_t(i) + 1] += inc_offset[size_t(i)];
  std::vector<std::int32_t> incident(size_t(inc_offset.back()));
  {
    std::vector<std::int64_t> fill(inc_offset.begin(), inc_offset.end() - 1);
    for (size_t k = 0; k < p.edges.size(); ++k) {
      incident[size_t(fill[size_t(p.edges[k].first)]++)] = std::int32_t(k);
      incident[size_t(fill[size_t(p.edges[k].second)]++)] = std::int32_t(k);
    }
  }
  // Sites where each label is feasible.
  std::vector<std::vector<std::int32_t>> feasible(size_t(p.labels));
  for (Index i = 0; i < p.sites; ++i)
    for (std::int64_t e = p.unary_offset[size_t(i)]; e < p.unary_offset[size_t(i) + 1]; ++e)
      feasible[size_t(p.unary_label[size_t(e)])].push_back(std::int32_t(i));

  BinaryEnergy move;
  std::vector<std::int32_t> var(size_t(p.sites), -1);  // site -> move variable, -1 if fixed
  std::vector<Index> count(size_t(p.labels), 0);       // sites per label in f
  for (const int l : f) ++count[size_t(l)];
  std::vector<std::int32_t> vars, switched;                                          // reused by every move
  std::vector<Index> switchable(size_t(p.labels), 0), leaving(size_t(p.labels), 0);  // per label, zero between uses
  double energy = result.energy_before;
  const bool costs = !p.label_cost.empty();
  auto V = [&](Index e, int ls, int lt) { return ls == lt ? 0.0 : p.pairwise(e, ls, lt); };

  for (result.cycles = 0; result.cycles < options.max_cycles;) {
    ++result.cycles;
    bool changed = false;
    for (int a = 0; a < p.labels; ++a) {
      if (feasible[size_t(a)].empty()) continue;
      move.reset();
      vars.clear();
      for (const auto i : feasible[size_t(a)])
        if (f[size_t(i)] != a) {
          var[size_t(i)] = std::int32_t(move.add_variable());
          vars.push_back(i);
        }
      if (vars.empty()) continue;
      // Unary terms of the variables.
      for (const auto i : vars) move.add_unary(var[size_t(i)], unary(p, i, f[size_t(i)]), unary(p, i, a));
      // Pairwise terms touching a variable (each edge once: from its lower-numbered variable end, or its only one).
      for (const auto i : vars) {
        for (std::int64_t k = inc_offset[size_t(i)]; k < inc_offset[size_t(i) + 1]; ++k) {
          const Index e = incident[size_t(k)];
          auto [s, t] = p.edges[size_t(e)];
          const bool s_var = var[size_t(s)] >= 0, t_var = var[size_t(t)] >= 0;
          const std::int32_t other = s == i ? t : s;
          if (s_var && t_var && other < i) continue;  // added from the other end
          const int fs = f[size_t(s)], ft = f[size_t(t)];
          if (s_var && t_var) {
            move.add_pairwise(var[size_t(s)], var[size_t(t)], V(e, fs, ft), V(e, fs, a), V(e, a, ft), 0.0);
          } else if (s_var) {
            move.add_unary(var[size_t(s)], V(e, fs, ft), V(e, a, ft));
          } else {
            move.add_unary(var[size_t(t)], V(e, fs, ft), V(e, fs, a));
          }
        }
      }
      // Label costs of the labels the move may empty. Labels whose sites are not all variables stay used whatever
      // the move does: nothing to model. a's own cost, when a is unused, needs no term either: min over moves of
      // E(x) + h_a [x != 0] is min(E(0), h_a + min E(x)), which the acceptance test below decides exactly (this
      // replaces Delong et al.'s auxiliary variable joined to every site, a hub that slows the max-flow badly).
      if (costs) {
        for (const auto i : vars) ++switchable[size_t(f[size_t(i)])];
        for (const auto i : vars) {
          const int l = f[size_t(i)];
          if (switchable[size_t(l)] <= 0) continue;  // done
          const bool all = switchable[size_t(l)] == count[size_t(l)];
          switchable[size_t(l)] = 0;
          const double h = p.label_cost[size_t(l)];
          if (!all || h == 0) continue;
          const Index y = move.add_variable();  // y = 1: every site of l switches and h_l is saved
          move.add_unary(y, h, 0.0);
          for (const auto j : vars)
            if (f[size_t(j)] == l) move.add_pairwise(y, var[size_t(j)], 0.0, 0.0, h, 0.0);
        }
      }
      move.minimize();
      result.truncated_terms += move.truncated();
      // The true energy change of the move (not the truncated one), from the switching sites and their edges.
      switched.clear();
      for (const auto i : vars)
        if (move.value(var[size_t(i)])) switched.push_back(i);
      double delta = 0;
      for (const auto i : switched) {
        delta += unary(p, i, a) - unary(p, i, f[size_t(i)]);
        var[size_t(i)] = -2;  // marks a switching site
      }
      for (const auto i : switched)
        for (std::int64_t k = inc_offset[size_t(i)]; k < inc_offset[size_t(i) + 1]; ++k) {
          const Index e = incident[size_t(k)];
          const auto [s, t] = p.edges[size_t(e)];
          const std::int32_t other = s == i ? t : s;
          if (var[size_t(other)] == -2 && other < i) continue;  // counted from the other end
          const int gs = var[size_t(s)] == -2 ? a : f[size_t(s)], gt = var[size_t(t)] == -2 ? a : f[size_t(t)];
          delta += V(e, gs, gt) - V(e, f[size_t(s)], f[size_t(t)]);
        }
      if (costs && !switched.empty()) {
        if (count[size_t(a)] == 0) delta += p.label_cost[size_t(a)];
        for (const auto i : switched) ++leaving[size_t(f[size_t(i)])];
        for (const auto i : switched) {
          const int l = f[size_t(i)];
          if (leaving[size_t(l)] == count[size_t(l)]) delta -= p.label_cost[size_t(l)];  // l is emptied
          leaving[size_t(l)] = 0;  // each label once (count >= 1, so no second match)
        }
      }
      for (const auto i : vars) var[size_t(i)] = -1;
      if (!switched.empty() && delta < -1e-12 * std::max(1.0, std::abs(energy))) {
        for (const auto i : switched) {
          --count[size_t(f[size_t(i)])];
          ++count[size_t(a)];
          f[size_t(i)] = a;
        }
        energy += delta;
        changed = true;
        ++result.moves_accepted;
        result.energy_trace.push_back(energy);
      }
    }
    if (!changed) {
      result.converged = true;
      break;
    }
  }
  result.energy_after = labeling_energy(p, f);  // exact, free of the moves' summed rounding
  result.labeling = std::move(f);
  return result;
}

}  // namespace scanfill
