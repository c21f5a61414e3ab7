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
    tree.knn(s.centre + back * (x - s.centre), 1, &j, &d2);
    const Eigen::Vector3d d = x - (s.centre + forward * (source.positions().col(j) - s.centre));
    const Eigen::Vector3d n = (back * source.normals().col(j)).normalized();
    on[size_t(i)] = d.squaredNorm() <= 4 * spacing * spacing && std::abs(d.dot(n)) <= 0.5 * spacing;
  });
  return double(std::count(on.begin(), on.end(), 1)) / double(points.cols());
}

TemplateScaling scaling_that_fits(const Eigen::Matrix3Xd& points, const PointSet& source, const KdTree& tree,
                                  double spacing, double& share) {
  std::vector<std::vector<int>> groups;
  TemplateScaling best = principal_axes(source, groups);
  share = share_on_scaled(points, source, tree, best, spacing);
  const int steps = int(std::lround((kLargest - kSmallest) / kStep));
  for (int pass = 0; pass < kPasses; ++pass)
    for (const std::vector<int>& g : groups)
      for (int k = 0; k <= steps; ++k) {
        TemplateScaling trial = best;
        for (const int axis : g) trial.scale[axis] = kSmallest + k * kStep;
        const double on = share_on_scaled(points, source, tree, trial, spacing);
        if (on > share) {
          share = on;
          best = trial;
        }
      }
  return best;
}

PointSet scaled_source(const PointSet& source, const TemplateScaling& s) {
  const Eigen::Matrix3d forward = scaling_matrix(s, false), back = scaling_matrix(s, true);
  PointSet out = source;
  out.set_positions((forward * (source.positions().colwise() - s.centre)).colwise() + s.centre);
  if (source.has_normals()) out.set_normals((back * source.normals()).colwise().normalized());
  return out;
}

double largest_scaling_move(const PointSet& source, const TemplateScaling& s) {
  const Eigen::Matrix3d change = scaling_matrix(s, false) - Eigen::Matrix3d::Identity();
  return (change * (source.positions().colwise() - s.centre)).colwise().norm().maxCoeff();
}

}  // namespace scanfill
