#include "nodes/exchange/box_transform.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>

namespace scanfill {

const std::vector<Eigen::Matrix3d>& axis_rotations() {
  static const std::vector<Eigen::Matrix3d> rotations = [] {
    std::vector<Eigen::Matrix3d> out;
    int perm[3] = {0, 1, 2};
    do {
      for (int signs = 0; signs < 8; ++signs) {
        Eigen::Matrix3d R = Eigen::Matrix3d::Zero();
        for (int r = 0; r < 3; ++r) R(r, perm[r]) = (signs >> r) & 1 ? -1.0 : 1.0;
        if (R.determinant() > 0) out.push_back(R);
      }
    } while (std::next_permutation(perm, perm + 3));
    // By angle (trace = 1 + 2 cos angle, larger first); stable so that the order is fixed.
    std::stable_sort(out.begin(), out.end(),
                     [](const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) { return a.trace() > b.trace(); });
    return out;
  }();
  return rotations;
}

PartBox BoxTransform::apply(const PartBox& box) const {
  const Eigen::Vector3d a = apply(box.min), b = apply(box.max);
  return {a.cwiseMin(b), a.cwiseMax(b)};
}

double BoxTransform::angle() const {
  return std::acos(std::clamp((rotation_matrix.trace() - 1) / 2, -1.0, 1.0));
}

double BoxTransform::distortion() const {
  const Eigen::Array3d l = scales.array().log();
  return (l - l.mean()).square().mean();
}

double BoxTransform::log_scale() const {
  return scales.array().log().mean();
}

BoxTransform box_transform(const PartBox& source, int i, const PartBox& target, int j, int rotation) {
  BoxTransform t;
  t.source_box = i;
  t.target_box = j;
  t.rotation = rotation;
  t.rotation_matrix = axis_rotations()[size_t(rotation)];
  t.scales = target.size().cwiseQuotient((t.rotation_matrix * source.size()).cwiseAbs());
  t.translation = target.centre() - t.linear() * source.centre();
  return t;
}

double depth_in_box(const PartBox& box, const Eigen::Vector3d& p) {
  const Eigen::Vector3d below = box.min - p, above = p - box.max;
  const Eigen::Vector3d outside = below.cwiseMax(above);  // per axis: > 0 outside that slab
  if ((outside.array() <= 0).all()) return -outside.maxCoeff();
  return -outside.cwiseMax(0.0).norm();
}

double distance_to_box_surface(const PartBox& box, const Eigen::Vector3d& p) {
  return std::abs(depth_in_box(box, p));
}

}  // namespace scanfill
