#include "nodes/graphcut/expansion.h"

#include <tbb/parallel_invoke.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
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

// An expansion move on one label, computed against the current labelling without changing it: the sites that
// switch, the true energy change, and the move's truncated terms.
struct Proposal {
  int label = -1;
  std::vector<std::int32_t> switched;
  double delta = 0;
  Index truncated = 0;
};

// One expansion run's shared state: the problem's incidence lists and per-label sites, the current labelling with its
// label counts. Moves are computed by Workspaces, which only read it, and committed here.
class Expansion {
 public:
  Expansion(const LabelingProblem& p, std::vector<int> f) : p_(p), f_(std::move(f)) {
    index_incident_edges();
    index_feasible_sites();
    count_.assign(size_t(p.labels), 0);
    for (const int l : f_) ++count_[size_t(l)];
  }

  // Applies an accepted move.
  void commit(const Proposal& move) {
    for (const auto i : move.switched) {
      --count_[size_t(f_[size_t(i)])];
      ++count_[size_t(move.label)];
      f_[size_t(i)] = move.label;
    }
  }

  double V(Index e, int ls, int lt) const { return ls == lt ? 0.0 : p_.pairwise(e, ls, lt); }

  const LabelingProblem& p_;
  std::vector<int> f_;
  std::vector<std::int64_t> inc_offset_;
  std::vector<std::int32_t> incident_;
  std::vector<std::vector<std::int32_t>> feasible_;  // sites where each label is feasible
  std::vector<Index> count_;                         // sites per label in f

 private:
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
};

// Every buffer a move needs, the flow graph's included, kept from move to move.
class Workspace {
 public:
  explicit Workspace(const Expansion& x) : x_(x), p_(x.p_) {
    var_.assign(size_t(p_.sites), -1);
    switchable_.assign(size_t(p_.labels), 0);
    leaving_.assign(size_t(p_.labels), 0);
  }

  // The expansion move on `a` against the current labelling (no switched sites when it has no variables).
  void propose(int a, Proposal& out) {
    out.label = a;
    out.switched.clear();
    out.delta = 0;
    out.truncated = 0;
    if (x_.feasible_[size_t(a)].empty() || !collect_variables(a)) return;
    add_unary_terms(a);
    add_pairwise_terms(a);
    if (!p_.label_cost.empty()) add_label_cost_terms();
    move_.minimize();
    out.truncated = move_.truncated();
    collect_switched();
    out.delta = move_delta(a);
    for (const auto i : vars_) var_[size_t(i)] = -1;
    out.switched = switched_;
  }

 private:
  int f(Index i) const { return x_.f_[size_t(i)]; }

  // The move's variables: the sites where `a` is feasible and not already taken. False if there are none.
  bool collect_variables(int a) {
    move_.reset();
    vars_.clear();
    for (const auto i : x_.feasible_[size_t(a)])
      if (f(i) != a) {
        var_[size_t(i)] = std::int32_t(move_.add_variable());
        vars_.push_back(i);
      }
    return !vars_.empty();
  }

  void add_unary_terms(int a) {
    for (const auto i : vars_) move_.add_unary(var_[size_t(i)], unary(p_, i, f(i)), unary(p_, i, a));
  }

  // Pairwise terms touching a variable (each edge once: from its lower-numbered variable end, or its only one).
  void add_pairwise_terms(int a) {
    for (const auto i : vars_)
      for (std::int64_t k = x_.inc_offset_[size_t(i)]; k < x_.inc_offset_[size_t(i) + 1]; ++k) {
        const Index e = x_.incident_[size_t(k)];
        auto [s, t] = p_.edges[size_t(e)];
        const bool s_var = var_[size_t(s)] >= 0, t_var = var_[size_t(t)] >= 0;
        const std::int32_t other = s == i ? t : s;
        if (s_var && t_var && other < i) continue;  // added from the other end
        const int fs = f(s), ft = f(t);
        if (s_var && t_var) {
          move_.add_pairwise(var_[size_t(s)], var_[size_t(t)], x_.V(e, fs, ft), x_.V(e, fs, a), x_.V(e, a, ft), 0.0);
        } else if (s_var) {
          move_.add_unary(var_[size_t(s)], x_.V(e, fs, ft), x_.V(e, a, ft));
        } else {
          move_.add_unary(var_[size_t(t)], x_.V(e, fs, ft), x_.V(e, fs, a));
        }
      }
  }

