// sample node: a cloud of N points (range(0)) thinned to N/10 samples, and the vase mesh sampled to N/10, on
// range(1) threads. Items per second = input points per second.
#include <benchmark/benchmark.h>

#include "bench_util.h"
#include "nodes/sample/sample.h"

namespace scanfill {
namespace {

void BM_SampleCloud(benchmark::State& state) {
  const PointSet& cloud = bench::cached_cloud(state.range(0));
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, size_t(state.range(1)));
  SampleOptions o;
  o.count = state.range(0) / 10;
  for (auto _ : state) benchmark::DoNotOptimize(sample(cloud, o));
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_SampleCloud)->ArgsProduct({{100000, 1000000}, {1, 2}})->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_SampleMesh(benchmark::State& state) {
  static const PointSet mesh = make_vase();
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, size_t(state.range(1)));
  SampleOptions o;
  o.count = state.range(0);
  for (auto _ : state) benchmark::DoNotOptimize(sample(mesh, o));
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_SampleMesh)->ArgsProduct({{10000, 100000}, {1, 2}})->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace scanfill
