#include "nodes/label/label.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
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

namespace {

// Scales of eq. 5 and 7: 2 (sigma_p alpha)^2 and sigma_n^2.
struct DataScales {
  double position2, normal2;
};

// The object's up direction: o.up, +z when unset.
Eigen::Vector3d up_of(const LabelOptions& o) {
  return o.up ? o.up->normalized() : Eigen::Vector3d::UnitZ();
}

// Whether q tips the object onto its side: turns its up direction more than 60 degrees from both up and down.
bool tips_over(const Similarity& q, const Eigen::Vector3d& up) {
  return std::abs(up.dot(q.rotation * up)) < 0.5;
}

// Whether a target sample with normal n lies on a cap: faces within 30 degrees of up or down.
bool on_cap(const Eigen::Vector3d& n, const Eigen::Vector3d& up) {
  return std::abs(n.dot(up)) > std::cos(M_PI / 6);
}

// Feasible labels, sparse: the sites within `dilation` alpha of each label's support, found by radius queries
// around the support samples (never a test of every site against every label). Sorted, without repeats.
// Ours, in completion (caps_take_tips false): a transform that tips the object onto its side is not feasible on its
// caps. It lays the style of the scan's sides on a lid or a floor the scan did not see, where a real object's
// caps are rarely its sides' (a box's, a column's, a vase's). The ribbed box seen square to its short side
// (-1, 0.01, 0.03) took the side's ribs onto its top and bottom by quarter turns about the horizontal, the votes'
// best supported (a 0.5 by 0.6 side fits inside the 0.8 by 0.5 lid): F 0.917, the caps 32% off the model.
std::vector<std::vector<std::int32_t>> feasible_sites(const PointSet& target, const KdTree& target_tree,
                                                      const std::vector<SupportedTransform>& transforms, double reach,
                                                      const LabelOptions& o) {
  const double reach2 = reach * reach + 1e-30;
  const Eigen::Vector3d up = up_of(o);
  std::vector<std::vector<std::int32_t>> feasible(transforms.size());
  tbb::parallel_for(0, int(transforms.size()), [&](int l) {
    auto& sites = feasible[size_t(l)];
    const bool caps_closed = !o.caps_take_tips && tips_over(transforms[size_t(l)].transform, up);
    const auto open = [&](Index t) { return !caps_closed || !on_cap(target.normals().col(t), up); };
    std::vector<Neighbor> hits;
    for (const auto t : transforms[size_t(l)].support) {
      if (open(t)) sites.push_back(t);
      target_tree.radius(target.positions().col(t), reach * (1 + 1e-9) + 1e-15, hits);
      for (const Neighbor& h : hits)
        if (h.distance2 <= reach2 && open(h.index)) sites.push_back(h.index);
    }
    std::sort(sites.begin(), sites.end());
    sites.erase(std::unique(sites.begin(), sites.end()), sites.end());
  });
  return feasible;
}

// The unary table's layout, CSR by site: each site's feasible labels in increasing order, then the self label L.
void list_feasible_labels(const std::vector<std::vector<std::int32_t>>& feasible, Index n, LabelingProblem& problem) {
  const int L = int(feasible.size());
  problem.unary_offset.assign(size_t(n) + 1, 0);
  for (const auto& sites : feasible)
    for (const auto t : sites) ++problem.unary_offset[size_t(t) + 1];
  for (Index t = 0; t < n; ++t) problem.unary_offset[size_t(t) + 1] += problem.unary_offset[size_t(t)] + 1;  // + self
  problem.unary_label.resize(size_t(problem.unary_offset.back()));
  problem.unary_cost.resize(size_t(problem.unary_offset.back()));
  std::vector<std::int64_t> fill(problem.unary_offset.begin(), problem.unary_offset.end() - 1);
  for (int l = 0; l < L; ++l)
    for (const auto t : feasible[size_t(l)]) problem.unary_label[size_t(fill[size_t(t)]++)] = l;
  for (Index t = 0; t < n; ++t) problem.unary_label[size_t(fill[size_t(t)])] = L;
}

// Eq. 5 in the log domain, capped, for target sample t under transform q.
double eq5_unary(const PointSet& source, const KdTree& source_tree, const PointSet& target, Index t,
                 const Similarity& q, double spacing, DataScales scales, const LabelOptions& o) {
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
  return std::min(o.unary_cap, d * d / scales.position2 + (1 - c) / scales.normal2);
}

// (1 - cos tilt) / 2, tilt the angle by which q's rotation turns the object's up direction (o.up, +z when unset).
double tilt(const Similarity& q, const LabelOptions& o) {
  const Eigen::Vector3d up = up_of(o);
  return (1 - up.dot(q.rotation * up)) / 2;
}

// Ours: each sample's own preference for the transform that keeps the object upright, o.upright_unary (1 - cos tilt)
// / 2, where such a transform is feasible. Where the template fits a flip and a turn about the vertical alike (a box's
// back faces), the label cost alone lets one flip cover the back faces and the bottom at once, turning the style
// upside down; this makes each sample pay for it. Where no upright transform reaches (a gear's unseen face, which
// only a flip carries the seen one onto), the flip competes with the plain copy unburdened.
double upright_unary(const Similarity& q, const LabelOptions& o) {
  return o.upright_unary * tilt(q, o);
}

constexpr double kUpright = 0.0076;  // (1 - cos 10 degrees) / 2: a transform tilted less keeps the object upright

// How far an upright turn q stands from the nearest quarter turn about the up direction, over 45 degrees: 0 for the
// identity and the quarter and half turns, 1 for turns of 45 and 135 degrees. 0 for a transform that is not upright:
// the upright terms price it.
double off_quarter(const Similarity& q, const LabelOptions& o) {
  if (tilt(q, o) >= kUpright) return 0.0;
  const double turn = rotation_angle(q.rotation), quarter = M_PI / 2;
  return std::abs(turn - std::round(turn / quarter) * quarter) / (quarter / 2);
}

// Ours: each sample's own preference for a quarter or half turn about the vertical over other turns, o.quarter_unary
// off_quarter, where an upright quarter turn (within 2 degrees) is feasible. On a body of revolution every turn fits
// the template alike, so eq. 9's label costs alone cannot tell where a turn's region should end once its label is paid
// for (a turn of 150 degrees, say, needed where the half turn's image stops short at the scan's grazing edge). The
// text2mesh vase seen from the front, a knob in front and behind, got turns of 30, 60, 120 and 150 degrees over its
// back, the front's knob beside the back's (F 0.898 with the turns exact); 0.972 with the half turn taking the back.
// At 0.6, the weight took regions from turns the gear's and the fluted column's repeats phase correctly (the column
// from behind obliquely: unseen-detail 0.98 -> 0.83), so it was 0.3. The engine now sets it to 0 where the scan
// repeats about the target's axis (synthesize turns every image to those repeats, whatever the turn), and 1.0 serves
// the scans that do not: the text2mesh vase from (-1, 0.01, 0.03), whose faceted body repeats every 90 degrees, took
// turns of 120 and 150 degrees at 0.3 (F 0.865, under template blending's 0.910), the half turn at 1.0 (0.963).
double quarter_unary(const Similarity& q, const LabelOptions& o) {
  return o.quarter_unary * off_quarter(q, o);
}

// Whether some transform feasible at sample t passes `test`.
template <class Test>
bool some_feasible(const LabelingProblem& problem, Index t, const std::vector<SupportedTransform>& transforms,
                   const Test& test) {
  for (std::int64_t e = problem.unary_offset[size_t(t)]; e < problem.unary_offset[size_t(t) + 1]; ++e) {
    const int l = problem.unary_label[size_t(e)];
    if (l < int(transforms.size()) && test(transforms[size_t(l)].transform)) return true;
  }
  return false;
}

void fill_unary_costs(const PointSet& source, const KdTree& source_tree, const PointSet& target,
                      const std::vector<SupportedTransform>& transforms, double spacing, DataScales scales,
                      const LabelOptions& o, LabelingProblem& problem) {
  const int L = int(transforms.size());
  tbb::parallel_for(Index(0), target.size(), [&](Index t) {
    const bool upright =
        some_feasible(problem, t, transforms, [&](const Similarity& q) { return tilt(q, o) < kUpright; });
    constexpr double kQuarter = 2.0 / 45;  // off_quarter of a turn 2 degrees off a quarter turn
    const bool quarter = o.quarter_unary > 0 && some_feasible(problem, t, transforms, [&](const Similarity& q) {
                           return tilt(q, o) < kUpright && off_quarter(q, o) < kQuarter;
                         });
    for (std::int64_t e = problem.unary_offset[size_t(t)]; e < problem.unary_offset[size_t(t) + 1]; ++e) {
      const int l = problem.unary_label[size_t(e)];
      if (l == L) {
        problem.unary_cost[size_t(e)] = o.self_cost;
        continue;
      }
      const Similarity& q = transforms[size_t(l)].transform;
      problem.unary_cost[size_t(e)] = eq5_unary(source, source_tree, target, t, q, spacing, scales, o) +
                                      (upright ? upright_unary(q, o) : 0) + (quarter ? quarter_unary(q, o) : 0);
    }
  });
}

// MRF edges: mrf_k nearest neighbours whose normals' dot product exceeds min_normal_dot, each pair once.
std::vector<std::pair<std::int32_t, std::int32_t>> knn_mrf_edges(const PointSet& target, const KdTree& target_tree,
                                                                 int mrf_k, double min_normal_dot) {
  const Index n = target.size();
  const int k = std::min<int>(mrf_k, int(n) - 1);
  const std::vector<std::int32_t> knn = knn_graph(target_tree, target.positions(), k);  // self excluded, -1 fill
  auto is_neighbor = [&](Index a, Index b) {
    for (int j = 0; j < k; ++j)
      if (knn[size_t(a) * size_t(k) + size_t(j)] == b) return true;
    return false;
  };
  std::vector<std::pair<std::int32_t, std::int32_t>> edges;
  for (Index t = 0; t < n; ++t)
    for (int j = 0; j < k; ++j) {
      const Index u = knn[size_t(t) * size_t(k) + size_t(j)];
      if (u < 0 || (u < t && is_neighbor(u, t))) continue;  // none, or listed from the other end
      if (target.normals().col(t).dot(target.normals().col(u)) < min_normal_dot) continue;
      edges.push_back({std::int32_t(t), std::int32_t(u)});
    }
  return edges;
}

// MRF edges of the paper: every pair within `radius` (a Euclidean ball for its geodesic ring) whose normals' dot
// product is at least min_normal_dot, each pair once. Found per thread, then sorted: the same list on any number of
// threads.
std::vector<std::pair<std::int32_t, std::int32_t>> ring_mrf_edges(const PointSet& target, const KdTree& target_tree,
                                                                  double radius, double min_normal_dot) {
  tbb::enumerable_thread_specific<std::vector<std::pair<std::int32_t, std::int32_t>>> found;
  tbb::parallel_for(tbb::blocked_range<Index>(0, target.size(), 256), [&](const tbb::blocked_range<Index>& range) {
    auto& edges = found.local();
    std::vector<Neighbor> ring;
    for (Index t = range.begin(); t != range.end(); ++t) {
      target_tree.radius(target.positions().col(t), radius, ring);
      for (const Neighbor& nb : ring)
        if (nb.index > t && target.normals().col(t).dot(target.normals().col(nb.index)) >= min_normal_dot)
          edges.push_back({std::int32_t(t), std::int32_t(nb.index)});
    }
  });
  std::vector<std::pair<std::int32_t, std::int32_t>> edges;
  for (const auto& part : found) edges.insert(edges.end(), part.begin(), part.end());
  std::sort(edges.begin(), edges.end());
  return edges;
}

// Eq. 7 as corrected in the header: V(a, b) on edge e, evaluated at the edge's midpoint and mean normal.
class Eq7Pairwise {
 public:
  Eq7Pairwise(const PointSet& target, const LabelingProblem& problem, const std::vector<SupportedTransform>& transforms,
              DataScales scales, const LabelOptions& o)
      : transforms_(transforms), scales_(scales), o_(o), self_(int(transforms.size())) {
    mid_.resize(problem.edges.size());
    normal_.resize(problem.edges.size());
    for (size_t e = 0; e < problem.edges.size(); ++e) {
      const auto [a, b] = problem.edges[e];
      mid_[e] = 0.5 * (target.positions().col(a) + target.positions().col(b));
      normal_[e] = (target.normals().col(a) + target.normals().col(b)).normalized();
    }
  }