  // Label costs of the labels the move may empty. Labels whose sites are not all variables stay used whatever the
  // move does: nothing to model. a's own cost, when a is unused, needs no term either: min over moves of
  // E(x) + h_a [x != 0] is min(E(0), h_a + min E(x)), which the acceptance test decides exactly (this replaces Delong
  // et al.'s auxiliary variable joined to every site, a hub that slows the max-flow badly).
  void add_label_cost_terms() {
    for (const auto i : vars_) ++switchable_[size_t(f(i))];
    for (const auto i : vars_) {
      const int l = f(i);
      if (switchable_[size_t(l)] <= 0) continue;  // done
      const bool all = switchable_[size_t(l)] == x_.count_[size_t(l)];
      switchable_[size_t(l)] = 0;
      const double h = p_.label_cost[size_t(l)];
      if (!all || h == 0) continue;
      const Index y = move_.add_variable();  // y = 1: every site of l switches and h_l is saved
      move_.add_unary(y, h, 0.0);
      for (const auto j : vars_)
        if (f(j) == l) move_.add_pairwise(y, var_[size_t(j)], 0.0, 0.0, h, 0.0);
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
      delta += unary(p_, i, a) - unary(p_, i, f(i));
      var_[size_t(i)] = -2;  // marks a switching site
    }
    for (const auto i : switched_)
      for (std::int64_t k = x_.inc_offset_[size_t(i)]; k < x_.inc_offset_[size_t(i) + 1]; ++k) {
        const Index e = x_.incident_[size_t(k)];
        const auto [s, t] = p_.edges[size_t(e)];
        const std::int32_t other = s == i ? t : s;
        if (var_[size_t(other)] == -2 && other < i) continue;  // counted from the other end
        const int gs = var_[size_t(s)] == -2 ? a : f(s), gt = var_[size_t(t)] == -2 ? a : f(t);
        delta += x_.V(e, gs, gt) - x_.V(e, f(s), f(t));
      }
    if (!p_.label_cost.empty() && !switched_.empty()) add_label_cost_change(a, delta);
    return delta;
  }

  // Adds the label costs the move starts paying (a, if unused) and stops paying (the labels it empties), in that
  // order, to `delta`.
  void add_label_cost_change(int a, double& delta) {
    if (x_.count_[size_t(a)] == 0) delta += p_.label_cost[size_t(a)];
    for (const auto i : switched_) ++leaving_[size_t(f(i))];
    for (const auto i : switched_) {
      const int l = f(i);
      if (leaving_[size_t(l)] == x_.count_[size_t(l)]) delta -= p_.label_cost[size_t(l)];  // l is emptied
      leaving_[size_t(l)] = 0;  // each label once (count >= 1, so no second match)
    }
  }

  const Expansion& x_;
  const LabelingProblem& p_;
  BinaryEnergy move_;
  std::vector<std::int32_t> var_;              // site -> move variable, -1 if fixed
  std::vector<std::int32_t> vars_, switched_;  // reused by every move
  std::vector<Index> switchable_, leaving_;    // per label, zero between uses
};

// Whether a proposed move lowers the energy.
bool lowers(const Proposal& move, double energy) {
  return !move.switched.empty() && move.delta < -1e-12 * std::max(1.0, std::abs(energy));
}

// One sweep over the labels, in order. With a second thread, the move on a + 1 is computed beside the move on a,
// against the same labelling: when the move on a is rejected (most are, after the first sweep) that is exactly the
// labelling the sequential sweep would give it, so it is used; when a is accepted it is discarded and computed again.
// The result is the sequential sweep's, bit for bit, on any number of threads.
bool sweep(Expansion& x, std::array<Workspace, 2>& work, std::array<Proposal, 2>& moves, bool speculate, double& energy,
           ExpansionResult& result) {
  bool changed = false;
  const auto decide = [&](const Proposal& move) {
    result.truncated_terms += move.truncated;
    if (!lowers(move, energy)) return false;
    x.commit(move);
    energy += move.delta;
    ++result.moves_accepted;
    result.energy_trace.push_back(energy);
    return changed = true;
  };
  const int labels = x.p_.labels;
  for (int a = 0; a < labels;) {
    if (!speculate || a + 1 == labels) {
      work[0].propose(a, moves[0]);
      decide(moves[0]);
      ++a;
      continue;
    }
    tbb::parallel_invoke([&] { work[0].propose(a, moves[0]); }, [&] { work[1].propose(a + 1, moves[1]); });
    if (decide(moves[0])) {
      ++a;  // a + 1 starts again from the new labelling
      continue;
    }
    decide(moves[1]);
    a += 2;
  }
  return changed;
}

}  // namespace

ExpansionResult alpha_expansion(const LabelingProblem& p, std::vector<int> f, const ExpansionOptions& options) {
  if (Index(p.unary_offset.size()) != p.sites + 1)
    throw InvariantError("labelling problem: unary offsets do not match");
  ExpansionResult result;
  result.energy_before = labeling_energy(p, f);
  if (!std::isfinite(result.energy_before))
    throw InvariantError("alpha expansion: the initial labelling is infeasible");
  Expansion expansion(p, std::move(f));
  std::array<Workspace, 2> work{Workspace(expansion), Workspace(expansion)};
  std::array<Proposal, 2> moves;
  const bool speculate = tbb::this_task_arena::max_concurrency() > 1;
  double energy = result.energy_before;
  for (result.cycles = 0; result.cycles < options.max_cycles;) {
    ++result.cycles;
    if (!sweep(expansion, work, moves, speculate, energy, result)) {
      result.converged = true;
      break;
    }
  }
  result.energy_after = labeling_energy(p, expansion.f_);  // exact, free of the moves' summed rounding
  result.labeling = std::move(expansion.f_);
  return result;
}

}  // namespace scanfill
