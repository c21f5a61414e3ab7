// The size a template is drawn at against its scan (correspond node, DESIGN section 4).
//
// The paper assumes inputs consistently scaled (section 3). A user's plain template rarely is: a box drawn 8% narrower
// than the crate it stands for, a sphere 6% too large. Rigid ICP then lays the scan on one face of it, and every turned
// image of the scan lands off the unseen faces by the difference, twice over for a half turn (a studded box in a box
// 8% narrower, seen from the front: F 0.39, under its scan alone's 0.42; in the scan's own pose, 0.98). Whether the
// scan's own pose and ICP's differ by a pose or by a size is asked of the template scaled about its centroid: scaled,
// it lays the scan in its own pose on itself as well as ICP's move does where the difference is a size, and cannot
// where it is a pose (scaling moves opposite faces apart, a pose moves them together). A user's box may be drawn off
// at one end only (taller, its floor below the crate's and its top level with it): the scaling is then about that
// other end, which stays, and moves the template's centroid, about which its own turns and flips turn. Where the scan
// does not see that end, the scan's faces still end at it, and the template is trimmed to them. A template drawn too
// short at one end lays the scan's faces on its own, and ICP hardly moves the scan; the scan runs on past that end,
// and the template scaled to reach where it ends lays more of it on itself.
#pragma once

#include <Eigen/Core>

#include "nodes/core/kdtree.h"
#include "nodes/core/point_set.h"

namespace scanfill {

// The template scaled along its principal axes about its centroid, then shifted: a point x goes to
// centre + shift + A diag(scale) A^T (x - centre). The shift is that of a scaling about an end of the template, which
// stays (a box drawn taller than the crate, its top level with the crate's and its floor below it).
struct TemplateScaling {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();  // columns: principal axes, spread ascending
  Eigen::Vector3d scale = Eigen::Vector3d::Ones();     // per axis
  Eigen::Vector3d shift = Eigen::Vector3d::Zero();     // in the template's own coordinates, after the scaling
};

// The share of `points` on the source scaled by `s` (its samples in `tree`): within half a spacing of the tangent plane
// of their nearest scaled source sample, and within two spacings of it (placement_on_source's `on`).
double share_on_scaled(const Eigen::Matrix3Xd& points, const PointSet& source, const KdTree& tree,
                       const TemplateScaling& s, double spacing);

// The scaling of the source, 0.8 to 1.25 per axis in steps of 0.01 and axes of nearly equal spread (within 3%: a
// square box's sides, a cylinder's radius) scaled alike, that lays the most of `points` on it, by coordinate descent
// from no scaling. An axis of its own is scaled about the centroid or about either end (which stays: the shift), axes
// scaled alike about the centroid only. A step is taken only where it lays a hundredth more of the points on, and of
// steps laying as much on and leaving as few of them past the template's ends, the one moving the ends least. No free
// shift is tried: a scan that sees one face along an axis lies on it as well shifted as scaled, and a shift is a pose,
// which the registration fits. The source needs normals.
TemplateScaling scaling_that_fits(const Eigen::Matrix3Xd& points, const PointSet& source, const KdTree& tree,
                                  double spacing, double& share);

// The scaling of the source at its ends one at a time, for a template drawn too short at an end, which the scan runs
// past: ICP lays the scan's faces on the template's and hardly moves it. Each step scales one of the source's axes of
// a spread of its own (not a square box's sides, not a disk's radius) up about either end of it, which stays, where a
// hundredth of `points` runs on past the other end (a scan sunk in the box that bounds it, the scanned pillar's panels,
// lays more of itself on that box shrunk, or stretched along its height, and is not drawn at another size): of the
// trials of scaling_that_fits over every such axis and end, where the best of them lays a hundredth more of `points`
// on, the least-moving of those laying as many as it and leaving fewest past the ends at all (a scan seen nearly level
// lays as much on at any scale past its end, give or take its noise), else one laying as many on and leaving a
// hundredth fewer past the ends at all (the scan runs on past the end only as relief standing out of the template: a
// crate's frames, seen from below). Up to four steps, the last end moved staying (a box drawn short at both ends), then
// scaling_that_fits's descent from there, scaling up only; no scaling where no end alone gains. The full search from no
// scaling also scales a disk radially onto a gear's teeth; a disk's one axis of its own is its thickness, which the
// teeth share.
TemplateScaling scaling_at_one_end(const Eigen::Matrix3Xd& points, const PointSet& source, const KdTree& tree,
                                   double spacing, double& share);

// `s` refined so that the template fits the scan both ways: the least of its surface facing the sensor left without
// the scan on it, plus the least of `points` left off it, where that lays as many of them on (within a hundredth). Per
// group of axes, the trials of scaling_that_fits (scales and pivots) from `s`, taken where that misfit falls by a
// hundredth; of those at nearly the least, the one moving the template's ends least. The sensor lies along
// `towards_sensor` (the scan's mean normal: a scan's points are dense in proportion to the area it sees square on). A
// convex template sees what faces the sensor, so a template end drawn beyond the scan's own end there is no surface
// the scan saw: a box drawn taller than the crate, its floor below the crate's, seen from above (the scan's sides end
// at the crate's floor, the template's run on below it). An end that faces away, or a scan that ends where the
// template does, leaves `s` as it is. Needs the source's normals.
TemplateScaling trimmed_to_the_seen(const Eigen::Matrix3Xd& points, const Eigen::Vector3d& towards_sensor,
                                    const PointSet& source, const KdTree& tree, double spacing, TemplateScaling s);

// The source's samples scaled: positions about the centre, normals by the inverse transpose (still unit length).
PointSet scaled_source(const PointSet& source, const TemplateScaling& s);

// The farthest the scaling moves any source sample about the centre, its shift left out (a shift is a pose).
double largest_scaling_move(const PointSet& source, const TemplateScaling& s);

}  // namespace scanfill
