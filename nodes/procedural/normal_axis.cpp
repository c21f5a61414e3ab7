#include "nodes/procedural/normal_axis.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

#include "nodes/core/errors.h"

namespace scanfill {
namespace {

constexpr int kReweightings = 10;
constexpr double kNearAxis = 1e-9;  // relative to the elements' spread: an element on the axis has no plane
const double kNearCoordinate = std::cos(25 * M_PI / 180);  // a coordinate axis this near the fitted one is tried
constexpr double kNearlyAsWell = 1.1;                      // and taken where its normals meet it nearly as well
constexpr double kNearlyAsWellBySine = 0.005;

// Each element's sine (normal_axis_misfit's), and -1 for elements on the axis.
Eigen::VectorXd sines(const SurfaceElements& s, const RevolutionAxis& axis, double scale) {
  Eigen::VectorXd out(s.size());
  for (Index i = 0; i < s.size(); ++i) {
    const Eigen::Vector3d d = s.points.col(i) - axis.centre;
    const Eigen::Vector3d across = axis.direction.cross(d);
    const double r = across.norm();
    out(i) = r > kNearAxis * scale ? std::abs(s.normals.col(i).dot(across)) / r : -1;
  }
  return out;
}

// The median of the values >= 0, each counted with its weight; 0 when there are none.
double weighted_median(const Eigen::VectorXd& value, const Eigen::VectorXd& weight) {
  std::vector<Index> order;
  double total = 0;
  for (Index i = 0; i < value.size(); ++i)
    if (value(i) >= 0 && weight(i) > 0) order.push_back(i), total += weight(i);
  std::sort(order.begin(), order.end(), [&](Index a, Index b) { return value(a) < value(b); });
  double sum = 0;
  for (const Index i : order)
    if ((sum += weight(i)) >= total / 2) return value(i);
  return 0;
}

double spread(const SurfaceElements& s) {
  return bounding_box(s.points).diagonal();
}

// `a` pointing to the positive side of the coordinate it is largest in.
Eigen::Vector3d positive(const Eigen::Vector3d& a) {
  Index k;
  a.cwiseAbs().maxCoeff(&k);
  return a(k) < 0 ? Eigen::Vector3d(-a) : a;
}

// One weighted least-squares solve for the Plücker coordinates, about the origin `o`: the axis; its direction `fixed`
// where that is given (a non-zero vector), else solved for.
RevolutionAxis solve_axis(const SurfaceElements& s, const Eigen::VectorXd& w, const Eigen::Vector3d& o,
                          const Eigen::Vector3d& fixed) {
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero(), B = Eigen::Matrix3d::Zero(), C = Eigen::Matrix3d::Zero();
  for (Index i = 0; i < s.size(); ++i) {
    const Eigen::Vector3d n = s.normals.col(i), m = (s.points.col(i) - o).cross(n);
    A += w(i) * m * m.transpose(), B += w(i) * m * n.transpose(), C += w(i) * n * n.transpose();
  }
  // C is singular where the normals lie in a plane (a cylinder's): its pseudo-inverse leaves the moment's component
  // along the axis, which no element constrains, at zero.
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> c(C);
  Eigen::Vector3d inverse = Eigen::Vector3d::Zero();
  for (int k = 0; k < 3; ++k)
    if (c.eigenvalues()(k) > 1e-9 * c.eigenvalues()(2)) inverse(k) = 1 / c.eigenvalues()(k);
  const Eigen::Matrix3d Cinv = c.eigenvectors() * inverse.asDiagonal() * c.eigenvectors().transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> reduced(A - B * Cinv * B.transpose());
  const Eigen::Vector3d a = fixed.norm() > 0 ? fixed.normalized() : reduced.eigenvectors().col(0).normalized();
  const Eigen::Vector3d moment = -Cinv * B.transpose() * a;  // c x a
  return {o + a.cross(moment), a};
}

// The axis solve_axis gives, reweighted kReweightings times by each element's sine (a Cauchy weight at twice the
// sines' robust spread); its centre is the axis's point nearest the elements' mean.
RevolutionAxis reweighted_axis(const SurfaceElements& surface, const Eigen::Vector3d& fixed) {
  const Eigen::Vector3d mean = surface.points * surface.weights / surface.weights.sum();
  const double size = spread(surface);
  Eigen::VectorXd w = surface.weights;
  RevolutionAxis axis;
  for (int round = 0; round <= kReweightings; ++round) {
    axis = solve_axis(surface, w, mean, fixed);
    if (round == kReweightings) break;
    const Eigen::VectorXd s = sines(surface, axis, size);
    const double scale = std::max(1.4826 * weighted_median(s, surface.weights), 1e-3);
    for (Index i = 0; i < s.size(); ++i)
      w(i) = s(i) < 0 ? 0.0 : surface.weights(i) / (1 + (s(i) / (2 * scale)) * (s(i) / (2 * scale)));
  }
  const Eigen::Vector3d d = mean - axis.centre;
  axis.centre += d.dot(axis.direction) * axis.direction;
  return axis;
}

}  // namespace

double normal_axis_misfit(const SurfaceElements& surface, const RevolutionAxis& axis) {
  return weighted_median(sines(surface, axis, spread(surface)), surface.weights);
}

RevolutionAxis axis_from_normals(const SurfaceElements& surface) {
  if (surface.size() < 16) throw InputError("an axis from normals needs at least 16 surface elements");
  const RevolutionAxis free = reweighted_axis(surface, Eigen::Vector3d::Zero());
  const double misfit = normal_axis_misfit(surface, free);
  RevolutionAxis best = free;
  double best_misfit = kNearlyAsWell * misfit + kNearlyAsWellBySine;
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d e = Eigen::Vector3d::Unit(k);
    if (std::abs(free.direction.dot(e)) < kNearCoordinate) continue;
    const RevolutionAxis along = reweighted_axis(surface, e);
    if (const double m = normal_axis_misfit(surface, along); m <= best_misfit) best = along, best_misfit = m;
  }
  best.direction = positive(best.direction);
  return best;
}

RevolutionAxis axis_along(const SurfaceElements& surface, const Eigen::Vector3d& direction) {
  if (surface.size() < 16) throw InputError("an axis from normals needs at least 16 surface elements");
  return reweighted_axis(surface, direction);
}

}  // namespace scanfill
