#include "nodes/core/surface_elements.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <vector>

#include "nodes/core/kdtree.h"

namespace scanfill {
namespace {

constexpr int kNeighbours = 12;

SurfaceElements face_elements(const PointSet& mesh) {
  const Eigen::Matrix3Xd& P = mesh.positions();
  const Matrix3Xi& F = mesh.faces();
  SurfaceElements e;
  e.points.resize(3, F.cols());
  e.normals.resize(3, F.cols());
  e.weights.resize(F.cols());
  Index m = 0;
  for (Index f = 0; f < F.cols(); ++f) {
    const Eigen::Vector3d a = P.col(F(0, f)), b = P.col(F(1, f)), c = P.col(F(2, f));
    const Eigen::Vector3d n = (b - a).cross(c - a);
    if (!(n.norm() > 0)) continue;
    e.points.col(m) = (a + b + c) / 3;
    e.normals.col(m) = n.normalized();
    e.weights(m++) = n.norm() / 2;
  }
  e.points.conservativeResize(3, m);
  e.normals.conservativeResize(3, m);
  e.weights.conservativeResize(m);
  return e;
}

// The direction in which a point and its neighbours (graph row `row`, -1 for none) spread least; zero when fewer than
// three neighbours. Summed relative to the point, so that coordinates far from the origin (a georeferenced scan) keep
// their precision.
Eigen::Vector3d flattest_direction(const Eigen::Matrix3Xd& P, Index i, const std::int32_t* row) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  Eigen::Matrix3d outer = Eigen::Matrix3d::Zero();
  int n = 1;
  for (int k = 0; k < kNeighbours; ++k)
    if (row[k] >= 0) {
      const Eigen::Vector3d d = P.col(row[k]) - P.col(i);
      sum += d, outer += d * d.transpose(), ++n;
    }
  if (n < 4) return Eigen::Vector3d::Zero();
  const Eigen::Vector3d mean = sum / n;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(outer / n - mean * mean.transpose());
  return eig.eigenvectors().col(0);
}

}  // namespace

SurfaceElements surface_elements(const PointSet& model, Index most) {
  if (model.faces().cols() > 0) return face_elements(model);
  const Index stride = std::max<Index>(1, (model.size() + most - 1) / std::max<Index>(1, most));
  Eigen::Matrix3Xd P(3, (model.size() + stride - 1) / stride);
  for (Index i = 0; i < P.cols(); ++i) P.col(i) = model.positions().col(i * stride);
  SurfaceElements e;
  e.points.resize(3, P.cols());
  e.normals.resize(3, P.cols());
  Index m = 0;
  const auto keep = [&](Index i, const Eigen::Vector3d& n) {
    if (!(n.norm() > 0.5)) return;
    e.points.col(m) = P.col(i);
    e.normals.col(m++) = n.normalized();
  };
  if (model.has_normals()) {
    for (Index i = 0; i < P.cols(); ++i) keep(i, model.normals().col(i * stride));
  } else {
    KdTree tree;
    tree.build(P);
    const std::vector<std::int32_t> graph = knn_graph(tree, P, kNeighbours);
    for (Index i = 0; i < P.cols(); ++i) keep(i, flattest_direction(P, i, &graph[size_t(i * kNeighbours)]));
  }
  e.points.conservativeResize(3, m);
  e.normals.conservativeResize(3, m);
  e.weights = Eigen::VectorXd::Ones(m);
  return e;
}

}  // namespace scanfill
