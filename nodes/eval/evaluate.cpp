#include "nodes/eval/evaluate.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include "nodes/core/errors.h"
#include "nodes/core/kdtree.h"
#include "nodes/features/estimate_features.h"
#include "nodes/sample/sample.h"

namespace scanfill {
namespace {

// Points and unit normals of a surface: area-uniform random points of a mesh, or a cloud's own points.
PointSet surface_points(const PointSet& in, const EvalOptions& o) {
  if (!in.has_faces()) {
    if (in.has_normals() || in.size() < 17) return in;
    FeaturesOptions f;
    f.smooth_directions = false;
    return estimate_features(in, f).points;
  }
  return random_surface_points(in, o.surface_samples, o.seed);
}

struct Directed {
  std::vector<double> distance;  // per point of `from`, to the nearest point of `to`
  std::vector<double> cosine;    // |n . n_nearest|
};

Directed directed(const PointSet& from, const PointSet& to, const KdTree& to_tree) {
  Directed d;
  d.distance.resize(static_cast<size_t>(from.size()));
  d.cosine.resize(static_cast<size_t>(from.size()));
  tbb::parallel_for(tbb::blocked_range<Index>(0, from.size(), 4096), [&](const tbb::blocked_range<Index>& r) {
    for (Index i = r.begin(); i != r.end(); ++i) {
      std::int32_t j;
      double d2;
      to_tree.knn(from.positions().col(i), 1, &j, &d2);
      d.distance[size_t(i)] = std::sqrt(d2);
      d.cosine[size_t(i)] = std::abs(from.normals().col(i).dot(to.normals().col(j)));
    }
  });
  return d;
}

double mean(const std::vector<double>& v, bool squared = false) {
  double s = 0;
  for (double x : v) s += squared ? x * x : x;
  return v.empty() ? 0 : s / double(v.size());
}

double share_within(const std::vector<double>& v, double tau) {
  return v.empty() ? 0
                   : double(std::count_if(v.begin(), v.end(), [tau](double x) { return x <= tau; })) / double(v.size());
}

}  // namespace

EvalResult evaluate(const PointSet& output, const PointSet& reference, const EvalOptions& o, const PointSet* scan,
                    const PointSet* template_shape) {
  if (output.empty() || reference.empty()) throw InputError("evaluation needs a non-empty output and reference");
  if ((scan == nullptr) != (template_shape == nullptr))
    throw InputError("unseen-detail recall needs both the scan and the template");
  EvalResult r;
  r.tau = o.threshold * bounding_box(reference.positions()).diagonal();
  const PointSet O = surface_points(output, o), R = surface_points(reference, o);
  KdTree o_tree, r_tree;
  o_tree.build(O.positions());
  r_tree.build(R.positions());
  const Directed o_to_r = directed(O, R, r_tree), r_to_o = directed(R, O, o_tree);
  r.chamfer_l1 = 0.5 * (mean(o_to_r.distance) + mean(r_to_o.distance));
  r.chamfer_l2 = 0.5 * (mean(o_to_r.distance, true) + mean(r_to_o.distance, true));
  r.precision = share_within(o_to_r.distance, r.tau);
  r.recall = share_within(r_to_o.distance, r.tau);
  r.fscore = r.precision + r.recall > 0 ? 2 * r.precision * r.recall / (r.precision + r.recall) : 0;
  r.hausdorff = std::max(*std::max_element(o_to_r.distance.begin(), o_to_r.distance.end()),
                         *std::max_element(r_to_o.distance.begin(), r_to_o.distance.end()));
  r.normal_consistency = 0.5 * (mean(o_to_r.cosine) + mean(r_to_o.cosine));
  if (scan) {
    const PointSet S = surface_points(*scan, o), T = surface_points(*template_shape, o);
    KdTree s_tree, t_tree;
    s_tree.build(S.positions());
    t_tree.build(T.positions());
    Index detail = 0, reached = 0;
    for (Index i = 0; i < R.size(); ++i) {
      std::int32_t j;
      double d2s, d2t;
      t_tree.knn(R.positions().col(i), 1, &j, &d2t);
      s_tree.knn(R.positions().col(i), 1, &j, &d2s);
      if (d2t <= r.tau * r.tau || d2s <= r.tau * r.tau) continue;
      ++detail;
      reached += r_to_o.distance[size_t(i)] <= r.tau;
    }
    r.unseen_detail_points = detail;
    r.unseen_detail_recall = detail ? double(reached) / double(detail) : 0.0;
  }
  return r;
}

PointSet template_blend(const PointSet& scan, const PointSet& template_shape, double gap, const EvalOptions& options) {
  const PointSet t = template_shape.has_faces()
                         ? random_surface_points(template_shape, options.surface_samples, options.seed)
                         : template_shape;
  KdTree tree;
  tree.build(scan.positions());
  std::vector<std::int32_t> nearest;
  std::vector<double> d2;
  nearest_each(tree, t.positions(), nearest, d2);
  std::vector<Eigen::Vector3d> p;
  for (Index i = 0; i < scan.size(); ++i) p.push_back(scan.positions().col(i));
  for (Index i = 0; i < t.size(); ++i)
    if (d2[size_t(i)] > gap * gap) p.push_back(t.positions().col(i));
  Eigen::Matrix3Xd P(3, Index(p.size()));
  for (size_t i = 0; i < p.size(); ++i) P.col(Index(i)) = p[i];
  return PointSet(std::move(P));
}

}  // namespace scanfill
