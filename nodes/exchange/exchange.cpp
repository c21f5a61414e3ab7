#include "nodes/exchange/exchange.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>

#include "nodes/core/errors.h"
#include "nodes/graphcut/expansion.h"

namespace scanfill {
namespace {

// One face of a box sampled on a grid of cell centres, with links to the right and upper neighbours.
void sample_face(const PartBox& box, int axis, int side, double spacing, int box_index, std::vector<double>& xyz,
                 std::vector<double>& normals, BoxSamples& out) {
  const int a = (axis + 1) % 3, b = (axis + 2) % 3;
  const Eigen::Vector3d size = box.size();
  const int na = std::max(2, int(std::ceil(size(a) / spacing))), nb = std::max(2, int(std::ceil(size(b) / spacing)));
  const auto first = std::int32_t(out.box.size());
  for (int u = 0; u < na; ++u)
    for (int v = 0; v < nb; ++v) {
      Eigen::Vector3d p;
      p(axis) = side > 0 ? box.max(axis) : box.min(axis);
      p(a) = box.min(a) + (u + 0.5) * size(a) / na;
      p(b) = box.min(b) + (v + 0.5) * size(b) / nb;
      Eigen::Vector3d n = Eigen::Vector3d::Zero();
      n(axis) = side;
      xyz.insert(xyz.end(), p.data(), p.data() + 3);
      normals.insert(normals.end(), n.data(), n.data() + 3);
      out.box.push_back(box_index);
      const std::int32_t self = first + std::int32_t(u * nb + v);
      if (v + 1 < nb) out.edges.push_back({self, self + 1});
      if (u + 1 < na) out.edges.push_back({self, self + std::int32_t(nb)});
    }
}

void check_boxes(const PartBoxes& boxes, const char* what) {
  if (boxes.empty()) throw InvariantError(std::string(what) + " has no part boxes");
  for (const PartBox& b : boxes)
    if (!(b.size().array() > 0).all() || !b.size().allFinite())
      throw InvariantError(std::string(what) + " has a part box without volume");
}

PartBox bounds_of(const PartBoxes& boxes) {
  PartBox all = boxes.front();
  for (const PartBox& b : boxes) all = {all.min.cwiseMin(b.min), all.max.cwiseMax(b.max)};
  return all;
}

// Every (i, j, R) map, equal maps merged (translation compared on a grid of `step`, the linear part to 1e-9).
std::vector<BoxTransform> candidate_maps(const PartBoxes& source, const PartBoxes& target, double step,
                                         const std::vector<bool>& usable) {
  std::vector<BoxTransform> out;
  std::map<std::array<long long, 12>, int> seen;
  for (int i = 0; i < int(source.size()); ++i)
    if (usable[size_t(i)])
      for (int j = 0; j < int(target.size()); ++j)
        for (int r = 0; r < int(axis_rotations().size()); ++r) {
          const BoxTransform t = box_transform(source[size_t(i)], i, target[size_t(j)], j, r);
          std::array<long long, 12> key{};
          const Eigen::Matrix3d L = t.linear();
          for (int k = 0; k < 9; ++k) key[size_t(k)] = std::llround(L(k) * 1e9);
          for (int k = 0; k < 3; ++k) key[size_t(9 + k)] = std::llround(t.translation(k) / step);
          if (seen.emplace(key, int(out.size())).second) out.push_back(t);
        }
  return out;
}

// For each map, per target box the source box it carries onto it (-1: none).
std::vector<std::vector<int>> box_matches(const std::vector<BoxTransform>& maps, const PartBoxes& source,
                                          const PartBoxes& target, double tolerance, const std::vector<bool>& usable) {
  std::vector<std::vector<int>> matches(maps.size(), std::vector<int>(target.size(), -1));
  for (size_t l = 0; l < maps.size(); ++l)
    for (int k = 0; k < int(source.size()); ++k) {
      if (!usable[size_t(k)]) continue;
      const PartBox image = maps[l].apply(source[size_t(k)]);
      for (size_t j = 0; j < target.size(); ++j) {
        const double tol = tolerance * target[j].size().norm();
        const bool fits = (image.min - target[j].min).cwiseAbs().maxCoeff() <= tol &&
                          (image.max - target[j].max).cwiseAbs().maxCoeff() <= tol;
        if (fits && matches[l][j] < 0) matches[l][j] = k;
      }
    }
  return matches;
}

// h_l: eq. 8 with the preferences of eq. 9 (see exchange.h).
double map_cost(const BoxTransform& t, const ExchangeOptions& o) {
  return o.label_cost * (1 + o.rotation_cost * (1 - std::cos(t.angle())) / 2 + o.distortion_cost * t.distortion() +
                         o.scale_cost * t.log_scale() * t.log_scale());
}

// The labelling problem on T's box samples.
LabelingProblem box_problem(const BoxSamples& samples, const std::vector<BoxTransform>& maps,
                            const std::vector<std::vector<int>>& matches, const PartBoxes& source,
                            const PartBoxes& target, const ExchangeOptions& o) {
  LabelingProblem problem;
  problem.labels = int(maps.size());
  std::vector<std::pair<int, double>> costs;
  for (Index s = 0; s < samples.points.size(); ++s) {
    const int j = samples.box[size_t(s)];
    const double tol = o.match_tolerance * target[size_t(j)].size().norm();
    costs.clear();
    for (size_t l = 0; l < maps.size(); ++l) {
      const int k = matches[l][size_t(j)];
      if (k < 0) continue;
      const double d = distance_to_box_surface(maps[l].apply(source[size_t(k)]), samples.points.positions().col(s));
      costs.push_back({int(l), std::min(1.0, (d / tol) * (d / tol))});
    }
    problem.add_site(costs);
  }
  problem.edges = samples.edges;
  const double smoothness = o.smoothness;
  problem.pairwise = [smoothness](Index, int a, int b) { return a == b ? 0.0 : smoothness; };
  for (const BoxTransform& t : maps) problem.label_cost.push_back(map_cost(t, o));
  return problem;
}

// The start: every sample of box j takes the cheapest map that explains j.
std::vector<int> cheapest_per_box(const BoxSamples& samples, const std::vector<std::vector<int>>& matches,
                                  const std::vector<double>& label_cost, size_t boxes) {
  std::vector<int> best(boxes, -1);
  for (size_t l = 0; l < matches.size(); ++l)
    for (size_t j = 0; j < boxes; ++j)
      if (matches[l][j] >= 0 && (best[j] < 0 || label_cost[l] < label_cost[size_t(best[j])])) best[j] = int(l);
  std::vector<int> labeling(samples.box.size());
  for (size_t s = 0; s < labeling.size(); ++s) labeling[s] = best[size_t(samples.box[s])];
  return labeling;
}

// Per target box, the label most of its samples took (ties: the lower label).
std::vector<int> majority_per_box(const BoxSamples& samples, const std::vector<int>& labeling, size_t boxes) {
  std::vector<std::map<int, Index>> votes(boxes);
  for (size_t s = 0; s < labeling.size(); ++s) ++votes[size_t(samples.box[s])][labeling[s]];
  std::vector<int> out(boxes, -1);
  for (size_t j = 0; j < boxes; ++j) {
    Index most = 0;
    for (const auto& [label, count] : votes[j])
      if (count > most) most = count, out[j] = label;
  }
  return out;
}

// The labels used, renumbered in the order the target boxes first use them: per box its label and source box, per
// sample its label.
void record_labels(const std::vector<BoxTransform>& maps, const std::vector<std::vector<int>>& matches,
                   const std::vector<int>& labeling, const std::vector<int>& box_labels, BoxAnalogy& out) {
  std::map<int, int> renumber;
  const auto number = [&](int l) {
    if (renumber.emplace(l, int(out.transforms.size())).second) out.transforms.push_back(maps[size_t(l)]);
    return renumber.at(l);
  };
  for (size_t j = 0; j < box_labels.size(); ++j) {
    out.box_label.push_back(number(box_labels[j]));
    out.box_source.push_back(matches[size_t(box_labels[j])][j]);
  }
  for (const int l : labeling) out.sample_label.push_back(number(l));
}

Eigen::Matrix3Xd to_matrix(const std::vector<Eigen::Vector3d>& v) {
  Eigen::Matrix3Xd m(3, Index(v.size()));
  for (size_t i = 0; i < v.size(); ++i) m.col(Index(i)) = v[i];
  return m;
}

}  // namespace

std::vector<std::vector<Index>> points_by_part(const PointSet& exemplar, const PartBoxes& source) {
  const std::vector<int> part = assign_parts(exemplar.positions(), source);
  std::vector<std::vector<Index>> members(source.size());
  for (size_t p = 0; p < part.size(); ++p) members[size_t(part[p])].push_back(Index(p));
  return members;
}

std::vector<std::vector<Index>> triangles_by_part(const PointSet& exemplar, const PartBoxes& source) {
  const Matrix3Xi& F = exemplar.faces();
  Eigen::Matrix3Xd centroids(3, F.cols());
  for (Index f = 0; f < F.cols(); ++f)
    centroids.col(f) =
        (exemplar.positions().col(F(0, f)) + exemplar.positions().col(F(1, f)) + exemplar.positions().col(F(2, f))) / 3;
  const std::vector<int> part = assign_parts(centroids, source);
  std::vector<std::vector<Index>> members(source.size());
  for (size_t f = 0; f < part.size(); ++f) members[size_t(part[f])].push_back(Index(f));
  return members;
}

const std::vector<std::string>& common_part_properties() {
  static const std::vector<std::string> names{"part",  "part_id",     "segment",     "segment_id",
                                              "label", "scalar_part", "scalar_label"};
  return names;
}

BoxSamples sample_boxes(const PartBoxes& boxes, double spacing) {
  BoxSamples out;
  std::vector<double> xyz, normals;
  for (size_t j = 0; j < boxes.size(); ++j)
    for (int axis = 0; axis < 3; ++axis)
      for (const int side : {-1, 1}) sample_face(boxes[j], axis, side, spacing, int(j), xyz, normals, out);
  const auto n = Index(out.box.size());
  out.points = PointSet(Eigen::Map<const Eigen::Matrix3Xd>(xyz.data(), 3, n));
  out.points.set_normals(Eigen::Map<const Eigen::Matrix3Xd>(normals.data(), 3, n));
  return out;
}

BoxAnalogy label_box_analogy(const PartBoxes& source, const PartBoxes& target, const ExchangeOptions& options,
                             const std::vector<bool>& usable_boxes) {
  check_boxes(source, "the source");
  check_boxes(target, "the target");
  const std::vector<bool> usable = usable_boxes.empty() ? std::vector<bool>(source.size(), true) : usable_boxes;
  if (usable.size() != source.size() || std::find(usable.begin(), usable.end(), true) == usable.end())
    throw InvariantError("no source box holds any of the exemplar");
  const double diagonal = bounds_of(target).size().norm();
  BoxAnalogy out;
  out.samples = sample_boxes(target, options.box_spacing * diagonal);
  const std::vector<BoxTransform> maps = candidate_maps(source, target, 1e-6 * diagonal, usable);
  const auto matches = box_matches(maps, source, target, options.match_tolerance, usable);
  out.candidates = Index(maps.size());
  const LabelingProblem problem = box_problem(out.samples, maps, matches, source, target, options);
  ExpansionOptions expansion;
  expansion.max_cycles = options.max_cycles;
  const ExpansionResult result =
      alpha_expansion(problem, cheapest_per_box(out.samples, matches, problem.label_cost, target.size()), expansion);
  out.energy_before = result.energy_before;
  out.energy_after = result.energy_after;
  out.converged = result.converged;
  record_labels(maps, matches, result.labeling, majority_per_box(out.samples, result.labeling, target.size()), out);
  return out;
}

PartBoxes boxes_of_parts(const std::vector<Eigen::Vector3d>& positions, const std::vector<int>& labels,
                         std::vector<int>& parts) {
  std::map<int, PartBox> boxes;
  for (size_t p = 0; p < labels.size(); ++p) {
    if (labels[p] < 0) continue;
    const auto [it, fresh] = boxes.emplace(labels[p], PartBox{positions[p], positions[p]});
    if (!fresh) it->second = {it->second.min.cwiseMin(positions[p]), it->second.max.cwiseMax(positions[p])};
  }
  PartBoxes out;
  parts.clear();
  for (const auto& [label, box] : boxes) out.push_back(box), parts.push_back(label);
  return out;
}

std::vector<int> assign_parts(const Eigen::Matrix3Xd& points, const PartBoxes& boxes) {
  std::vector<int> part(size_t(points.cols()), 0);
  for (Index p = 0; p < points.cols(); ++p) {
    double deepest = -std::numeric_limits<double>::infinity();
    for (size_t k = 0; k < boxes.size(); ++k) {
      const double depth = depth_in_box(boxes[k], points.col(p));
      if (depth > deepest) deepest = depth, part[size_t(p)] = int(k);
    }
  }
  return part;
}

Exchange synthesize_exchange(const PointSet& exemplar, const std::vector<std::vector<Index>>& members,
                             BoxAnalogy analogy) {
  Exchange out;
  std::vector<Eigen::Vector3d> xyz, normals;
  std::vector<std::int32_t> faces;
  std::vector<std::int32_t> new_index(size_t(exemplar.size()), -1);
  for (size_t j = 0; j < analogy.box_label.size(); ++j) {
    const BoxTransform& t = analogy.transforms[size_t(analogy.box_label[j])];
    std::fill(new_index.begin(), new_index.end(), -1);  // each target box gets its own copy of the vertices
    const auto carry = [&](Index v) {
      if (new_index[size_t(v)] >= 0) return new_index[size_t(v)];
      new_index[size_t(v)] = std::int32_t(xyz.size());
      xyz.push_back(t.apply(Eigen::Vector3d(exemplar.positions().col(v))));
      if (exemplar.has_normals()) normals.push_back(t.apply_normal(exemplar.normals().col(v)));
      out.output_label.push_back(analogy.box_label[j]);
      return new_index[size_t(v)];
    };
    for (const Index m : members[size_t(analogy.box_source[j])]) {
      if (!exemplar.has_faces()) {
        carry(m);
        continue;
      }
      for (int c = 0; c < 3; ++c) faces.push_back(carry(exemplar.faces()(c, m)));
    }
  }
  out.output = PointSet(to_matrix(xyz));
  if (exemplar.has_normals()) out.output.set_normals(to_matrix(normals));
  if (!faces.empty()) out.output.set_faces(Eigen::Map<const Matrix3Xi>(faces.data(), 3, Index(faces.size() / 3)));
  out.output.check();
  out.analogy = std::move(analogy);
  return out;
}

Exchange exchange_style(const PointSet& exemplar, const PartBoxes& source, const PartBoxes& target,
                        const ExchangeOptions& options) {
  const std::vector<std::vector<Index>> members =
      exemplar.has_faces() ? triangles_by_part(exemplar, source) : points_by_part(exemplar, source);
  std::vector<bool> holds(source.size());
  for (size_t k = 0; k < source.size(); ++k) holds[k] = !members[k].empty();
  return synthesize_exchange(exemplar, members, label_box_analogy(source, target, options, holds));
}

}  // namespace scanfill
