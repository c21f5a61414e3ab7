#include "nodes/graphcut/max_flow.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "nodes/core/errors.h"

namespace scanfill {
namespace {

bool finite_non_negative(double c) {
  return std::isfinite(c) && c >= 0;
}

}  // namespace

void MaxFlow::build(std::int32_t nodes, const std::vector<double>& source, const std::vector<double>& sink,
                    const std::vector<Arc>& arcs) {
  if (nodes < 0 || source.size() < size_t(nodes) || sink.size() < size_t(nodes))
    throw InvariantError("max flow: terminal capacities do not match the nodes");
  n_ = nodes;
  const size_t n = size_t(nodes);
  terminal_.resize(n);
  base_flow_ = 0;
  for (size_t v = 0; v < n; ++v) {
    if (!finite_non_negative(source[v]) || !finite_non_negative(sink[v]))
      throw InvariantError("max flow: a terminal capacity is negative or not finite");
    // s -> v -> t carries min(source, sink) at once; what is left is one terminal arc.
    base_flow_ += std::min(source[v], sink[v]);
    terminal_[v] = source[v] - sink[v];
  }
  first_.assign(n + 1, 0);
  for (const Arc& a : arcs) {
    if (a.from < 0 || a.to < 0 || a.from >= nodes || a.to >= nodes || a.from == a.to)
      throw InvariantError("max flow: arc with an invalid end");
    if (!finite_non_negative(a.capacity) || !finite_non_negative(a.reverse_capacity))
      throw InvariantError("max flow: an arc capacity is negative or not finite");
    ++first_[size_t(a.from) + 1];
    ++first_[size_t(a.to) + 1];
  }
  for (size_t v = 0; v < n; ++v) first_[v + 1] += first_[v];
  const size_t m = size_t(first_[n]);
  head_.resize(m);
  sister_.resize(m);
  residual_.resize(m);
  fill_.assign(first_.begin(), first_.end() - 1);
  for (const Arc& a : arcs) {
    const auto forward = std::int32_t(fill_[size_t(a.from)]++), backward = std::int32_t(fill_[size_t(a.to)]++);
    head_[size_t(forward)] = a.to;
    head_[size_t(backward)] = a.from;
    sister_[size_t(forward)] = backward;
    sister_[size_t(backward)] = forward;
    residual_[size_t(forward)] = a.capacity;
    residual_[size_t(backward)] = a.reverse_capacity;
  }
}

void MaxFlow::activate(std::int32_t v) {
  if (active_[size_t(v)]) return;
  active_[size_t(v)] = 1;
  queue_.push_back(v);
}

std::int32_t MaxFlow::next_active() {
  while (queue_head_ < queue_.size()) {
    const std::int32_t v = queue_[queue_head_++];
    active_[size_t(v)] = 0;
    if (parent_[size_t(v)] != kNone) return v;  // nodes freed by adoption since they were queued are skipped
  }
  queue_.clear();
  queue_head_ = 0;
  return -1;
}

void MaxFlow::make_orphan(std::int32_t v) {
  parent_[size_t(v)] = kOrphan;
  orphans_.push_back(v);
}

void MaxFlow::augment(std::int32_t bridge) {
  // The path: source tree from head(sister(bridge)) up to s, the bridge, sink tree from head(bridge) down to t.
  const std::int32_t from = head_[size_t(sister_[size_t(bridge)])], to = head_[size_t(bridge)];
  double bottleneck = residual_[size_t(bridge)];
  for (std::int32_t v = from;;) {
    const std::int32_t a = parent_[size_t(v)];
    if (a == kTerminal) {
      bottleneck = std::min(bottleneck, terminal_[size_t(v)]);
      break;
    }
    bottleneck = std::min(bottleneck, residual_[size_t(sister_[size_t(a)])]);
    v = head_[size_t(a)];
  }
  for (std::int32_t v = to;;) {
    const std::int32_t a = parent_[size_t(v)];
    if (a == kTerminal) {
      bottleneck = std::min(bottleneck, -terminal_[size_t(v)]);
      break;
    }
    bottleneck = std::min(bottleneck, residual_[size_t(a)]);
    v = head_[size_t(a)];
  }
  residual_[size_t(bridge)] -= bottleneck;
  residual_[size_t(sister_[size_t(bridge)])] += bottleneck;
  // Saturated arcs leave orphans: the arc's lower end loses its parent (exact zero: the bottleneck is one of the
  // capacities it is subtracted from).
  for (std::int32_t v = from;;) {
    const std::int32_t a = parent_[size_t(v)];
    if (a == kTerminal) {
      terminal_[size_t(v)] -= bottleneck;
      if (terminal_[size_t(v)] == 0) make_orphan(v);
      break;
    }
    residual_[size_t(a)] += bottleneck;
    residual_[size_t(sister_[size_t(a)])] -= bottleneck;
    if (residual_[size_t(sister_[size_t(a)])] == 0) make_orphan(v);
    v = head_[size_t(a)];
  }
  for (std::int32_t v = to;;) {
    const std::int32_t a = parent_[size_t(v)];
    if (a == kTerminal) {
      terminal_[size_t(v)] += bottleneck;
      if (terminal_[size_t(v)] == 0) make_orphan(v);
      break;
    }
    residual_[size_t(sister_[size_t(a)])] += bottleneck;
    residual_[size_t(a)] -= bottleneck;
    if (residual_[size_t(a)] == 0) make_orphan(v);
    v = head_[size_t(a)];
  }
  flow_ += bottleneck;
}

void MaxFlow::adopt(std::int32_t v) {
  constexpr std::int32_t kInfinite = std::numeric_limits<std::int32_t>::max();
  const std::uint8_t tree = tree_[size_t(v)];
  std::int32_t best = kNone, best_distance = kInfinite;
  for (std::int64_t a = first_[size_t(v)]; a < first_[size_t(v) + 1]; ++a) {
    const std::int32_t u = head_[size_t(a)];
    if (tree_[size_t(u)] != tree) continue;
    // A parent must be able to send flow to v (source tree) or receive it from v (sink tree).
    const double r = tree == kSource ? residual_[size_t(sister_[size_t(a)])] : residual_[size_t(a)];
    if (!(r > 0)) continue;
    // u qualifies if its path to the terminal does not pass through an orphan; timestamps cache the answer.
    std::int32_t d = 0;
    for (std::int32_t w = u;;) {
      if (timestamp_[size_t(w)] == time_) {
        d += distance_[size_t(w)];
        break;
      }
      const std::int32_t p = parent_[size_t(w)];
      ++d;
      if (p == kTerminal) {
        timestamp_[size_t(w)] = time_;
        distance_[size_t(w)] = 1;
        break;
      }
      if (p == kOrphan || p == kNone) {
        d = kInfinite;
        break;
      }
      w = head_[size_t(p)];
    }
    if (d == kInfinite) continue;
    if (d < best_distance) {
      best = std::int32_t(a);
      best_distance = d;
    }
    for (std::int32_t w = u; timestamp_[size_t(w)] != time_; w = head_[size_t(parent_[size_t(w)])]) {
      timestamp_[size_t(w)] = time_;
      distance_[size_t(w)] = d--;
    }
  }
  if (best != kNone) {
    parent_[size_t(v)] = best;
    timestamp_[size_t(v)] = time_;
    distance_[size_t(v)] = best_distance + 1;
    return;
  }
  // No valid parent: v leaves its tree; its children become orphans and the neighbours that could reach it are
  // activated, so the tree may grow back into it.
  for (std::int64_t a = first_[size_t(v)]; a < first_[size_t(v) + 1]; ++a) {
    const std::int32_t u = head_[size_t(a)];
    if (tree_[size_t(u)] != tree) continue;
    const double r = tree == kSource ? residual_[size_t(sister_[size_t(a)])] : residual_[size_t(a)];
    if (r > 0) activate(u);
    const std::int32_t p = parent_[size_t(u)];
    if (p >= 0 && head_[size_t(p)] == v) make_orphan(u);
  }
  tree_[size_t(v)] = kFree;
  parent_[size_t(v)] = kNone;
}

double MaxFlow::solve() {
  const size_t n = size_t(n_);
  tree_.assign(n, kFree);
  parent_.assign(n, kNone);
  timestamp_.assign(n, 0);
  distance_.assign(n, 0);
  active_.assign(n, 0);
  queue_.clear();
  orphans_.clear();
  queue_head_ = orphan_head_ = 0;
  time_ = 0;
  flow_ = base_flow_;
  for (std::int32_t v = 0; v < n_; ++v) {
    if (terminal_[size_t(v)] == 0) continue;
    tree_[size_t(v)] = terminal_[size_t(v)] > 0 ? kSource : kSink;
    parent_[size_t(v)] = kTerminal;
    distance_[size_t(v)] = 1;
    activate(v);
  }
  std::int32_t current = -1;  // the node last grown from: it may have more paths
  for (;;) {
    std::int32_t v = current >= 0 && parent_[size_t(current)] != kNone ? current : next_active();
    current = -1;
    if (v < 0) break;
    // Growth: claim free neighbours, and find an arc into the other tree.
    std::int32_t bridge = -1;  // an arc from the source tree to the sink tree with residual capacity
    const bool source = tree_[size_t(v)] == kSource;
    for (std::int64_t a = first_[size_t(v)]; a < first_[size_t(v) + 1]; ++a) {
      const std::int32_t back = sister_[size_t(a)];
      if (!((source ? residual_[size_t(a)] : residual_[size_t(back)]) > 0)) continue;
      const std::int32_t u = head_[size_t(a)];
      if (tree_[size_t(u)] == kFree) {
        tree_[size_t(u)] = tree_[size_t(v)];
        parent_[size_t(u)] = back;
        timestamp_[size_t(u)] = timestamp_[size_t(v)];
        distance_[size_t(u)] = distance_[size_t(v)] + 1;
        activate(u);
      } else if (tree_[size_t(u)] != tree_[size_t(v)]) {
        bridge = source ? std::int32_t(a) : back;
        break;
      } else if (timestamp_[size_t(u)] <= timestamp_[size_t(v)] && distance_[size_t(u)] > distance_[size_t(v)]) {
        // A shorter path to the terminal through v (the paper's distance heuristic).
        parent_[size_t(u)] = back;
        timestamp_[size_t(u)] = timestamp_[size_t(v)];
        distance_[size_t(u)] = distance_[size_t(v)] + 1;
      }
    }
    if (bridge < 0) continue;
    current = v;
    ++time_;
    augment(bridge);
    // Adoption, first in first out.
    while (orphan_head_ < orphans_.size()) adopt(orphans_[orphan_head_++]);
    orphans_.clear();
    orphan_head_ = 0;
  }
  return flow_;
}

}  // namespace scanfill
