#include "nodes/transfer/transfer.h"

#include <tbb/parallel_for.h>

#include "nodes/core/errors.h"
#include "nodes/core/kdtree.h"
#include "nodes/sample/sample.h"

namespace scanfill {
namespace {

// Nearest sample of every point.
std::vector<std::int32_t> nearest_samples(const PointSet& full, const Eigen::Matrix3Xd& samples) {
  KdTree tree;
  tree.build(samples);
  std::vector<std::int32_t> nearest;
  std::vector<double> d2;
  nearest_each(tree, full.positions(), nearest, d2);
  return nearest;
}

// Per patch and base sample: the carried sample it became (index into plan.patch), or -1.
std::vector<std::vector<std::int32_t>> carried_of(const TransferPlan& plan) {
  std::vector<std::vector<std::int32_t>> made(plan.patches.size());
  for (size_t p = 0; p < made.size(); ++p)
    made[p].assign(size_t(plan.patches[p].from_target ? plan.target_samples.cols() : plan.exemplar_samples.cols()), -1);
  for (size_t k = 0; k < plan.patch.size(); ++k) made[size_t(plan.patch[k])][size_t(plan.base[k])] = std::int32_t(k);
  return made;
}

// The output being filled, patch by patch.
struct Filling {
  Eigen::Matrix3Xd P, N;
  Matrix3Xu8 C;       // 3 by 0 unless the plan has colours
  Eigen::VectorXf I;  // empty unless the plan has intensity
  std::vector<Origin> origin;
  std::vector<std::int32_t> label;
  std::vector<Eigen::Vector3i> tris;
  Index next = 0;
};

// The points of `full` patch p emits (`e`: per point, the carried sample or -1), and its triangles.
void fill_patch(const TransferPlan& plan, size_t p, const PointSet& full, const std::vector<std::int32_t>& e,
                Filling& out) {
  const PlanPatch& patch = plan.patches[p];
  std::vector<std::int32_t> slot(e.size(), -1);
  for (size_t i = 0; i < e.size(); ++i)
    if (e[i] >= 0) slot[i] = std::int32_t(out.next++);
  const Similarity& whole = patch.whole;
  tbb::parallel_for(size_t(0), e.size(), [&](size_t i) {
    const auto k = e[i];
    if (k < 0) return;
    const Index o = slot[i];
    // The offset moves along the sample's normal (both in the output frame).
    out.P.col(o) = whole.apply(full.positions().col(Index(i))) + plan.shift[size_t(k)] * plan.normal.col(k);
    out.N.col(o) = full.has_normals() ? whole.apply_normal(full.normals().col(Index(i))) : plan.normal.col(k);
    if (plan.colours) out.C.col(o) = patch.from_target ? kCopiedColour : full.colours().col(Index(i));
    if (plan.intensity) out.I(o) = patch.from_target ? kCopiedIntensity : full.intensity()(Index(i));
    out.origin[size_t(o)] = patch.origin;
    out.label[size_t(o)] = patch.origin == Origin::kExemplar ? -1 : patch.label;
  });
  if (plan.mesh_output && full.has_faces())
    for (Index f = 0; f < full.faces().cols(); ++f) {
      const Eigen::Vector3i c = full.faces().col(f);
      const Eigen::Vector3i m(slot[size_t(c(0))], slot[size_t(c(1))], slot[size_t(c(2))]);
      if (m.minCoeff() >= 0) out.tris.push_back(m);
    }
}

TransferResult result_of(const TransferPlan& plan, Filling&& f) {
  TransferResult out;
  out.points = PointSet(std::move(f.P));
  out.points.set_normals(std::move(f.N));
  if (plan.colours) out.points.set_colours(std::move(f.C));
  if (plan.intensity) out.points.set_intensity(std::move(f.I));
  out.origin = std::move(f.origin);
  out.label = std::move(f.label);
  if (!f.tris.empty()) {
    Matrix3Xi F(3, Index(f.tris.size()));
    for (size_t t = 0; t < f.tris.size(); ++t) F.col(Index(t)) = f.tris[t];
    out.points.set_faces(std::move(F));
  }
  return out;
}

bool uses(const TransferPlan& plan, bool from_target) {
  for (const auto& p : plan.patches)
    if (p.from_target == from_target) return true;
  return false;
}

}  // namespace

PointSet copy_surface(const PointSet& target, Index exemplar_points, Index exemplar_samples, Index target_samples) {
  if (!target.has_faces() || exemplar_samples <= 0) return target;
  const double per_sample = std::max(1.0, double(exemplar_points) / double(exemplar_samples));
  const auto wanted = Index(std::ceil(per_sample * double(target_samples)));
  if (target.size() >= wanted) return target;
  return random_surface_points(target, wanted, 1);
}

bool plan_copies_target(const TransferPlan& plan) {
  return uses(plan, true);
}

TransferResult apply_plan(const TransferPlan& plan, const PointSet* exemplar, const PointSet* copies,
                          const ProgressFn& progress) {
  if (!exemplar || !uses(plan, false)) exemplar = nullptr;
  if (!copies || !uses(plan, true)) copies = nullptr;
  if (exemplar && ((plan.colours && !exemplar->has_colours()) || (plan.intensity && !exemplar->has_intensity())))
    throw InvariantError("apply_plan: the plan's exemplar had colours or intensity that these points lack");
  const auto made = carried_of(plan);
  const auto exemplar_nearest = exemplar ? nearest_samples(*exemplar, plan.exemplar_samples) : std::vector<int>{};
  report(progress, 0.2);
  const auto target_nearest = copies ? nearest_samples(*copies, plan.target_samples) : std::vector<int>{};
  report(progress, 0.4);
  // Count, then fill, patch by patch.
  const size_t np = plan.patches.size();
  std::vector<std::vector<std::int32_t>> emitted(np);  // per patch: per base point, the carried sample or -1
  Index total = 0;
  for (size_t p = 0; p < np; ++p) {
    const bool t = plan.patches[p].from_target;
    if (!(t ? copies : exemplar)) continue;
    const auto& nearest = t ? target_nearest : exemplar_nearest;
    auto& e = emitted[p];
    e.resize(nearest.size());
    for (size_t i = 0; i < nearest.size(); ++i) {
      e[i] = made[p][size_t(nearest[i])];
      total += e[i] >= 0;
    }
  }
  Filling out{Eigen::Matrix3Xd(3, total),
              Eigen::Matrix3Xd(3, total),
              Matrix3Xu8(3, plan.colours ? total : 0),
              Eigen::VectorXf(plan.intensity ? total : 0),
              std::vector<Origin>(size_t(total)),
              std::vector<std::int32_t>(size_t(total)),
              {},
              0};
  for (size_t p = 0; p < np; ++p) {
    const PointSet* full = plan.patches[p].from_target ? copies : exemplar;
    if (full) fill_patch(plan, p, *full, emitted[p], out);
    report(progress, 0.4 + 0.6 * double(p + 1) / double(np));
  }
  return result_of(plan, std::move(out));
}

TransferResult transfer_planned(const TransferPlan& plan, const PointSet* exemplar, const PointSet* target,
                                const ProgressFn& progress) {
  if (!target || !plan_copies_target(plan)) return apply_plan(plan, exemplar, nullptr, progress);
  // Copies come from the target's surface at the exemplar's density, not from a low-poly template's few vertices.
  const PointSet copies =
      copy_surface(*target, plan.exemplar_points, plan.exemplar_samples.cols(), plan.target_samples.cols());
  return apply_plan(plan, exemplar, &copies, progress);
}

TransferResult transfer(const TransferInputs& in, const ProgressFn& progress) {
  return transfer_planned(plan_transfer(in), &in.exemplar, &in.target, progress);
}

}  // namespace scanfill
