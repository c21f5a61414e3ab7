// Our Boykov-Kolmogorov max-flow against Boost.Graph's implementation (a test oracle only: the library no longer
// uses it) on random graphs and grids, and the cut it reports against its own flow value.
#include "nodes/graphcut/max_flow.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "max_flow_oracle.h"

namespace scanfill {
namespace {

using test::boost_max_flow;
using test::FlowProblem;
using Problem = FlowProblem;

// Capacity of the cut that puts the sink-side nodes of `flow` on the sink side.
double cut_capacity(const Problem& p, const MaxFlow& flow) {
  double c = 0;
  for (std::int32_t v = 0; v < p.nodes; ++v) c += flow.sink_side(v) ? p.source[size_t(v)] : p.sink[size_t(v)];
  for (const auto& a : p.arcs) {
    if (!flow.sink_side(a.from) && flow.sink_side(a.to)) c += a.capacity;
    if (flow.sink_side(a.from) && !flow.sink_side(a.to)) c += a.reverse_capacity;
  }
  return c;
}

Problem random_graph(std::mt19937& rng, std::int32_t nodes, int arcs_per_node, bool integer) {
  std::uniform_real_distribution<double> u(0, 1);
  auto capacity = [&] {
    const double c = u(rng) < 0.2 ? 0.0 : u(rng);
    return integer ? std::floor(10 * c) : c;
  };
  Problem p;
  p.nodes = nodes;
  for (std::int32_t v = 0; v < nodes; ++v) {
    p.source.push_back(u(rng) < 0.5 ? capacity() : 0.0);
    p.sink.push_back(u(rng) < 0.5 ? capacity() : 0.0);
  }
  std::uniform_int_distribution<std::int32_t> node(0, nodes - 1);
  for (std::int64_t k = 0; k < std::int64_t(nodes) * arcs_per_node; ++k) {
    const std::int32_t a = node(rng), b = node(rng);
    if (a != b) p.arcs.push_back({a, b, capacity(), capacity()});
  }
  return p;
}

TEST(MaxFlow, MatchesBoostOnRandomGraphs) {
  std::mt19937 rng(3);
  MaxFlow flow;  // one object for every graph: storage reused across sizes
  for (int trial = 0; trial < 300; ++trial) {
    const Problem p = random_graph(rng, 2 + trial % 60 * 3, 1 + trial % 5, trial % 2 == 0);
    flow.build(p.nodes, p.source, p.sink, p.arcs);
    const double f = flow.solve(), expected = boost_max_flow(p);
    EXPECT_NEAR(f, expected, 1e-9 * std::max(1.0, expected)) << "trial " << trial;
    EXPECT_NEAR(cut_capacity(p, flow), f, 1e-9 * std::max(1.0, f)) << "trial " << trial;  // max flow = min cut
  }
}

TEST(MaxFlow, MatchesBoostOnGrids) {
  MaxFlow flow;
  for (const int side : {1, 2, 7, 40, 120, 30}) {
    const Problem p = test::grid_problem(side, std::uint32_t(4 + side));
    flow.build(p.nodes, p.source, p.sink, p.arcs);
    const double f = flow.solve(), expected = boost_max_flow(p);
    EXPECT_NEAR(f, expected, 1e-9 * std::max(1.0, expected)) << "side " << side;
    EXPECT_NEAR(cut_capacity(p, flow), f, 1e-9 * std::max(1.0, f)) << "side " << side;
  }
}

TEST(MaxFlow, KnownSmallCut) {
  // s -> 0 (3), s -> 1 (2), 0 -> 1 (1), 0 -> t (2), 1 -> t (3): max flow 5, every terminal arc saturated but 0 -> 1.
  MaxFlow flow;
  flow.build(2, {3, 2}, {2, 3}, {{0, 1, 1, 0}});
  EXPECT_DOUBLE_EQ(flow.solve(), 5);
  // A chain s -> 0 -> 1 -> 2 -> t with a bottleneck in the middle: the cut falls there.
  flow.build(3, {5, 0, 0}, {0, 0, 5}, {{0, 1, 4, 0}, {1, 2, 1, 0}});
  EXPECT_DOUBLE_EQ(flow.solve(), 1);
  EXPECT_FALSE(flow.sink_side(1));
  EXPECT_TRUE(flow.sink_side(2));
}

TEST(MaxFlow, RefusesBadArcs) {
  MaxFlow flow;
  EXPECT_THROW(flow.build(2, {1, 0}, {0, 1}, {{0, 2, 1, 0}}), std::exception);
  EXPECT_THROW(flow.build(2, {1, 0}, {0, 1}, {{0, 0, 1, 0}}), std::exception);
  EXPECT_THROW(flow.build(2, {-1, 0}, {0, 1}, {}), std::exception);
  EXPECT_THROW(flow.build(2, {1, 0}, {0, 1}, {{0, 1, std::numeric_limits<double>::infinity(), 0}}), std::exception);
  EXPECT_THROW(flow.build(2, {std::nan(""), 0}, {0, 1}, {}), std::exception);
}

}  // namespace
}  // namespace scanfill
