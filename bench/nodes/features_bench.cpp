// features node on a cloud of N points (range(0)) with a known viewpoint (as a scan has), on range(1) threads; and
// the whole "sample + features" of a 10^6-point scan (sample to 10^5, features on the samples).
#include <benchmark/benchmark.h>

#include "bench_util.h"
#include "nodes/features/estimate_features.h"
#include "nodes/sample/sample.h"

namespace scanfill {
namespace {

void BM_Features(benchmark::State& state) {
  PointSet cloud = bench::cached_cloud(state.range(0));
  cloud.set_viewpoint(Eigen::Vector3d(3, 0, 0.5));
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, size_t(state.range(1)));
  for (auto _ : state) benchmark::DoNotOptimize(estimate_features(cloud, {}));
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_Features)->ArgsProduct({{100000, 1000000}, {1, 2}})->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_FeaturesPropagate(benchmark::State& state) {  // closed-model orientation: the spanning tree is sequential
  const PointSet& cloud = bench::cached_cloud(state.range(0));
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, size_t(state.range(1)));
  FeaturesOptions o;
  o.orientation = NormalOrientation::kPropagate;
  for (auto _ : state) benchmark::DoNotOptimize(estimate_features(cloud, o));
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_FeaturesPropagate)->ArgsProduct({{100000}, {1, 2}})->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_SampleThenFeatures(benchmark::State& state) {
  PointSet cloud = bench::cached_cloud(state.range(0));
  cloud.set_viewpoint(Eigen::Vector3d(3, 0, 0.5));
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, size_t(state.range(1)));
  SampleOptions o;
  o.count = state.range(0) / 10;
  for (auto _ : state) benchmark::DoNotOptimize(estimate_features(sample(cloud, o).samples, {}));
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_SampleThenFeatures)->ArgsProduct({{1000000}, {1, 2}})->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace scanfill
