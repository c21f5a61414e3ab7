// Boost.Graph's Boykov-Kolmogorov max-flow on an adjacency_list: the oracle our MaxFlow is tested against
// (tests/nodes/graphcut/max_flow_test.cpp) and compared with (bench/nodes/label_bench.cpp), and the grid problems both
// use.
#pragma once

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <boost/graph/adjacency_list.hpp>
#include <boost/graph/boykov_kolmogorov_max_flow.hpp>
#pragma GCC diagnostic pop

#include <chrono>
#include <random>
#include <vector>

#include "nodes/graphcut/max_flow.h"

namespace scanfill::test {

struct FlowProblem {
  std::int32_t nodes = 0;
  std::vector<double> source, sink;  // terminal capacities s -> v and v -> t
  std::vector<MaxFlow::Arc> arcs;
};

// A 4-connected side x side grid with random terminal capacities: the shape of an expansion move on a surface.
inline FlowProblem grid_problem(int side, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  FlowProblem p;
  p.nodes = side * side;
  for (std::int32_t i = 0; i < p.nodes; ++i) {
    const double d = u(rng) - 0.5;
    p.source.push_back(std::max(0.0, d));
    p.sink.push_back(std::max(0.0, -d));
  }
  for (int y = 0; y < side; ++y)
    for (int x = 0; x < side; ++x) {
      const std::int32_t i = y * side + x;
      if (x + 1 < side) p.arcs.push_back({i, i + 1, 0.3 * u(rng), 0.3 * u(rng)});
      if (y + 1 < side) p.arcs.push_back({i, i + side, 0.3 * u(rng), 0.3 * u(rng)});
    }
  return p;
}

// Maximum flow by Boost.Graph; the time spent building its graph is added to *build_ms when given.
inline double boost_max_flow(const FlowProblem& p, double* build_ms = nullptr) {
  using Traits = boost::adjacency_list_traits<boost::vecS, boost::vecS, boost::directedS>;
  using Graph = boost::adjacency_list<
      boost::vecS, boost::vecS, boost::directedS, boost::no_property,
      boost::property<boost::edge_capacity_t, double,
                      boost::property<boost::edge_residual_capacity_t, double,
                                      boost::property<boost::edge_reverse_t, Traits::edge_descriptor>>>>;
  const auto start = std::chrono::steady_clock::now();
  const size_t n = size_t(p.nodes) + 2, s = size_t(p.nodes), t = s + 1;
  Graph g(n);
  auto capacity = boost::get(boost::edge_capacity, g);
  auto reverse = boost::get(boost::edge_reverse, g);
  auto add = [&](size_t a, size_t b, double ab, double ba) {
    const auto e1 = boost::add_edge(a, b, g).first, e2 = boost::add_edge(b, a, g).first;
    capacity[e1] = ab;
    capacity[e2] = ba;
    reverse[e1] = e2;
    reverse[e2] = e1;
  };
  for (size_t v = 0; v < size_t(p.nodes); ++v) {
    if (p.source[v] > 0) add(s, v, p.source[v], 0);
    if (p.sink[v] > 0) add(v, t, p.sink[v], 0);
  }
  for (const auto& a : p.arcs) add(size_t(a.from), size_t(a.to), a.capacity, a.reverse_capacity);
  std::vector<boost::default_color_type> color(n);
  std::vector<Traits::edge_descriptor> predecessor(n);
  std::vector<long> distance(n);
  const auto index = boost::get(boost::vertex_index, g);
  if (build_ms)
    *build_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return boost::boykov_kolmogorov_max_flow(g, capacity, boost::get(boost::edge_residual_capacity, g), reverse,
                                           boost::make_iterator_property_map(predecessor.begin(), index),
                                           boost::make_iterator_property_map(color.begin(), index),
                                           boost::make_iterator_property_map(distance.begin(), index), index, s, t);
}

}  // namespace scanfill::test
