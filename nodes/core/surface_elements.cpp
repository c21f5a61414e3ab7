#include "nodes/core/surface_elements.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_set>
#include <vector>

#include "nodes/core/kdtree.h"

namespace scanfill {
namespace {

constexpr int kNeighbours = 12;
// Points whose normals are estimated here, at most: a grid this coarse gives 12 neighbours a reach wider than a stereo
// or Kinect scan's noise (PCL's table-top mug: its axis 35 degrees off from every point, 12 from 4000).
constexpr Index kEstimatedNormals = 4000;

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

// The first point of each occupied cell of a cubic grid whose cell is sized for about `most` points (a surface
// occupies cells in proportion to 1 / size^2; three passes settle the size). Unlike a stride, even on a range image's
// rows: a stride of a row-major organised cloud keeps whole rows, whose PCA neighbourhoods are lines, and a stereo
// scan's noise needs neighbourhoods wider than the sensor's own spacing.
std::vector<std::int32_t> one_per_cell(const Eigen::Matrix3Xd& p, Index most) {
  if (p.cols() <= most) return strided_indices(p.cols(), most);
  const BoundingBox box = bounding_box(p);
  double size = box.diagonal() / std::sqrt(double(std::max<Index>(1, most)));
  std::vector<std::int32_t> out;
  for (int pass = 0; pass < 3 && size > 0; ++pass) {
    std::unordered_set<std::uint64_t> seen;
    out.clear();
    for (Index i = 0; i < p.cols(); ++i) {
      const Eigen::Array3d c = ((p.col(i) - box.min) / size).array().floor();
      const std::uint64_t key = (std::uint64_t(c.x()) << 42) ^ (std::uint64_t(c.y()) << 21) ^ std::uint64_t(c.z());
      if (seen.insert(key).second) out.push_back(std::int32_t(i));
    }
    size *= std::sqrt(double(out.size()) / double(most));
  }
  return out;
}

}  // namespace

SurfaceElements surface_elements(const PointSet& model, Index most) {
  if (model.faces().cols() > 0) return face_elements(model);
  const std::vector<std::int32_t> picked = model.has_normals()
                                               ? strided_indices(model.size(), most)
                                               : one_per_cell(model.positions(), std::min(most, kEstimatedNormals));
  Eigen::Matrix3Xd P(3, Index(picked.size()));
  for (Index i = 0; i < P.cols(); ++i) P.col(i) = model.positions().col(picked[size_t(i)]);
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
    for (Index i = 0; i < P.cols(); ++i) keep(i, model.normals().col(picked[size_t(i)]));
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
