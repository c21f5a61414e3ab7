// Inputs for the benchmarks: a dense cloud on the procedural vase, Morton-ordered as the loader leaves it.
#pragma once

#include <tbb/global_control.h>

#include <Eigen/Geometry>
#include <map>
#include <random>

#include "nodes/core/kdtree.h"
#include "nodes/procedural/shapes.h"

namespace scanfill::bench {

// n points uniformly (area-weighted) on the vase surface, in Morton order, positions only (a scan-like cloud).
inline PointSet vase_cloud(Index n) {
  const PointSet mesh = make_vase();
  const auto& P = mesh.positions();
  const auto& F = mesh.faces();
  std::vector<double> cumulative(static_cast<size_t>(F.cols()));
  double total = 0;
  for (Index f = 0; f < F.cols(); ++f) {
    total += 0.5 * (P.col(F(1, f)) - P.col(F(0, f))).cross(P.col(F(2, f)) - P.col(F(0, f))).norm();
    cumulative[size_t(f)] = total;
  }
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> u(0, 1);
  Eigen::Matrix3Xd pts(3, n);
  for (Index i = 0; i < n; ++i) {
    const Index f = std::min<Index>(
        F.cols() - 1, std::upper_bound(cumulative.begin(), cumulative.end(), u(rng) * total) - cumulative.begin());
    const double s = std::sqrt(u(rng)), t = u(rng);
    pts.col(i) = (1 - s) * P.col(F(0, f)) + s * (1 - t) * P.col(F(1, f)) + s * t * P.col(F(2, f));
  }
  const std::vector<Index> order = morton_order(pts);
  Eigen::Matrix3Xd sorted(3, n);
  for (Index i = 0; i < n; ++i) sorted.col(i) = pts.col(order[size_t(i)]);
  return PointSet(std::move(sorted));
}

// Cached per size: set-up stays outside the timed loops.
inline const PointSet& cached_cloud(Index n) {
  static std::map<Index, PointSet> cache;
  auto it = cache.find(n);
  if (it == cache.end()) it = cache.emplace(n, vase_cloud(n)).first;
  return it->second;
}

}  // namespace scanfill::bench
