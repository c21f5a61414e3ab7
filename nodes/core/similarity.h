// A similarity transform x -> s R x + t (R a rotation, s > 0): the paper's simple transforms Q.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <optional>

#include "nodes/core/point_set.h"

namespace scanfill {

struct Similarity {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  double scale = 1.0;

  Eigen::Vector3d apply(const Eigen::Vector3d& p) const { return scale * (rotation * p) + translation; }
  Eigen::Vector3d apply_normal(const Eigen::Vector3d& n) const { return rotation * n; }
  // x -> R^T (x - t) / s
  Similarity inverse() const {
    return Similarity{rotation.transpose(), -(rotation.transpose() * translation) / scale, 1.0 / scale};
  }
  // (this o b)(x) = this(b(x))
  Similarity compose(const Similarity& b) const {
    return Similarity{rotation * b.rotation, scale * (rotation * b.translation) + translation, scale * b.scale};
  }
};

// The rotation nearest to M in the Frobenius norm (SVD projection, det +1).
inline Eigen::Matrix3d nearest_rotation(const Eigen::Matrix3d& M) {
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  if ((svd.matrixU() * svd.matrixV().transpose()).determinant() < 0) D(2, 2) = -1;
  return svd.matrixU() * D * svd.matrixV().transpose();
}

// Angle of a rotation matrix, in radians, in [0, pi].
inline double rotation_angle(const Eigen::Matrix3d& R) {
  return std::acos(std::clamp((R.trace() - 1.0) / 2.0, -1.0, 1.0));
}

// The unit axis of a rotation (z for the identity).
inline Eigen::Vector3d rotation_axis(const Eigen::Matrix3d& R) {
  const Eigen::AngleAxisd aa(R);
  return aa.angle() > 0 ? Eigen::Vector3d(aa.axis()) : Eigen::Vector3d::UnitZ();
}

// R seen in the frame whose axes are the columns of the rotation `axes` (unset: the world's).
inline Eigen::Matrix3d in_frame(const Eigen::Matrix3d& R, const std::optional<Eigen::Matrix3d>& axes) {
  return axes ? Eigen::Matrix3d(axes->transpose() * R * *axes) : R;
}

// True when R is within `tolerance` radians of one of the 24 rotations that map axes to axes (the kappa pi / 2
// rotations the paper's eq. 9 prefers).
inline bool is_axis_rotation(const Eigen::Matrix3d& R, double tolerance) {
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
  for (int r = 0; r < 3; ++r) {
    Eigen::Index c = 0;
    R.row(r).cwiseAbs().maxCoeff(&c);
    A(r, c) = R(r, c) > 0 ? 1 : -1;
  }
  return A.determinant() > 0 && rotation_angle(A.transpose() * R) <= tolerance;
}

// Least-squares similarity (or rigid motion, when allow_scale is false) taking the columns of `from` to those of
// `to` (Umeyama 1991). Returns identity for fewer than 3 points.
Similarity fit_similarity(const Eigen::Matrix3Xd& from, const Eigen::Matrix3Xd& to, bool allow_scale);

// One linearised point-to-plane step (Chen and Medioni 1992, with a scale term): the small similarity D about the
// centroid of `moved` minimising sum ((D moved_i - to_i) . normal_i)^2; returns D q. `moved` = q(from), already
// applied.
Similarity point_to_plane_step(const Similarity& q, const Eigen::Matrix3Xd& moved, const Eigen::Matrix3Xd& to,
                               const Eigen::Matrix3Xd& normals, bool allow_scale);

// The points' positions and normals (which they must have) moved by q; no other attribute.
PointSet moved_by(const PointSet& points, const Similarity& q);

// The farthest q moves any of the points (columns); 0 for none.
double largest_displacement(const Eigen::Matrix3Xd& points, const Similarity& q);

}  // namespace scanfill