  double operator()(Index e, int a, int b) const {
    if (a == b) return 0.0;
    if (a == self_ || b == self_) return o_.pairwise_weight * (o_.pairwise_cap + o_.mu);
    const Similarity &qa = transforms_[size_t(a)].transform, &qb = transforms_[size_t(b)].transform;
    const double data =
        (qa.apply(mid_[size_t(e)]) - qb.apply(mid_[size_t(e)])).squaredNorm() / scales_.position2 +
        (1 - qa.apply_normal(normal_[size_t(e)]).dot(qb.apply_normal(normal_[size_t(e)]))) / scales_.normal2;
    return o_.pairwise_weight * (std::min(o_.pairwise_cap, data) + o_.mu);
  }

 private:
  const std::vector<SupportedTransform>& transforms_;
  DataScales scales_;
  const LabelOptions& o_;
  int self_;
  std::vector<Eigen::Vector3d> mid_, normal_;
};

// Eq. 9 with the gimbal-safe residual rotation, the scale prior and the upright prior (ours).
double our_label_cost(const Similarity& q, Index n, const LabelOptions& o) {
  return o.label_cost_per_sample * double(n) *
         (1 + o.rotation_prior * residual_axis_angle(in_frame(q.rotation, o.axes)) / (M_PI / 4) +
          o.scale_prior * std::abs(std::log2(q.scale)) + o.upright_prior * tilt(q, o));
}

// Euler angles (a, b, c) of R = R_x(a) R_y(b) R_z(c). At gimbal lock (cos b = 0) only a + c or a - c is defined:
// a = 0 there, so that an axis rotation always gives multiples of 90 degrees (Eigen's eulerAngles reads the angle
// from two entries that are rounding noise there).
Eigen::Vector3d xyz_euler_angles(const Eigen::Matrix3d& R) {
  const double b = std::asin(std::clamp(R(0, 2), -1.0, 1.0));
  if (std::abs(std::cos(b)) < 1e-9) return {0.0, b, std::atan2(R(1, 0), R(1, 1))};
  return {std::atan2(-R(1, 2), R(2, 2)), b, std::atan2(-R(0, 1), R(0, 0))};
}

// Eq. 8 and 9 as printed: -N log P(E_l), P = 1 for the identity and 0.5 prod_a exp(cos 4 R_a) / e exp(-(s - 1)^2)
// otherwise, R_a the Euler angles of R = R_x R_y R_z.
double paper_label_cost(const Similarity& q, Index n, double spacing, const LabelOptions& o) {
  const bool identity =
      rotation_angle(q.rotation) < 2 * M_PI / 180 && std::abs(q.scale - 1) < 0.01 && q.translation.norm() < spacing;
  if (identity) return 0.0;
  const Eigen::Vector3d euler = xyz_euler_angles(in_frame(q.rotation, o.axes));
  double minus_log_p = std::log(2.0) + (q.scale - 1) * (q.scale - 1);
  for (int a = 0; a < 3; ++a) minus_log_p += 1 - std::cos(4 * euler(a));
  return double(n) * minus_log_p;
}

// h_l per label; the self label costs nothing.
std::vector<double> label_costs(const std::vector<SupportedTransform>& transforms, Index n, double spacing,
                                const LabelOptions& o) {
  std::vector<double> cost(transforms.size() + 1, 0.0);
  for (size_t l = 0; l < transforms.size(); ++l)
    cost[l] = o.paper_label_costs ? paper_label_cost(transforms[l].transform, n, spacing, o)
                                  : our_label_cost(transforms[l].transform, n, o);
  return cost;
}

// Clean-up on the ring: a sample whose label disagrees with more than cleanup_majority of its ring takes the ring's
// majority label. Buffers per chunk of samples, not per sample. Returns how many samples moved.
Index cleanup_on_ring(const PointSet& target, const KdTree& target_tree, int labels, double radius, double majority,
                      std::vector<int>& labeling) {
  const Index n = target.size();
  std::vector<int> cleaned = labeling;
  tbb::parallel_for(tbb::blocked_range<Index>(0, n, 256), [&](const tbb::blocked_range<Index>& range) {
    std::vector<Neighbor> ring;
    std::vector<Index> votes(size_t(labels), 0);
    for (Index t = range.begin(); t != range.end(); ++t) {
      target_tree.radius(target.positions().col(t), radius, ring);
      const int own = labeling[size_t(t)];
      Index others = 0, total = 0;
      for (const Neighbor& nb : ring) {
        if (nb.index == t) continue;
        const int l = labeling[size_t(nb.index)];
        ++total;
        ++votes[size_t(l)];
        others += l != own;
      }
      if (total > 0 && double(others) > majority * double(total)) {
        int best = 0;  // the ring's majority; ties go to the lower label
        for (int l = 1; l < labels; ++l)
          if (votes[size_t(l)] > votes[size_t(best)]) best = l;
        cleaned[size_t(t)] = best;
      }
      for (const Neighbor& nb : ring) votes[size_t(labeling[size_t(nb.index)])] = 0;
    }
  });
  Index moved = 0;
  for (Index t = 0; t < n; ++t) moved += cleaned[size_t(t)] != labeling[size_t(t)];
  labeling.swap(cleaned);
  return moved;
}

}  // namespace

