#include "nodes/core/similarity.h"

#include <Eigen/Geometry>

namespace scanfill {

Similarity fit_similarity(const Eigen::Matrix3Xd& from, const Eigen::Matrix3Xd& to, bool allow_scale) {
  Similarity q;
  if (from.cols() < 3 || from.cols() != to.cols()) return q;
  const Eigen::Matrix4d m = Eigen::umeyama(from, to, allow_scale);
  q.rotation = m.topLeftCorner<3, 3>();
  q.scale = allow_scale ? std::cbrt(q.rotation.determinant()) : 1.0;
  q.rotation /= q.scale;
  q.rotation = nearest_rotation(q.rotation);
  q.translation = m.topRightCorner<3, 1>();
  return q;
}

Similarity point_to_plane_step(const Similarity& q, const Eigen::Matrix3Xd& moved, const Eigen::Matrix3Xd& to,
                               const Eigen::Matrix3Xd& normals, bool allow_scale) {
  const Eigen::Index n = moved.cols();
  if (n < 7) return q;
  const Eigen::Vector3d c = moved.rowwise().mean();
  const int u = allow_scale ? 7 : 6;  // unknowns: rotation w, translation tau, scale sigma
  Eigen::Matrix<double, 7, 7> A = Eigen::Matrix<double, 7, 7>::Zero();
  Eigen::Matrix<double, 7, 1> b = Eigen::Matrix<double, 7, 1>::Zero();
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Vector3d p = moved.col(i) - c, nq = normals.col(i);
    Eigen::Matrix<double, 7, 1> J;
    J << p.cross(nq), nq, nq.dot(p);
    const double r = nq.dot(moved.col(i) - to.col(i));
    A.noalias() += J * J.transpose();
    b -= J * r;
  }
  // A little damping: directions no plane constrains (sliding along one flat face) stay put instead of drifting.
  Eigen::MatrixXd Au = A.topLeftCorner(u, u);
  Au.diagonal().array() += 1e-6 * Au.trace() / u + 1e-300;
  const Eigen::VectorXd x = Au.ldlt().solve(b.head(u));
  if (!x.allFinite()) return q;
  const Eigen::Vector3d w = x.head<3>(), tau = x.segment<3>(3);
  const double sigma = allow_scale ? x(6) : 0.0;
  const Eigen::Matrix3d Rw =
      w.norm() > 1e-15 ? Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix() : Eigen::Matrix3d::Identity();
  // D(p) = (1 + sigma) Rw (p - c) + c + tau, composed after q.
  Similarity out;
  out.rotation = nearest_rotation(Rw * q.rotation);
  out.scale = (1 + sigma) * q.scale;
  out.translation = (1 + sigma) * Rw * (q.translation - c) + c + tau;
  return out;
}

double largest_displacement(const Eigen::Matrix3Xd& points, const Similarity& q) {
  double most = 0;
  for (Index i = 0; i < points.cols(); ++i) most = std::max(most, (q.apply(points.col(i)) - points.col(i)).norm());
  return most;
}

PointSet moved_by(const PointSet& points, const Similarity& q) {
  Eigen::Matrix3Xd p(3, points.size()), n(3, points.size());
  for (Index i = 0; i < points.size(); ++i) {
    p.col(i) = q.apply(points.positions().col(i));
    n.col(i) = q.apply_normal(points.normals().col(i));
  }
  PointSet out(std::move(p));
  out.set_normals(std::move(n));
  return out;
}

}  // namespace scanfill
