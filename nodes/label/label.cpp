#include "nodes/label/label.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "nodes/core/kdtree.h"
#include "nodes/label/label_options.h"

namespace scanfill {
namespace {

const std::vector<Eigen::Matrix3d>& axis_rotations() {
  static const std::vector<Eigen::Matrix3d> rotations = [] {
    std::vector<Eigen::Matrix3d> r;
    const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
    for (const auto& p : perms)
      for (int signs = 0; signs < 8; ++signs) {
        Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
        for (int i = 0; i < 3; ++i) m(i, p[i]) = (signs >> i & 1) ? -1 : 1;
        if (m.determinant() > 0) r.push_back(m);
      }
    return r;
  }();
  return rotations;
}

}  // namespace

double residual_axis_angle(const Eigen::Matrix3d& R) {
  double best = M_PI;
  for (const auto& A : axis_rotations()) best = std::min(best, rotation_angle(A.transpose() * R));
  return best;
}

LabelResult label_target(const PointSet& source, const PointSet& target,
                         const std::vector<SupportedTransform>& transforms, double spacing, const LabelOptions& o) {
  check_options(o);  // the config checks these too; a direct caller gets the same checks
  const Index n = target.size();
  const int L = int(transforms.size());
  LabelResult result;
  result.self_label = L;
  KdTree source_tree, target_tree;
  source_tree.build(source.positions());
  target_tree.build(target.positions());
  const double sp2 = 2 * std::pow(o.sigma_p * spacing, 2), sn2 = o.sigma_n * o.sigma_n;

  // Feasible labels, sparse: the sites within `dilation` alpha of a label's support, found by radius queries around
  // the support samples (never a test of every site against every label).
  const double reach = o.dilation * spacing, reach2 = reach * reach + 1e-30;
  std::vector<std::vector<std::int32_t>> feasible(static_cast<size_t>(L));
  tbb::parallel_for(0, L, [&](int l) {
    auto& sites = feasible[size_t(l)];
    std::vector<Neighbor> hits;
    for (const auto t : transforms[size_t(l)].support) {
      sites.push_back(t);
      target_tree.radius(target.positions().col(t), reach * (1 + 1e-9) + 1e-15, hits);
      for (const Neighbor& h : hits)
        if (h.distance2 <= reach2) sites.push_back(h.index);
    }
    std::sort(sites.begin(), sites.end());
    sites.erase(std::unique(sites.begin(), sites.end()), sites.end());
  });
  // Unaries (eq. 5, log domain, capped) in CSR by site: the feasible labels in increasing order, then the self label.
  LabelingProblem problem;
  problem.labels = L + 1;
  problem.sites = n;
  problem.unary_offset.assign(size_t(n) + 1, 0);
  for (const auto& sites : feasible)
    for (const auto t : sites) ++problem.unary_offset[size_t(t) + 1];
  for (Index t = 0; t < n; ++t) problem.unary_offset[size_t(t) + 1] += problem.unary_offset[size_t(t)] + 1;  // + self
  problem.unary_label.resize(size_t(problem.unary_offset.back()));
  problem.unary_cost.resize(size_t(problem.unary_offset.back()));
  {
    std::vector<std::int64_t> fill(problem.unary_offset.begin(), problem.unary_offset.end() - 1);
    for (int l = 0; l < L; ++l)
      for (const auto t : feasible[size_t(l)]) problem.unary_label[size_t(fill[size_t(t)]++)] = l;
    for (Index t = 0; t < n; ++t) problem.unary_label[size_t(fill[size_t(t)])] = L;
  }
  tbb::parallel_for(Index(0), n, [&](Index t) {
    for (std::int64_t e = problem.unary_offset[size_t(t)]; e < problem.unary_offset[size_t(t) + 1]; ++e) {
      const int l = problem.unary_label[size_t(e)];
      if (l == L) {
        problem.unary_cost[size_t(e)] = o.self_cost;
        continue;
      }
      const Similarity& q = transforms[size_t(l)].transform;
      const Eigen::Vector3d p = q.apply(target.positions().col(t));
      std::int32_t s;
      double d2;
      source_tree.knn(p, 1, &s, &d2);
      const double d_point = std::sqrt(d2);
      double d = d_point;
      if (o.point_to_plane) {
        const double plane = std::abs(source.normals().col(s).dot(p - source.positions().col(s)));
        d = std::hypot(plane, std::max(0.0, d_point - spacing));
      }
      const double c = q.apply_normal(target.normals().col(t)).dot(source.normals().col(s));
      problem.unary_cost[size_t(e)] = std::min(o.unary_cap, d * d / sp2 + (1 - c) / sn2);
    }
  });
  // MRF edges: mrf_k nearest neighbours with compatible normals, each pair once.
  const int k = std::min<int>(o.mrf_k, int(n) - 1);
  const std::vector<std::int32_t> knn = knn_graph(target_tree, target.positions(), k);  // self excluded, -1 fill
  auto is_neighbor = [&](Index a, Index b) {
    for (int j = 0; j < k; ++j)
      if (knn[size_t(a) * size_t(k) + size_t(j)] == b) return true;
    return false;
  };
  for (Index t = 0; t < n; ++t)
    for (int j = 0; j < k; ++j) {
      const Index u = knn[size_t(t) * size_t(k) + size_t(j)];
      if (u < 0 || (u < t && is_neighbor(u, t))) continue;  // none, or listed from the other end
      if (target.normals().col(t).dot(target.normals().col(u)) < 0.5) continue;
      problem.edges.push_back({std::int32_t(t), std::int32_t(u)});
    }
  std::vector<Eigen::Vector3d> mid(problem.edges.size()), normal(problem.edges.size());
  for (size_t e = 0; e < problem.edges.size(); ++e) {
    const auto [a, b] = problem.edges[e];
    mid[e] = 0.5 * (target.positions().col(a) + target.positions().col(b));
    normal[e] = (target.normals().col(a) + target.normals().col(b)).normalized();
  }
  problem.pairwise = [&](Index e, int a, int b) {
    if (a == b) return 0.0;
    if (a == L || b == L) return o.pairwise_weight * (o.pairwise_cap + o.mu);
    const Similarity &qa = transforms[size_t(a)].transform, &qb = transforms[size_t(b)].transform;
    const double data = (qa.apply(mid[size_t(e)]) - qb.apply(mid[size_t(e)])).squaredNorm() / sp2 +
                        (1 - qa.apply_normal(normal[size_t(e)]).dot(qb.apply_normal(normal[size_t(e)]))) / sn2;
    return o.pairwise_weight * (std::min(o.pairwise_cap, data) + o.mu);
  };
  // Label costs (eq. 9 with the gimbal-safe residual rotation).
  problem.label_cost.assign(size_t(L + 1), 0.0);
  for (int l = 0; l < L; ++l) {
    const Similarity& q = transforms[size_t(l)].transform;
    problem.label_cost[size_t(l)] =
        o.label_cost_per_sample * double(n) *
        (1 + o.rotation_prior * residual_axis_angle(q.rotation) / (M_PI / 4) +
         o.scale_prior * std::abs(std::log2(q.scale)) + o.upright_prior * (1 - q.rotation(2, 2)) / 2);
  }
  result.label_costs.assign(problem.label_cost.begin(), problem.label_cost.end() - 1);

  const ExpansionResult r = alpha_expansion(problem, std::vector<int>(size_t(n), L), {.max_cycles = o.max_cycles});
  result.energy_before = r.energy_before;
  result.energy_after = r.energy_after;
  result.truncated_terms = r.truncated_terms;
  result.cycles = r.cycles;
  result.labels = r.labeling;

  // Clean-up on the 5-alpha ring. Buffers per chunk of samples, not per sample.
  if (o.cleanup_ring > 0) {
    std::vector<int> cleaned = result.labels;
    tbb::parallel_for(tbb::blocked_range<Index>(0, n, 256), [&](const tbb::blocked_range<Index>& range) {
      std::vector<Neighbor> ring;
      std::vector<Index> votes(size_t(L) + 1, 0);
      for (Index t = range.begin(); t != range.end(); ++t) {
        target_tree.radius(target.positions().col(t), o.cleanup_ring * spacing, ring);
        const int own = result.labels[size_t(t)];
        Index others = 0, total = 0;
        for (const Neighbor& nb : ring) {
          if (nb.index == t) continue;
          const int l = result.labels[size_t(nb.index)];
          ++total;
          ++votes[size_t(l)];
          others += l != own;
        }
        if (total > 0 && double(others) > o.cleanup_majority * double(total)) {
          int best = 0;  // the ring's majority; ties go to the lower label
          for (int l = 1; l <= L; ++l)
            if (votes[size_t(l)] > votes[size_t(best)]) best = l;
          cleaned[size_t(t)] = best;
        }
        for (const Neighbor& nb : ring) votes[size_t(result.labels[size_t(nb.index)])] = 0;
      }
    });
    for (Index t = 0; t < n; ++t) result.cleaned += cleaned[size_t(t)] != result.labels[size_t(t)];
    result.labels.swap(cleaned);
  }
  return result;
}

}  // namespace scanfill
