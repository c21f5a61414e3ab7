// The free space a single-view scan shows. The scanner at its eye saw each scan point along a ray, so nothing stands
// on that ray before the point: a template drawn there is not the object. Completion copies the template only where
// no image of the scan reaches; a plain closed cylinder drawn about an open vase seen from above would have its lid
// copied over the vase's mouth, through which the scan shows the vase's inside.
#pragma once

#include <cstdint>
#include <vector>

#include "nodes/core/point_set.h"
#include "nodes/core/similarity.h"

namespace scanfill {

// Per target sample, 1 where the scanner saw through it: a scan sample lies farther along its ray from `eye`, by more
// than 4 spacings (a template drawn a little proud of the scan's surface is left to coverage), in the same cell of a
// view grid about `spacing` wide at the scan's depth, and every occupied cell of the 3 x 3 about it lies farther too (a
// silhouette's cell holds the near side's samples as well). Only target samples whose normal faces the eye are judged:
// a scanner that keeps front faces only (as the virtual one does) sees through the inside of a thin open shell, but
// never through a face turned to it. The scan is carried into the targets' frame by
// `scan_to_targets`, `eye` with it (`eye` is in the scan's frame). Nothing is judged (all 0) where the eye lies within
// 10% of the targets' bounding box (a viewpoint no sensor had, such as a PCD's default origin at the object's centre)
// or the scan spans more than a half-space about it. Deterministic; O(n log n).
std::vector<std::uint8_t> seen_through(const PointSet& scan, const Similarity& scan_to_targets,
                                       const Eigen::Vector3d& eye, const PointSet& targets, double spacing);

}  // namespace scanfill
