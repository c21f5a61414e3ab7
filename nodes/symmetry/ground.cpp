#include "nodes/symmetry/ground.h"

#include <cmath>

namespace scanfill {

namespace {

constexpr double kOnGround = 0.02;  // of the extent: how near 0 it starts
constexpr double kAbout = 0.1;      // of the extent: how near 0 its middle lies

struct Extent {
  double low = 0, high = 0;
  double length() const { return high - low; }
};

Extent extent_along(const PointSet& points, const Eigen::Vector3d& direction) {
  const Eigen::RowVectorXd along = direction.normalized().transpose() * points.positions();
  return {along.minCoeff(), along.maxCoeff()};
}

// +1 where the extent stands on 0 and rises from it, -1 where it hangs from 0 below, 0 otherwise.
int standing_side(const Extent& e) {
  if (e.length() <= 0) return 0;
  if (std::abs(e.low) <= kOnGround * e.length()) return 1;
  if (std::abs(e.high) <= kOnGround * e.length()) return -1;
  return 0;
}

bool about_origin(const Extent& e) {
  return std::abs(e.low + e.high) / 2 <= kAbout * e.length();
}

}  // namespace

std::optional<Eigen::Vector3d> grounded_axis(const PointSet& target, const std::vector<SymmetryAxis>& axes) {
  if (target.empty()) return std::nullopt;
  std::optional<Eigen::Vector3d> up;
  for (const SymmetryAxis& a : axes) {
    const Extent e = extent_along(target, a.direction);
    if (about_origin(e)) continue;
    const int side = standing_side(e);
    if (side == 0 || up) return std::nullopt;
    up = side * a.direction.normalized();
  }
  return up;
}

}  // namespace scanfill
