#include "nodes/symmetry/plain_faces.h"

#include <algorithm>
#include <cmath>

#include "nodes/core/kdtree.h"

namespace scanfill {

namespace {

const double kFacesAlong = std::cos(30 * M_PI / 180);  // a template sample faces along an axis
const double kFacesAlike = std::cos(20 * M_PI / 180);  // a scan sample faces its nearest template sample's way
constexpr double kPlainDistance = 0.5;                 // alpha off that sample's plane
constexpr double kSeenShare = 0.02;                    // of the tallied samples, for an axis to count as seen
constexpr Index kSeenMin = 30;
constexpr double kPlainMin = 0.4;        // the plainest axis' plain share, at least
constexpr double kMargin = 0.25;         // over every other seen axis' share
constexpr double kRaisedDistance = 1.5;  // alpha off that sample's plane, facing its way: relief, above scan noise
constexpr double kRaisedMax = 0.05;      // the plainest axis' raised share, under
constexpr double kSideShare = 0.1;       // of the tallied samples, facing along each side's axis seen from around

// The index of the axis `normal` faces along, or -1.
int axis_faced(const Eigen::Vector3d& normal, const std::vector<SymmetryAxis>& axes) {
  int best = -1;
  double best_cos = kFacesAlong;
  for (size_t a = 0; a < axes.size(); ++a) {
    const double c = std::abs(normal.dot(axes[a].direction));
    if (c > best_cos) best = int(a), best_cos = c;
  }
  return best;
}

// `d` signed so that its largest coordinate is positive.
Eigen::Vector3d canonical_sign(const Eigen::Vector3d& d) {
  Eigen::Index largest;
  d.cwiseAbs().maxCoeff(&largest);
  return d[largest] < 0 ? Eigen::Vector3d(-d) : d;
}

// The share of an axis' near samples that `count` of them are.
double share_of(Index count, const FaceTally& t) {
  return t.near > 0 ? double(count) / double(t.near) : 0.0;
}

double plain_share(const FaceTally& t) {
  return share_of(t.plain, t);
}

Index tallied_samples(const std::vector<FaceTally>& tallies) {
  Index tallied = 0;
  for (const FaceTally& t : tallies) tallied += t.near;
  return tallied;
}

// The axes the scan sees: at least `share` of the tallied samples (and kSeenMin) face along them.
std::vector<size_t> axes_seen(const std::vector<FaceTally>& tallies, double share) {
  const Index least = std::max<Index>(kSeenMin, Index(std::ceil(share * double(tallied_samples(tallies)))));
  std::vector<size_t> seen;
  for (size_t a = 0; a < tallies.size(); ++a)
    if (tallies[a].facing >= least) seen.push_back(a);
  return seen;
}

}  // namespace

std::vector<FaceTally> plain_face_tallies(const PointSet& exemplar, const Similarity& exemplar_to_target,
                                          const PointSet& target, const std::vector<SymmetryAxis>& axes,
                                          double spacing) {
  std::vector<FaceTally> tallies(axes.size());
  if (!exemplar.has_normals() || !target.has_normals() || target.empty()) return tallies;
  KdTree tree;
  tree.build(target.positions());
  for (Index i = 0; i < exemplar.size(); ++i) {
    const Eigen::Vector3d p = exemplar_to_target.apply(exemplar.positions().col(i));
    std::int32_t j;
    double d2;
    if (tree.knn(p, 1, &j, &d2) < 1) continue;
    const Eigen::Vector3d m = target.normals().col(j);
    const Eigen::Vector3d n = exemplar_to_target.apply_normal(exemplar.normals().col(i));
    const int a = axis_faced(m, axes);
    if (a < 0) continue;
    ++tallies[a].near;
    tallies[a].facing += std::abs(n.dot(axes[a].direction)) >= kFacesAlong;
    const bool alike = std::abs(n.dot(m)) >= kFacesAlike;
    const double off_plane = std::abs(m.dot(p - target.positions().col(j)));
    tallies[a].plain += alike && off_plane <= kPlainDistance * spacing;
    tallies[a].raised += alike && off_plane > kRaisedDistance * spacing;
  }
  return tallies;
}

std::optional<Eigen::Vector3d> plainest_face_axis(const PointSet& exemplar, const Similarity& exemplar_to_target,
                                                  const PointSet& target, const std::vector<SymmetryAxis>& axes,
                                                  double spacing) {
  return plainest_face_axis(plain_face_tallies(exemplar, exemplar_to_target, target, axes, spacing), axes);
}

std::optional<Eigen::Vector3d> plainest_face_axis(const std::vector<FaceTally>& tallies,
                                                  const std::vector<SymmetryAxis>& axes) {
  std::vector<size_t> seen = axes_seen(tallies, kSeenShare);
  if (seen.size() < 2) return std::nullopt;
  const auto plainer = [&](size_t a, size_t b) { return plain_share(tallies[a]) > plain_share(tallies[b]); };
  std::stable_sort(seen.begin(), seen.end(), plainer);
  const double best = plain_share(tallies[seen[0]]);
  if (best < kPlainMin || best < plain_share(tallies[seen[1]]) + kMargin) return std::nullopt;
  if (share_of(tallies[seen[0]].raised, tallies[seen[0]]) >= kRaisedMax) return std::nullopt;
  return canonical_sign(axes[seen[0]].direction.normalized());
}

std::optional<Eigen::Vector3d> unseen_face_axis(const std::vector<FaceTally>& tallies,
                                                const std::vector<SymmetryAxis>& axes) {
  if (tallies.size() != 3 || axes.size() != 3) return std::nullopt;
  const std::vector<size_t> sides = axes_seen(tallies, kSideShare);
  if (sides.size() != 2 || axes_seen(tallies, kSeenShare).size() != 2) return std::nullopt;
  const size_t unseen = 3 - sides[0] - sides[1];
  return canonical_sign(axes[unseen].direction.normalized());
}

}  // namespace scanfill
