#include "nodes/scan/crop.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "nodes/core/disjoint_sets.h"
#include "nodes/core/errors.h"
#include "nodes/core/kdtree.h"

namespace scanfill {
namespace {

using Indices = std::vector<std::int32_t>;

// At most this many points are tried against each RANSAC triple and enter the median spacing: the answer of a
// strided subset, the cost independent of a scene's size.
constexpr Index kSubsetPoints = 20000;

Indices inside_box(const Eigen::Matrix3Xd& p, const BoundingBox& box) {
  Indices out;
  for (Index i = 0; i < p.cols(); ++i)
    if ((p.col(i).array() >= box.min.array()).all() && (p.col(i).array() <= box.max.array()).all())
      out.push_back(std::int32_t(i));
  return out;
}

// The median distance from a point to its nearest other point, over a strided subset.
double median_spacing(const Eigen::Matrix3Xd& p, const KdTree& tree) {
  std::vector<double> d;
  std::int32_t index[2];
  double d2[2];
  for (std::int32_t i : strided_indices(p.cols(), kSubsetPoints))
    if (tree.knn(p.col(i), 2, index, d2) == 2) d.push_back(std::sqrt(d2[1]));
  if (d.empty()) return 0;
  std::nth_element(d.begin(), d.begin() + std::ptrdiff_t(d.size() / 2), d.end());
  return d[d.size() / 2];
}

struct Plane {
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  double offset = 0;
  double distance(const Eigen::Vector3d& x) const { return std::abs(normal.dot(x) + offset); }
};

Index count_within(const Eigen::Matrix3Xd& p, const Indices& which, const Plane& plane, double d) {
  Index n = 0;
  for (std::int32_t i : which) n += plane.distance(p.col(i)) < d;
  return n;
}

// The plane through the most of `p` (within d): random triples scored on a strided subset.
Plane ransac_plane(const Eigen::Matrix3Xd& p, double d, int trials, std::uint64_t seed) {
  const Indices scored = strided_indices(p.cols(), kSubsetPoints);
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<Index> pick(0, p.cols() - 1);
  Plane best;
  Index best_count = -1;
  for (int t = 0; t < trials; ++t) {
    const Eigen::Vector3d a = p.col(pick(rng)), b = p.col(pick(rng)), c = p.col(pick(rng));
    const Eigen::Vector3d n = (b - a).cross(c - a);
    if (n.norm() < 1e-12 * std::max(1.0, (b - a).squaredNorm())) continue;
    Plane plane{n.normalized(), -n.normalized().dot(a)};
    const Index count = count_within(p, scored, plane, d);
    if (count > best_count) {
      best = plane;
      best_count = count;
    }
  }
  return best;
}

// The least-squares plane of the points of `p` within d of `plane`.
Plane refit_plane(const Eigen::Matrix3Xd& p, const Plane& plane, double d) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  Index n = 0;
  for (Index i = 0; i < p.cols(); ++i)
    if (plane.distance(p.col(i)) < d) mean += p.col(i), ++n;
  if (n < 3) return plane;
  mean /= double(n);
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (Index i = 0; i < p.cols(); ++i)
    if (plane.distance(p.col(i)) < d) cov += (p.col(i) - mean) * (p.col(i) - mean).transpose();
  const Eigen::Vector3d normal = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(cov).eigenvectors().col(0);
  return {normal, -normal.dot(mean)};
}

// The points of the largest connected part, joined across gaps shorter than `gap`; `parts` gets their number.
Indices largest_connected_part(const Eigen::Matrix3Xd& p, const KdTree& tree, double gap, Index& parts) {
  DisjointSets sets(p.cols());
  std::vector<Neighbor> near;
  for (Index i = 0; i < p.cols(); ++i) {
    tree.radius(p.col(i), gap, near);
    for (const Neighbor& n : near) sets.join(std::int32_t(i), n.index);
  }
  std::vector<Index> size(size_t(p.cols()), 0);
  for (Index i = 0; i < p.cols(); ++i) ++size[size_t(sets.find(std::int32_t(i)))];
  parts = Index(std::count_if(size.begin(), size.end(), [](Index s) { return s > 0; }));
  const auto largest = std::int32_t(std::max_element(size.begin(), size.end()) - size.begin());
  Indices out;
  for (Index i = 0; i < p.cols(); ++i)
    if (sets.find(std::int32_t(i)) == largest) out.push_back(std::int32_t(i));
  return out;
}

PointSet keep(const PointSet& points, const Indices& which, const char* what) {
  if (which.empty()) throw InputError(std::string("crop: no point is left ") + what);
  PointSet out = subset(points, which);
  out.set_viewpoint(points.viewpoint());
  return out;
}

// `value`, or `times` the median spacing when it is 0; a spacing of 0 (every point doubled) gives no default.
double scaled_default(double value, double times, double spacing, const char* what) {
  if (value > 0) return value;
  if (!(spacing > 0))
    throw InputError(std::string("crop: the points' median spacing is 0 (points repeated), so the ") + what +
                     " needs a value");
  return times * spacing;
}

void check(const CropOptions& o) {
  if (o.box && !(o.box->min.array() <= o.box->max.array()).all())
    throw ConfigError("crop: the box's minimum must not exceed its maximum on any axis");
  if (!(o.plane_distance >= 0) || !std::isfinite(o.plane_distance))
    throw ConfigError("crop: the plane distance must be finite and >= 0");
  if (!(o.gap >= 0) || !std::isfinite(o.gap)) throw ConfigError("crop: the gap must be finite and >= 0");
  if (o.plane_trials < 1) throw ConfigError("crop: plane_trials must be >= 1");
}

}  // namespace

CropResult crop(const PointSet& points, const CropOptions& options) {
  check(options);
  if (points.size() == 0) throw InputError("crop: the input has no points");
  CropResult r;
  r.points = options.box ? keep(points, inside_box(points.positions(), *options.box), "inside the box") : points;
  r.in_box = r.points.size();
  if (!options.drop_plane && !options.largest_part) return r;
  KdTree tree;
  tree.build(r.points.positions());
  r.spacing = median_spacing(r.points.positions(), tree);
  if (options.drop_plane) {
    const double d = scaled_default(options.plane_distance, 2, r.spacing, "plane distance");
    const Plane plane =
        refit_plane(r.points.positions(), ransac_plane(r.points.positions(), d, options.plane_trials, options.seed), d);
    Indices off;
    for (Index i = 0; i < r.points.size(); ++i)
      if (plane.distance(r.points.positions().col(i)) >= d) off.push_back(std::int32_t(i));
    r.plane_points = r.points.size() - Index(off.size());
    r.plane_normal = plane.normal;
    r.plane_offset = plane.offset;
    r.points = keep(r.points, off, "off the largest plane");
  }
  if (options.largest_part) {
    if (options.drop_plane) {  // the tree indexed the points before the plane was dropped
      tree = KdTree();
      tree.build(r.points.positions());
    }
    const double gap = scaled_default(options.gap, 4, r.spacing, "gap");
    r.points = keep(r.points, largest_connected_part(r.points.positions(), tree, gap, r.parts), "in a part");
  }
  return r;
}

}  // namespace scanfill
