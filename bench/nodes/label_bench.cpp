// The label node's solvers alone: our Boykov-Kolmogorov max-flow on a 4-connected grid of range(0)^2 nodes (random
// terminal capacities, the shape of an expansion move on a surface; DESIGN section 7 quotes 0.7 s to build and 0.2 s
// to cut at 10^6 nodes), built and solved again in the same object, as the expansion does; and alpha-expansion with
// label costs on a grid with range(0)^2 sites and 6 sparse labels.
#include <benchmark/benchmark.h>

#include <chrono>
#include <random>

#include "bench_util.h"
#include "max_flow_oracle.h"
#include "nodes/graphcut/expansion.h"
#include "nodes/graphcut/max_flow.h"

namespace scanfill {
namespace {

void BM_MaxFlowGrid(benchmark::State& state) {
  const test::FlowProblem g = test::grid_problem(int(state.range(0)), 1);
  const std::int32_t n = g.nodes;
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
  const test::FlowProblem grid = test::grid_problem(int(state.range(0)), 1);
  double build_ms = 0, total_ms = 0;
  for (auto _ : state) {
    bench::Stopwatch clock;
    benchmark::DoNotOptimize(test::boost_max_flow(grid, &build_ms));
    total_ms += clock.lap_ms();
  }
  state.SetItemsProcessed(state.iterations() * grid.nodes);
  state.counters["build_ms"] = build_ms / double(state.iterations());
  state.counters["solve_ms"] = (total_ms - build_ms) / double(state.iterations());
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
