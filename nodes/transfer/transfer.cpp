#include "nodes/transfer/transfer.h"

#include <tbb/parallel_for.h>

#include "nodes/core/errors.h"
#include "nodes/core/kdtree.h"
#include "nodes/sample/sample.h"

namespace scanfill {

PointSet copy_surface(const PointSet& target, Index exemplar_points, Index exemplar_samples, Index target_samples) {
  if (!target.has_faces() || exemplar_samples <= 0) return target;
  const double per_sample = std::max(1.0, double(exemplar_points) / double(exemplar_samples));
  const auto wanted = Index(std::ceil(per_sample * double(target_samples)));
  if (target.size() >= wanted) return target;
  return random_surface_points(target, wanted, 1);
}

TransferResult transfer(const TransferInputs& in, const ProgressFn& progress) {
  const Synthesis& s = in.synthesis;
  const Index ns = s.points.size();
  if (in.alignment.offset.size() != size_t(ns) || in.alignment.keep.size() != size_t(ns))
    throw InvariantError("transfer: the alignment does not match the synthesis");
  const bool faces = in.exemplar.has_faces();
  // Copies come from the target's surface at the exemplar's density, not from a low-poly template's few vertices.
  bool need_exemplar = false, need_target = false;
  for (const auto& p : s.patches) (p.from_target ? need_target : need_exemplar) = true;
  const PointSet target =
      need_target ? copy_surface(in.target, in.exemplar.size(), in.exemplar_samples.size(), in.target_samples.size())
                  : in.target;

  // Per patch and base sample: the synthesis point it became (or -1).
  const size_t np = s.patches.size();
  std::vector<std::vector<std::int32_t>> made(np);
  for (size_t p = 0; p < np; ++p)
    made[p].assign(size_t(s.patches[p].from_target ? in.target_samples.size() : in.exemplar_samples.size()), -1);
  for (Index j = 0; j < ns; ++j)
    if (in.alignment.keep[size_t(j)]) made[size_t(s.patch[size_t(j)])][size_t(s.base[size_t(j)])] = std::int32_t(j);

  // Nearest sample of every original point, per input (shared by that input's patches).
  const auto nearest_samples = [](const PointSet& full, const PointSet& samples) {
    KdTree tree;
    tree.build(samples.positions());
    std::vector<std::int32_t> nearest;
    std::vector<double> d2;
    nearest_each(tree, full.positions(), nearest, d2);
    return nearest;
  };
  const std::vector<std::int32_t> exemplar_nearest =
      need_exemplar ? nearest_samples(in.exemplar, in.exemplar_samples) : std::vector<std::int32_t>{};
  report(progress, 0.2);
  const std::vector<std::int32_t> target_nearest =
      need_target ? nearest_samples(target, in.target_samples) : std::vector<std::int32_t>{};
  report(progress, 0.4);

  // Count, then fill, patch by patch.
  std::vector<std::vector<std::int32_t>> emitted(np);  // per patch: per base point, the synthesis point or -1
  Index total = 0;
  for (size_t p = 0; p < np; ++p) {
    const bool t = s.patches[p].from_target;
    const auto& nearest = t ? target_nearest : exemplar_nearest;
    auto& e = emitted[p];
    e.resize(nearest.size());
    for (size_t i = 0; i < nearest.size(); ++i) {
      e[i] = made[p][size_t(nearest[i])];
      total += e[i] >= 0;
    }
  }
  TransferResult out;
  Eigen::Matrix3Xd P(3, total), N(3, total);
  const bool colours = in.exemplar.has_colours(), intensity = in.exemplar.has_intensity();
  Matrix3Xu8 C(3, colours ? total : 0);
  Eigen::VectorXf I(intensity ? total : 0);
  out.origin.resize(size_t(total));
  out.label.resize(size_t(total));
  std::vector<Eigen::Vector3i> tris;
  const Similarity& W = in.working_to_output;
  Index base = 0;
  for (size_t p = 0; p < np; ++p) {
    const Patch& patch = s.patches[p];
    const PointSet& full = patch.from_target ? target : in.exemplar;
    const Similarity to_working = patch.from_target ? Similarity{} : in.exemplar_to_working;
    const Similarity whole = W.compose(patch.transform.compose(to_working));
    const auto& e = emitted[p];
    std::vector<std::int32_t> slot(e.size(), -1);
    Index next = base;
    for (size_t i = 0; i < e.size(); ++i)
      if (e[i] >= 0) slot[i] = std::int32_t(next++);
    tbb::parallel_for(size_t(0), e.size(), [&](size_t i) {
      const auto j = e[i];
      if (j < 0) return;
      const Index o = slot[i];
      const Eigen::Vector3d nj = s.points.normals().col(j);
      // The offset moves along the sample's (working-frame) normal, mapped to the output frame.
      P.col(o) =
          whole.apply(full.positions().col(Index(i))) + in.alignment.offset[size_t(j)] * W.scale * W.apply_normal(nj);
      N.col(o) = full.has_normals() ? whole.apply_normal(full.normals().col(Index(i))) : W.apply_normal(nj);
      if (colours) C.col(o) = patch.from_target ? kCopiedColour : in.exemplar.colours().col(Index(i));
      if (intensity) I(o) = patch.from_target ? kCopiedIntensity : in.exemplar.intensity()(Index(i));
      out.origin[size_t(o)] = patch.origin;
      out.label[size_t(o)] = patch.origin == Origin::kExemplar ? -1 : patch.label;
    });
    if (faces && full.has_faces())
      for (Index f = 0; f < full.faces().cols(); ++f) {
        const Eigen::Vector3i c = full.faces().col(f);
        const Eigen::Vector3i m(slot[size_t(c(0))], slot[size_t(c(1))], slot[size_t(c(2))]);
        if (m.minCoeff() >= 0) tris.push_back(m);
      }
    base = next;
    report(progress, 0.4 + 0.6 * double(p + 1) / double(np));
  }
  out.points = PointSet(std::move(P));
  out.points.set_normals(std::move(N));
  if (colours) out.points.set_colours(std::move(C));
  if (intensity) out.points.set_intensity(std::move(I));
  if (!tris.empty()) {
    Matrix3Xi F(3, Index(tris.size()));
    for (size_t f = 0; f < tris.size(); ++f) F.col(Index(f)) = tris[f];
    out.points.set_faces(std::move(F));
  }
  return out;
}

}  // namespace scanfill
