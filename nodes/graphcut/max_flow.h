// s-t maximum flow / minimum cut by the Boykov-Kolmogorov algorithm (Boykov and Kolmogorov, "An experimental
// comparison of min-cut/max-flow algorithms for energy minimization in vision", PAMI 2004), written from the paper:
// two search trees grown from the terminals, augmentation along the path where they meet, adoption of the orphans that
// saturated arcs leave, with the paper's timestamp and distance heuristics for choosing new parents.
//
// Written here rather than linked: Debian's libmaxflow is GPL-3, and Boost.Graph's version needs an adjacency_list that
// allocates per vertex each time a graph is built. This one keeps its arrays (compressed rows of arcs, each arc with
// its reverse) between solves: the alpha-expansion solves one cut per label and sweep on graphs of up to all the target
// samples, so build() reuses the capacity of the previous one (DESIGN section 7).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace scanfill {

class MaxFlow {
 public:
  struct Arc {
    std::int32_t from, to;
    double capacity, reverse_capacity;  // from -> to, and to -> from
  };

  // Builds the graph on `nodes` nodes: terminal capacities source[v] (s -> v) and sink[v] (v -> t), both >= 0, and
  // the arcs. Replaces any previous graph; keeps allocated storage.
  void build(std::int32_t nodes, const std::vector<double>& source, const std::vector<double>& sink,
             const std::vector<Arc>& arcs);
  // Maximum flow value; afterwards sink_side(v) says on which side of a minimum cut v lies.
  double solve();
  // True if v is on the sink side (reachable from t in the residual graph's sink tree); nodes that neither tree reached
  // are on the source side.
  bool sink_side(std::int32_t v) const { return tree_[size_t(v)] == kSink; }

 private:
  static constexpr std::uint8_t kFree = 0, kSource = 1, kSink = 2;
  static constexpr std::int32_t kNone = -1, kTerminal = -2, kOrphan = -3;

  void activate(std::int32_t v);
  std::int32_t next_active();
  // Pushes the bottleneck along the path through `bridge` (an arc from the source tree to the sink tree).
  void augment(std::int32_t bridge);
  // Finds v a new parent in its tree, or frees it.
  void adopt(std::int32_t v);
  void make_orphan(std::int32_t v);

  std::int32_t n_ = 0;
  double base_flow_ = 0, flow_ = 0;
  // Arcs in compressed rows by tail: the arcs leaving v are [first_[v], first_[v + 1]); sister_[a] is the reverse.
  std::vector<std::int64_t> first_;
  std::vector<std::int32_t> head_, sister_;
  std::vector<double> residual_;
  std::vector<double> terminal_;  // > 0: residual s -> v; < 0: residual v -> t (net of both terminal arcs)
  // Search trees.
  std::vector<std::uint8_t> tree_;
  std::vector<std::int32_t> parent_;  // arc from v to its parent, or kNone / kTerminal / kOrphan
  std::vector<std::int32_t> timestamp_, distance_;
  std::vector<std::uint8_t> active_;
  std::vector<std::int32_t> queue_, orphans_;
  size_t queue_head_ = 0, orphan_head_ = 0;
  std::int32_t time_ = 0;
  std::vector<std::int64_t> fill_;  // scratch of build()
};

}  // namespace scanfill
