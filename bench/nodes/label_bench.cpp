// The label node's solvers alone: our Boykov-Kolmogorov max-flow on a 4-connected grid of range(0)^2 nodes (random
// terminal capacities, the shape of an expansion move on a surface; DESIGN section 7 quotes 0.7 s to build and 0.2 s
// to cut at 10^6 nodes), built and solved again in the same object, as the expansion does; and alpha-expansion with
// label costs on a grid with range(0)^2 sites and 6 sparse labels.
#include <benchmark/benchmark.h>

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <boost/graph/adjacency_list.hpp>
#include <boost/graph/boykov_kolmogorov_max_flow.hpp>
#pragma GCC diagnostic pop

#include <chrono>
#include <random>

#include "bench_util.h"
#include "nodes/label/expansion.h"
#include "nodes/label/max_flow.h"

namespace scanfill {
namespace {

struct Grid {
  std::int32_t n = 0;
  std::vector<double> source, sink;
  std::vector<MaxFlow::Arc> arcs;
};

Grid make_grid(int side) {
  Grid g;
  g.n = side * side;
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(0, 1);
  for (std::int32_t i = 0; i < g.n; ++i) {
    const double d = u(rng) - 0.5;
    g.source.push_back(std::max(0.0, d));
    g.sink.push_back(std::max(0.0, -d));
  }
  for (int y = 0; y < side; ++y)
    for (int x = 0; x < side; ++x) {
      const std::int32_t i = y * side + x;
      if (x + 1 < side) g.arcs.push_back({i, i + 1, 0.3 * u(rng), 0.3 * u(rng)});
      if (y + 1 < side) g.arcs.push_back({i, i + side, 0.3 * u(rng), 0.3 * u(rng)});
    }
  return g;
}

void BM_MaxFlowGrid(benchmark::State& state) {
  const Grid g = make_grid(int(state.range(0)));
  const std::int32_t n = g.n;
  MaxFlow flow;
  double build_ms = 0, solve_ms = 0;
  for (auto _ : state) {
    bench::Stopwatch clock;
    flow.build(n, g.source, g.sink, g.arcs);
    build_ms += clock.lap_ms();
    benchmark::DoNotOptimize(flow.solve());
    solve_ms += clock.lap_ms();
  }
  state.SetItemsProcessed(state.iterations() * n);
  state.counters["build_ms"] = build_ms / double(state.iterations());
  state.counters["solve_ms"] = solve_ms / double(state.iterations());
}
BENCHMARK(BM_MaxFlowGrid)->Arg(300)->Arg(1000)->Unit(benchmark::kMillisecond)->UseRealTime();

// The same grids through Boost.Graph's boykov_kolmogorov_max_flow on an adjacency_list (what the label node used
// before), for comparison.
void BM_BoostMaxFlowGrid(benchmark::State& state) {
  using Traits = boost::adjacency_list_traits<boost::vecS, boost::vecS, boost::directedS>;
  using Graph = boost::adjacency_list<
      boost::vecS, boost::vecS, boost::directedS, boost::no_property,
      boost::property<boost::edge_capacity_t, double,
                      boost::property<boost::edge_residual_capacity_t, double,
                                      boost::property<boost::edge_reverse_t, Traits::edge_descriptor>>>>;
  const Grid grid = make_grid(int(state.range(0)));
  double build_ms = 0, solve_ms = 0;
  for (auto _ : state) {
    bench::Stopwatch clock;
    const size_t n = size_t(grid.n) + 2, s = size_t(grid.n), t = s + 1;
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
    for (size_t v = 0; v < size_t(grid.n); ++v) {
      if (grid.source[v] > 0) add(s, v, grid.source[v], 0);
      if (grid.sink[v] > 0) add(v, t, grid.sink[v], 0);
    }
    for (const auto& a : grid.arcs) add(size_t(a.from), size_t(a.to), a.capacity, a.reverse_capacity);
    std::vector<boost::default_color_type> color(n);
    std::vector<Traits::edge_descriptor> predecessor(n);
    std::vector<long> distance(n);
    const auto index = boost::get(boost::vertex_index, g);
    build_ms += clock.lap_ms();
    benchmark::DoNotOptimize(
        boost::boykov_kolmogorov_max_flow(g, capacity, boost::get(boost::edge_residual_capacity, g), reverse,
                                          boost::make_iterator_property_map(predecessor.begin(), index),
                                          boost::make_iterator_property_map(color.begin(), index),
                                          boost::make_iterator_property_map(distance.begin(), index), index, s, t));
    solve_ms += clock.lap_ms();
  }
  state.SetItemsProcessed(state.iterations() * grid.n);
  state.counters["build_ms"] = build_ms / double(state.iterations());
  state.counters["solve_ms"] = solve_ms / double(state.iterations());
}
BENCHMARK(BM_BoostMaxFlowGrid)->Arg(300)->Arg(1000)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_ExpansionGrid(benchmark::State& state) {
  const int side = int(state.range(0)), labels = 6;
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(0, 1);
  LabelingProblem p;
  p.labels = labels;
  std::vector<std::pair<int, double>> costs;
  for (int y = 0; y < side; ++y)
    for (int x = 0; x < side; ++x) {
      costs.assign(1, {0, 8.0});        // the self-reference label, everywhere
      for (int l = 1; l < labels; ++l)  // label l feasible on a band of the grid, cheap in its middle
        if (std::abs(x - l * side / labels) < side / 4)
          costs.push_back({l, 10.0 * u(rng) * std::abs(x - l * side / labels) / side * 4});
      p.add_site(costs);
    }
  for (int y = 0; y < side; ++y)
    for (int x = 0; x < side; ++x) {
      const int i = y * side + x;
      if (x + 1 < side) p.edges.push_back({i, i + 1});
      if (y + 1 < side) p.edges.push_back({i, i + side});
    }
  p.pairwise = [](Index, int a, int b) { return a == labels - 1 || b == labels - 1 ? 2.0 : 1.0; };
  p.label_cost.assign(size_t(labels), 0.05 * side * side);
  p.label_cost[0] = 0;
  for (auto _ : state) benchmark::DoNotOptimize(alpha_expansion(p, std::vector<int>(size_t(side) * size_t(side), 0)));
  state.SetItemsProcessed(state.iterations() * side * side);
}
BENCHMARK(BM_ExpansionGrid)->Arg(150)->Arg(450)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace scanfill
