#pragma once

#include <Eigen/Core>

#include "nodes/core/point_set.h"

namespace scanfill {

// The axes of a box-like model, as the columns of a rotation: the three square directions its surface faces (a
// Manhattan frame), each up to sign. A real scan of a carton lies turned in its sensor's frame, and its axis-aligned
// bounding box is then no template for it. Directions: the model's surface_elements (a mesh's face normals weighted
// by area, else each point's own normal or one from its 12 nearest neighbours, at most 20000 points). From the identity
// and 64 seeded turns, each normal within 25 degrees of an axis pulls that axis towards itself (orthogonal Procrustes,
// at most 30 steps); the frame kept is the one with most weight within 10 degrees of an axis. The identity is kept when
// it holds at least 97% of that weight, so a model drawn square to its axes keeps its axis-aligned box. Deterministic.
Eigen::Matrix3d box_axes(const PointSet& model);

}  // namespace scanfill
