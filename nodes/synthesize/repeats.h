// The exemplar's own repeats about an axis (DESIGN section 9): the turns under which its detail maps onto itself.
//
// On a body of revolution the template fixes no phase, and the refinement fits each image's phase to the images
// placed so far, where they overlap. That overlap can be small or seen at a grazing angle, and detail of two periods
// (a vase's 12 flutes above its ring of 16 beads) has no one phase that suits both. The exemplar itself says which
// turns are right: turned by 30 degrees its flutes land on its flutes, by 22.5 degrees its beads on its beads, over
// most of what it saw. So the exemplar's samples, sorted by height along the axis, are turned by every step up to
// `max_turn` and scored against the exemplar (point-to-plane, pairs within the limit); a band of heights repeats with
// order n when its misfit has a deep minimum (at most a quarter of its median over the turns, both measured above what
// the scan's noise leaves at a perfect repeat) near 360 / n degrees, the first one past the start. At most one cut
// across the axis splits two bands of different orders.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <vector>

#include "nodes/core/point_set.h"
#include "nodes/core/similarity.h"

namespace scanfill {

class KdTree;

// An axis, and the part of space about it that turns (a table's leg): within `radius` of it, between heights `low` and
// `high` along it (from `point`). Unbounded by default: the whole shape.
struct TurningPart {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction = Eigen::Vector3d::UnitZ();  // unit
  double radius = std::numeric_limits<double>::infinity();
  double low = -std::numeric_limits<double>::infinity(), high = std::numeric_limits<double>::infinity();

  bool contains(const Eigen::Vector3d& p) const {
    const Eigen::Vector3d x = p - point;
    const double h = direction.dot(x);
    return h >= low && h <= high && (x - direction * h).squaredNorm() <= radius * radius;
  }
};

// The part about the axis through `point` along `direction` that holds `samples` (columns of `positions`): their
// largest distance from the axis and their range of heights along it, `margin` wider each way.
TurningPart part_holding(const Eigen::Vector3d& point, const Eigen::Vector3d& direction,
                         const Eigen::Matrix3Xd& positions, const std::vector<std::int32_t>& samples, double margin);

constexpr int kRevolutionTurns = 8;  // a body of revolution fills with its turns by multiples of 45 degrees

struct AxialRepeats {
  TurningPart part;                // the axis (point, direction) and the exemplar's part that turns about it
  double cut = 0;                  // height along the axis (from point) between the two bands
  std::array<int, 2> order{0, 0};  // per band (below, above the cut): n-fold, 0 = no repeat
  bool continuous = false;         // the part is a body of revolution: every turn tried fits (orders 0, one band)
  double radius = 0;               // the part's RMS distance from the axis
};

// The repeats of the exemplar's samples in `part` (positions ep, normals en) about its axis, against the whole
// exemplar. `spacing` is alpha; pairs count within `limit` (model units). None when no band repeats and the part is
// not a body of revolution (at least 5 turns scored, each with a mean misfit under a quarter alpha squared).
// Deterministic.
std::optional<AxialRepeats> axial_repeats(const Eigen::Matrix3Xd& ep, const Eigen::Matrix3Xd& en,
                                          const TurningPart& part, double spacing, double limit);

// Whether the exemplar, carried into the template's frame by `to_template`, repeats about the axis through `point`
// along `direction` (unit): axial_repeats finds a band of some order n, and the exemplar is no body of revolution
// about it. Where it does, synthesize turns every image to its repeats, whatever turn the labelling chose. False for an
// exemplar without normals.
bool repeats_about(const PointSet& exemplar, const Similarity& to_template, const Eigen::Vector3d& point,
                   const Eigen::Vector3d& direction, double spacing, double limit);

// The turn by `angle` (radians, right-handed about the direction) about the axis.
Similarity turn_about(const AxialRepeats& r, double angle);

// Per exemplar sample (ep, en; `tree` holds ep), 1 where it repeats with its band's order n: for n of 8 or more, its
// image under a turn by 360 / n degrees one way or the other lies on the exemplar, within `limit` of a sample that
// faces within 25 degrees and within half an alpha (`spacing`) of its plane. The rest is detail that the scan shows
// once (a teapot's spout and handle), which the band's order does not turn: the teapot's facets repeat its body with
// orders 23 and 47. Turns of 90 degrees or more and bodies of revolution are not checked (one view seldom sees both a
// sample and its turned image): 1. 0 outside the part and in a band of order 0.
std::vector<std::uint8_t> repeating_samples(const KdTree& tree, const Eigen::Matrix3Xd& ep, const Eigen::Matrix3Xd& en,
                                            const AxialRepeats& r, double spacing, double limit);

// The band of a point: 0 below the cut, 1 at or above it.
inline int band_of(const AxialRepeats& r, const Eigen::Vector3d& p) {
  return r.part.direction.dot(p - r.part.point) >= r.cut ? 1 : 0;
}

// For an image q of the exemplar that turns it about the axis (a rotation about `direction` within 2 degrees that
// moves the axis' point by at most half an alpha), the correction c (applied after q) that turns the image to the
// nearest multiple of 360 / order degrees, if that moves the exemplar's points at its RMS radius at most `most`
// (model units). None otherwise, or for order 0.
std::optional<Similarity> turn_to_repeat(const AxialRepeats& r, int order, const Similarity& q, double most,
                                         double spacing);

// A plane about which the exemplar is its own mirror image: a lion's head, mirror-symmetric about the plane through
// the vase's axis and its face, which no turn about the axis maps onto itself.
struct MirrorPlane {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitX();  // unit
  double misfit = 0;                                  // median point-to-plane misfit of the mirrored pairs
  std::int64_t pairs = 0;                             // exemplar samples whose mirror image pairs with the exemplar
};

// The reflection across the plane: a similarity whose rotation has determinant -1.
Similarity reflection_across(const MirrorPlane& m);

// The plane through the part's axis about which the exemplar's relief in the part fits its own mirror image best.
// `tree` holds ep. Relief: the samples that a turn about the axis by 2 alpha of arc moves more than half an alpha off
// the exemplar (a plain body of revolution, its flat ends and a sphere fit every plane through the axis, and say
// nothing). Each at least 1.5 alpha off the plane, mirrored, pairs with its nearest exemplar sample within `limit`
// whose normal agrees with its mirrored normal (within 60 degrees), and the fit is the pairs' median point-to-plane
// misfit. Planes 3 degrees apart, each up to 2 alpha either side of the axis by half alphas; the six best basins are
// refined by point-to-plane ICP of the mirrored relief, free to tilt (the template's axis is the scan's only to a
// degree or two, and on the Vase-Lion a tilt of 1.5-2 degrees costs 0.2-0.4 alpha), and kept within 5 degrees of square
// to the axis and 3 alpha of its point. None unless at least 100 samples and a fifth of the relief pair and the fit is
// under 0.25 alpha (`spacing`), in quadrature with the median misfit the scan's noise leaves (the crate scanned with
// noise of 0.3% of its diagonal: its true plane fits to 2.3 mm, about a quarter alpha, and was refused). On the
// Vase-Lion the true plane fits to 0.07-0.17 alpha from five views and the other basins to 0.29 or more; a blob's
// planes drift off its axis. Deterministic.
std::optional<MirrorPlane> mirror_plane(const KdTree& tree, const Eigen::Matrix3Xd& ep, const Eigen::Matrix3Xd& en,
                                        const TurningPart& part, double spacing, double limit);

}  // namespace scanfill
