#include "nodes/input/box_axes.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "nodes/core/kdtree.h"

namespace scanfill {
namespace {

constexpr Index kMostPoints = 20000;
constexpr int kNeighbours = 12;
constexpr int kStarts = 64;
constexpr int kSteps = 30;
const double kPulls = std::cos(25 * M_PI / 180);  // a normal this near an axis pulls it
const double kHolds = std::cos(10 * M_PI / 180);  // and this near, counts for it
constexpr double kKeepSquare = 0.97;

struct Directions {
  std::vector<Eigen::Vector3d> normal;
  std::vector<double> weight;
};

Directions face_normals(const PointSet& mesh) {
  Directions d;
  const auto& P = mesh.positions();
  for (Index f = 0; f < mesh.faces().cols(); ++f) {
    const Eigen::Vector3d n = (P.col(mesh.faces()(1, f)) - P.col(mesh.faces()(0, f)))
                                  .cross(P.col(mesh.faces()(2, f)) - P.col(mesh.faces()(0, f)));
    if (!(n.norm() > 0)) continue;
    d.normal.push_back(n.normalized());
    d.weight.push_back(n.norm() / 2);
  }
  return d;
}

// Each (strided) point's normal: the direction its nearest neighbours spread least in.
Directions point_normals(const PointSet& cloud) {
  const Index stride = std::max<Index>(1, (cloud.size() + kMostPoints - 1) / kMostPoints);
  Eigen::Matrix3Xd P(3, (cloud.size() + stride - 1) / stride);
  for (Index i = 0; i < P.cols(); ++i) P.col(i) = cloud.positions().col(i * stride);
  KdTree tree;
  tree.build(P);
  const std::vector<std::int32_t> graph = knn_graph(tree, P, kNeighbours);
  Directions d;
  for (Index i = 0; i < P.cols(); ++i) {
    Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
    Eigen::Vector3d mean = P.col(i);
    int n = 1;
    for (int k = 0; k < kNeighbours; ++k)
      if (const auto j = graph[size_t(i * kNeighbours + k)]; j >= 0) mean += P.col(j), ++n;
    mean /= n;
    C += (P.col(i) - mean) * (P.col(i) - mean).transpose();
    for (int k = 0; k < kNeighbours; ++k)
      if (const auto j = graph[size_t(i * kNeighbours + k)]; j >= 0)
        C += (P.col(j) - mean) * (P.col(j) - mean).transpose();
    if (n < 4) continue;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(C);
    d.normal.push_back(eig.eigenvectors().col(0));
    d.weight.push_back(1.0);
  }
  return d;
}

// The frame each normal near an axis pulls towards itself, in kSteps orthogonal Procrustes steps.
Eigen::Matrix3d pulled_frame(const Directions& d, Eigen::Matrix3d R) {
  for (int step = 0; step < kSteps; ++step) {
    Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
    for (size_t i = 0; i < d.normal.size(); ++i) {
      const Eigen::Vector3d c = R.transpose() * d.normal[i];
      Index k;
      const double along = c.cwiseAbs().maxCoeff(&k);
      if (along >= kPulls) M.col(k) += d.weight[i] * (c(k) < 0 ? -1.0 : 1.0) * d.normal[i];
    }
    const Eigen::JacobiSVD<Eigen::Matrix3d> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::Matrix3d U = svd.matrixU();
    if ((U * svd.matrixV().transpose()).determinant() < 0) U.col(2) *= -1;
    R = U * svd.matrixV().transpose();
  }
  return R;
}

// The weight of the normals within kHolds of one of the frame's axes.
double held_weight(const Directions& d, const Eigen::Matrix3d& R) {
  double w = 0;
  for (size_t i = 0; i < d.normal.size(); ++i)
    if ((R.transpose() * d.normal[i]).cwiseAbs().maxCoeff() >= kHolds) w += d.weight[i];
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
  const Directions d = model.faces().cols() > 0 ? face_normals(model) : point_normals(model);
  if (d.normal.empty()) return Eigen::Matrix3d::Identity();
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
