#include "nodes/symmetry/face_repeat.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "nodes/core/kdtree.h"

namespace scanfill {

namespace {

// Whether `x` (normal n) lands on the exemplar: its nearest sample lies within 1.5 alpha, faces within 25 degrees of
// n, and has x within half an alpha of its plane.
bool lands_on(const PointSet& exemplar, const KdTree& tree, const Eigen::Vector3d& x, const Eigen::Vector3d& n,
              double spacing) {
  std::int32_t j;
  double d2;
  if (tree.knn(x, 1, &j, &d2) < 1 || d2 > std::pow(1.5 * spacing, 2)) return false;
  const Eigen::Vector3d m = exemplar.normals().col(j);
  return m.dot(n) >= std::cos(25 * M_PI / 180) && std::abs(m.dot(x - exemplar.positions().col(j))) <= 0.5 * spacing;
}

// Per shift (every half alpha from one alpha on), the share of `near` that lands on the exemplar, among those whose
// shifted position stays within their extent along `direction`; and how many those were at the shortest shift.
std::vector<double> landing_shares(const PointSet& exemplar, const KdTree& tree, const std::vector<std::int32_t>& near,
                                   const Eigen::Vector3d& direction, double spacing, double max_shift, Index& counted) {
  double hi = -std::numeric_limits<double>::infinity();  // the shifts go along `direction`: only this end bounds
  for (const std::int32_t i : near) hi = std::max(hi, direction.dot(exemplar.positions().col(i)));
  const double step = 0.5 * spacing;
  std::vector<double> share;
  counted = 0;
  for (double s = spacing; s <= max_shift; s += step) {
    Index count = 0, landed = 0;
    for (const std::int32_t i : near) {
      const Eigen::Vector3d x = exemplar.positions().col(i) + s * direction;
      if (direction.dot(x) > hi) continue;
      ++count;
      landed += lands_on(exemplar, tree, x, exemplar.normals().col(i), spacing);
    }
    if (share.empty()) counted = count;
    share.push_back(count > 0 ? double(landed) / double(count) : 0.0);
  }
  return share;
}

// Where the peak at k lies between the steps: the centroid of the shares above a tenth under it, over the run of steps
// around k that stay above (a sampled relief lands within reach of itself over a plateau of shifts, not at one).
double peak_centre(const std::vector<double>& share, size_t k) {
  const double base = share[k] - 0.1;
  size_t lo = k, hi = k;
  while (lo > 0 && share[lo - 1] > base) --lo;
  while (hi + 1 < share.size() && share[hi + 1] > base) ++hi;
  double sum = 0, weight = 0;
  for (size_t i = lo; i <= hi; ++i) {
    sum += double(i) * (share[i] - base);
    weight += share[i] - base;
  }
  return sum / weight;
}

}  // namespace

std::optional<FaceRepeat> repeat_along(const PointSet& exemplar, const KdTree& tree,
                                       const std::vector<std::int32_t>& near, const Eigen::Vector3d& direction,
                                       double spacing, double max_shift) {
  constexpr Index kMinSamples = 30;
  constexpr double kPlain = 0.95, kFits = 0.6, kDip = 0.25;
  Index counted = 0;
  const std::vector<double> share = landing_shares(exemplar, tree, near, direction, spacing, max_shift, counted);
  if (share.size() < 3 || counted < kMinSamples) return std::nullopt;
  if (*std::min_element(share.begin(), share.end()) >= kPlain) return FaceRepeat{0.0};
  // The first peak that fits, past a dip: the shares fall as the relief slides off itself and rise where it lands
  // on its next repeat.
  double lowest = share[0];
  for (size_t k = 1; k + 1 < share.size(); ++k) {
    lowest = std::min(lowest, share[k]);
    const bool peak = share[k] >= share[k - 1] && share[k] >= share[k + 1];
    if (!peak || share[k] < kFits || share[k] - lowest < kDip) continue;
    return FaceRepeat{spacing + peak_centre(share, k) * 0.5 * spacing};
  }
  return std::nullopt;
}

}  // namespace scanfill
