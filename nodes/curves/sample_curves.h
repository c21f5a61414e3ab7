// Curve sampling for mode curves (issue 12): the 2D drawing as the planar point set the analogy nodes work on, and the
// way back from output points to curves.
//
// sample_curves: samples at equal arc-length steps along every curve (the 1-D limit of Poisson-disk sampling: the
// densest set with no two samples closer than the step), placed in the z = 0 plane. Per sample, from the curve itself
// rather than a neighbourhood fit (the features node's PCA would see a line, whose normal is undetermined in 3D):
//   tangent   t = p(s + h) - p(s - h), normalised, h = curvature_window alpha (clamped at the ends of open curves);
//   normal    n = t turned by -90 degrees in the plane, oriented outward on closed curves (by the sign of their area)
//             and away from the drawing's centroid on balance on open ones;
//   curvature k1 = the signed turning angle from p(s - h) -> p(s) to p(s) -> p(s + h), divided by the mean of the two
//             chord lengths; positive where the curve bends away from its normal (1/r on a circle with outward
//             normals, as the 3D curvature of nodes/features); k2 = 0 (a curve bends one way);
//   direction d1 = z x n, so the frame (d1, n x d1, n) of the vote node is (d1, z, n): a rotation about z maps frames
//   of
//             the plane onto each other.
// A corner of a polyline is spread over the samples within h of it, as the 3D features spread an edge over their
// neighbourhood.
//
// order_into_curves: output points back into polylines, by following the target's curves: each point takes the curve
// and arc parameter of its nearest target sample (plus its offset along that sample's tangent); each curve's points
// are walked from the lowest parameter to the nearest point not yet taken (so detail that folds back along the
// target's curve, a serif's hook, is followed along itself) and cut where consecutive points lie more than `gap`
// alpha apart; a cut-free run round a closed target curve is closed.
#pragma once

#include <cstdint>
#include <vector>

#include "nodes/core/point_set.h"
#include "nodes/curves/curves.h"

namespace scanfill {

struct CurveSampleOptions {
  double spacing = 0.0;           // arc length between samples (alpha), model units; 0 = from count; >= 0
  Index count = 400;              // samples over the whole drawing when spacing is 0; [16, 10^7]
  double curvature_window = 1.0;  // half-width h of the tangent and curvature stencil, in alpha; [0.25, 10]
  double gap = 3.0;               // output points farther apart than this (alpha) start a new polyline; > 0
};

struct CurveSamples {
  PointSet samples;                  // z = 0: positions, normals, curvatures (k, 0), directions z x n
  std::vector<std::int32_t> curve;   // per sample: its curve in the drawing
  std::vector<double> arc;           // per sample: arc length from its curve's first vertex
  std::vector<std::uint8_t> closed;  // per curve: 1 when closed
  double spacing = 0;                // alpha used
  double length = 0;                 // total arc length of the drawing
};

// The spacing `options` asks for on a drawing of total arc length `length`: spacing, else length / count.
double curve_spacing(double length, const CurveSampleOptions& options);

// Samples `curves` at arc-length steps of `spacing` (> 0). Throws InputError for an empty drawing or fewer than 16
// samples in all (spacing too coarse for the drawing).
CurveSamples sample_curves(const Curves& curves, double spacing, const CurveSampleOptions& options);

// The points (3 by N, z ignored) as polylines along the target's curves; `spacing` is alpha.
Curves order_into_curves(const Eigen::Matrix3Xd& points, const CurveSamples& target, const CurveSampleOptions& options);

// The curves as a planar point set (their vertices at z = 0): the loaded input's points, for bounds and counts.
PointSet curve_vertices(const Curves& curves);

}  // namespace scanfill
