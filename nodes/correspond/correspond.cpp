#include "nodes/correspond/correspond.h"

#include <lemon/network_simplex.h>
#include <lemon/smart_graph.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <iomanip>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <utility>

#include "nodes/core/errors.h"
#include "nodes/core/icp.h"
#include "nodes/core/kdtree.h"
#include "nodes/core/surface_elements.h"
#include "nodes/correspond/correspond_options.h"
#include "nodes/correspond/deformation_node.h"
#include "nodes/correspond/deformation_solve.h"
#include "nodes/correspond/template_size.h"
#include "nodes/io/read_pp.h"
#include "nodes/procedural/normal_axis.h"
#include "nodes/sample/sample.h"
#include "nodes/symmetry/profile.h"
#include "nodes/symmetry/symmetry.h"

namespace scanfill {
namespace {

// Share of `points` within `limit` of the tree's points.
double share_within(const KdTree& tree, const Eigen::Matrix3Xd& points, double limit) {
  std::vector<std::int32_t> idx;
  std::vector<double> d2;
  nearest_each(tree, points, idx, d2);
  const auto close = std::count_if(d2.begin(), d2.end(), [&](double d) { return d <= limit * limit; });
  return double(close) / double(d2.size());
}

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  auto mid = v.begin() + std::ptrdiff_t(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

// Trimmed ICP of the exemplar samples onto the source: point-to-point for the first third of the steps (robust from
// a rough pose, pairs within rigid_trim x the median distance), point-to-plane after (fast convergence on smooth
// surfaces) on the pairs within rigid_fine_trim x the median. Where relief covers much of a scan, a mean over all pairs
// registers it off the template by the relief's mean height (1 cm on the crate fixture, whose sides are half covered
// by 2 cm of relief); rigid_fine_trim 1 keeps only the closer half, which fixes that scan but locks others onto their
// relief layer (the gear's teeth), so the default keeps the mean (3). Rigid: the inputs share a scale.
// Point-to-plane pairs whose normals agree within 60 degrees are trusted: the steps move only along the motions they
// constrain (icp.h). The others still count in the fit (a gear's tooth flanks against a plain rim), but cannot pull
// the scan along a motion only they decide: seen edge-on, its tooth roots pair with the faces of the template's
// annulus and drag it along the axis.
constexpr double kTrustedAgreement = 0.5;

Similarity rigid_icp(const PointSet& exemplar, const PointSet& source, const KdTree& tree, const CorrespondOptions& o,
                     double& rms) {
  const Eigen::Matrix3Xd& from = exemplar.positions();
  const bool oriented = exemplar.has_normals() && source.has_normals();
  const int coarse = source.has_normals() ? o.rigid_iterations / 3 : o.rigid_iterations;  // point-to-point steps
  std::vector<std::int32_t> idx;
  std::vector<double> d2;
  std::vector<Index> keep;
  const auto find_pairs = [&](const Similarity& q, int it, IcpPairs& pairs) {
    pairs.moved.resize(3, from.cols());
    for (Index i = 0; i < from.cols(); ++i) pairs.moved.col(i) = q.apply(from.col(i));
    nearest_each(tree, pairs.moved, idx, d2);
    const double trim = it >= coarse ? o.rigid_fine_trim : o.rigid_trim;
    const double limit = trim * trim * std::max(median(d2), 1e-300);
    keep.clear();
    pairs.trusted.clear();
    for (size_t i = 0; i < idx.size(); ++i) {
      if (d2[i] > limit) continue;
      const double agree =
          oriented ? q.apply_normal(exemplar.normals().col(Index(i))).dot(source.normals().col(idx[i])) : 1.0;
      if (agree < 0) continue;
      keep.push_back(Index(i));
      if (oriented && it >= coarse) pairs.trusted.push_back(agree >= kTrustedAgreement);
    }
    Eigen::Matrix3Xd a(3, Index(keep.size())), b(3, Index(keep.size())), n(3, Index(keep.size()));
    double sum = 0;
    for (size_t j = 0; j < keep.size(); ++j) {
      const Index i = keep[j];
      a.col(Index(j)) = pairs.moved.col(i);
      b.col(Index(j)) = source.positions().col(idx[size_t(i)]);
      if (source.has_normals()) n.col(Index(j)) = source.normals().col(idx[size_t(i)]);
      sum += d2[size_t(i)];
    }
    pairs.moved = std::move(a);
    pairs.to = std::move(b);
    pairs.normals = std::move(n);
    pairs.rms = keep.empty() ? 0.0 : std::sqrt(sum / double(keep.size()));
    if (keep.size() >= 7) rms = pairs.rms;
  };
  return icp(Similarity{}, find_pairs,
             {.iterations = o.rigid_iterations,
              .point_to_point_iterations = coarse,
              .min_pairs = 7,
              .converged_change = 1e-6});
}

// Moves below this many spacings and turns below this angle that put less of the scan on the template are the
// relief's pull, not a registration: relief pulls a scan along the normal of the ground it stands on, hardly turning it
// (the crate's front: 1.1 spacings, 0.05 degrees). Where at least kGrounded of the scan lies on the template as given
// (its ground does) and ICP's pose puts a tenth less on it (it took the ground off), the pull may reach
// the relief's thickness, and the turn move the scan's far end as much again.
constexpr double kReliefPull = 2.0;
constexpr double kReliefTurn = 0.5 * M_PI / 180;
constexpr double kGrounded = 1.0 / 3.0;
constexpr double kOffGround = 0.9;

// The farthest any of the points lies from their centroid.
double radius_about_centroid(const Eigen::Matrix3Xd& p) {
  if (p.cols() == 0) return 0;
  return (p.colwise() - p.rowwise().mean()).colwise().norm().maxCoeff();
}

// Where q lays the exemplar's samples against the source, as shares of them:
// - on: within half a spacing of the tangent plane of their nearest source sample (of the sample itself without
//   normals), and within two spacings of it;
// - outside, inside: more than a spacing outside the source along the outward normal of their nearest source sample,
//   or inside it (both zero without source normals).
struct Placement {
  double on = 0, outside = 0, inside = 0;
  double lesser_side() const { return std::min(outside, inside); }
};

Placement placement_on_source(const PointSet& exemplar, const PointSet& source, const KdTree& tree, const Similarity& q,
                              double spacing) {
  Eigen::Matrix3Xd moved(3, exemplar.size());
  for (Index i = 0; i < exemplar.size(); ++i) moved.col(i) = q.apply(exemplar.positions().col(i));
  std::vector<std::int32_t> idx;
  std::vector<double> d2;
  nearest_each(tree, moved, idx, d2);
  Index on = 0, outside = 0, inside = 0;
  for (Index i = 0; i < moved.cols(); ++i) {
    const Eigen::Vector3d d = moved.col(i) - source.positions().col(idx[size_t(i)]);
    const double height = source.has_normals() ? d.dot(source.normals().col(idx[size_t(i)])) : 0.0;
    outside += height > spacing;
    inside += height < -spacing;
    if (d2[size_t(i)] > 4 * spacing * spacing) continue;
    on += (source.has_normals() ? std::abs(height) : d.norm()) <= 0.5 * spacing;
  }
  const double n = double(std::max<Index>(1, moved.cols()));
  return {double(on) / n, double(outside) / n, double(inside) / n};
}

// Exemplar sample i moved by q, against its nearest source sample: where it lands, that sample's normal, its height
// over that sample's tangent plane, and the cosine between its own normal, moved, and that one. Both need normals.
struct AgainstNearest {
  Eigen::Vector3d point, normal;
  double height, agreement;
};

AgainstNearest against_nearest(const PointSet& exemplar, const PointSet& source, const KdTree& tree,
                               const Similarity& q, Index i) {
  const Eigen::Vector3d p = q.apply(exemplar.positions().col(i));
  std::int32_t s;
  double d2;
  tree.knn(p, 1, &s, &d2);
  const Eigen::Vector3d n = source.normals().col(s);
  return {p, n, n.dot(p - source.positions().col(s)), q.apply_normal(exemplar.normals().col(i)).dot(n)};
}

// The thickness of the exemplar's relief over the source as q lays it: the spread between the 5th and 95th percentiles
// of the samples' heights over the plane of their nearest source sample, where the two normals agree within 37 degrees
// (not an edge's other face). Registered between its relief and its ground, a scan's heights span both layers; a
// plain scan's, however far ICP moved it, hardly any. Zero without normals.
double relief_thickness(const PointSet& exemplar, const PointSet& source, const KdTree& tree, const Similarity& q) {
  if (!exemplar.has_normals() || !source.has_normals()) return 0;
  std::vector<double> heights;
  heights.reserve(size_t(exemplar.size()));
  for (Index i = 0; i < exemplar.size(); ++i) {
    const AgainstNearest a = against_nearest(exemplar, source, tree, q, i);
    if (std::abs(a.agreement) >= 0.8) heights.push_back(a.height);
  }
  if (heights.size() < 20) return 0;
  const auto at = [&](double f) {
    auto it = heights.begin() + std::ptrdiff_t(f * double(heights.size() - 1));
    std::nth_element(heights.begin(), it, heights.end());
    return *it;
  };
  return at(0.95) - at(0.05);  // each nth_element finds its own rank, whatever the order
}

// A template that bounds the scan as given, touching it and cutting through none of it, is the hull its relief is sunk
// in or the ground it stands on. ICP lays such a scan between its layers, and where that cuts the template through it
// (a tenth of it on each side), the relief has pulled it, however far: the scanned pillar, its faces' panels sunk up
// to 10 spacings inside its `box:`, was turned 1.6-17.7 degrees and moved 5-20 spacings by ICP, and every turned image
// of it landed twice that off the unseen faces (F 0.44-0.64; 0.61-0.72 in its own pose). A scan moved or turned off
// its template cuts through it as given, and ICP's pose stands. Seen level with its sides, the pillar touches its box
// only with the edges of its capital and base: 2.4-4.7% of the scan as given (5% was asked until stop 64), and ICP
// turned it 5-9 degrees and moved it 2.5 cm, a third of it outside the box (F 0.51-0.59; 0.72-0.75 in its own pose).
constexpr double kBoundsAsGiven = 0.02;  // at most this share on the far side as given
constexpr double kTouches = 0.02;        // at least this share on the template as given
constexpr double kCutThrough = 0.1;      // at least this share on each side in ICP's pose

bool cut_through_its_bounding_template(const Placement& as_given, const Placement& registered) {
  return as_given.lesser_side() <= kBoundsAsGiven && as_given.on >= kTouches && registered.lesser_side() >= kCutThrough;
}

// Whether ICP's pose is the relief's pull on a scan whose own pose is `own` (`as_given`: where it lays the scan on the
// template): it moves the scan by less than the relief's pull, turns it by less than the relief's turn (both above),
// and puts less of it on the template than `own` does. A scan whose relief covers much of what it saw has no pose that
// puts all of it on a plain template: ICP settles between the relief and the ground it stands on, off both, and every
// turned image of the scan then lands off the template by twice that (the crate seen square on its front: one face,
// half of it 2 cm of raised frame and diamond, registered 1.1 cm (1.1 spacings) off, its opposite face turned onto the
// template 2.1 cm inside it; 47% of the scan on the template as given, 15% as registered). A larger motion is a
// registration: the same scan moved 1.5 cm and 2 degrees off has 24% on the template, ICP's pose 16% (between
// layers; 2.0 spacings, 2.1 degrees), and ICP's is right. So a scan moved less than the relief's pull keeps its own
// pose, as a scanner's registered output or a virtual scan needs; a gear seen edge-on, tilted 1.9 degrees by its teeth,
// is still registered by ICP (`correspond.rigid: false` keeps a registered scan's pose whole). Relief deeper than that
// pulls further: a ribbed box seen from above, inside a `box:` template that touches its ribs' tops (2.2 cm, 2.4
// spacings, of relief on the two sides it sees), was slid 1.7 cm outwards by ICP, 39% of it on the template against 56%
// as given, and every turned image landed twice that off the unseen sides (F 0.742); registered between its layers, its
// heights span 2.7 spacings. And it turns further: the same box seen square on its long side from a little below,
// inside its 8-vertex template, was turned 0.83 degrees (2.2 spacings) by the ribs and plinth, 13% of it on the
// template against 60% as given (F 0.661). The moved crate above is not grounded (24% as given): its 2.1 degrees and 2
// cm lie within its relief's 2.1 cm, and only ICP's pose is right. The ribbed box seen from below in its `box:`, turned
// 0.84 degrees and moved 3.0 spacings at its far end by a relief 2.9 spacings thick, keeps its pose (F 0.630 -> 0.919).
// A scan its template bounds keeps its pose however far ICP moved it, where that pose cuts the template through it
// (cut_through_its_bounding_template): the scanned pillar, whose panels lie 10 spacings inside its `box:`, moved 5
// spacings and turned 1.8 degrees from above with 36% of it on the box either way.
bool relief_pulled_from(const PointSet& exemplar, const PointSet& source, const KdTree& tree, double spacing,
                        const Similarity& own, const Placement& as_given, const Similarity& icp_pose,
                        const Placement& registered) {
  if (cut_through_its_bounding_template(as_given, registered)) return true;
  const bool off_its_ground = as_given.on >= kGrounded && registered.on <= kOffGround * as_given.on;
  const double thickness = off_its_ground ? relief_thickness(exemplar, source, tree, icp_pose) : 0.0;
  const double pull = std::max(kReliefPull * spacing, thickness);
  const double turn = std::max(kReliefTurn, thickness / std::max(radius_about_centroid(exemplar.positions()), spacing));
  const Similarity motion = icp_pose.compose(own.inverse());
  Eigen::Matrix3Xd placed(3, exemplar.size());
  for (Index i = 0; i < exemplar.size(); ++i) placed.col(i) = own.apply(exemplar.positions().col(i));
  return rotation_angle(motion.rotation) <= turn && largest_displacement(placed, motion) <= pull + thickness &&
         as_given.on > registered.on;
}

// A round template runs through the middle of relief that stands both in and out of it (a gear's teeth about its
// plain disk), so a scan of it has no ground on it: the gear seen edge-on from (-0.99, 0.11, 0.06), its teeth 8.5
// spacings from tip to root, 28% of it on the disk as given (kGrounded asks a third), was moved 2.4 spacings and
// turned 0.94 degrees by ICP, 19% on (F 0.879; 0.988 as given). On a round template, ICP's move under kDeepPull of
// the relief's thickness, and a turn under what that thickness turns the scan, that take a fifth of it off the
// template (kTakenOff) are that relief's pull. The Vase-Lion's lion head, 12 cm of relief out of its body of
// revolution, lets ICP move its scan 3.9 cm, but with as much of it on the body (8.6% as given, 8.4%), and ICP's pose
// serves its images better there (F 0.653 against 0.615 in its own pose, from seed 6565's (0.58, -0.10, -0.81)). A
// box's relief sunk as deep does not count so: a pillar moved 1.5 cm and 2 degrees off its box, its panels 10 spacings
// deep, is registered by ICP (relief_pulled_from's moved crate and pillar). The cost: a scan of such relief given off
// its round template by less than half the relief's thickness keeps that offset.
constexpr double kDeepPull = 0.5;
constexpr double kTakenOff = 0.8;

bool pulled_by_relief_about_a_round_template(const PointSet& exemplar, const PointSet& source, const KdTree& tree,
                                             double spacing, const Placement& as_given, const Similarity& icp_pose,
                                             const Placement& registered) {
  if (registered.on >= kTakenOff * as_given.on) return false;
  const double depth = relief_thickness(exemplar, source, tree, icp_pose);
  const double radius = std::max(radius_about_centroid(exemplar.positions()), spacing);
  return rotation_angle(icp_pose.rotation) <= depth / radius &&
         largest_displacement(exemplar.positions(), icp_pose) <= kDeepPull * depth;
}

// A round template of another profile than the scan (a plain cylinder drawn about the real Vase-Lion, its body
// bulging and its neck narrow, 77-85% of the scan inside the cylinder as given): ICP balances the scan across the
// cylinder's wall, tilting its axis 14 degrees and moving it 7-19 cm, and every image turned about the template's axis
// then stands askew (F 0.37-0.60, under the scan alone's 0.57-0.64). A pose that tilts the template's axis beyond
// kTilted yet lays no more of the scan on the template than its own pose does (within kTiltGain), where half the
// template or more stands outside the scan's own radii about its axis as given (of_another_profile), is no
// registration: the scan keeps its own pose (F 0.49-0.68). Seen from below, ICP lays the vase's foot on the cylinder's
// floor (3.5% of it on as given, 32% registered), and its pose stands. On its own body of revolution, the Vase-Lion
// seen from below is tilted 7 degrees by ICP for under 1% more of it on, and its images serve better so (F 0.610;
// 0.573 in its own pose): that body lies on the scan's radii.
constexpr double kTilted = 3.0 * M_PI / 180;  // as onto_template_axis's kAxisTurn
constexpr double kTiltGain = 0.03;

bool tilted_off_a_round_template_for_nothing(const PointSet& exemplar, const PointSet& source, double spacing,
                                             const Placement& as_given, const Similarity& icp_pose,
                                             const Placement& registered, const RevolutionAxis& axis) {
  if (as_given.on < kTouches || registered.on >= as_given.on + kTiltGain) return false;
  const RadialProfile own =
      radial_profile(exemplar, Similarity{}, SymmetryAxis{axis.centre, axis.direction, 0}, spacing);
  if (!of_another_profile(own, source, spacing)) return false;
  const double tilt =
      std::acos(std::clamp(std::abs((icp_pose.rotation * axis.direction).dot(axis.direction)), 0.0, 1.0));
  return tilt > kTilted;
}

// A template drawn at another size than the scan (template_size.h): ICP moved the scan over a spacing; the template
// scaled (about its centroid, or an end that stays) lays as much of the scan in its own pose on itself as ICP's pose
// lays on it unscaled (within kAsMuchOn), a third of the scan at least (kGrounded), with the scaling moving some of
// the template kAnotherSize spacings; and ICP on the scaled template moves the scan at most half as far as ICP's move
// (kHeldShare; it may slide the scan along a face it sees, as relief pulls it). A studded box in a box 8% narrower: ICP
// moved the scan 2.9-4.0 spacings onto the template's faces it sees, 75-81% of it on; scaled 1.1 across, the template
// lays 81-91% of it on itself as given, and ICP on it moves it 0.1-1.3 spacings. The scanned pillar moved 1.5 cm and
// turned 2 degrees off its `box:` (its relief sunk up to 10 spacings inside it) is laid on as much by the box shrunk
// (36% against ICP's 27%), but ICP moves it 4.2 spacings and turns it 3.4 degrees on its box, and 5.7 and 3.4 on the
// shrunk box: a pose, not a size. The 86 runs of the sweep's named views, whose scans are given in their models'
// frames, have no scaling that lays a third on where ICP moved the scan a spacing. The same box 10% wider and 5%
// taller, its floor 4.5 cm below the box's, seen from below: ICP laid the scan on the floor and the two sides it sees
// (4.5 cm down, 3 cm out), 92.3% of it on; scaled about its centroid, the template lays the floor or the sides' tops
// on, not both (89.4%); scaled about its top, it lays 91.9% on, and ICP on it moves the scan 0.26 spacings, where ICP's
// move was 5.9. Seen from above, that box's floor is unseen and scaling lays no more of the scan on where it moves it;
// but the scan's sides end at the box's floor, and a size once told is trimmed to what the scan saw
// (trimmed_to_the_seen): scaled 0.95 about its top, the template's floor lands on the box's (seed 6969's eyes 12-67
// degrees above level: F 0.738-0.902 -> 0.977-0.997). A template drawn too short at one end (a box 8% shorter
// standing on the studded box's floor) lays the scan's faces on its own, so ICP moves the scan under a spacing (or
// only as its relief pulls it, and the scan keeps its own pose), and the scan runs 7 cm on past the template's top.
// Where the scan's pose moves it under a spacing, a size is searched for from one end only (scaling_at_one_end: along
// an axis of a spread of its own, outwards about either end, where the scan runs past the other), and only then
// refined across; ICP on the scaled template may move the scan half of ICP's own move on the template as drawn, or
// half a spacing, or, where the scan keeps its own pose against its relief, as far as that relief pulls it on the
// scaled template (keeps_its_pose_against_relief); and the size is not trimmed (a relief standing flat out of a face,
// the crate's frames, leaves the template under it uncovered, and the trim raised a crate's template floor 5 cm off
// its floor). The studded box from the front: 1.09 up about its floor (F 0.879 ->
// 0.992); the crate from above, its frames pulling ICP 7.7 spacings: 1.09 (F 0.713 -> 0.988). A plain disk under a
// gear's teeth has no axis of its own but its thickness, which the teeth share: not a size.
constexpr double kAnotherSize = 1.5;
constexpr double kAsMuchOn = 0.01;  // of the scan: laid on "as much" within a hundredth
constexpr double kHeldShare = 0.5;  // ICP on the scaled template moves the scan at most this share of ICP's move
constexpr Index kSizeStride = 4;    // every this-many-th scan sample is asked (a scaling is a global fit)

// The direction towards the sensor of a scan seen from one side: its mean normal, where that is at least kOneSided
// long (a scan's points are dense in proportion to the area it sees square on, so its mean normal leans towards the
// sensor; fragments seen from around cancel out).
constexpr double kOneSided = 0.3;

std::optional<Eigen::Vector3d> towards_sensor(const PointSet& exemplar) {
  if (!exemplar.has_normals() || exemplar.size() == 0) return std::nullopt;
  const Eigen::Vector3d mean = exemplar.normals().rowwise().mean();
  if (mean.norm() < kOneSided) return std::nullopt;
  return mean.normalized();
}

// Whether the scan in its own pose is held on `source` but for its relief's pull: ICP's pose there (`icp_pose`) is
// that pull (relief_pulled_from).
bool keeps_its_pose_against_relief(const PointSet& exemplar, const PointSet& source, const KdTree& tree, double spacing,
                                   const Similarity& icp_pose) {
  const Placement as_given = placement_on_source(exemplar, source, tree, Similarity{}, spacing);
  const Placement registered = placement_on_source(exemplar, source, tree, icp_pose, spacing);
  return relief_pulled_from(exemplar, source, tree, spacing, Similarity{}, as_given, icp_pose, registered);
}

std::optional<TemplateScaling> drawn_at_another_size(const PointSet& exemplar, const PointSet& source,
                                                     const KdTree& tree, double spacing, const Similarity& pose,
                                                     double icp_move, const CorrespondOptions& o) {
  if (!source.has_normals()) return std::nullopt;
  const Index n = (exemplar.size() + kSizeStride - 1) / kSizeStride;
  Eigen::Matrix3Xd own(3, n), moved(3, n);
  for (Index i = 0; i < n; ++i) {
    own.col(i) = exemplar.positions().col(i * kSizeStride);
    moved.col(i) = pose.apply(own.col(i));
  }
  double scaled_on = 0;
  const bool hardly_moved = largest_displacement(exemplar.positions(), pose) <= spacing;
  const TemplateScaling scaling = hardly_moved ? scaling_at_one_end(own, source, tree, spacing, scaled_on)
                                               : scaling_that_fits(own, source, tree, spacing, scaled_on);
  const double registered_on = share_on_scaled(moved, source, tree, TemplateScaling{}, spacing);
  if (scaled_on < kGrounded || scaled_on < registered_on - kAsMuchOn ||
      largest_scaling_move(source, scaling) < kAnotherSize * spacing)
    return std::nullopt;
  const PointSet scaled = scaled_source(source, scaling);
  KdTree scaled_tree;
  scaled_tree.build(scaled.positions());
  double rms = 0;
  const Similarity held = rigid_icp(exemplar, scaled, scaled_tree, o, rms);
  if (largest_displacement(exemplar.positions(), held) > kHeldShare * std::max(icp_move, spacing) &&
      !(hardly_moved && icp_move > spacing &&
        keeps_its_pose_against_relief(exemplar, scaled, scaled_tree, spacing, held)))
    return std::nullopt;
  const auto sensor = towards_sensor(exemplar);
  return sensor && !hardly_moved ? trimmed_to_the_seen(own, *sensor, source, tree, spacing, scaling) : scaling;
}

std::string another_size_warning(const TemplateScaling& s, bool stands_in) {
  std::ostringstream w;
  w << std::fixed << std::setprecision(2) << "the template looks drawn at another size than the scan: scaled by "
    << s.scale[0] << " x " << s.scale[1] << " x " << s.scale[2] << " along its principal axes about its centroid";
  if (s.shift.norm() > 0) w << std::setprecision(4) << " and shifted by " << s.shift.norm();
  w << ", it lays as much of the scan in the scan's own pose on itself as the rigid registration's move does "
       "unscaled; the scan keeps its own pose, and "
    << (stands_in ? "the template so scaled stands in for it" : "a template at the scan's size serves best");
  return w.str();
}

// A template is a body of revolution where its normals meet an axis this nearly (normal_axis_misfit: 0 on a cylinder,
// about 0.7 for normals that ignore it).
constexpr double kRoundTemplate = 0.1;

// A template that bounds the scan in its own pose (as cut_through_its_bounding_template), where ICP's pose puts a
// twentieth of the scan on that far side: the relief has pushed the scan through it, or cut it through. One side's
// rib tops are about that share of a sparse scan of the ribbed box from above (its 160 by 160 scan: 8%, where ICP slid
// it 2 cm off its box), whose lid, facing the sensor, holds most of its points.
constexpr double kPushedThrough = 0.05;

bool pushed_through_its_bounding_template(const Placement& own, const Placement& registered) {
  if (own.on < kTouches) return false;
  return (own.outside <= kBoundsAsGiven && registered.outside >= kPushedThrough) ||
         (own.inside <= kBoundsAsGiven && registered.inside >= kPushedThrough);
}

// The layer's half-width (Gaussian sigma) in spacings, and the most steps that turn the scan flat on it.
constexpr double kLayerWidth = 0.5;
constexpr int kLayerSteps = 10;
constexpr double kConstrained = 0.02;  // of the largest eigenvalue: a motion the pairs constrain

// The least-squares solution of A x = b (A symmetric, positive semi-definite) along the eigenvectors of A whose
// eigenvalues are at least kConstrained of its largest; zero along the others.
Eigen::Vector3d solved_where_constrained(const Eigen::Matrix3d& A, const Eigen::Vector3d& b) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(A);
  const double largest = eig.eigenvalues().maxCoeff();
  Eigen::Vector3d x = Eigen::Vector3d::Zero();
  for (int k = 0; k < 3 && largest > 0; ++k)
    if (eig.eigenvalues()(k) >= kConstrained * largest)
      x += eig.eigenvectors().col(k) * (eig.eigenvectors().col(k).dot(b) / eig.eigenvalues()(k));
  return x;
}

// The turn about `centre` that lays the layer of the scan `pose` puts on the template (its samples within about
// kLayerWidth spacings of it, by a Gaussian weight) flat on it, from `pose`'s: linearised point-to-plane steps on the
// pairs whose normals agree (kTrustedAgreement), along the turns they constrain. ICP's turn is the relief's as well
// as the template's: the ribbed box from the front, in its box drawn turned 5 degrees, was turned 4.45.
Similarity turned_flat_on_its_layer(const PointSet& exemplar, const PointSet& source, const KdTree& tree,
                                    const Eigen::Vector3d& centre, Similarity pose, double spacing) {
  if (!exemplar.has_normals() || !source.has_normals()) return pose;
  const double width2 = std::pow(kLayerWidth * spacing, 2);
  for (int step = 0; step < kLayerSteps; ++step) {
    Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
    Eigen::Vector3d b = Eigen::Vector3d::Zero();
    for (Index i = 0; i < exemplar.size(); ++i) {
      const AgainstNearest on = against_nearest(exemplar, source, tree, pose, i);
      if (on.agreement < kTrustedAgreement) continue;
      const double w = std::exp(-0.5 * on.height * on.height / width2);
      const Eigen::Vector3d a = (on.point - centre).cross(on.normal);
      A += w * a * a.transpose();
      b -= w * on.height * a;
    }
    const Eigen::Vector3d turn = solved_where_constrained(A, b);
    const Eigen::Matrix3d R = turn.norm() > 0 ? Eigen::AngleAxisd(turn.norm(), turn.normalized()).toRotationMatrix()
                                              : Eigen::Matrix3d::Identity();
    pose = Similarity{R, centre - R * centre, 1.0}.compose(pose);
    if (turn.norm() < 1e-6) break;
  }
  return pose;
}

// Within this many spacings, the scan spans as much of a direction as the template does: it sees both ends.
constexpr double kSameSpan = 2.0;

// The span of `points` moved by `pose` along the axis, as offsets from its centre: (lowest, highest).
std::pair<double, double> span_along(const Eigen::Matrix3Xd& points, const Similarity& pose,
                                     const RevolutionAxis& axis) {
  double low = std::numeric_limits<double>::infinity(), high = -low;
  for (Index i = 0; i < points.cols(); ++i) {
    const double h = axis.direction.dot(pose.apply(points.col(i)) - axis.centre);
    low = std::min(low, h);
    high = std::max(high, h);
  }
  return {low, high};
}

// `pose` moved along the axis until the scan's span along it is centred on the template's, where the two spans are
// the same length (kSameSpan): the scan sees both ends; else `pose`. Along a direction no face pins (a round
// template's axis, the common edge of a face and its lid), ICP's place is what the ends make of it: the procedural
// vase in a closed cylinder of its height stood 3.4 cm (3 spacings) up, and the cylinder's copied wall and cap stood
// out below its foot.
Similarity centred_along(const PointSet& exemplar, const PointSet& source, const Similarity& pose,
                         const RevolutionAxis& axis, double spacing) {
  const auto [scan_low, scan_high] = span_along(exemplar.positions(), pose, axis);
  const auto [low, high] = span_along(source.positions(), Similarity{}, axis);
  if (std::abs((scan_high - scan_low) - (high - low)) > kSameSpan * spacing) return pose;
  const Eigen::Vector3d shift = 0.5 * ((low + high) - (scan_low + scan_high)) * axis.direction;
  return Similarity{Eigen::Matrix3d::Identity(), shift, 1.0}.compose(pose);
}

// `pose` centred along each direction that no face of the scan pins against the template (a face and its lid seen
// from the front slide along their common edge; ICP's place along it is its start's). The ribbed box from the front,
// in its box drawn turned 5 degrees and 1.5 cm along its length, lands within a millimetre of it.
Similarity centred_where_unpinned(const PointSet& exemplar, const PointSet& source, const KdTree& tree, Similarity pose,
                                  double spacing) {
  if (!exemplar.has_normals() || !source.has_normals()) return pose;
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  for (Index i = 0; i < exemplar.size(); ++i) {
    const AgainstNearest on = against_nearest(exemplar, source, tree, pose, i);
    if (on.agreement >= kTrustedAgreement) A += on.normal * on.normal.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(A);
  const double largest = eig.eigenvalues().maxCoeff();
  for (int k = 0; k < 3 && largest > 0; ++k) {
    if (eig.eigenvalues()(k) >= kConstrained * largest) continue;
    pose = centred_along(exemplar, source, pose, {Eigen::Vector3d::Zero(), eig.eigenvectors().col(k)}, spacing);
  }
  return pose;
}

// ICP's turn made about the template's centroid: the scan as given, turned in place, then turned flat on the layer
// that pose lays on the template and centred where no face pins it. A template drawn a little turned about its own
// centre (a user's box, 5 degrees about the vertical) turns the scan, and ICP's turn is nearly right; but its move is
// the relief's pull as above, and ICP turns about the scan's centroid, so a scan that sees one face and its lid also
// slides along their common edge: the ribbed box from the front, its long side's ribs 2.2 cm proud, was registered 2.0
// cm off (the box's own 5 degrees about its centre moves nothing), and every turned image landed twice that off the
// unseen sides (F 0.54 from the front, 0.52 from the side; 0.95 and 0.97 turned in place).
Similarity turned_in_place(const PointSet& exemplar, const PointSet& source, const KdTree& tree,
                           const Similarity& icp_pose, double spacing) {
  const Eigen::Vector3d centre = source.positions().rowwise().mean();
  const Similarity in_place{icp_pose.rotation, centre - icp_pose.rotation * centre, 1.0};
  return centred_where_unpinned(exemplar, source, tree,
                                turned_flat_on_its_layer(exemplar, source, tree, centre, in_place, spacing), spacing);
}

// A turn about the axis that is no rotational symmetry of a polygon of up to 24 sides (a 24-gon's facets are 15
// degrees apart), and the share of the template's samples it must leave on the template. It is within a degree of a
// 10- and a 20-gon's (36 degrees), which may lie on themselves nearly enough to count as round. It decides only
// whether ICP's turn about the axis is taken out (registration_or_input_pose); whether the template is a polygon is
// asked of round templates too (template_axis).
constexpr double kSymmetryProbe = 37.0 * M_PI / 180;
constexpr double kOnItself = 0.9;

// Whether the template, turned about its axis, lies on itself: a body of revolution, or a polygon of so many sides
// that a facet's sagitta is under half a spacing. Normals meeting an axis do not show it: a sphere with bumps has
// them, and its bumps pin every turn.
bool turned_onto_itself(const PointSet& source, const KdTree& tree, const RevolutionAxis& axis, double spacing) {
  const Eigen::Matrix3d R = Eigen::AngleAxisd(kSymmetryProbe, axis.direction).toRotationMatrix();
  const double on = placement_on_source(source, source, tree, {R, axis.centre - R * axis.centre, 1.0}, spacing).on;
  return on >= kOnItself;
}

// A low-poly drawing of a body of revolution has this many sides at least (a pentagon; a box's four are its own
// shape), and at most this many are told apart from a circle.
constexpr int kFewestSides = 5;
constexpr int kMostSides = 32;

// Samples whose normals lean from the axis by at least this sine lie on a wall, not a cap.
constexpr double kWall = 0.5;

// Two unit vectors across the axis, at right angles: a frame of the plane across it.
std::pair<Eigen::Vector3d, Eigen::Vector3d> plane_across(const Eigen::Vector3d& axis) {
  const Eigen::Vector3d e1 = axis.unitOrthogonal();
  return {e1, axis.cross(e1)};
}

// The part of v across the axis (a unit direction).
Eigen::Vector3d across_axis(const Eigen::Vector3d& v, const Eigen::Vector3d& axis) {
  return v - v.dot(axis) * axis;
}

// Each turn is tried on this many of the template's wall samples, evenly spread: a turn slides a cap on itself.
constexpr Index kSideProbes = 2000;
// A turn lays the template on itself where its samples land, on average, within this share of a spacing of its
// surface (a hexagon, an octagon and a 12-gon sampled at 20000: 0.02-0.03 by their own turns). A turn near its own
// lays a polygon nearly as well (a 12-gon turned by 2 pi / 13: 0.13), so its own turn is the one that lays it best,
// and of those within kOwnTurn of that (a 12-gon's 6-fold turn is one too), the smallest.
constexpr double kLaysOnItself = 0.1;
constexpr double kOwnTurn = 0.05;
// The facets' normals agree on one phase of the polygon this well (the length of the mean of their angles times the
// sides, as unit vectors: 1 for a regular polygon's flat facets).
constexpr double kRegularFacets = 0.5;

// The template's samples `probe` turned by `angle` about the axis: their mean distance from the template's surface
// (the tangent plane of the nearest sample), each at most two spacings.
double mean_distance_turned(const PointSet& probe, const PointSet& source, const KdTree& tree,
                            const RevolutionAxis& axis, double angle, double spacing) {
  const Eigen::Matrix3d R = Eigen::AngleAxisd(angle, axis.direction).toRotationMatrix();
  const Similarity q{R, axis.centre - R * axis.centre, 1.0};
  double sum = 0;
  for (Index i = 0; i < probe.size(); ++i) {
    const Eigen::Vector3d p = q.apply(probe.positions().col(i));
    std::int32_t s;
    double d2;
    tree.knn(p, 1, &s, &d2);
    const double height = std::abs(source.normals().col(s).dot(p - source.positions().col(s)));
    sum += d2 > 4 * spacing * spacing ? 2 * spacing : std::min(height, 2 * spacing);
  }
  return sum / double(std::max<Index>(1, probe.size()));
}

// Up to kSideProbes of the template's wall samples (kWall), evenly spread.
PointSet wall_probes(const PointSet& source, const RevolutionAxis& axis) {
  std::vector<Index> walls;
  for (Index i = 0; i < source.size(); ++i)
    if (across_axis(source.normals().col(i), axis.direction).norm() >= kWall) walls.push_back(i);
  const Index m = std::min(Index(walls.size()), kSideProbes);
  Eigen::Matrix3Xd p(3, m), n(3, m);
  for (Index k = 0; k < m; ++k) {
    const Index i = walls[size_t(k * Index(walls.size()) / m)];
    p.col(k) = source.positions().col(i);
    n.col(k) = source.normals().col(i);
  }
  PointSet probe(std::move(p));
  probe.set_normals(std::move(n));
  return probe;
}

// The number of sides of a template that is a regular polygon about the axis (a prism, a low-poly cylinder or vase),
// from kFewestSides to kMostSides: the most sides n whose turn by 2 pi / n lays its walls on it best (kOwnTurn); 0
// for none.
int sides_about(const PointSet& source, const KdTree& tree, const RevolutionAxis& axis, double spacing) {
  const PointSet probe = wall_probes(source, axis);
  if (probe.size() < 16) return 0;
  std::vector<double> misfit(kMostSides + 1, std::numeric_limits<double>::infinity());
  for (int sides = kFewestSides; sides <= kMostSides; ++sides)
    misfit[size_t(sides)] = mean_distance_turned(probe, source, tree, axis, 2 * M_PI / sides, spacing);
  const double best = *std::min_element(misfit.begin(), misfit.end());
  if (best > kLaysOnItself * spacing) return 0;
  for (int sides = kMostSides; sides >= kFewestSides; --sides)
    if (misfit[size_t(sides)] <= best + kOwnTurn * spacing) return sides;
  return 0;
}

// A regular polygon's sides about the axis, and the angle across the axis of one facet's outward normal (the others
// are it plus multiples of 2 pi / sides). sides 0: none.
struct Facets {
  int sides = 0;
  double phase = 0;
};

// The template's facets about the axis (sides_about), their phase the mean of sides times the angles of the wall
// samples' normals, each turned to face away from the axis; none where those normals do not agree on one phase
// (kRegularFacets): not a polygon's flat facets.
Facets facets_about(const PointSet& source, const KdTree& tree, const RevolutionAxis& axis, double spacing) {
  const int sides = sides_about(source, tree, axis, spacing);
  if (sides == 0) return {};
  const auto [e1, e2] = plane_across(axis.direction);
  std::complex<double> sum = 0;
  Index walls = 0;
  for (Index i = 0; i < source.size(); ++i) {
    Eigen::Vector3d n = across_axis(source.normals().col(i), axis.direction);
    if (n.norm() < kWall) continue;
    if (n.dot(source.positions().col(i) - axis.centre) < 0) n = -n;
    sum += std::polar(1.0, sides * std::atan2(n.dot(e2), n.dot(e1)));
    ++walls;
  }
  if (std::abs(sum) < kRegularFacets * double(walls)) return {};
  return {sides, std::arg(sum) / sides};
}

// on_polygon_body about `axis`, for its `facets`.
PointSet circumscribed_body(const PointSet& points, const RevolutionAxis& axis, const Facets& facets) {
  const auto [e1, e2] = plane_across(axis.direction);
  const double facet = 2 * M_PI / facets.sides;
  Eigen::Matrix3Xd p = points.positions(), n = points.normals();
  for (Index i = 0; i < p.cols(); ++i) {
    const Eigen::Vector3d radial = across_axis(p.col(i) - axis.centre, axis.direction);
    if (radial.norm() == 0) continue;
    const double angle = std::atan2(radial.dot(e2), radial.dot(e1)) - facets.phase;
    const double off_facet_centre = angle - facet * std::round(angle / facet);
    p.col(i) += (std::cos(off_facet_centre) / std::cos(M_PI / facets.sides) - 1) * radial;
    if (!points.has_normals()) continue;
    const Eigen::Vector3d across = across_axis(n.col(i), axis.direction);
    if (across.norm() >= kWall)
      n.col(i) = n.col(i).dot(axis.direction) * axis.direction +
                 std::copysign(across.norm(), across.dot(radial)) * radial.normalized();
  }
  PointSet body = points;
  body.set_positions(std::move(p));
  if (points.has_normals()) body.set_normals(std::move(n));
  return body;
}

// ICP's pose, unless it is the relief's pull on the scan as given (kept_input_pose) or, turning the scan further
// than a relief turns it, on the scan as given turned in place by ICP's turn (turned_in_place). A round template is
// not turned in place: a turn about its axis is its own, and onto_template_axis lays a round scan's axis on it; on the
// sweep, turning in place moved its runs both ways (the 24-gon column's unseen-detail 0.96 -> 1.00, the Vase-Lion
// with `revolution:` of its scan from one seed-2027 view F 0.512 -> 0.455). Turned in place, a template that bounds
// the scan is the hull its relief is sunk in wherever ICP's pose pushes a tenth of the scan through it; as given, only
// where ICP's pose cuts it through (stop 54's rule, measured on 229 runs). ICP's turn about the axis of a template
// that turned lies on itself is taken out first.
Similarity registration_or_input_pose(const PointSet& exemplar, const PointSet& source, const KdTree& tree,
                                      const Similarity& icp_fit, const std::optional<RevolutionAxis>& round,
                                      double spacing, const CorrespondOptions& o, CorrespondResult& r) {
  // A turn about a body of revolution's axis is its own symmetry: it lays the scan on the template as well at any
  // angle, so only the scan's relief sets ICP's, and it must not count as a turn against the relief's in
  // relief_pulled_from. The sparse fluted column seen from its side, turned 1.86 degrees about the axis and pulled 6 mm
  // towards the sensor by its flutes, kept ICP's pose (its relief's turn is 1.1 degrees), and its images turned about
  // the axis landed up to twice 6 mm off: 5% of its synthesised points beyond the F-score's threshold. Without the
  // turn (the member of ICP's pose's family of turns about the axis nearest the identity), the relief's pull alone is
  // left, and the scan keeps its own pose (none beyond; F 0.957 -> 0.998).
  const bool symmetric = round && turned_onto_itself(source, tree, *round, spacing);
  const Similarity icp_pose =
      symmetric ? nearest_identity_member(icp_fit, {round->centre, round->direction, 0}) : icp_fit;
  const Placement registered = placement_on_source(exemplar, source, tree, icp_pose, spacing);
  const Placement as_given = placement_on_source(exemplar, source, tree, Similarity{}, spacing);
  const double icp_move = largest_displacement(exemplar.positions(), icp_pose);
  if (relief_pulled_from(exemplar, source, tree, spacing, Similarity{}, as_given, icp_pose, registered) ||
      (round &&
       (pulled_by_relief_about_a_round_template(exemplar, source, tree, spacing, as_given, icp_pose, registered) ||
        tilted_off_a_round_template_for_nothing(exemplar, source, spacing, as_given, icp_pose, registered, *round)))) {
    r.kept_input_pose = true;
    // In its own pose, the scan may still run on past an end of a template drawn too short.
    if (const auto scaling = drawn_at_another_size(exemplar, source, tree, spacing, Similarity{}, icp_move, o)) {
      r.another_size = true;
      r.template_scaling = *scaling;
    }
    return Similarity{};
  }
  if (const auto scaling = drawn_at_another_size(exemplar, source, tree, spacing, icp_pose, icp_move, o)) {
    r.kept_input_pose = r.another_size = true;
    r.template_scaling = *scaling;
    return Similarity{};
  }
  if (round) return icp_pose;
  const Similarity in_place = turned_in_place(exemplar, source, tree, icp_pose, spacing);
  const Placement placed = placement_on_source(exemplar, source, tree, in_place, spacing);
  if (pushed_through_its_bounding_template(placed, registered) ||
      relief_pulled_from(exemplar, source, tree, spacing, in_place, placed, icp_pose, registered)) {
    r.turned_in_place = true;
    return in_place;
  }
  return icp_pose;
}

// Min-cost flow assignment of exemplar samples to source samples (partial, many-to-one).
Index assign(bool exemplar_normals, const Eigen::Matrix3Xd& positions, const Eigen::Matrix3Xd& normals,
             const PointSet& source, const KdTree& tree, double spacing, const CorrespondOptions& o,
             std::vector<std::int32_t>& match, std::int64_t* total = nullptr) {
  const Index ne = positions.cols(), ns = source.size();
  const int k = int(std::min<Index>(o.candidates, ns));
  const double scale = 1000.0;  // integer cost units per (alpha^2)
  const auto escape = std::int64_t(std::llround(scale * o.escape_distance * o.escape_distance));
  std::vector<std::int32_t> cand(size_t(ne) * size_t(k), -1);
  std::vector<std::int64_t> cost(size_t(ne) * size_t(k), 0);
  const bool with_normals = exemplar_normals && source.has_normals();
  tbb::parallel_for(Index(0), ne, [&](Index e) {
    std::array<std::int32_t, 64> idx;
    std::array<double, 64> d2;
    const int got = tree.knn(positions.col(e), k, idx.data(), d2.data());
    for (int a = 0; a < got; ++a) {
      double c = d2[size_t(a)] / (spacing * spacing);
      if (with_normals) c += o.normal_weight * (1 - normals.col(e).dot(source.normals().col(idx[size_t(a)])));
      const auto ic = std::int64_t(std::llround(scale * c));
      if (ic >= escape) continue;  // never better than escaping
      cand[size_t(e) * size_t(k) + size_t(a)] = idx[size_t(a)];
      cost[size_t(e) * size_t(k) + size_t(a)] = ic;
    }
  });

  using Graph = lemon::SmartDigraph;
  Graph g;
  g.reserveNode(int(ne + ns + 1));
  g.reserveArc(int(ne * (k + 1) + ns));
  std::vector<Graph::Node> en(static_cast<size_t>(ne)), sn(static_cast<size_t>(ns));
  for (auto& n : en) n = g.addNode();
  for (auto& n : sn) n = g.addNode();
  const Graph::Node sink = g.addNode();
  Graph::ArcMap<std::int64_t> upper(g), arc_cost(g);
  Graph::NodeMap<std::int64_t> supply(g, 0);
  std::vector<Graph::Arc> arcs(cand.size(), lemon::INVALID);
  for (Index e = 0; e < ne; ++e) {
    supply[en[size_t(e)]] = 1;
    for (int a = 0; a < k; ++a) {
      const size_t slot = size_t(e) * size_t(k) + size_t(a);
      if (cand[slot] < 0) continue;
      arcs[slot] = g.addArc(en[size_t(e)], sn[size_t(cand[slot])]);
      upper[arcs[slot]] = 1;
      arc_cost[arcs[slot]] = cost[slot];
    }
    const Graph::Arc out = g.addArc(en[size_t(e)], sink);
    upper[out] = 1;
    arc_cost[out] = escape;
  }
  for (Index s = 0; s < ns; ++s) {
    const Graph::Arc a = g.addArc(sn[size_t(s)], sink);
    upper[a] = o.many_to_one;
    arc_cost[a] = 0;
  }
  supply[sink] = -ne;
  lemon::NetworkSimplex<Graph, std::int64_t, std::int64_t> solver(g);
  solver.upperMap(upper).costMap(arc_cost).supplyMap(supply);
  if (solver.run() != decltype(solver)::OPTIMAL) throw InvariantError("correspond: the assignment has no solution");
  if (total) *total = solver.totalCost();
  match.assign(size_t(ne), -1);
  Index matched = 0;
  for (Index e = 0; e < ne; ++e)
    for (int a = 0; a < k; ++a) {
      const size_t slot = size_t(e) * size_t(k) + size_t(a);
      if (cand[slot] >= 0 && solver.flow(arcs[slot]) > 0) {
        match[size_t(e)] = cand[slot];
        ++matched;
        break;
      }
    }
  return matched;
}

// A sample's deformation nodes and their weights (deformation_node.h).
struct Binding {
  std::array<std::int32_t, kNodesPerPoint> node;
  std::array<double, kNodesPerPoint> weight;
};

class Deformation {
 public:
  Deformation(const Eigen::Matrix3Xd& points, double spacing, const CorrespondOptions& o) {
    PointSet cloud(points);
    SampleOptions so;
    so.count = std::min<Index>(o.deformation_nodes, std::max<Index>(points.cols() / 4, kNodesPerPoint + 1));
    so.oversampling = 2;
    so.seed = 7;
    const SampleResult nodes = sample(cloud, so);
    nodes_ = nodes.samples.positions();
    params_.assign(size_t(nodes_.cols()) * 12, 0.0);
    for (Index j = 0; j < nodes_.cols(); ++j)
      for (int r = 0; r < 3; ++r) params_[size_t(j) * 12 + size_t(4 * r)] = 1.0;  // A = I, t = 0
    tree_.build(nodes_);
    node_spacing_ = std::max(nodes.spacing, spacing);
    const int kk = std::min<int>(o.node_neighbors + 1, int(nodes_.cols()));
    for (Index j = 0; j < nodes_.cols(); ++j) {
      std::array<std::int32_t, 17> idx;
      std::array<double, 17> d2;
      const int got = tree_.knn(nodes_.col(j), kk, idx.data(), d2.data());
      for (int a = 1; a < got; ++a) edges_.emplace_back(std::int32_t(j), idx[size_t(a)]);
    }
  }

  Binding bind(const Eigen::Vector3d& p) const {
    std::array<std::int32_t, kNodesPerPoint + 1> idx;
    std::array<double, kNodesPerPoint + 1> d2;
    tree_.knn(p, kNodesPerPoint + 1, idx.data(), d2.data());
    Binding b;
    const double dmax = std::sqrt(d2[kNodesPerPoint]) + 1e-12;
    double sum = 0;
    for (int i = 0; i < kNodesPerPoint; ++i) {
      b.node[size_t(i)] = idx[size_t(i)];
      b.weight[size_t(i)] = std::pow(1 - std::sqrt(d2[size_t(i)]) / dmax, 2) + 1e-9;
      sum += b.weight[size_t(i)];
    }
    for (auto& w : b.weight) w /= sum;
    return b;
  }

  Eigen::Vector3d apply(const Binding& b, const Eigen::Vector3d& p) const {
    Eigen::Vector3d v = Eigen::Vector3d::Zero();
    for (int i = 0; i < kNodesPerPoint; ++i) {
      const Index j = b.node[size_t(i)];
      v += b.weight[size_t(i)] * deform_by(&params_[size_t(j) * 12], p, nodes_.col(j));
    }
    return v;
  }

  // One solve, summarised: data pairs (point, binding, goal, goal normal), landmarks (weighted, point-to-point),
  // stiffness.
  SolverSummary solve(const Eigen::Matrix3Xd& points, const std::vector<Binding>& bindings,
                      const std::vector<std::int32_t>& match, const PointSet& source, double spacing,
                      const std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>>& landmarks, double stiffness,
                      const CorrespondOptions& o) {
    DeformationProblem problem;
    problem.nodes = nodes_;
    problem.edges = edges_;
    problem.huber = o.robust_scale;
    const auto add_data = [&](const Eigen::Vector3d& p, const Binding& b, const Eigen::Vector3d& q,
                              const Eigen::Vector3d& n, double weight, double plane, bool robust) {
      problem.data.push_back({p, q, n, b.node, b.weight, std::sqrt(weight) / spacing, plane, robust});
    };
    // A deformation graph of ~150 nodes is fixed by a few thousand data terms: take every stride-th matched sample
    // (weighted by the stride, so the balance with stiffness does not change).
    const size_t stride = std::max<size_t>(1, match.size() / size_t(std::max<Index>(1, o.deformation_samples)));
    problem.data.reserve(match.size() / stride + landmarks.size() + 1);
    for (size_t e = 0; e < match.size(); e += stride) {
      if (match[e] < 0) continue;
      const Eigen::Vector3d n =
          source.has_normals() ? Eigen::Vector3d(source.normals().col(match[e])) : Eigen::Vector3d::Zero();
      add_data(points.col(Index(e)), bindings[e], source.positions().col(match[e]), n, double(stride), 1.0, true);
    }
    // Data terms per node: rigidity and smoothness are weighted by it, so stiffness means the same at any sample
    // count, and a landmark outweighs a whole node's data terms (a constraint, not one more sample).
    const double per_node = double(std::max<Index>(1, Index(match.size()))) / double(nodes_.cols());
    for (const auto& [p, q] : landmarks)
      add_data(p, bind(p), q, Eigen::Vector3d::Zero(), o.landmark_weight * per_node, 0.0, false);
    problem.rotation_scale = std::sqrt(stiffness * per_node);
    problem.edge_scale = std::sqrt(stiffness * per_node / double(std::max(1, o.node_neighbors))) / node_spacing_;
    return solve_deformation(problem, params_, 10);
  }

 private:
  Eigen::Matrix3Xd nodes_;
  std::vector<double> params_;
  std::vector<std::pair<std::int32_t, std::int32_t>> edges_;
  KdTree tree_;
  double node_spacing_ = 1;
};

// M^-1: each source sample's exemplar sample (the nearest of those matched to it); unmatched source samples take
// their nearest matched neighbour's.
void inverse_match(const PointSet& source, CorrespondResult& r) {
  r.source_match.assign(size_t(source.size()), -1);
  std::vector<double> best(size_t(source.size()), 1e300);
  for (size_t e = 0; e < r.exemplar_match.size(); ++e) {
    const auto s = r.exemplar_match[e];
    if (s < 0) continue;
    const double d = (r.deformed.col(Index(e)) - source.positions().col(s)).squaredNorm();
    if (d < best[size_t(s)]) {
      best[size_t(s)] = d;
      r.source_match[size_t(s)] = std::int32_t(e);
    }
  }
  std::vector<std::int32_t> matched_sources;
  for (Index s = 0; s < source.size(); ++s)
    if (r.source_match[size_t(s)] >= 0) matched_sources.push_back(std::int32_t(s));
  if (matched_sources.empty()) throw InputError("no exemplar sample matched any source sample");
  if (matched_sources.size() < size_t(source.size())) {
    Eigen::Matrix3Xd mp(3, Index(matched_sources.size()));
    for (size_t i = 0; i < matched_sources.size(); ++i) mp.col(Index(i)) = source.positions().col(matched_sources[i]);
    KdTree mt;
    mt.build(mp);
    tbb::parallel_for(Index(0), source.size(), [&](Index s) {
      if (r.source_match[size_t(s)] >= 0) return;
      std::int32_t i;
      double d2;
      mt.knn(source.positions().col(s), 1, &i, &d2);
      r.source_match[size_t(s)] = r.source_match[size_t(matched_sources[size_t(i)])];
    });
  }
}

// The config's landmarks, and those of its picked-points files paired by name (names in one file only: a warning).
std::vector<Landmark> user_landmarks(const CorrespondOptions& o, std::vector<std::string>& warnings) {
  std::vector<Landmark> all = o.landmarks;
  if (o.landmarks_file.exemplar.empty()) return all;
  std::vector<std::string> unpaired;
  const std::vector<Landmark> named = landmarks_by_name(o.landmarks_file, unpaired);
  all.insert(all.end(), named.begin(), named.end());
  if (!unpaired.empty()) {
    std::string names;
    for (const auto& n : unpaired) names += (names.empty() ? "" : ", ") + n;
    warnings.push_back("landmarks_file: " + std::to_string(unpaired.size()) + " point names are in one file only (" +
                       names + ")");
  }
  return all;
}

// A scan is a body of revolution seen from a side where its normals meet an axis this nearly (as kRoundTemplate).
// The Vase-Lion's seen from its side meet theirs at 0.30.
constexpr double kRoundScan = 0.15;
// ICP's pose is taken where it lays the scan's axis within this turn and this many spacings of the template's, or
// where the scan's normals meet the template's axis, as laid, within this ratio and slack of their own axis's misfit
// (the vase in a cylinder: 0.10-0.13 against its own 0.02-0.04; a gear's face 0.0004 against 0).
constexpr double kAxisTurn = 3.0 * M_PI / 180;
constexpr double kAxisShift = 3.0;
// Nor is the scan turned by more than this to lay its axis: inputs are roughly aligned (paper section 3), and a thin
// band seen edge-on (the gear's teeth) meets an axis across it too, at half its thickness: laid on that, the gear
// was turned 90 degrees (F 0.124; 0.999 in ICP's pose). ICP tilted the vase in a cylinder 5-26 degrees.
constexpr double kMostAxisTurn = 45.0 * M_PI / 180;
constexpr double kAxisMisfitRatio = 2.0;
constexpr double kAxisMisfitSlack = 0.01;

// The elements whose normals lean across `direction` (kWall): a wall's, not a lid's.
SurfaceElements walls_across(const SurfaceElements& surface, const Eigen::Vector3d& direction) {
  std::vector<Index> keep;
  for (Index i = 0; i < surface.size(); ++i)
    if (surface.normals.col(i).cross(direction).norm() >= kWall) keep.push_back(i);
  SurfaceElements walls{Eigen::Matrix3Xd(3, Index(keep.size())), Eigen::Matrix3Xd(3, Index(keep.size())),
                        Eigen::VectorXd(Index(keep.size()))};
  for (size_t j = 0; j < keep.size(); ++j) {
    walls.points.col(Index(j)) = surface.points.col(keep[j]);
    walls.normals.col(Index(j)) = surface.normals.col(keep[j]);
    walls.weights(Index(j)) = surface.weights(keep[j]);
  }
  return walls;
}

// A scan is rounder than a polygon template where its walls' normals meet their axis at most this share as far off
// as the polygon's walls meet its own (a hexagon's 0.2, an octagon's 0.13; the vase's one-sided scan 0.017): a 12-gon's
// own scan is as far off as its template.
constexpr double kRounder = 0.5;

// The share of the scan's samples the body through a polygon's corners must lay on itself beyond the polygon's share
// for it to stand in for the polygon (rigid_pose).
constexpr double kClearlyOnBody = 0.03;

// How nearly the normals of the elements on walls across the axis (kWall) meet it; infinity with too few.
double wall_misfit(const SurfaceElements& surface, const RevolutionAxis& axis) {
  const SurfaceElements walls = walls_across(surface, axis.direction);
  return walls.size() < 16 ? std::numeric_limits<double>::infinity() : normal_axis_misfit(walls, axis);
}

// Whether the scan, as given, is a body of revolution about an axis near the template's `axis` (within
// kMostAxisTurn): the normals of its walls (across that axis) meet an axis within kRoundScan and `most_misfit`. A
// lid's normals meet every axis along them, and a hexagonal box seen from above is mostly lid.
bool round_about(const PointSet& exemplar, const RevolutionAxis& axis, double most_misfit) {
  const SurfaceElements walls = walls_across(surface_elements(exemplar), axis.direction);
  if (walls.size() < 16) return false;
  const RevolutionAxis own = axis_from_normals(walls);
  return normal_axis_misfit(walls, own) <= std::min(kRoundScan, most_misfit) &&
         std::abs(own.direction.dot(axis.direction)) >= std::cos(kMostAxisTurn);
}

// The pose that lays the scan's own axis of revolution on the template's, from `pose`: turned about the scan's axis
// centre until the axes are parallel, then moved across the axis (not along it) onto it. Where the scan is a body of
// revolution that the template is not in profile (a vase in a plain cylinder), ICP fits the scan's bulge to the
// cylinder by tilting it: 5-26 degrees and 5-11 cm off the axis for the procedural vase in a cylinder of its height,
// whose every turned image then stood askew (F 0.49-0.83; 0.91 in the scan's own pose). Unchanged (nullopt) where
// the scan is not round, or where ICP already lays the axes together. `axis`: the round template's.
std::optional<Similarity> onto_template_axis(const PointSet& exemplar, const PointSet& source, const Similarity& pose,
                                             const RevolutionAxis& axis, double spacing) {
  const SurfaceElements scan_surface = surface_elements(exemplar);
  if (scan_surface.size() < 16) return std::nullopt;
  const RevolutionAxis own = axis_from_normals(scan_surface);
  const double own_misfit = normal_axis_misfit(scan_surface, own);
  if (own_misfit > kRoundScan) return std::nullopt;
  // Where the scan's normals meet the template's axis, as ICP lays it, nearly as well as their own, ICP's pose is a
  // pose about the axis: a gear's face (parallel normals meet any axis along them) and the vase in its own body.
  const RevolutionAxis template_axis_on_scan{pose.inverse().apply(axis.centre),
                                             pose.rotation.transpose() * axis.direction};
  if (normal_axis_misfit(scan_surface, template_axis_on_scan) <= kAxisMisfitRatio * own_misfit + kAxisMisfitSlack)
    return std::nullopt;
  Eigen::Vector3d direction = pose.rotation * own.direction;
  if (direction.dot(axis.direction) < 0) direction = -direction;
  const Eigen::Vector3d centre = pose.apply(own.centre);
  const Eigen::Vector3d off = centre - axis.centre, across = off - off.dot(axis.direction) * axis.direction;
  const double tilt = std::acos(std::clamp(direction.dot(axis.direction), -1.0, 1.0));
  if ((tilt <= kAxisTurn && across.norm() <= kAxisShift * spacing) || tilt > kMostAxisTurn) return std::nullopt;
  const Eigen::Matrix3d R = Eigen::Quaterniond::FromTwoVectors(direction, axis.direction).toRotationMatrix();
  const Similarity upright{R, centre - R * centre - across, 1.0};
  return centred_along(exemplar, source, upright.compose(pose), axis, spacing);  // at the template's height
}

// The scan's pose on the template, from ICP's: registration_or_input_pose's, then its own axis laid on a round
// template's (onto_template_axis).
Similarity pose_on(const PointSet& exemplar, const PointSet& source, const KdTree& tree, const Similarity& icp_fit,
                   const std::optional<RevolutionAxis>& round, double spacing, const CorrespondOptions& o,
                   CorrespondResult& r) {
  const Similarity pose = registration_or_input_pose(exemplar, source, tree, icp_fit, round, spacing, o, r);
  if (const auto laid = round ? onto_template_axis(exemplar, source, pose, *round, spacing) : std::nullopt) {
    r.kept_input_pose = r.turned_in_place = false;
    r.laid_on_axis = true;
    return *laid;
  }
  return pose;
}

// The template's axis (axis_from_normals), whether its normals meet it (kRoundTemplate), and the facets of the
// regular polygon it is about that axis (facets_about; none for a body of revolution), with how nearly their normals
// meet it (wall_misfit). A polygon may count as round (the vase's 10-gon turned 37 degrees lies on itself), and is
// still asked (Correspond.AsksATemplateThatCountsAsRoundWhetherItIsAPolygon).
struct TemplateAxis {
  RevolutionAxis axis;
  bool round = false;
  Facets facets;
  double wall_misfit = 0;
};

TemplateAxis template_axis(const PointSet& source, const KdTree& tree, double spacing) {
  const SurfaceElements surface = surface_elements(source);
  if (surface.size() < 16) return {};
  TemplateAxis t;
  t.axis = axis_from_normals(surface);
  t.round = normal_axis_misfit(surface, t.axis) <= kRoundTemplate;
  if (!source.has_normals()) return t;
  t.facets = facets_about(source, tree, t.axis, spacing);
  if (t.facets.sides > 0) t.wall_misfit = wall_misfit(surface, t.axis);
  return t;
}

// The rigid pose of the scan on the template. A low-poly drawing of a body of revolution (a hexagon, an octagon) has
// corners that a round scan's arc fits only in part: ICP pulled the fluted column seen square on a corner of its
// hexagon 2.8 cm into it (of an octagon's, 1.4 cm), and its turned images landed twice that off the far side (F 0.590
// and 0.915). Where the scan lies on the body of revolution through the polygon's corners (circumscribed_body), as
// ICP lays it there, better than on the polygon as ICP lays it there, the polygon draws that body, and the scan is
// registered on it as on a round template, as it is where the scan is rounder than the polygon (round_about, kRounder:
// the vase lies on neither, 7% either way). A scan of the polygon itself (a hexagonal prism in its hexagon) lies
// better on the polygon, and is no rounder. A scan of an end face lies on both (a hexagon inside the body's disk, a
// share 0.01 apart seen straight from below), and takes the template as drawn: the body must lay kClearlyOnBody more
// of the scan on itself (the fluted column's scans, on an octagon or a hexagon, 0.08 to 0.30 more).
Similarity rigid_pose(const PointSet& exemplar, const PointSet& source, const KdTree& tree, double spacing,
                      const CorrespondOptions& o, CorrespondResult& r) {
  const TemplateAxis t = template_axis(source, tree, spacing);
  const Similarity icp_fit = rigid_icp(exemplar, source, tree, o, r.rigid_rms);
  if (o.polygon_body && t.facets.sides > 0) {
    const PointSet body = circumscribed_body(source, t.axis, t.facets);
    KdTree body_tree;
    body_tree.build(body.positions());
    double body_rms = 0;
    const Similarity body_fit = rigid_icp(exemplar, body, body_tree, o, body_rms);
    const double on_body = placement_on_source(exemplar, body, body_tree, body_fit, spacing).on;
    const double on_polygon = placement_on_source(exemplar, source, tree, icp_fit, spacing).on;
    if (on_body > on_polygon + kClearlyOnBody || round_about(exemplar, t.axis, kRounder * t.wall_misfit)) {
      r.polygon = {t.axis.centre, t.axis.direction, t.facets.sides, t.facets.phase};
      r.rigid_rms = body_rms;
      return pose_on(exemplar, body, body_tree, body_fit, t.axis, spacing, o, r);
    }
  }
  return pose_on(exemplar, source, tree, icp_fit, t.round ? std::optional(t.axis) : std::nullopt, spacing, o, r);
}

// A landmark's place on the template, on the body where a polygon stands for it.
Eigen::Vector3d on_body_if_any(const Eigen::Vector3d& p, const PolygonBody& body) {
  return body.sides > 0 ? Eigen::Vector3d(on_polygon_body(PointSet(Eigen::Matrix3Xd(p)), body).positions().col(0)) : p;
}

// Whether a template bounds the scan where `placed` says it lies, touching it (as cut_through_its_bounding_template
// asks as given). The scanned pillar seen square on a side, level with it, in its `box:`: its panel lies up to 10
// spacings inside the box, and only its capital and base, 16% of the scan, lay within escape_distance of it; it was
// refused as not overlapping its template, which bounds it as drawn.
bool sunk_in_its_bounding_template(const Placement& placed) {
  return placed.outside <= kBoundsAsGiven && placed.on >= kTouches;
}

// Roughly aligned inputs (paper section 3) need a turn of a few degrees at most: over the robustness sweep's real
// and procedural runs ICP turned scans up to 9.3 degrees (the Vase-Lion, the scanned pillar). The teapot in its
// bounding box, a template of another shape, was turned 27-56 degrees, half of it out of the box (F 0.25-0.35 against
// the scan alone's 0.6): past this, the user is told.
constexpr double kRoughlyAlignedDegrees = 20;

// The warning for a rigid registration that turned the scan further than roughly aligned inputs need, if it did.
std::optional<std::string> turned_far_warning(const Similarity& rigid) {
  const double degrees = rotation_angle(rigid.rotation) * 180 / M_PI;
  if (degrees <= kRoughlyAlignedDegrees) return std::nullopt;
  return "the rigid registration turned the scan " + std::to_string(int(std::round(degrees))) +
         " degrees onto the template, where roughly aligned inputs need a few: a template of another shape than the "
         "scan's, or in another frame, is fitted wrongly so; correspond.rigid: false keeps the scan's own pose";
}

// Throws InputError unless at least min_overlap of `points` lie within `within` of the source (`tree`): `when` says at
// which step ("" before registration), `limit` how `within` was chosen.
void require_overlap(const KdTree& tree, const Eigen::Matrix3Xd& points, double within, const CorrespondOptions& o,
                     const std::string& when, const std::string& limit) {
  const double share = share_within(tree, points, within);
  if (share >= o.min_overlap) return;
  throw InputError("the exemplar (scan) and the source (template) do not overlap: " + when + "only " +
                   std::to_string(int(std::round(100 * share))) + "% of the scan's samples lie within " +
                   std::to_string(within) + " of the template (" + limit + "at least " +
                   std::to_string(int(std::round(100 * o.min_overlap))) +
                   "% needed); inputs must be roughly aligned and at the same scale");
}

// After the rigid registration r.rigid: the overlap check, then assignment alternating with embedded deformation onto
// `source` (its samples in `tree`), and the matches.
void deform_onto(const PointSet& exemplar, const PointSet& source, const KdTree& tree, double spacing,
                 const CorrespondOptions& o, const ProgressFn& progress, CorrespondResult& r) {
  const double ds = bounding_box(source.positions()).diagonal();
  r.registered.resize(3, exemplar.size());
  Eigen::Matrix3Xd normals(3, exemplar.size());
  for (Index i = 0; i < exemplar.size(); ++i) {
    r.registered.col(i) = r.rigid.apply(exemplar.positions().col(i));
    normals.col(i) = exemplar.has_normals() ? r.rigid.apply_normal(exemplar.normals().col(i)) : Eigen::Vector3d::Zero();
  }
  // A scan laid on the template's axis may stand off it in profile (a vase in a cylinder), and one its template bounds
  // lies in the hull its relief is sunk in: it must lie as near as the inputs had to before registration.
  const bool sunk = sunk_in_its_bounding_template(placement_on_source(exemplar, source, tree, r.rigid, spacing));
  const double near =
      r.laid_on_axis || sunk ? std::max(o.escape_distance * spacing, 0.1 * ds) : o.escape_distance * spacing;
  require_overlap(tree, r.registered, near, o, "after rigid registration ", "");

  // Alternate assignment and embedded deformation, relaxing the stiffness.
  r.deformed = r.registered;
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> landmarks;
  for (const auto& l : user_landmarks(o, r.warnings))
    landmarks.emplace_back(r.rigid.apply(l.exemplar), on_body_if_any(l.source, r.polygon));
  if (o.outer_iterations > 0 && exemplar.size() >= 4 * (kNodesPerPoint + 1)) {
    Deformation def(r.registered, spacing, o);
    std::vector<Binding> bindings(size_t(exemplar.size()));
    tbb::parallel_for(Index(0), exemplar.size(), [&](Index i) { bindings[size_t(i)] = def.bind(r.registered.col(i)); });
    double stiffness = o.stiffness;
    for (int it = 0; it < o.outer_iterations; ++it) {
      std::vector<std::int32_t> match;
      assign(exemplar.has_normals(), r.deformed, normals, source, tree, spacing, o, match);
      r.deformation_solves.push_back(
          def.solve(r.registered, bindings, match, source, spacing, landmarks, stiffness, o));
      tbb::parallel_for(Index(0), exemplar.size(),
                        [&](Index i) { r.deformed.col(i) = def.apply(bindings[size_t(i)], r.registered.col(i)); });
      stiffness *= 0.5;
      report(progress, 0.2 + 0.7 * double(it + 1) / o.outer_iterations);
    }
  }
  r.matched = assign(exemplar.has_normals(), r.deformed, normals, source, tree, spacing, o, r.exemplar_match);
  double sum = 0;
  for (size_t e = 0; e < r.exemplar_match.size(); ++e)
    if (r.exemplar_match[e] >= 0)
      sum += (r.deformed.col(Index(e)) - source.positions().col(r.exemplar_match[e])).squaredNorm();
  r.deformed_rms = r.matched > 0 ? std::sqrt(sum / double(r.matched)) : 0.0;
  if (r.matched < exemplar.size() / 2)
    r.warnings.push_back(std::to_string(exemplar.size() - r.matched) + " of " + std::to_string(exemplar.size()) +
                         " exemplar samples found no source sample within " + std::to_string(o.escape_distance) +
                         " alpha after registration");

  r.exemplar_source = r.exemplar_match;
  {
    const double limit = std::pow(2 * o.escape_distance * spacing, 2);
    tbb::parallel_for(Index(0), exemplar.size(), [&](Index e) {
      if (r.exemplar_source[size_t(e)] >= 0) return;
      std::int32_t s;
      double d2;
      tree.knn(r.deformed.col(e), 1, &s, &d2);
      if (d2 <= limit) r.exemplar_source[size_t(e)] = s;
    });
  }

  inverse_match(source, r);
  report(progress, 1.0);
}

}  // namespace

PointSet on_polygon_body(const PointSet& points, const PolygonBody& body) {
  if (body.sides < kFewestSides || body.sides > kMostSides)
    throw InvariantError("on_polygon_body: a polygon of " + std::to_string(body.sides) + " sides (5 to 32 are read)");
  if (std::abs(body.direction.norm() - 1) > 1e-9)
    throw InvariantError("on_polygon_body: the axis is not a unit vector");
  return circumscribed_body(points, {body.centre, body.direction}, {body.sides, body.phase});
}

PointSet polygon_body_surface(const PointSet& surface, const PolygonBody& body, double spacing, Index most_faces) {
  return on_polygon_body(surface.has_faces() ? subdivided_mesh(surface, spacing, most_faces) : surface, body);
}

// Whether the template's scaling moves its centroid over a spacing: its own symmetries (a box's turns and flips) then
// turn about another centre than the scan's, and the template scaled stands in for it (template_scaled). Scaled about
// its centroid, it keeps them, and stays as drawn: the studded box in a box 8% narrower scored 0.960-0.999 with its
// box scaled standing in, 0.973-0.996 without, and the golf ball in spheres 6% larger and 5% smaller 0.951-0.990,
// against 0.964-0.999 (on its own sphere, 0.946-0.982). The box drawn 10% wider and 5% taller, its floor 4.5 cm
// below the box's, is scaled about its top, which moves its centroid 2.4 cm: seen from below, F 0.498 in its own
// centre, 0.989 with the template scaled standing in.
bool moves_the_template_off(const CorrespondResult& r, double spacing) {
  return r.template_scaling.shift.norm() > spacing;
}

PointSet template_in_place(const PointSet& points, const CorrespondResult& r) {
  const PointSet body = r.polygon.sides > 0 ? on_polygon_body(points, r.polygon) : points;
  return r.template_scaled ? scaled_source(body, r.template_scaling) : body;
}

CorrespondResult correspond(const PointSet& exemplar, const PointSet& source, double spacing,
                            const CorrespondOptions& o, const ProgressFn& progress) {
  check_options(o);  // the config checks these too; a direct caller gets the same checks
  CorrespondResult r;
  if (exemplar.size() < o.min_samples)
    throw InputError("the exemplar (scan) has " + std::to_string(exemplar.size()) + " samples; at least " +
                     std::to_string(o.min_samples) + " are needed to register it");
  if (source.size() < o.min_samples)
    throw InputError("the source (template) has " + std::to_string(source.size()) + " samples; at least " +
                     std::to_string(o.min_samples) + " are needed");
  const double ds = bounding_box(source.positions()).diagonal();
  KdTree tree;
  tree.build(source.positions());

  // Roughly aligned inputs (paper section 3) overlap before any registration: ICP from a pose that shares nothing
  // with the template would only find some arbitrary local fit.
  require_overlap(tree, exemplar.positions(), std::max(o.escape_distance * spacing, 0.1 * ds), o, "",
                  "10% of its diagonal; ");
  if (o.rigid) r.rigid = rigid_pose(exemplar, source, tree, spacing, o, r);
  if (const auto w = turned_far_warning(r.rigid)) r.warnings.push_back(*w);
  report(progress, 0.2);
  r.template_scaled = o.scaled_template && r.another_size && r.kept_input_pose && moves_the_template_off(r, spacing);
  if (r.another_size) r.warnings.push_back(another_size_warning(r.template_scaling, r.template_scaled));
  if (r.polygon.sides == 0 && !r.template_scaled) {
    deform_onto(exemplar, source, tree, spacing, o, progress, r);
    return r;
  }
  const PointSet stand_in = template_in_place(source, r);
  KdTree stand_in_tree;
  stand_in_tree.build(stand_in.positions());
  deform_onto(exemplar, stand_in, stand_in_tree, spacing, o, progress, r);
  return r;
}

void check_shared_scale(const std::string& name_a, const PointSet& a, const std::string& name_b, const PointSet& b,
                        double max_ratio) {
  const double diagonal_a = bounding_box(a.positions()).diagonal(), diagonal_b = bounding_box(b.positions()).diagonal();
  if (diagonal_a <= max_ratio * diagonal_b && diagonal_b <= max_ratio * diagonal_a) return;
  throw InputError("inputs must share a scale: the bounding-box diagonal of " + name_a + " is " +
                   std::to_string(diagonal_a) + ", of " + name_b + " " + std::to_string(diagonal_b) + " (more than " +
                   std::to_string(max_ratio) + "x apart; are the units the same?)");
}

Index assign_samples(const Eigen::Matrix3Xd& positions, const Eigen::Matrix3Xd& normals, const PointSet& source,
                     double spacing, const CorrespondOptions& options, std::vector<std::int32_t>& match,
                     std::int64_t* cost) {
  KdTree tree;
  tree.build(source.positions());
  return assign(normals.cols() == positions.cols(), positions, normals, source, tree, spacing, options, match, cost);
}

std::vector<std::int32_t> covered_samples(const PointSet& source, const Eigen::Matrix3Xd& points, double distance) {
  std::vector<std::int32_t> out;
  if (points.cols() == 0) return out;
  KdTree tree;
  tree.build(points);
  std::vector<std::int32_t> idx;
  std::vector<double> d2;
  nearest_each(tree, source.positions(), idx, d2);
  for (Index s = 0; s < source.size(); ++s)
    if (d2[size_t(s)] <= distance * distance) out.push_back(std::int32_t(s));
  return out;
}

namespace {

// Marks the template samples over which the scan stands in relief: a scan sample within `height` along the sample's
// normal (either way), within `lateral` of the normal's line and with a normal within 60 degrees. A gear's tooth
// gaps and a leg's bulb lie further from the plain template than the deformation pulls them, yet the scan sees them.
void cover_relief(const PointSet& templ, const Eigen::Matrix3Xd& scan, const Eigen::Matrix3Xd& scan_normals,
                  double lateral, double height, std::vector<std::uint8_t>& covered) {
  KdTree tree;
  tree.build(scan);
  const double reach = std::sqrt(lateral * lateral + height * height);
  tbb::parallel_for(tbb::blocked_range<Index>(0, templ.size()), [&](const tbb::blocked_range<Index>& range) {
    std::vector<Neighbor> near;
    for (Index t = range.begin(); t < range.end(); ++t) {
      if (covered[size_t(t)]) continue;
      const Eigen::Vector3d p = templ.positions().col(t), n = templ.normals().col(t);
      tree.radius(p, reach, near);
      for (const Neighbor& q : near) {
        const Eigen::Vector3d d = scan.col(q.index) - p;
        const double along = d.dot(n);
        if ((d - along * n).squaredNorm() <= lateral * lateral && scan_normals.col(q.index).dot(n) > 0.5) {
          covered[size_t(t)] = 1;
          break;
        }
      }
    }
  });
}

}  // namespace

CoverResult cover_template(const PointSet& templ, const CorrespondResult& map, const PointSet& exemplar, double spacing,
                           const CoverOptions& options) {
  check_options(options);
  CoverResult r;
  r.samples = covered_samples(templ, map.deformed, options.distance * spacing);
  r.covered.assign(size_t(templ.size()), 0);
  for (const auto s : r.samples) r.covered[size_t(s)] = 1;
  if (options.relief > 0 && templ.has_normals() && exemplar.has_normals() && exemplar.size() == map.deformed.cols()) {
    Eigen::Matrix3Xd normals(3, exemplar.size());
    for (Index e = 0; e < exemplar.size(); ++e) normals.col(e) = map.rigid.apply_normal(exemplar.normals().col(e));
    cover_relief(templ, map.deformed, normals, options.distance * spacing, options.relief * spacing, r.covered);
  }
  r.source = subset(templ, r.samples);
  if (Index(r.samples.size()) < options.min_samples)
    throw InputError("the registered scan covers only " + std::to_string(r.samples.size()) +
                     " template samples: too little of the template to learn from");
  return r;
}

std::vector<Landmark> landmarks_by_name(const LandmarkFiles& files, std::vector<std::string>& unpaired) {
  const std::vector<NamedPoint> exemplar = read_picked_points(files.exemplar),
                                source = read_picked_points(files.source);
  std::vector<Landmark> pairs;
  for (const NamedPoint& e : exemplar) {
    const auto s = std::find_if(source.begin(), source.end(), [&](const NamedPoint& p) { return p.name == e.name; });
    if (s == source.end())
      unpaired.push_back(e.name);
    else
      pairs.push_back({e.position, s->position});
  }
  for (const NamedPoint& s : source)
    if (std::none_of(exemplar.begin(), exemplar.end(), [&](const NamedPoint& p) { return p.name == s.name; }))
      unpaired.push_back(s.name);
  if (pairs.empty())
    throw InputError("correspond.landmarks_file: no point name is in both " + files.exemplar.string() + " and " +
                     files.source.string());
  return pairs;
}

}  // namespace scanfill
