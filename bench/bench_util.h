// Inputs for the benchmarks: a dense cloud on the procedural vase, Morton-ordered as the loader leaves it.
#pragma once

#include <tbb/global_control.h>

#include <map>

#include "nodes/core/kdtree.h"
#include "nodes/procedural/shapes.h"
#include "nodes/sample/sample.h"

namespace scanfill::bench {

// n points uniformly (area-weighted) on the vase surface, in Morton order, positions only (a scan-like cloud).
inline PointSet vase_cloud(Index n) {
  return PointSet(random_surface_points(make_vase(), n, 42).positions());
}

// Cached per size: set-up stays outside the timed loops.
inline const PointSet& cached_cloud(Index n) {
  static std::map<Index, PointSet> cache;
  auto it = cache.find(n);
  if (it == cache.end()) it = cache.emplace(n, vase_cloud(n)).first;
  return it->second;
}

}  // namespace scanfill::bench
