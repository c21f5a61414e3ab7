// A static 3-D kd-tree over a 3 by N position matrix, for k-nearest and radius queries.
//
// Built once (costly set-up, so a class with build(), per CONVENTIONS), then queried concurrently from any number of
// threads: queries are const and allocation-free when the caller reuses its output buffers. The implementation is
// nanoflann's single-index tree behind a pimpl so that no header of ours carries it; bench/kdtree_bench.cpp compares
// it with FLANN's KDTreeSingleIndex on the same queries (DESIGN section 7 allows it where a benchmark shows it faster).
#pragma once

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "nodes/core/point_set.h"

namespace scanfill {

struct Neighbor {
  std::int32_t index;
  double distance2;  // squared Euclidean distance
};

class KdTree {
 public:
  KdTree();
  ~KdTree();
  KdTree(KdTree&&) noexcept;
  KdTree& operator=(KdTree&&) noexcept;

  // Keeps a reference to `points` (3 by N): it must outlive the tree and stay unchanged.
  void build(const Eigen::Matrix3Xd& points);
  Index size() const;

  // The k nearest points to q, nearest first, the query point itself included when it is in the set. Writes
  // min(k, size()) entries to index/distance2 and returns that count.
  int knn(const Eigen::Vector3d& q, int k, std::int32_t* index, double* distance2) const;

  // All points within `radius` of q (distance < radius), in no particular order, appended to `out` after clearing it.
  void radius(const Eigen::Vector3d& q, double radius, std::vector<Neighbor>& out) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// For every column of `points`, its nearest point in `tree`: index and squared distance (in parallel).
void nearest_each(const KdTree& tree, const Eigen::Matrix3Xd& points, std::vector<std::int32_t>& index,
                  std::vector<double>& distance2);

// The kNN graph of the tree's own points: for each point i, its k nearest other points (itself excluded) at
// [i k, (i + 1) k), nearest first, -1 where fewer exist; `distance2` (optional) gets their squared distances. k <= 64.
std::vector<std::int32_t> knn_graph(const KdTree& tree, const Eigen::Matrix3Xd& points, int k,
                                    std::vector<double>* distance2 = nullptr);

// Morton (Z-order) permutation of the points on a 2^21 grid over their bounding box: order[i] is the index of the
// point that goes to position i. Reordering points this way makes kd-tree queries in index order cache-friendly.
std::vector<Index> morton_order(const Eigen::Matrix3Xd& points);

// A point's Morton key on the 2^21 grid over `box` (morton_order's key, with the box of all its points).
std::uint64_t morton_key(const Eigen::Vector3d& p, const BoundingBox& box);

// Mean distance from each point to its nearest other point (the sample spacing alpha of the paper).
double mean_nearest_neighbor_distance(const Eigen::Matrix3Xd& points, const KdTree& tree);

}  // namespace scanfill
