#include "nodes/curves/sample_curves.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numeric>

#include "nodes/core/errors.h"
#include "nodes/core/kdtree.h"

namespace scanfill {
namespace {

// A polyline parameterised by arc length.
class ArcCurve {
 public:
  explicit ArcCurve(const Polyline& c) : c_(c), cum_(size_t(c.points.cols() + (c.closed ? 1 : 0)), 0.0) {
    for (size_t i = 1; i < cum_.size(); ++i) cum_[i] = cum_[i - 1] + (vertex(i) - vertex(i - 1)).norm();
  }
  double length() const { return cum_.back(); }
  bool closed() const { return c_.closed; }
  // The point at arc length s: wrapped on a closed curve, clamped on an open one.
  Eigen::Vector2d at(double s) const {
    const double L = length();
    s = c_.closed ? s - L * std::floor(s / L) : std::clamp(s, 0.0, L);
    const size_t i = size_t(std::upper_bound(cum_.begin(), cum_.end(), s) - cum_.begin());
    const size_t a = std::min(i, cum_.size() - 1) - 1 + (i == 0), b = a + 1;
    const double span = cum_[b] - cum_[a];
    const double u = span > 0 ? (s - cum_[a]) / span : 0.0;
    return (1 - u) * vertex(a) + u * vertex(b);
  }

 private:
  Eigen::Vector2d vertex(size_t i) const { return c_.points.col(Eigen::Index(i % size_t(c_.points.cols()))); }
  const Polyline& c_;
  std::vector<double> cum_;
};

double signed_area(const Polyline& c) {
  double a = 0;
  const Eigen::Index n = c.points.cols();
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Vector2d p = c.points.col(i), q = c.points.col((i + 1) % n);
    a += p.x() * q.y() - q.x() * p.y();
  }
  return 0.5 * a;
}

double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

struct Frame2 {
  Eigen::Vector2d tangent;
  double curvature = 0;  // turning to the left per unit length
};

// Tangent and signed (left-turning) curvature at arc length s, from the stencil s - h, s, s + h.
Frame2 frame_at(const ArcCurve& c, double s, double h) {
  const double a = c.closed() ? s - h : std::max(0.0, s - h), b = c.closed() ? s + h : std::min(c.length(), s + h);
  const Eigen::Vector2d p0 = c.at(a), p1 = c.at(s), p2 = c.at(b);
  Frame2 f;
  f.tangent = p2 - p0;
  if (f.tangent.norm() == 0) f.tangent = c.at(s + 1e-6 * c.length()) - c.at(s - 1e-6 * c.length());
  f.tangent.normalize();
  const Eigen::Vector2d u = p1 - p0, v = p2 - p1;
  if (u.norm() > 0 && v.norm() > 0) f.curvature = std::atan2(cross(u, v), u.dot(v)) / (0.5 * (u.norm() + v.norm()));
  return f;
}

// +1 or -1 per curve: the normal (t.y, -t.x) times this points outward (closed) or away from `centre` (open).
double orientation(const Polyline& c, const ArcCurve& arc, const Eigen::Vector2d& centre, double h) {
  if (c.closed) return signed_area(c) >= 0 ? 1.0 : -1.0;
  double away = 0;
  const int steps = 64;
  for (int i = 0; i <= steps; ++i) {
    const double s = arc.length() * i / steps;
    const Eigen::Vector2d t = frame_at(arc, s, h).tangent;
    away += Eigen::Vector2d(t.y(), -t.x()).dot(arc.at(s) - centre);
  }
  return away >= 0 ? 1.0 : -1.0;
}

}  // namespace

double curve_spacing(double length, const CurveSampleOptions& options) {
  return options.spacing > 0 ? options.spacing : length / double(options.count);
}

PointSet curve_vertices(const Curves& curves) {
  Index n = 0;
  for (const auto& c : curves) n += c.points.cols();
  Eigen::Matrix3Xd p = Eigen::Matrix3Xd::Zero(3, n);
  Index at = 0;
  for (const auto& c : curves) {
    p.block(0, at, 2, c.points.cols()) = c.points;
    at += c.points.cols();
  }
  return PointSet(std::move(p));
}

