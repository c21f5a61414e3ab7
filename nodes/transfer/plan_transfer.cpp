#include <string>

#include "nodes/core/errors.h"
#include "nodes/transfer/transfer.h"

namespace scanfill {

TransferPlan plan_transfer(const TransferInputs& in) {
  const Synthesis& s = in.synthesis;
  const Index ns = s.points.size();
  if (in.alignment.offset.size() != size_t(ns) || in.alignment.keep.size() != size_t(ns))
    throw InvariantError("transfer: the alignment does not match the synthesis");
  TransferPlan plan;
  plan.exemplar_samples = in.exemplar_samples.positions();
  plan.target_samples = in.target_samples.positions();
  plan.exemplar_points = in.exemplar.size();
  if (!in.exemplar.empty()) plan.exemplar_bounds = bounding_box(in.exemplar.positions());
  plan.mesh_output = in.exemplar.has_faces();
  plan.colours = in.exemplar.has_colours();
  plan.intensity = in.exemplar.has_intensity();
  const Similarity& W = in.working_to_output;
  for (const Patch& patch : s.patches) {
    const Similarity to_working = patch.from_target ? Similarity{} : in.exemplar_to_working;
    plan.patches.push_back(
        {patch.label, patch.origin, patch.from_target, W.compose(patch.transform.compose(to_working))});
  }
  Index kept = 0;
  for (const auto k : in.alignment.keep) kept += k != 0;
  plan.normal.resize(3, kept);
  for (Index j = 0, k = 0; j < ns; ++j) {
    if (!in.alignment.keep[size_t(j)]) continue;
    plan.patch.push_back(s.patch[size_t(j)]);
    plan.base.push_back(s.base[size_t(j)]);
    plan.shift.push_back(in.alignment.offset[size_t(j)] * W.scale);
    const Eigen::Vector3d nj = s.points.normals().col(j);
    plan.normal.col(k++) = W.apply_normal(nj);
  }
  return plan;
}

Index first_point_outside(const TransferPlan& plan, const PointSet& points) {
  const BoundingBox& b = plan.exemplar_bounds;
  // Room for rounding only: a tile of the planned exemplar lies inside exactly.
  const double slack = 1e-9 * std::max(1.0, b.diagonal());
  for (Index i = 0; i < points.size(); ++i) {
    const Eigen::Vector3d p = points.positions().col(i);
    if ((p.array() < b.min.array() - slack).any() || (p.array() > b.max.array() + slack).any()) return i;
  }
  return -1;
}

std::string plan_inconsistency(const TransferPlan& plan) {
  const size_t k = plan.patch.size();
  if (plan.base.size() != k || plan.shift.size() != k || size_t(plan.normal.cols()) != k)
    return "per-sample arrays of different lengths";
  for (size_t i = 0; i < k; ++i) {
    const auto p = plan.patch[i];
    if (p < 0 || size_t(p) >= plan.patches.size()) return "sample " + std::to_string(i) + ": patch out of range";
    const Index bases = plan.patches[size_t(p)].from_target ? plan.target_samples.cols() : plan.exemplar_samples.cols();
    if (plan.base[i] < 0 || plan.base[i] >= bases) return "sample " + std::to_string(i) + ": base out of range";
  }
  if (plan.exemplar_points < 0) return "negative exemplar point count";
  return "";
}

std::vector<std::pair<Index, Index>> tile_ranges(Index n, Index tiles) {
  if (tiles <= 0 || n < 0) throw InvariantError("tile_ranges: needs tiles > 0 and n >= 0");
  std::vector<std::pair<Index, Index>> out;
  for (Index t = 0, begin = 0; t < tiles; ++t) {
    const Index end = begin + n / tiles + (t < n % tiles ? 1 : 0);
    out.emplace_back(begin, end);
    begin = end;
  }
  return out;
}

PointSet tile_points(const PointSet& points, std::pair<Index, Index> range) {
  if (range.first < 0 || range.second > points.size() || range.first > range.second)
    throw InvariantError("tile_points: a range outside the points");
  std::vector<std::int32_t> idx(size_t(range.second - range.first));
  for (size_t i = 0; i < idx.size(); ++i) idx[i] = std::int32_t(range.first + Index(i));
  return subset(points, idx);
}

}  // namespace scanfill
