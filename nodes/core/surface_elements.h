// A model's surface as unoriented elements (a point, a unit normal and a weight), for statistics of the directions it
// faces: the frame of a box-like model (box_axes) and the axis of a body of revolution (axis_from_normals).
#pragma once

#include <Eigen/Core>

#include "nodes/core/point_set.h"

namespace scanfill {

struct SurfaceElements {
  Eigen::Matrix3Xd points;   // 3 by M
  Eigen::Matrix3Xd normals;  // 3 by M unit vectors, each up to sign
  Eigen::VectorXd weights;   // M non-negative weights
  Index size() const { return points.cols(); }
};

// A mesh's faces (centroid, normal, area; degenerate faces left out). A point set's points, about `most` of them, each
// with the file's normal where it has them (evenly strided), else the direction in which the point and its 12
// nearest neighbours spread least (the first point of each cell of a grid sized for at most 4000 of them; weight 1; a
// point with fewer than 3 neighbours is left out). Deterministic.
SurfaceElements surface_elements(const PointSet& model, Index most = 20000);

}  // namespace scanfill
