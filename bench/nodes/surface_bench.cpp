// surface node: pcl::Poisson's cost against depth (range(0)) and the point budget (range(1)) on a vase-sized output
// (170 k area-uniform points with normals on the procedural vase, as many as the vase example's completion); the mesh's
// F-score at 1% against the vase is a counter, so cost and accuracy are read off one table.
#include <benchmark/benchmark.h>

#include "bench_util.h"
#include "nodes/eval/evaluate.h"
#include "nodes/surface/surface.h"

namespace scanfill {
namespace {

void BM_PoissonSurface(benchmark::State& state) {
  static const PointSet vase = make_vase();
  static const PointSet points = random_surface_points(vase, 170000, 42);
  SurfaceOptions o;
  o.depth = int(state.range(0));
  o.max_points = state.range(1);
  SurfaceResult r;
  for (auto _ : state) r = poisson_surface(points, o);
  state.SetItemsProcessed(state.iterations() * points.size());
  state.counters["faces"] = double(r.mesh.faces().cols());
  state.counters["F"] = evaluate(r.mesh, vase, {}).fscore;
}
BENCHMARK(BM_PoissonSurface)
    ->ArgsProduct({{6, 7, 8}, {10000, 25000, 50000}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(1);

}  // namespace
}  // namespace scanfill