CurveSamples sample_curves(const Curves& curves, double spacing, const CurveSampleOptions& options) {
  if (curves.empty()) throw InputError("the drawing has no curves");
  if (!(spacing > 0)) throw InputError("curve sample spacing must be > 0");
  const PointSet vertices = curve_vertices(curves);
  const Eigen::Vector2d centre = vertices.positions().topRows<2>().rowwise().mean();
  const double h = options.curvature_window * spacing;
  std::vector<Eigen::Vector2d> pos, nrm;
  std::vector<double> k;
  CurveSamples out;
  for (size_t ci = 0; ci < curves.size(); ++ci) {
    const ArcCurve arc(curves[ci]);
    const double L = arc.length(), sign = orientation(curves[ci], arc, centre, h);
    out.length += L;
    out.closed.push_back(curves[ci].closed ? 1 : 0);
    const Index steps = std::max<Index>(1, Index(std::llround(L / spacing)));
    const Index n = curves[ci].closed ? std::max<Index>(steps, 3) : steps + 1;
    const double step = L / double(curves[ci].closed ? n : n - 1);
    for (Index i = 0; i < n; ++i) {
      const double s = double(i) * step;
      const Frame2 f = frame_at(arc, s, h);
      pos.push_back(arc.at(s));
      nrm.push_back(sign * Eigen::Vector2d(f.tangent.y(), -f.tangent.x()));
      k.push_back(sign * f.curvature);
      out.curve.push_back(std::int32_t(ci));
      out.arc.push_back(s);
    }
  }
  if (pos.size() < 16)
    throw InputError("only " + std::to_string(pos.size()) + " curve samples at spacing " + std::to_string(spacing) +
                     " (at least 16 needed: use a smaller curves.spacing)");
  const Index N = Index(pos.size());
  Eigen::Matrix3Xd P = Eigen::Matrix3Xd::Zero(3, N), Nn = P, D = P;
  Eigen::Matrix2Xd K = Eigen::Matrix2Xd::Zero(2, N);
  for (Index i = 0; i < N; ++i) {
    P.col(i).head<2>() = pos[size_t(i)];
    Nn.col(i).head<2>() = nrm[size_t(i)];
    D.col(i) = Eigen::Vector3d::UnitZ().cross(Eigen::Vector3d(Nn.col(i)));
    K(0, i) = k[size_t(i)];
  }
  out.samples = PointSet(std::move(P));
  out.samples.set_normals(std::move(Nn));
  out.samples.set_curvatures(std::move(K));
  out.samples.set_directions(std::move(D));
  out.spacing = spacing;
  return out;
}

