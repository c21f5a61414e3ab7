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

namespace {

// One expansion run: the problem's incidence lists and per-label sites, the current labelling with its label
// counts, and every buffer a move needs, kept from move to move.
class Expansion {
 public:
  Expansion(const LabelingProblem& p, std::vector<int> f) : p_(p), f_(std::move(f)) {
    index_incident_edges();
    index_feasible_sites();
    var_.assign(size_t(p.sites), -1);
    count_.assign(size_t(p.labels), 0);
    for (const int l : f_) ++count_[size_t(l)];
    switchable_.assign(size_t(p.labels), 0);
    leaving_.assign(size_t(p.labels), 0);
  }

  // Tries the expansion on `a`; true if it was accepted. `energy` is E of the current labelling, updated on accept.
  bool expand(int a, double& energy, ExpansionResult& result) {
    if (feasible_[size_t(a)].empty() || !collect_variables(a)) return false;
    add_unary_terms(a);
    add_pairwise_terms(a);
    if (!p_.label_cost.empty()) add_label_cost_terms();
    move_.minimize();
    result.truncated_terms += move_.truncated();
    collect_switched();
    const double delta = move_delta(a);
    for (const auto i : vars_) var_[size_t(i)] = -1;
    if (switched_.empty() || delta >= -1e-12 * std::max(1.0, std::abs(energy))) return false;
    for (const auto i : switched_) {
      --count_[size_t(f_[size_t(i)])];
      ++count_[size_t(a)];
      f_[size_t(i)] = a;
    }
    energy += delta;
    ++result.moves_accepted;
    result.energy_trace.push_back(energy);
    return true;
  }

  std::vector<int>& labeling() { return f_; }

 private:
  double V(Index e, int ls, int lt) const { return ls == lt ? 0.0 : p_.pairwise(e, ls, lt); }

  void index_incident_edges() {
    inc_offset_.assign(size_t(p_.sites) + 1, 0);
    for (const auto& [i, j] : p_.edges) {
      ++inc_offset_[size_t(i) + 1];
      ++inc_offset_[size_t(j) + 1];
    }
    for (Index i = 0; i < p_.sites; ++i) inc_offset_[size_t(i) + 1] += inc_offset_[size_t(i)];
    incident_.resize(size_t(inc_offset_.back()));
    std::vector<std::int64_t> fill(inc_offset_.begin(), inc_offset_.end() - 1);
    for (size_t k = 0; k < p_.edges.size(); ++k) {
      incident_[size_t(fill[size_t(p_.edges[k].first)]++)] = std::int32_t(k);
      incident_[size_t(fill[size_t(p_.edges[k].second)]++)] = std::int32_t(k);
    }
  }

  void index_feasible_sites() {
    feasible_.assign(size_t(p_.labels), {});
    for (Index i = 0; i < p_.sites; ++i)
      for (std::int64_t e = p_.unary_offset[size_t(i)]; e < p_.unary_offset[size_t(i) + 1]; ++e)
        feasible_[size_t(p_.unary_label[size_t(e)])].push_back(std::int32_t(i));
  }

  // The move's variables: the sites where `a` is feasible and not already taken. False if there are none.
  bool collect_variables(int a) {
    move_.reset();
    vars_.clear();
    for (const auto i : feasible_[size_t(a)])
      if (f_[size_t(i)] != a) {
        var_[size_t(i)] = std::int32_t(move_.add_variable());
        vars_.push_back(i);
      }
    return !vars_.empty();
  }

  void add_unary_terms(int a) {
    for (const auto i : vars_) move_.add_unary(var_[size_t(i)], unary(p_, i, f_[size_t(i)]), unary(p_, i, a));
  }

  // Pairwise terms touching a variable (each edge once: from its lower-numbered variable end, or its only one).
  void add_pairwise_terms(int a) {
    for (const auto i : vars_)
      for (std::int64_t k = inc_offset_[size_t(i)]; k < inc_offset_[size_t(i) + 1]; ++k) {
        const Index e = incident_[size_t(k)];
        auto [s, t] = p_.edges[size_t(e)];
        const bool s_var = var_[size_t(s)] >= 0, t_var = var_[size_t(t)] >= 0;
        const std::int32_t other = s == i ? t : s;
        if (s_var && t_var && other < i) continue;  // added from the other end
        const int fs = f_[size_t(s)], ft = f_[size_t(t)];
        if (s_var && t_var) {
          move_.add_pairwise(var_[size_t(s)], var_[size_t(t)], V(e, fs, ft), V(e, fs, a), V(e, a, ft), 0.0);
        } else if (s_var) {
          move_.add_unary(var_[size_t(s)], V(e, fs, ft), V(e, a, ft));
        } else {
          move_.add_unary(var_[size_t(t)], V(e, fs, ft), V(e, fs, a));
        }
      }
  }

