// k = 16 nearest-neighbour queries for every point of a 10^6-point cloud: our KdTree (nanoflann inside) against FLANN's
// KDTreeSingleIndex, both queried one point at a time inside tbb::parallel_for (DESIGN section 7).
#include <benchmark/benchmark.h>
#include <tbb/parallel_for.h>
#include <flann/flann.hpp>

#include "bench_util.h"

namespace scanfill {
namespace {

constexpr int kK = 16;

void BM_KnnKdTree(benchmark::State& state) {
  const PointSet& cloud = bench::cached_cloud(state.range(0));
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, size_t(state.range(1)));
  KdTree tree;
  tree.build(cloud.positions());
  for (auto _ : state) {
    tbb::parallel_for(tbb::blocked_range<Index>(0, cloud.size(), 2048), [&](const tbb::blocked_range<Index>& r) {
      std::int32_t idx[kK];
      double d2[kK];
      for (Index i = r.begin(); i != r.end(); ++i) tree.knn(cloud.positions().col(i), kK, idx, d2);
      benchmark::DoNotOptimize(idx);
    });
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_KnnKdTree)->ArgsProduct({{1000000}, {1, 2}})->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_KnnFlann(benchmark::State& state) {
  const PointSet& cloud = bench::cached_cloud(state.range(0));
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, size_t(state.range(1)));
  std::vector<float> data(static_cast<size_t>(cloud.size() * 3));
  for (Index i = 0; i < cloud.size() * 3; ++i) data[size_t(i)] = float(cloud.positions().data()[i]);
  flann::Matrix<float> points(data.data(), size_t(cloud.size()), 3);
  flann::Index<flann::L2_Simple<float>> index(points, flann::KDTreeSingleIndexParams(12));
  index.buildIndex();
  for (auto _ : state) {
    tbb::parallel_for(tbb::blocked_range<Index>(0, cloud.size(), 2048), [&](const tbb::blocked_range<Index>& r) {
      std::vector<size_t> idx(kK);
      std::vector<float> d2(kK);
      flann::Matrix<size_t> mi(idx.data(), 1, kK);
      flann::Matrix<float> md(d2.data(), 1, kK);
      for (Index i = r.begin(); i != r.end(); ++i) {
        flann::Matrix<float> q(&data[size_t(3 * i)], 1, 3);
        index.knnSearch(q, mi, md, kK, flann::SearchParams(-1));
      }
      benchmark::DoNotOptimize(idx.data());
    });
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_KnnFlann)->ArgsProduct({{1000000}, {1, 2}})->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace scanfill