namespace {

// One target curve's points in walking order: from the first in parameter order, each step to the nearest point not
// yet taken within `gap` (ties by index), else to the next untaken one in parameter order. Detail that folds back
// along the target's curve (a serif's hook, a wave taller than it is wide) is so followed along itself, where an
// order by parameter alone would zigzag across it.
std::vector<Index> walk(const std::vector<Index>& order, const Eigen::Matrix3Xd& flat, double gap) {
  const size_t n = order.size();
  Eigen::Matrix3Xd p(3, Eigen::Index(n));
  for (size_t j = 0; j < n; ++j) p.col(Eigen::Index(j)) = flat.col(order[j]);
  KdTree tree;
  tree.build(p);
  std::vector<char> taken(n, 0);
  std::vector<Index> out;
  std::vector<Neighbor> near;
  size_t first_untaken = 0;
  Index at = -1;
  for (size_t step = 0; step < n; ++step) {
    Index pick = -1;
    double best = 0;
    if (at >= 0) tree.radius(p.col(at), gap, near);
    for (const Neighbor& q : at >= 0 ? near : std::vector<Neighbor>{})
      if (!taken[size_t(q.index)] &&
          (pick < 0 || std::make_pair(q.distance2, Index(q.index)) < std::make_pair(best, pick)))
        pick = q.index, best = q.distance2;
    if (pick < 0) {
      while (taken[first_untaken]) ++first_untaken;
      pick = Index(first_untaken);
    }
    taken[size_t(pick)] = 1;
    out.push_back(order[size_t(pick)]);
    at = pick;
  }
  return out;
}

// One target curve's points, walked (above), cut where consecutive points lie more than `gap` apart, runs whose ends
// meet joined again; a single run round a closed curve is closed.
void runs_of_curve(const std::vector<Index>& order, const Eigen::Matrix3Xd& flat, bool closed, double gap,
                   Curves& out) {
  std::vector<std::vector<Index>> runs{{}};
  for (const Index i : walk(order, flat, gap)) {
    if (!runs.back().empty() && (flat.col(i) - flat.col(runs.back().back())).norm() > gap) runs.emplace_back();
    runs.back().push_back(i);
  }
  const auto meets = [&](Index a, Index b) { return (flat.col(a) - flat.col(b)).norm() <= gap; };
  // Runs whose ends meet are one (the seam of a closed curve, or a walk that set off backwards): joined, turned as
  // needed, until no two meet.
  const auto join = [&](std::vector<Index>& a, std::vector<Index>& b) {
    if (meets(a.front(), b.front()) || meets(a.front(), b.back())) std::reverse(a.begin(), a.end());
    if (!meets(a.back(), b.front()) && meets(a.back(), b.back())) std::reverse(b.begin(), b.end());
    if (!meets(a.back(), b.front())) return false;
    a.insert(a.end(), b.begin(), b.end());
    return true;
  };
  for (bool joined = true; joined;) {
    joined = false;
    for (size_t a = 0; a < runs.size() && !joined; ++a)
      for (size_t b = a + 1; b < runs.size() && !joined; ++b)
        if ((joined = join(runs[a], runs[b]))) runs.erase(runs.begin() + std::ptrdiff_t(b));
  }
  const bool round = closed && runs.size() == 1 && runs[0].size() >= 3 && meets(runs[0].back(), runs[0].front());
  for (const auto& run : runs) {
    if (run.size() < 2) continue;
    Polyline c;
    c.points.resize(2, Eigen::Index(run.size()));
    for (size_t j = 0; j < run.size(); ++j) c.points.col(Eigen::Index(j)) = flat.col(run[j]).head<2>();
    c.closed = round;
    out.push_back(std::move(c));
  }
}

}  // namespace

Curves order_into_curves(const Eigen::Matrix3Xd& points, const CurveSamples& target,
                         const CurveSampleOptions& options) {
  const PointSet& T = target.samples;
  KdTree tree;
  tree.build(T.positions());
  std::vector<std::int32_t> nearest;
  std::vector<double> d2;
  Eigen::Matrix3Xd flat = points;
  flat.row(2).setZero();
  nearest_each(tree, flat, nearest, d2);
  // Key per point: (curve, parameter); the parameter is the nearest sample's arc plus the offset along its tangent.
  std::vector<std::pair<std::int32_t, double>> key(size_t(points.cols()));
  for (Index i = 0; i < points.cols(); ++i) {
    const std::int32_t t = nearest[size_t(i)];
    const Eigen::Vector3d tangent = T.directions().col(t);
    key[size_t(i)] = {target.curve[size_t(t)],
                      target.arc[size_t(t)] + (flat.col(i) - T.positions().col(t)).dot(tangent)};
  }
  std::vector<Index> order(size_t(points.cols()));
  std::iota(order.begin(), order.end(), Index(0));
  std::stable_sort(order.begin(), order.end(), [&](Index a, Index b) { return key[size_t(a)] < key[size_t(b)]; });
  Curves out;
  for (size_t b = 0; b < order.size();) {
    size_t e = b;
    const std::int32_t curve = key[size_t(order[b])].first;
    while (e < order.size() && key[size_t(order[e])].first == curve) ++e;
    runs_of_curve({order.begin() + Eigen::Index(b), order.begin() + Eigen::Index(e)}, flat,
                  target.closed[size_t(curve)] != 0, options.gap * target.spacing, out);
    b = e;
  }
  return out;
}

}  // namespace scanfill