  // Label costs of the labels the move may empty. Labels whose sites are not all variables stay used whatever the
  // move does: nothing to model. a's own cost, when a is unused, needs no term either: min over moves of
  // E(x) + h_a [x != 0] is min(E(0), h_a + min E(x)), which the acceptance test decides exactly (this replaces Delong
  // et al.'s auxiliary variable joined to every site, a hub that slows the max-flow badly).
  void add_label_cost_terms() {
    for (const auto i : vars_) ++switchable_[size_t(f_[size_t(i)])];
    for (const auto i : vars_) {
      const int l = f_[size_t(i)];
      if (switchable_[size_t(l)] <= 0) continue;  // done
      const bool all = switchable_[size_t(l)] == count_[size_t(l)];
      switchable_[size_t(l)] = 0;
      const double h = p_.label_cost[size_t(l)];
      if (!all || h == 0) continue;
      const Index y = move_.add_variable();  // y = 1: every site of l switches and h_l is saved
      move_.add_unary(y, h, 0.0);
      for (const auto j : vars_)
        if (f_[size_t(j)] == l) move_.add_pairwise(y, var_[size_t(j)], 0.0, 0.0, h, 0.0);
    }
  }

  void collect_switched() {
    switched_.clear();
    for (const auto i : vars_)
      if (move_.value(var_[size_t(i)])) switched_.push_back(i);
  }

  // The true energy change of the move (not the truncated one), from the switching sites and their edges.
  double move_delta(int a) {
    double delta = 0;
    for (const auto i : switched_) {
      delta += unary(p_, i, a) - unary(p_, i, f_[size_t(i)]);
      var_[size_t(i)] = -2;  // marks a switching site
    }
    for (const auto i : switched_)
      for (std::int64_t k = inc_offset_[size_t(i)]; k < inc_offset_[size_t(i) + 1]; ++k) {
        const Index e = incident_[size_t(k)];
        const auto [s, t] = p_.edges[size_t(e)];
        const std::int32_t other = s == i ? t : s;
        if (var_[size_t(other)] == -2 && other < i) continue;  // counted from the other end
        const int gs = var_[size_t(s)] == -2 ? a : f_[size_t(s)], gt = var_[size_t(t)] == -2 ? a : f_[size_t(t)];
        delta += V(e, gs, gt) - V(e, f_[size_t(s)], f_[size_t(t)]);
      }
    if (!p_.label_cost.empty() && !switched_.empty()) add_label_cost_change(a, delta);
    return delta;
  }

  // Adds the label costs the move starts paying (a, if unused) and stops paying (the labels it empties), in that
  // order, to `delta`.
  void add_label_cost_change(int a, double& delta) {
    if (count_[size_t(a)] == 0) delta += p_.label_cost[size_t(a)];
    for (const auto i : switched_) ++leaving_[size_t(f_[size_t(i)])];
    for (const auto i : switched_) {
      const int l = f_[size_t(i)];
      if (leaving_[size_t(l)] == count_[size_t(l)]) delta -= p_.label_cost[size_t(l)];  // l is emptied
      leaving_[size_t(l)] = 0;  // each label once (count >= 1, so no second match)
    }
  }

  const LabelingProblem& p_;
  std::vector<int> f_;
  std::vector<std::int64_t> inc_offset_;
  std::vector<std::int32_t> incident_;
  std::vector<std::vector<std::int32_t>> feasible_;  // sites where each label is feasible
  BinaryEnergy move_;
  std::vector<std::int32_t> var_;              // site -> move variable, -1 if fixed
  std::vector<Index> count_;                   // sites per label in f
  std::vector<std::int32_t> vars_, switched_;  // reused by every move
  std::vector<Index> switchable_, leaving_;    // per label, zero between uses
};

}  // namespace

ExpansionResult alpha_expansion(const LabelingProblem& p, std::vector<int> f, const ExpansionOptions& options) {
  if (Index(p.unary_offset.size()) != p.sites + 1)
    throw InvariantError("labelling problem: unary offsets do not match");
  ExpansionResult result;
  result.energy_before = labeling_energy(p, f);
  if (!std::isfinite(result.energy_before))
    throw InvariantError("alpha expansion: the initial labelling is infeasible");
  Expansion expansion(p, std::move(f));
  double energy = result.energy_before;
  for (result.cycles = 0; result.cycles < options.max_cycles;) {
    ++result.cycles;
    bool changed = false;
    for (int a = 0; a < p.labels; ++a) changed |= expansion.expand(a, energy, result);
    if (!changed) {
      result.converged = true;
      break;
    }
  }
  result.energy_after = labeling_energy(p, expansion.labeling());  // exact, free of the moves' summed rounding
  result.labeling = std::move(expansion.labeling());
  return result;
}

}  // namespace scanfill
