#include "nodes/correspond/template_size.h"

#include <tbb/parallel_for.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cstdint>
#include <vector>

namespace scanfill {
namespace {

constexpr double kSmallest = 0.80, kLargest = 1.25, kStep = 0.01;
constexpr double kEqualSpread = 0.03;
constexpr int kPasses = 2;
constexpr int kShiftSteps = 12;        // each way
constexpr double kShiftStep = 0.5;     // spacings
constexpr double kClearlyMore = 0.01;  // share of the points

Eigen::Matrix3d scaling_matrix(const TemplateScaling& s, bool inverse) {
  const Eigen::Vector3d d = inverse ? Eigen::Vector3d(s.scale.cwiseInverse()) : s.scale;
  return s.axes * d.asDiagonal() * s.axes.transpose();
}

// The principal axes of the source's samples about their centroid, spread ascending, and which of them share a scale.
TemplateScaling principal_axes(const PointSet& source, std::vector<std::vector<int>>& groups) {
  TemplateScaling s;
  const Eigen::Matrix3Xd& p = source.positions();
  s.centre = p.rowwise().mean();
  const Eigen::Matrix3Xd d = p.colwise() - s.centre;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(d * d.transpose() / double(std::max<Index>(1, p.cols())));
  s.axes = eig.eigenvectors();
  const Eigen::Vector3d spread = eig.eigenvalues().cwiseMax(0).cwiseSqrt();
  for (int k = 0; k < 3; ++k) {
    auto same = std::find_if(groups.begin(), groups.end(), [&](const std::vector<int>& g) {
      return spread[k] > 0 && std::abs(spread[g.front()] / spread[k] - 1) < kEqualSpread;
    });
    if (same != groups.end())
      same->push_back(k);
    else
      groups.push_back({k});
  }
  return s;
}

// `s` scaled along its axes `group` to `scale`, about the place where `s` lays the template's point `pivot` (principal
// coordinates about its centre: the centre, or the template's near or far end along each axis), which stays.
TemplateScaling scaled_about(const TemplateScaling& s, const std::vector<int>& group, double scale,
                             const Eigen::Vector3d& pivot) {
  TemplateScaling t = s;
  for (const int k : group) {
    t.scale[k] = scale;
    t.shift += s.axes.col(k) * ((s.scale[k] - scale) * pivot[k]);
  }
  return t;
}

// `s` with its shift along its axis `axis` set to `shift`.
TemplateScaling shifted_to(const TemplateScaling& s, int axis, double shift) {
  const Eigen::Vector3d a = s.axes.col(axis);
  TemplateScaling t = s;
  t.shift += a * (shift - a.dot(s.shift));
  return t;
}

}  // namespace

double share_on_scaled(const Eigen::Matrix3Xd& points, const PointSet& source, const KdTree& tree,
                       const TemplateScaling& s, double spacing) {
  if (points.cols() == 0) return 0;
  const Eigen::Matrix3d forward = scaling_matrix(s, false), back = scaling_matrix(s, true);
  std::vector<std::uint8_t> on(size_t(points.cols()), 0);
  tbb::parallel_for(Index(0), points.cols(), [&](Index i) {
    const Eigen::Vector3d x = points.col(i);
    std::int32_t j;
    double d2;
    tree.knn(s.centre + back * (x - s.centre - s.shift), 1, &j, &d2);
    const Eigen::Vector3d d = x - (s.centre + s.shift + forward * (source.positions().col(j) - s.centre));
    const Eigen::Vector3d n = (back * source.normals().col(j)).normalized();
    on[size_t(i)] = d.squaredNorm() <= 4 * spacing * spacing && std::abs(d.dot(n)) <= 0.5 * spacing;
  });
  return double(std::count(on.begin(), on.end(), 1)) / double(points.cols());
}

TemplateScaling scaling_that_fits(const Eigen::Matrix3Xd& points, const PointSet& source, const KdTree& tree,
                                  double spacing, double& share) {
  std::vector<std::vector<int>> groups;
  TemplateScaling best = principal_axes(source, groups);
  const Eigen::Matrix3Xd along = best.axes.transpose() * (source.positions().colwise() - best.centre);
  const Eigen::Vector3d low = along.rowwise().minCoeff(), high = along.rowwise().maxCoeff();
  share = share_on_scaled(points, source, tree, best, spacing);
  // The trials of one group or axis all start from the scaling before them, and the one laying the most on is taken
  // where it lays kClearlyMore on than that scaling: a few samples more on are no evidence of a size, and a scan that
  // does not see an end of the template leaves that end where it is drawn.
  const auto take_most_on = [&](const std::vector<TemplateScaling>& trials) {
    const double before = share;
    for (const TemplateScaling& trial : trials)
      if (const double on = share_on_scaled(points, source, tree, trial, spacing);
          on > share && on > before + kClearlyMore) {
        share = on;
        best = trial;
      }
  };
  const int steps = int(std::lround((kLargest - kSmallest) / kStep));
  std::vector<TemplateScaling> trials;
  for (int pass = 0; pass < kPasses; ++pass) {
    for (const std::vector<int>& g : groups) {
      trials.clear();
      for (const Eigen::Vector3d& pivot : {Eigen::Vector3d(Eigen::Vector3d::Zero()), low, high})
        for (int k = 0; k <= steps; ++k) trials.push_back(scaled_about(best, g, kSmallest + k * kStep, pivot));
      take_most_on(trials);
    }
    for (int axis = 0; axis < 3; ++axis) {
      trials.clear();
      for (int k = -kShiftSteps; k <= kShiftSteps; ++k)
        trials.push_back(shifted_to(best, axis, k * kShiftStep * spacing));
      take_most_on(trials);
    }
  }
  return best;
}

PointSet scaled_source(const PointSet& source, const TemplateScaling& s) {
  const Eigen::Matrix3d forward = scaling_matrix(s, false), back = scaling_matrix(s, true);
  PointSet out = source;
  out.set_positions((forward * (source.positions().colwise() - s.centre)).colwise() + (s.centre + s.shift));
  if (source.has_normals()) out.set_normals((back * source.normals()).colwise().normalized());
  return out;
}

double largest_scaling_move(const PointSet& source, const TemplateScaling& s) {
  const Eigen::Matrix3d change = scaling_matrix(s, false) - Eigen::Matrix3d::Identity();
  return (change * (source.positions().colwise() - s.centre)).colwise().norm().maxCoeff();
}

}  // namespace scanfill
