#include "nodes/core/kdtree.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <nanoflann.hpp>

#include "nodes/core/errors.h"

namespace scanfill {
namespace {

struct MatrixAdaptor {
  const Eigen::Matrix3Xd* points = nullptr;
  size_t kdtree_get_point_count() const { return static_cast<size_t>(points->cols()); }
  double kdtree_get_pt(size_t i, size_t dim) const { return (*points)(static_cast<Eigen::Index>(dim), i); }
  template <class BBox>
  bool kdtree_get_bbox(BBox&) const {
    return false;
  }
};

using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, MatrixAdaptor>, MatrixAdaptor, 3,
                                                 std::uint32_t>;

// Collects radius hits into a caller-owned vector (no allocation once its capacity has grown).
class RadiusCollector {
 public:
  RadiusCollector(double radius2, std::vector<Neighbor>& out) : radius2_(radius2), out_(out) {}
  size_t size() const { return out_.size(); }
  bool full() const { return true; }
  bool addPoint(double d2, std::uint32_t index) {
    if (d2 < radius2_) out_.push_back({static_cast<std::int32_t>(index), d2});
    return true;
  }
  double worstDist() const { return radius2_; }

 private:
  double radius2_;
  std::vector<Neighbor>& out_;
};

}  // namespace

struct KdTree::Impl {
  MatrixAdaptor adaptor;
  std::unique_ptr<Tree> tree;
};

KdTree::KdTree() : impl_(std::make_unique<Impl>()) {}
KdTree::~KdTree() = default;
KdTree::KdTree(KdTree&&) noexcept = default;
KdTree& KdTree::operator=(KdTree&&) noexcept = default;

void KdTree::build(const Eigen::Matrix3Xd& points) {
  if (points.cols() > static_cast<Eigen::Index>(INT32_MAX))
    throw InputError("kd-tree: more than 2^31 points is not supported");
  impl_->adaptor.points = &points;
  impl_->tree = std::make_unique<Tree>(3, impl_->adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(12));
}

Index KdTree::size() const {
  return impl_->adaptor.points ? impl_->adaptor.points->cols() : 0;
}

int KdTree::knn(const Eigen::Vector3d& q, int k, std::int32_t* index, double* distance2) const {
  if (!impl_->tree) throw InvariantError("kd-tree queried before build()");
  static_assert(sizeof(std::int32_t) == sizeof(std::uint32_t));
  nanoflann::KNNResultSet<double, std::uint32_t> result(static_cast<size_t>(k));
  result.init(reinterpret_cast<std::uint32_t*>(index), distance2);
  impl_->tree->findNeighbors(result, q.data(), nanoflann::SearchParams());
  return static_cast<int>(result.size());
}

void KdTree::radius(const Eigen::Vector3d& q, double radius, std::vector<Neighbor>& out) const {
  if (!impl_->tree) throw InvariantError("kd-tree queried before build()");
  out.clear();
  RadiusCollector collector(radius * radius, out);
  impl_->tree->findNeighbors(collector, q.data(), nanoflann::SearchParams());
}

void nearest_each(const KdTree& tree, const Eigen::Matrix3Xd& points, std::vector<std::int32_t>& index,
                  std::vector<double>& distance2) {
  index.resize(size_t(points.cols()));
  distance2.resize(size_t(points.cols()));
  tbb::parallel_for(Index(0), points.cols(),
                    [&](Index i) { tree.knn(points.col(i), 1, &index[size_t(i)], &distance2[size_t(i)]); });
}

std::vector<std::int32_t> knn_graph(const KdTree& tree, const Eigen::Matrix3Xd& points, int k,
                                    std::vector<double>* distance2) {
  if (k < 0 || k > 64) throw InvariantError("knn_graph: k must lie in [0, 64]");
  std::vector<std::int32_t> graph(static_cast<size_t>(points.cols()) * size_t(k), -1);
  if (distance2) distance2->assign(graph.size(), 0.0);
  if (k == 0) return graph;
  tbb::parallel_for(Index(0), points.cols(), [&](Index i) {
    std::int32_t idx[65];
    double d2[65];
    const int got = tree.knn(points.col(i), k + 1, idx, d2);
    int w = 0;
    for (int a = 0; a < got && w < k; ++a) {
      if (idx[a] == i) continue;
      const size_t slot = size_t(i) * size_t(k) + size_t(w++);
      graph[slot] = idx[a];
      if (distance2) (*distance2)[slot] = d2[a];
    }
  });
  return graph;
}

std::uint64_t morton_key(const Eigen::Vector3d& p, const BoundingBox& box) {
  const double extent = std::max((box.max - box.min).maxCoeff(), 1e-300);
  const double scale = double((1u << 21) - 1) / extent;
  auto spread = [](std::uint64_t v) {  // 21 bits -> every third bit of 63
    v &= 0x1fffff;
    v = (v | v << 32) & 0x1f00000000ffffULL;
    v = (v | v << 16) & 0x1f0000ff0000ffULL;
    v = (v | v << 8) & 0x100f00f00f00f00fULL;
    v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
    v = (v | v << 2) & 0x1249249249249249ULL;
    return v;
  };
  const Eigen::Vector3d g = (p - box.min) * scale;
  return spread(std::uint64_t(g.x())) | spread(std::uint64_t(g.y())) << 1 | spread(std::uint64_t(g.z())) << 2;
}

std::vector<Index> morton_order(const Eigen::Matrix3Xd& points) {
  const Index n = points.cols();
  std::vector<Index> order(static_cast<size_t>(n));
  if (n == 0) return order;
  const BoundingBox box = bounding_box(points);
  std::vector<std::pair<std::uint64_t, Index>> keys(static_cast<size_t>(n));
  tbb::parallel_for(tbb::blocked_range<Index>(0, n, 4096), [&](const tbb::blocked_range<Index>& r) {
    for (Index i = r.begin(); i != r.end(); ++i) keys[size_t(i)] = {morton_key(points.col(i), box), i};
  });
  tbb::parallel_sort(keys.begin(), keys.end());  // ties broken by index: deterministic
  for (Index i = 0; i < n; ++i) order[size_t(i)] = keys[size_t(i)].second;
  return order;
}

double mean_nearest_neighbor_distance(const Eigen::Matrix3Xd& points, const KdTree& tree) {
  const Index n = points.cols();
  if (n < 2) throw InputError("nearest-neighbour spacing needs at least 2 points");
  const double sum = tbb::parallel_deterministic_reduce(
      tbb::blocked_range<Index>(0, n, 1024), 0.0,
      [&](const tbb::blocked_range<Index>& r, double acc) {
        std::int32_t idx[2];
        double d2[2];
        for (Index i = r.begin(); i != r.end(); ++i) {
          tree.knn(points.col(i), 2, idx, d2);
          acc += std::sqrt(d2[1]);
        }
        return acc;
      },
      std::plus<double>());
  return sum / double(n);
}

}  // namespace scanfill
