#include "nodes/input/box_axes.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <random>

#include "nodes/core/surface_elements.h"

namespace scanfill {
namespace {

constexpr int kStarts = 64;
constexpr int kSteps = 30;
const double kPulls = std::cos(25 * M_PI / 180);  // a normal this near an axis pulls it
const double kHolds = std::cos(10 * M_PI / 180);  // and this near, counts for it
constexpr double kKeepSquare = 0.97;

// The frame each normal near an axis pulls towards itself, in at most kSteps orthogonal Procrustes steps.
Eigen::Matrix3d pulled_frame(const SurfaceElements& d, Eigen::Matrix3d R) {
  for (int step = 0; step < kSteps; ++step) {
    Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
    for (Index i = 0; i < d.size(); ++i) {
      const Eigen::Vector3d c = R.transpose() * d.normals.col(i);
      Index k;
      const double along = c.cwiseAbs().maxCoeff(&k);
      if (along >= kPulls) M.col(k) += d.weights(i) * (c(k) < 0 ? -1.0 : 1.0) * d.normals.col(i);
    }
    const Eigen::JacobiSVD<Eigen::Matrix3d> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::Matrix3d U = svd.matrixU();
    if ((U * svd.matrixV().transpose()).determinant() < 0) U.col(2) *= -1;
    const Eigen::Matrix3d next = U * svd.matrixV().transpose();
    if ((next - R).cwiseAbs().maxCoeff() < 1e-12) return next;  // settled: the same normals pull it again
    R = next;
  }
  return R;
}

// The weight of the normals within kHolds of one of the frame's axes.
double held_weight(const SurfaceElements& d, const Eigen::Matrix3d& R) {
  double w = 0;
  for (Index i = 0; i < d.size(); ++i)
    if ((R.transpose() * d.normals.col(i)).cwiseAbs().maxCoeff() >= kHolds) w += d.weights(i);
  return w;
}

// Of the 24 frames with the same axes up to order and sign, the one turned least from the model's own.
Eigen::Matrix3d nearest_to_square(const Eigen::Matrix3d& R) {
  int order[3] = {0, 1, 2};
  Eigen::Matrix3d best = R;
  double best_trace = -4;
  do {
    for (int signs = 0; signs < 8; ++signs) {
      Eigen::Matrix3d Q;
      for (int c = 0; c < 3; ++c) Q.col(c) = ((signs >> c) & 1 ? -1.0 : 1.0) * R.col(order[c]);
      if (Q.determinant() > 0 && Q.trace() > best_trace) best_trace = Q.trace(), best = Q;
    }
  } while (std::next_permutation(order, order + 3));
  return best;
}

}  // namespace

Eigen::Matrix3d box_axes(const PointSet& model) {
  const SurfaceElements d = surface_elements(model);
  if (d.size() == 0) return Eigen::Matrix3d::Identity();
  std::mt19937_64 rng(7);
  std::normal_distribution<double> gauss;
  Eigen::Matrix3d best = Eigen::Matrix3d::Identity();
  double best_weight = -1;
  for (int s = 0; s <= kStarts; ++s) {
    Eigen::Matrix3d start = Eigen::Matrix3d::Identity();
    if (s > 0)
      start = Eigen::Quaterniond(gauss(rng), gauss(rng), gauss(rng), gauss(rng)).normalized().toRotationMatrix();
    const Eigen::Matrix3d R = pulled_frame(d, start);
    if (const double w = held_weight(d, R); w > best_weight) best_weight = w, best = R;
  }
  if (held_weight(d, Eigen::Matrix3d::Identity()) >= kKeepSquare * best_weight) return Eigen::Matrix3d::Identity();
  return nearest_to_square(best);
}

}  // namespace scanfill
