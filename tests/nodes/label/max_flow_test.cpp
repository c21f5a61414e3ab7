// Our Boykov-Kolmogorov max-flow against Boost.Graph's implementation (a test oracle only: the library no longer
// uses it) on random graphs and grids, and the cut it reports against its own flow value.
#include "nodes/label/max_flow.h"

#include <gtest/gtest.h>

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <boost/graph/adjacency_list.hpp>
#include <boost/graph/boykov_kolmogorov_max_flow.hpp>
#pragma GCC diagnostic pop

#include <cmath>
#include <limits>
#include <random>

namespace scanfill {
namespace {

struct Problem {
  std::int32_t nodes = 0;
  std::vector<double> source, sink;
  std::vector<MaxFlow::Arc> arcs;
};

double boost_max_flow(const Problem& p) {
  using Traits = boost::adjacency_list_traits<boost::vecS, boost::vecS, boost::directedS>;
  using Graph = boost::adjacency_list<
      boost::vecS, boost::vecS, boost::directedS, boost::no_property,
      boost::property<boost::edge_capacity_t, double,
                      boost::property<boost::edge_residual_capacity_t, double,
                                      boost::property<boost::edge_reverse_t, Traits::edge_descriptor>>>>;
  Graph g(size_t(p.nodes) + 2);
  auto capacity = boost::get(boost::edge_capacity, g);
  auto reverse = boost::get(boost::edge_reverse, g);
  auto add = [&](size_t a, size_t b, double ab, double ba) {
    const auto e1 = boost::add_edge(a, b, g).first, e2 = boost::add_edge(b, a, g).first;
    capacity[e1] = ab;
    capacity[e2] = ba;
    reverse[e1] = e2;
    reverse[e2] = e1;
  };
  const size_t s = size_t(p.nodes), t = s + 1;
  for (size_t v = 0; v < size_t(p.nodes); ++v) {
    add(s, v, p.source[v], 0);
    add(v, t, p.sink[v], 0);
  }
  for (const auto& a : p.arcs) add(size_t(a.from), size_t(a.to), a.capacity, a.reverse_capacity);
  const size_t n = size_t(p.nodes) + 2;
  std::vector<boost::default_color_type> color(n);
  std::vector<Traits::edge_descriptor> predecessor(n);
  std::vector<long> distance(n);
  const auto index = boost::get(boost::vertex_index, g);
  return boost::boykov_kolmogorov_max_flow(g, capacity, boost::get(boost::edge_residual_capacity, g), reverse,
                                           boost::make_iterator_property_map(predecessor.begin(), index),
                                           boost::make_iterator_property_map(color.begin(), index),
                                           boost::make_iterator_property_map(distance.begin(), index), index, s, t);
}

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

// A 4-connected grid with random terminal capacities: the shape of an expansion move on a surface.
Problem grid(std::mt19937& rng, int side) {
  std::uniform_real_distribution<double> u(0, 1);
  Problem p;
  p.nodes = side * side;
  for (int i = 0; i < p.nodes; ++i) {
    const double d = u(rng) - 0.5;
    p.source.push_back(std::max(0.0, d));
    p.sink.push_back(std::max(0.0, -d));
  }
  for (int y = 0; y < side; ++y)
    for (int x = 0; x < side; ++x) {
      const int i = y * side + x;
      if (x + 1 < side) p.arcs.push_back({i, i + 1, 0.3 * u(rng), 0.3 * u(rng)});
      if (y + 1 < side) p.arcs.push_back({i, i + side, 0.3 * u(rng), 0.3 * u(rng)});
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
  std::mt19937 rng(4);
  MaxFlow flow;
  for (const int side : {1, 2, 7, 40, 120, 30}) {
    const Problem p = grid(rng, side);
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
