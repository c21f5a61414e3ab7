// The up of a template drawn standing on its ground plane (DESIGN section 9): the last cue before +z.
//
// Modelling tools draw an object standing on the ground plane through the origin, its footprint about the origin: the
// teapot, the scanned square pillar and the furniture scene in ../shared/data stand so on y = 0, the procedural
// shapes on z = 0. Where neither the template's symmetry nor the scan tells the up of a box that is not square (the
// pillar seen square on one side shows no lid and only one side), that habit does: the pillar, drawn y-up, took +z,
// its front-back axis, and the quarter turns about it laid its side's relief on its lid and floor (F 0.439, under the
// scan alone's 0.502; 0.637 with `label.up: [0, 1, 0]`). Ours, not the paper's (its examples are upright).
#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "nodes/core/point_set.h"
#include "nodes/symmetry/symmetry.h"

namespace scanfill {

// Of `axes` (directions through the origin), the one along which `target` stands on the origin's plane: its extent
// along it starts within 2% of that extent from 0 and lies above it, while along every other axis its extent is about
// the origin (its middle within 10% of its length of 0). Signed to point from the ground into the object. None where
// no axis, or more than one, is so.
std::optional<Eigen::Vector3d> grounded_axis(const PointSet& target, const std::vector<SymmetryAxis>& axes);

}  // namespace scanfill
