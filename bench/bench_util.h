// Inputs for the benchmarks: a dense cloud on the procedural vase, Morton-ordered as the loader leaves it.
#pragma once

#include <tbb/global_control.h>

#include <chrono>
#include <map>

#include "nodes/core/kdtree.h"
#include "nodes/procedural/shapes.h"
#include "nodes/sample/sample.h"

namespace scanfill::bench {

// n points uniformly (area-weighted) on the vase surface, in Morton order, positions only (a scan-like cloud).
inline PointSet vase_cloud(Index n) {
  return PointSet(random_surface_points(make_vase(), n, 42).positions());
}

// Wall-clock laps inside a timed loop (per-stage counters).
class Stopwatch {
 public:
  double lap_ms() {
    const auto now = std::chrono::steady_clock::now();
    const double ms = std::chrono::duration<double, std::milli>(now - last_).count();
    last_ = now;
    return ms;
  }

 private:
  std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

// Cached per size: set-up stays outside the timed loops.
inline const PointSet& cached_cloud(Index n) {
  static std::map<Index, PointSet> cache;
  auto it = cache.find(n);
  if (it == cache.end()) it = cache.emplace(n, vase_cloud(n)).first;
  return it->second;
}

}  // namespace scanfill::bench
