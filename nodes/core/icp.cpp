#include "nodes/core/icp.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace scanfill {

namespace {

// A motion about the pairs' centroid c as one vector: rotation vector, then translation (D p = R (p - c) + c + tau).
using Motion = Eigen::Matrix<double, 6, 1>;

using Matrix6 = Eigen::Matrix<double, 6, 6>;

// The linearised point-to-plane fit's normal matrices in scaled coordinates (rotation times `length`): every pair's,
// and the trusted pairs' alone.
struct NormalMatrices {
  Matrix6 all = Matrix6::Zero(), trusted = Matrix6::Zero();
};
NormalMatrices normal_matrices(const IcpPairs& pairs, const Eigen::Vector3d& c, double length) {
  NormalMatrices h;
  for (Eigen::Index i = 0; i < pairs.moved.cols(); ++i) {
    const Eigen::Vector3d n = pairs.normals.col(i);
    Motion j;
    j << (pairs.moved.col(i) - c).cross(n) / length, n;
    const Matrix6 jj = j * j.transpose();
    h.all += jj;
    if (pairs.trusted[size_t(i)]) h.trusted += jj;
  }
  return h;
}

// The motions the trusted pairs constrain, as an orthonormal basis in scaled coordinates: the eigenvectors of their
// normal matrix whose eigenvalue is at least kTrustedStiffness of the largest, or whose stiffness is at least
// kTrustedShare of the whole fit's along them (a weak motion that only trusted pairs hold: a blob's turn).
constexpr double kTrustedStiffness = 0.03;
constexpr double kTrustedShare = 0.9;
Eigen::MatrixXd trusted_motions(const NormalMatrices& h) {
  const Eigen::SelfAdjointEigenSolver<Matrix6> eig(h.trusted);
  const double largest = eig.eigenvalues()(5), floor = 1e-9 * h.all.trace() + 1e-300;
  Eigen::MatrixXd basis(6, 0);
  for (int k = 0; k < 6; ++k) {
    const Motion v = eig.eigenvectors().col(k);
    const double own = eig.eigenvalues()(k), whole = v.dot(h.all * v) + floor;
    if ((largest > 0 && own >= kTrustedStiffness * largest) || own >= kTrustedShare * whole) {
      basis.conservativeResize(6, basis.cols() + 1);
      basis.col(basis.cols() - 1) = v;
    }
  }
  return basis;
}

// The rigid step q -> next, kept only along the motions the trusted pairs constrain. A scan's relief pairs with the
// template where their normals disagree (a gear's tooth roots with the faces of a plain annulus it does not see) and
// pulls along motions nothing else holds; this keeps the fit off them. Where every pair is trusted, the step is the
// plain fit's.
Similarity within_trusted_motions(const Similarity& q, const Similarity& next, const IcpPairs& pairs) {
  const Eigen::Vector3d c = pairs.moved.rowwise().mean();
  const double length = std::sqrt((pairs.moved.colwise() - c).colwise().squaredNorm().mean());
  if (!(length > 0)) return next;
  const Similarity d = next.compose(q.inverse());
  const Eigen::AngleAxisd turn(d.rotation);
  Motion x;
  x << turn.angle() * turn.axis() * length, d.translation - c + d.rotation * c;
  const Eigen::MatrixXd basis = trusted_motions(normal_matrices(pairs, c, length));
  const Motion kept = basis * (basis.transpose() * x);
  const Eigen::Vector3d w = kept.head<3>() / length;
  Similarity step;
  step.rotation =
      w.norm() > 1e-15 ? Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix() : Eigen::Matrix3d::Identity();
  step.translation = c + kept.tail<3>() - step.rotation * c;
  Similarity out = step.compose(q);
  out.rotation = nearest_rotation(out.rotation);
  return out;
}

}  // namespace

Similarity icp_step(const Similarity& q, const IcpPairs& pairs, bool point_to_plane, bool allow_scale) {
  if (point_to_plane) {
    const Similarity next = point_to_plane_step(q, pairs.moved, pairs.to, pairs.normals, allow_scale);
    if (allow_scale || pairs.trusted.size() != size_t(pairs.moved.cols())) return next;
    return within_trusted_motions(q, next, pairs);
  }
  const Similarity d = fit_similarity(pairs.moved, pairs.to, allow_scale);
  Similarity next = d.compose(q);
  next.rotation = nearest_rotation(next.rotation);
  return next;
}

Similarity icp(Similarity q, const IcpPairFinder& find_pairs, const IcpOptions& o, const IcpStepDone& step_done) {
  IcpPairs pairs;
  for (int it = 0; it < o.iterations; ++it) {
    find_pairs(q, it, pairs);
    if (pairs.moved.cols() < o.min_pairs) break;
    const Similarity next = icp_step(q, pairs, it >= o.point_to_point_iterations, o.allow_scale);
    const double change = rotation_angle(next.rotation * q.rotation.transpose()) +
                          (next.translation - q.translation).norm() / std::max(pairs.rms, 1e-300);
    q = next;
    if (step_done) step_done(q);
    if (change < o.converged_change) break;
  }
  return q;
}

}  // namespace scanfill
