#include "nodes/support/support.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <deque>

#include "nodes/core/icp.h"
#include "nodes/core/kdtree.h"
#include "nodes/support/support_options.h"

namespace scanfill {
namespace {

struct Context {
  const PointSet& source;
  const PointSet& target;
  const KdTree& source_tree;
  const std::vector<std::int32_t>& graph;  // target kNN, graph_k per sample (self excluded)
  int k;
  double max_distance;
  double cos_limit;
};

// Nearest source sample to Q p_t, when t is explained by Q; -1 otherwise.
std::int32_t explained(const Context& c, const Similarity& q, Index t) {
  std::int32_t s;
  double d2;
  c.source_tree.knn(q.apply(c.target.positions().col(t)), 1, &s, &d2);
  if (d2 > c.max_distance * c.max_distance) return -1;
  if (q.apply_normal(c.target.normals().col(t)).dot(c.source.normals().col(s)) < c.cos_limit) return -1;
  return s;
}

// Breadth-first growth from the seeds over the target graph; returns the explained samples, ascending.
std::vector<std::int32_t> grow(const Context& c, const Similarity& q, const std::vector<std::int32_t>& seeds) {
  std::vector<std::uint8_t> seen(static_cast<size_t>(c.target.size()), 0);
  std::vector<std::int32_t> support;
  std::deque<std::int32_t> queue;
  for (const auto t : seeds)
    if (!seen[size_t(t)]) {
      seen[size_t(t)] = 1;
      if (explained(c, q, t) >= 0) queue.push_back(t);
    }
  while (!queue.empty()) {
    const std::int32_t t = queue.front();
    queue.pop_front();
    support.push_back(t);
    for (int a = 0; a < c.k; ++a) {
      const std::int32_t u = c.graph[size_t(t) * size_t(c.k) + size_t(a)];
      if (seen[size_t(u)]) continue;
      seen[size_t(u)] = 1;
      if (explained(c, q, u) >= 0) queue.push_back(u);
    }
  }
  std::sort(support.begin(), support.end());
  return support;
}

// Each mode grown and refined into a supported transform (coarse to fine), in parallel, in mode order.
std::vector<SupportedTransform> grow_all(const PointSet& source, const PointSet& target, const std::vector<Mode>& modes,
                                         double spacing, double mode_accuracy, const SupportOptions& o) {
  KdTree source_tree, target_tree;
  source_tree.build(source.positions());
  target_tree.build(target.positions());
  const int k = std::max(0, std::min<int>(o.graph_k, int(target.size()) - 1));
  const std::vector<std::int32_t> graph = knn_graph(target_tree, target.positions(), k);
  const double fine = o.distance * spacing;
  const Context c{source, target, source_tree, graph, k, fine, std::cos(o.normal_angle_deg * M_PI / 180)};

  std::vector<SupportedTransform> found(modes.size());
  tbb::parallel_for(size_t(0), modes.size(), [&](size_t m) {
    SupportedTransform st;
    st.transform = modes[m].transform;
    // Coarse to fine: start at the mode's accuracy, halve each ICP step, end at `distance` alpha.
    Context cc = c;
    cc.max_distance = std::max(fine, mode_accuracy);
    st.support = grow(cc, st.transform, modes[m].voters);
    // Correspondences on an even subsample of the support: 7 parameters need a few thousand.
    const auto find_pairs = [&](const Similarity& q, int, IcpPairs& pairs) {
      const size_t stride = (st.support.size() + size_t(o.icp_samples) - 1) / size_t(o.icp_samples);
      const Index cap = st.support.empty() ? 0 : Index((st.support.size() + stride - 1) / stride);
      Eigen::Matrix3Xd moved(3, cap), to(3, cap), normals(3, cap);
      Index n = 0;
      for (size_t i = 0; i < st.support.size(); i += stride) {
        const std::int32_t t = st.support[i];
        const std::int32_t s = explained(cc, q, t);
        if (s < 0) continue;
        moved.col(n) = q.apply(target.positions().col(t));
        to.col(n) = source.positions().col(s);
        normals.col(n) = source.normals().col(s);
        ++n;
      }
      pairs.moved = moved.leftCols(n);
      pairs.to = to.leftCols(n);
      pairs.normals = normals.leftCols(n);
    };
    // After each step, a tighter distance (halved, down to `distance` alpha) and the support regrown.
    const auto regrow = [&](const Similarity& q) {
      cc.max_distance = std::max(fine, 0.5 * cc.max_distance);
      st.support = grow(cc, q, st.support);
    };
    st.transform = icp(st.transform, find_pairs,
                       {.iterations = o.icp_iterations,
                        .point_to_point_iterations = o.icp_iterations / 2,
                        .allow_scale = o.allow_scale},
                       regrow);
    st.support = grow(c, st.transform, st.support.empty() ? modes[m].voters : st.support);
    double sum = 0;
    Index n = 0;
    for (const auto t : st.support) {
      std::int32_t s;
      double d2;
      source_tree.knn(st.transform.apply(target.positions().col(t)), 1, &s, &d2);
      sum += d2;
      ++n;
    }
    st.rms = n ? std::sqrt(sum / double(n)) : 0;
    found[m] = std::move(st);
  });
  return found;
}

bool stronger(const SupportedTransform& a, const SupportedTransform& b) {
  return a.support.size() > b.support.size() || (a.support.size() == b.support.size() && a.rms < b.rms);
}

// Strongest first; drop the small and the duplicates. The first `first` of `found` are considered before the rest, each
// part strongest first; the kept ones are returned strongest first.
SupportResult select_transforms(std::vector<SupportedTransform> found, const PointSet& target, double spacing,
                                const SupportOptions& o, size_t first = 0) {
  first = std::min(first, found.size());
  std::stable_sort(found.begin(), found.begin() + std::ptrdiff_t(first), stronger);
  std::stable_sort(found.begin() + std::ptrdiff_t(first), found.end(), stronger);
  SupportResult result;
  const double cos_dup = std::cos(o.duplicate_angle_deg * M_PI / 180);
  for (auto& st : found) {
    if (Index(st.support.size()) < o.min_support) continue;
    if (!(st.transform.scale >= o.min_scale && st.transform.scale <= o.max_scale)) continue;
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    for (const auto t : st.support) centre += target.positions().col(t);
    centre /= double(st.support.size());
    bool duplicate = false;
    for (const auto& kept : result.transforms) {
      Index common = 0;  // |kept.support ∩ st.support|, both ascending
      for (size_t i = 0, j = 0; i < kept.support.size() && j < st.support.size();) {
        if (kept.support[i] < st.support[j])
          ++i;
        else if (st.support[j] < kept.support[i])
          ++j;
        else
          ++common, ++i, ++j;
      }
      if (double(common) >= o.redundant_overlap * double(st.support.size())) duplicate = true;
      const double cos_angle =
          (std::min(3.0, (kept.transform.rotation.transpose() * st.transform.rotation).trace()) - 1) / 2;
      if (cos_angle > cos_dup &&
          (kept.transform.apply(centre) - st.transform.apply(centre)).norm() < o.duplicate_distance * spacing)
        duplicate = true;
    }
    if (!duplicate) result.transforms.push_back(std::move(st));
  }
  std::stable_sort(result.transforms.begin(), result.transforms.end(), stronger);
  return result;
}

}  // namespace

SupportResult grow_supports(const PointSet& source, const PointSet& target, const std::vector<Mode>& modes,
                            double spacing, double mode_accuracy, const SupportOptions& options) {
  check_options(options);
  return select_transforms(grow_all(source, target, modes, spacing, mode_accuracy, options), target, spacing, options);
}

SupportResult extend_supports(const PointSet& source, const PointSet& target, const SupportResult& found,
                              const std::vector<Mode>& extra, double spacing, double accuracy,
                              const SupportOptions& options, const std::vector<Mode>& preferred) {
  check_options(options);
  if (extra.empty() && preferred.empty()) return found;
  // Compositions are exact (a refined transform and a symmetry of T): grown, not refined, since ICP would slide them
  // along a symmetric template's free motions, off the axis rotations they were made to be.
  SupportOptions grow_only = options;
  grow_only.icp_iterations = 0;
  // Coverage is what they are for (DESIGN section 9): an extra transform is kept only when it explains at least
  // min_support target samples that no found transform explains.
  std::vector<std::uint8_t> explained(size_t(target.size()), 0);
  for (const auto& st : found.transforms)
    for (const auto t : st.support) explained[size_t(t)] = 1;
  std::vector<SupportedTransform> all = grow_all(source, target, preferred, spacing, accuracy, grow_only);
  const size_t first = all.size();
  all.insert(all.end(), found.transforms.begin(), found.transforms.end());
  for (auto& st : grow_all(source, target, extra, spacing, accuracy, grow_only)) {
    const auto unexplained =
        std::count_if(st.support.begin(), st.support.end(), [&](std::int32_t t) { return explained[size_t(t)] == 0; });
    if (Index(unexplained) >= options.min_support) all.push_back(std::move(st));
  }
  return select_transforms(std::move(all), target, spacing, options, first);
}

}  // namespace scanfill
