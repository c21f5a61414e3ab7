// The candidates of style exchange (paper section 7): every map of a source box onto a target box, A x = c_j + D R
// (x - c_i) with R one of the 24 axis rotations and D = diag(size_j / |R size_i|), the non-uniform scale that makes
// A(box i) = box j exactly. The analogy nodes' Similarity has one scale; a box map needs three, so it has its own type.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "nodes/exchange/part_box.h"

namespace scanfill {

// The 24 rotations of the cube (signed permutation matrices with determinant +1), the identity first, then by
// increasing angle.
const std::vector<Eigen::Matrix3d>& axis_rotations();

struct BoxTransform {
  int source_box = -1;  // i, in the source's boxes
  int target_box = -1;  // j, in the target's boxes
  int rotation = 0;     // index in axis_rotations()
  Eigen::Matrix3d rotation_matrix = Eigen::Matrix3d::Identity();
  Eigen::Vector3d scales = Eigen::Vector3d::Ones();  // D's diagonal, > 0
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();

  Eigen::Matrix3d linear() const { return scales.asDiagonal() * rotation_matrix; }
  Eigen::Vector3d apply(const Eigen::Vector3d& x) const { return linear() * x + translation; }
  // A normal follows the inverse transpose, (D R)^-T = D^-1 R.
  Eigen::Vector3d apply_normal(const Eigen::Vector3d& n) const {
    return (scales.cwiseInverse().asDiagonal() * rotation_matrix * n).normalized();
  }
  // The image of an axis-aligned box: axis-aligned again, since R permutes the axes.
  PartBox apply(const PartBox& box) const;
  // Rotation angle of R, radians.
  double angle() const;
  // Variance of log d_k: 0 for a uniform scale, the same for a stretch and the matching squash.
  double distortion() const;
  // Mean of log d_k: the uniform part of the scale, 0 for a rigid map.
  double log_scale() const;
};

// A maps source box i onto target box j with rotation `rotation` (an index in axis_rotations()).
BoxTransform box_transform(const PartBox& source, int i, const PartBox& target, int j, int rotation);

// Distance from p to the surface of `box` (inside or out).
double distance_to_box_surface(const PartBox& box, const Eigen::Vector3d& p);

// How deep p lies in `box`: the distance to its surface inside, minus the distance to it outside.
double depth_in_box(const PartBox& box, const Eigen::Vector3d& p);

}  // namespace scanfill
