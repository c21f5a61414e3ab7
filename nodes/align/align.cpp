#include "nodes/align/align.h"

#include <ceres/ceres.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <array>
#include <cmath>
#include <memory>

#include "nodes/align/align_options.h"
#include "nodes/align/linear_pair_cost.h"
#include "nodes/align/pull_cost.h"
#include "nodes/core/ceres_summary.h"
#include "nodes/core/errors.h"
#include "nodes/core/kdtree.h"

namespace scanfill {
namespace {

struct Seam {
  std::int32_t i, j;
  double c, a, b;  // gap = c + a d_i + b d_j
};

}  // namespace

AlignResult align(const Synthesis& s, double spacing, const AlignOptions& o) {
  check_options(o);  // the config checks these too; a direct caller gets the same checks
  const Index n = s.points.size();
  AlignResult r;
  r.offset.assign(size_t(n), 0.0);
  r.keep.assign(size_t(n), 1);
  if (n < 2) return r;
  const Eigen::Matrix3Xd& P = s.points.positions();
  const Eigen::Matrix3Xd& N = s.points.normals();
  KdTree tree;
  tree.build(P);
  const int k = int(std::min<Index>(o.neighbors, n - 1));
  std::vector<double> dist2;
  const std::vector<std::int32_t> graph = knn_graph(tree, P, k, &dist2);

  const double inv = 1.0 / spacing;
  const auto fixed = [&](Index i) { return s.origin[size_t(i)] == Origin::kExemplar; };
  const double pair2 = std::pow(o.pair_distance * spacing, 2), cos_limit = 0.5;
  std::vector<Seam> seams;
  // The keep and pull terms are one cost function each, shared by all their residual blocks; every cost function
  // lives here, beside (and longer than) the problem: no allocation and no ownership count per residual.
  const std::unique_ptr<ceres::CostFunction> keep(LinearPairCost::Create(std::sqrt(o.keep_weight) * inv, 0, 1, -1)),
      pull(PullCost::Create(std::sqrt(o.pull) * inv));
  std::vector<std::unique_ptr<ceres::CostFunction>> gaps;
  ceres::Problem::Options po;
  po.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(po);
  for (Index i = 0; i < n; ++i) problem.AddParameterBlock(&r.offset[size_t(i)], 1);
  for (Index i = 0; i < n; ++i)
    for (int a = 0; a < k; ++a) {
      const auto j = graph[size_t(i) * size_t(k) + size_t(a)];
      if (j < 0) continue;  // an edge found from both ends counts twice: harmless in a least-squares sum
      if (fixed(i) && fixed(j)) continue;
      const double ni_nj = N.col(i).dot(N.col(j));
      if (ni_nj < cos_limit) continue;
      if (s.patch[size_t(i)] == s.patch[size_t(j)]) {
        if (o.keep_weight > 0)
          problem.AddResidualBlock(keep.get(), nullptr, &r.offset[size_t(i)], &r.offset[size_t(j)]);
        continue;
      }
      if (dist2[size_t(i) * size_t(k) + size_t(a)] > pair2) continue;
      const Eigen::Vector3d m = (N.col(i) + N.col(j)).normalized();
      const Seam seam{std::int32_t(i), j, (P.col(i) - P.col(j)).dot(m), N.col(i).dot(m), -N.col(j).dot(m)};
      seams.push_back(seam);
      if (o.gap_weight > 0) {
        gaps.push_back(std::make_unique<LinearPairCost>(std::sqrt(o.gap_weight) * inv, seam.c, seam.a, seam.b));
        problem.AddResidualBlock(gaps.back().get(), nullptr, &r.offset[size_t(i)], &r.offset[size_t(j)]);
      }
    }
  for (Index i = 0; i < n; ++i) {
    if (fixed(i)) {
      problem.SetParameterBlockConstant(&r.offset[size_t(i)]);
    } else {
      problem.AddResidualBlock(pull.get(), nullptr, &r.offset[size_t(i)]);
    }
  }
  const auto rms_gap = [&] {
    double sum = 0;
    for (const auto& q : seams) sum += std::pow(q.c + q.a * r.offset[size_t(q.i)] + q.b * r.offset[size_t(q.j)], 2);
    return seams.empty() ? 0.0 : std::sqrt(sum / double(seams.size()));
  };
  r.seam_pairs = Index(seams.size());
  r.gap_before = rms_gap();
  if (!seams.empty()) {
    ceres::Solver::Options so;
    so.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
    so.max_num_iterations = 5;
    so.num_threads = std::max(1, tbb::this_task_arena::max_concurrency());
    so.logging_type = ceres::SILENT;
    // Every term is linear in the offsets: an unbounded first trust region takes the Gauss-Newton step, which is the
    // minimum, and the next iteration sees it converged (the default radius, 1e4, damped it over three).
    so.initial_trust_region_radius = 1e16;
    ceres::Solver::Summary summary;
    ceres::Solve(so, &problem, &summary);
    r.solver = summarize(summary);
  }
  r.gap_after = rms_gap();

  if (o.thin_distance > 0) r.keep = thinned_overlaps(s, r.offset, spacing, o.thin_distance);
  return r;
}

std::vector<std::uint8_t> thinned_overlaps(const Synthesis& s, const std::vector<double>& offset, double spacing,
                                           double thin_distance) {
  const Index n = s.points.size();
  if (s.ring.size() != size_t(n) || s.patch.size() != size_t(n) || offset.size() != size_t(n))
    throw InvariantError("thinned_overlaps: the synthesis' rings, patches and the offsets must be one per point");
  std::vector<std::uint8_t> keep(size_t(n), 1);
  if (!(thin_distance > 0) || n == 0) return keep;
  const Eigen::Matrix3Xd& P = s.points.positions();
  const Eigen::Matrix3Xd& N = s.points.normals();
  const double thin2 = std::pow(thin_distance * spacing, 2), cos_limit = 0.5;
  Eigen::Matrix3Xd moved(3, n);
  for (Index i = 0; i < n; ++i) moved.col(i) = P.col(i) + offset[size_t(i)] * N.col(i);
  KdTree mt;
  mt.build(moved);
  tbb::parallel_for(Index(0), n, [&](Index i) {
    if (!s.ring[size_t(i)]) return;
    std::array<std::int32_t, 17> idx;
    std::array<double, 17> d2;
    const int got = mt.knn(moved.col(i), 16, idx.data(), d2.data());
    for (int a = 0; a < got; ++a) {
      const auto j = idx[size_t(a)];
      if (d2[size_t(a)] > thin2) break;
      if (s.patch[size_t(j)] != s.patch[size_t(i)] && !s.ring[size_t(j)] && N.col(i).dot(N.col(j)) >= cos_limit) {
        keep[size_t(i)] = 0;
        return;
      }
    }
  });
  return keep;
}

}  // namespace scanfill