LabelResult label_target(const PointSet& source, const PointSet& target,
                         const std::vector<SupportedTransform>& transforms, double spacing, const LabelOptions& o) {
  check_options(o);  // the config checks these too; a direct caller gets the same checks
  const Index n = target.size();
  const int L = int(transforms.size());
  KdTree source_tree, target_tree;
  source_tree.build(source.positions());
  target_tree.build(target.positions());
  const DataScales scales{2 * std::pow(o.sigma_p * spacing, 2), o.sigma_n * o.sigma_n};

  LabelingProblem problem;
  problem.labels = L + 1;
  problem.sites = n;
  list_feasible_labels(feasible_sites(target, target_tree, transforms, o.dilation * spacing, o), n, problem);
  fill_unary_costs(source, source_tree, target, transforms, spacing, scales, o, problem);
  problem.edges = o.mrf_radius > 0 ? ring_mrf_edges(target, target_tree, o.mrf_radius * spacing, o.mrf_min_normal_dot)
                                   : knn_mrf_edges(target, target_tree, o.mrf_k, o.mrf_min_normal_dot);
  const Eq7Pairwise pairwise(target, problem, transforms, scales, o);
  problem.pairwise = [&pairwise](Index e, int a, int b) { return pairwise(e, a, b); };
  problem.label_cost = label_costs(transforms, n, spacing, o);

  LabelResult result;
  result.self_label = L;
  result.label_costs.assign(problem.label_cost.begin(), problem.label_cost.end() - 1);
  const ExpansionResult r = alpha_expansion(problem, std::vector<int>(size_t(n), L), {.max_cycles = o.max_cycles});
  result.energy_before = r.energy_before;
  result.energy_after = r.energy_after;
  result.truncated_terms = r.truncated_terms;
  result.cycles = r.cycles;
  result.labels = r.labeling;
  if (o.cleanup_ring > 0)
    result.cleaned =
        cleanup_on_ring(target, target_tree, L + 1, o.cleanup_ring * spacing, o.cleanup_majority, result.labels);
  return result;
}

}  // namespace scanfill
