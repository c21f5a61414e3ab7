#include "nodes/correspond/free_space.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>

namespace scanfill {
namespace {

constexpr double kCell = 1.5;          // the view grid's cell, in samples' spacings at the scan's median depth
constexpr double kWidestRay = 0.17;    // cos 80 degrees: rays farther off the view's centre line are not gridded
constexpr double kEyeClearance = 0.1;  // the eye must lie this share of the targets' extent outside their box
constexpr double kMaxCellIndex = 1e9;  // a ray that far out in cells (a spacing of nothing) is not gridded
constexpr double kMargin = 4.0;        // spacings a scan sample must lie beyond a target sample to see through it

// The view: the eye, an orthonormal frame whose z is the centre line of the scan's rays, and the grid's cell in
// units of the image plane at distance 1.
struct View {
  Eigen::Vector3d eye, x, y, z;
  double cell = 0;
};

// The grid cell (i, j) the ray d (from the eye) falls in; false for a ray outside the gridded cone.
bool cell_of(const View& v, const Eigen::Vector3d& d, std::int64_t& i, std::int64_t& j) {
  const double forward = d.dot(v.z);
  if (!(forward > kWidestRay * d.norm())) return false;
  const double u = d.dot(v.x) / forward / v.cell, w = d.dot(v.y) / forward / v.cell;
  if (!(std::abs(u) < kMaxCellIndex && std::abs(w) < kMaxCellIndex)) return false;
  i = std::int64_t(std::floor(u));
  j = std::int64_t(std::floor(w));
  return true;
}

std::uint64_t cell_key(std::int64_t i, std::int64_t j) {
  return (std::uint64_t(i + (std::int64_t(1) << 31)) << 32) |
         (std::uint64_t(j + (std::int64_t(1) << 31)) & 0xffffffffu);
}

bool within_box_of(const Eigen::Matrix3Xd& points, const Eigen::Vector3d& eye) {
  const BoundingBox box = bounding_box(points);
  const Eigen::Vector3d margin = kEyeClearance * (box.max - box.min);
  return ((eye - box.min + margin).array() >= 0).all() && ((box.max + margin - eye).array() >= 0).all();
}

// The view of the scan's samples P from eye: its centre line the mean of their unit rays; nullopt where they do not
// lie on one side of the eye (their mean ray is shorter than half a ray).
std::optional<View> view_of(const Eigen::Matrix3Xd& P, const Eigen::Vector3d& eye, double spacing) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (Eigen::Index k = 0; k < P.cols(); ++k) {
    const Eigen::Vector3d d = P.col(k) - eye;
    if (d.norm() > 0) sum += d.normalized();
  }
  if (!(sum.norm() > 0.5 * double(P.cols()))) return std::nullopt;
  View v;
  v.eye = eye;
  v.z = sum.normalized();
  v.x = v.z.unitOrthogonal();
  v.y = v.z.cross(v.x);
  std::vector<double> forward;
  forward.reserve(size_t(P.cols()));
  for (Eigen::Index k = 0; k < P.cols(); ++k) forward.push_back((P.col(k) - eye).dot(v.z));
  auto mid = forward.begin() + std::ptrdiff_t(forward.size() / 2);
  std::nth_element(forward.begin(), mid, forward.end());
  if (!(*mid > 0)) return std::nullopt;
  v.cell = kCell * spacing / *mid;
  return v;
}

// The nearest scan sample's distance from the eye per occupied cell, sorted by cell.
std::vector<std::pair<std::uint64_t, double>> depth_grid(const View& v, const Eigen::Matrix3Xd& P) {
  std::vector<std::pair<std::uint64_t, double>> cells;
  cells.reserve(size_t(P.cols()));
  std::int64_t i = 0, j = 0;
  for (Eigen::Index k = 0; k < P.cols(); ++k) {
    const Eigen::Vector3d d = P.col(k) - v.eye;
    if (cell_of(v, d, i, j)) cells.emplace_back(cell_key(i, j), d.norm());
  }
  std::sort(cells.begin(), cells.end());
  cells.erase(std::unique(cells.begin(), cells.end(), [](const auto& a, const auto& b) { return a.first == b.first; }),
              cells.end());
  return cells;
}

double depth_at(const std::vector<std::pair<std::uint64_t, double>>& grid, std::uint64_t key) {
  const auto it =
      std::lower_bound(grid.begin(), grid.end(), std::make_pair(key, -std::numeric_limits<double>::infinity()));
  return it != grid.end() && it->first == key ? it->second : std::numeric_limits<double>::quiet_NaN();
}

// Whether the ray d (from the eye) reaches a scan sample beyond `margin` past its end in its own cell, and in every
// occupied cell about it.
bool seen_beyond(const View& v, const std::vector<std::pair<std::uint64_t, double>>& grid, const Eigen::Vector3d& d,
                 double margin) {
  std::int64_t i = 0, j = 0;
  if (!cell_of(v, d, i, j) || std::isnan(depth_at(grid, cell_key(i, j)))) return false;
  double nearest = std::numeric_limits<double>::infinity();
  for (std::int64_t di = -1; di <= 1; ++di)
    for (std::int64_t dj = -1; dj <= 1; ++dj) {
      const double depth = depth_at(grid, cell_key(i + di, j + dj));
      if (!std::isnan(depth)) nearest = std::min(nearest, depth);
    }
  return d.norm() + margin < nearest;
}

}  // namespace

std::vector<std::uint8_t> seen_through(const PointSet& scan, const Similarity& scan_to_targets,
                                       const Eigen::Vector3d& eye, const PointSet& targets, double spacing) {
  std::vector<std::uint8_t> out(size_t(targets.size()), 0);
  if (scan.size() == 0 || targets.size() == 0) return out;
  const Eigen::Vector3d eye_there = scan_to_targets.apply(eye);
  if (within_box_of(targets.positions(), eye_there)) return out;
  Eigen::Matrix3Xd P(3, scan.size());
  for (Index k = 0; k < scan.size(); ++k) P.col(k) = scan_to_targets.apply(scan.positions().col(k));
  const std::optional<View> view = view_of(P, eye_there, spacing);
  if (!view) return out;
  const auto grid = depth_grid(*view, P);
  const Eigen::Matrix3Xd& T = targets.positions();
  for (Index t = 0; t < targets.size(); ++t) {
    const Eigen::Vector3d d = T.col(t) - eye_there;
    const bool facing = !targets.has_normals() || targets.normals().col(t).dot(d) < 0;
    out[size_t(t)] = facing && seen_beyond(*view, grid, d, kMargin * spacing);
  }
  return out;
}

}  // namespace scanfill
