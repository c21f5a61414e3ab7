#include "nodes/transfer/transfer.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "nodes/core/errors.h"
#include "nodes/core/kdtree.h"
#include "nodes/sample/sample.h"

namespace scanfill {
namespace {

// Nearest sample (in `tree`) of every column of P, into nearest[0, P.cols()), in blocks (no per-point distance array).
void nearest_into(const KdTree& tree, const Eigen::Matrix3Xd& P, std::int32_t* nearest) {
  tbb::parallel_for(tbb::blocked_range<Index>(0, P.cols(), 4096), [&](const tbb::blocked_range<Index>& r) {
    double d2 = 0;
    for (Index i = r.begin(); i != r.end(); ++i) tree.knn(P.col(i), 1, &nearest[size_t(i)], &d2);
  });
}

// Nearest sample of every point.
std::vector<std::int32_t> nearest_samples(const PointSet& full, const Eigen::Matrix3Xd& samples) {
  KdTree tree;
  tree.build(samples);
  std::vector<std::int32_t> nearest(size_t(full.size()));
  nearest_into(tree, full.positions(), nearest.data());
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

// One patch's view of its base input: which carried sample each point follows (-1: none).
struct PatchInput {
  const PointSet* full = nullptr;            // null: the patch emits nothing
  const std::vector<std::int32_t>* nearest;  // per point of full: its nearest base sample
  const std::vector<std::int32_t>* made;     // per base sample: the carried sample, or -1
  Index first = 0;                           // full's point i is point first + i of the whole input (a run of it)
  std::int32_t carried(Index i) const { return (*made)[size_t((*nearest)[size_t(first + i)])]; }
};

// The output points patch p emits from points [begin, end) of its input, in order.
TransferResult emit_run(const TransferPlan& plan, size_t p, const PatchInput& in, Index begin, Index end,
                        std::vector<Index>& rows) {
  const PlanPatch& patch = plan.patches[p];
  const PointSet& full = *in.full;
  rows.clear();
  for (Index i = begin; i < end; ++i)
    if (in.carried(i) >= 0) rows.push_back(i);
  const Index n = Index(rows.size());
  Eigen::Matrix3Xd P(3, n), N(3, n);
  Matrix3Xu8 C(3, plan.colours ? n : 0);
  Eigen::VectorXf I(plan.intensity ? n : 0);
  const Similarity& whole = patch.whole;
  tbb::parallel_for(tbb::blocked_range<Index>(0, n, 4096), [&](const tbb::blocked_range<Index>& r) {
    for (Index o = r.begin(); o != r.end(); ++o) {
      const Index i = rows[size_t(o)];
      const auto k = in.carried(i);
      // The offset moves along the sample's normal (both in the output frame).
      P.col(o) = whole.apply(full.positions().col(i)) + plan.shift[size_t(k)] * plan.normal.col(k);
      N.col(o) = full.has_normals() ? whole.apply_normal(full.normals().col(i)) : plan.normal.col(k);
      if (plan.colours) C.col(o) = patch.from_target ? kCopiedColour : full.colours().col(i);
      if (plan.intensity) I(o) = patch.from_target ? kCopiedIntensity : full.intensity()(i);
    }
  });
  TransferResult out;
  out.points = PointSet(std::move(P));
  out.points.set_normals(std::move(N));
  if (plan.colours) out.points.set_colours(std::move(C));
  if (plan.intensity) out.points.set_intensity(std::move(I));
  out.origin.assign(size_t(n), patch.origin);
  out.label.assign(size_t(n), patch.origin == Origin::kExemplar ? -1 : patch.label);
  return out;
}

// Per point of the patch's input, its output index (-1: not emitted), from `first` on; for its triangles.
void slots_of(const PatchInput& in, Index first, std::vector<std::int32_t>& slot) {
  slot.assign(size_t(in.full->size()), -1);
  for (Index i = 0; i < in.full->size(); ++i)
    if (in.carried(i) >= 0) slot[size_t(i)] = std::int32_t(first++);
}

// The triangles of the patch's input whose three corners it emits, as output indices (`slot`); wound the other way
// when the patch mirrors its input (`mirrored`), so that they still face along their points' normals.
void add_triangles(const PointSet& full, const std::vector<std::int32_t>& slot, bool mirrored,
                   std::vector<Eigen::Vector3i>& tris) {
  for (Index f = 0; f < full.faces().cols(); ++f) {
    const Eigen::Vector3i c = full.faces().col(f);
    const Eigen::Vector3i m(slot[size_t(c(0))], slot[size_t(c(mirrored ? 2 : 1))], slot[size_t(c(mirrored ? 1 : 2))]);
    if (m.minCoeff() >= 0) tris.push_back(m);
  }
}

// The points and triangles patch p will emit.
std::pair<Index, Index> patch_counts(const PatchInput& in, bool mesh_output) {
  if (!in.full) return {0, 0};
  Index points = 0, faces = 0;
  for (Index i = 0; i < in.full->size(); ++i) points += in.carried(i) >= 0;
  if (mesh_output && in.full->has_faces())
    for (Index f = 0; f < in.full->faces().cols(); ++f) {
      const Eigen::Vector3i c = in.full->faces().col(f);
      faces += in.carried(c(0)) >= 0 && in.carried(c(1)) >= 0 && in.carried(c(2)) >= 0;
    }
  return {points, faces};
}

bool uses(const TransferPlan& plan, bool from_target) {
  for (const auto& p : plan.patches)
    if (p.from_target == from_target) return true;
  return false;
}

// The output of a stream gathered in one TransferResult (apply_plan): filled in place, chunk by chunk.
struct Gathered {
  Eigen::Matrix3Xd P, N;
  Matrix3Xu8 C;
  Eigen::VectorXf I;
  std::vector<Origin> origin;
  std::vector<std::int32_t> label;
  Index next = 0;

  void begin(const TransferPlan& plan, const TransferCounts& c) {
    P.resize(3, c.points);
    N.resize(3, c.points);
    C.resize(3, plan.colours ? c.points : 0);
    I.resize(plan.intensity ? c.points : 0);
    origin.reserve(size_t(c.points));
    label.reserve(size_t(c.points));
  }
  void add(const TransferResult& chunk) {
    const Index n = chunk.points.size();
    P.middleCols(next, n) = chunk.points.positions();
    N.middleCols(next, n) = chunk.points.normals();
    if (C.cols() > 0) C.middleCols(next, n) = chunk.points.colours();
    if (I.size() > 0) I.segment(next, n) = chunk.points.intensity();
    origin.insert(origin.end(), chunk.origin.begin(), chunk.origin.end());
    label.insert(label.end(), chunk.label.begin(), chunk.label.end());
    next += n;
  }
  TransferResult result(Matrix3Xi faces) {
    TransferResult out;
    out.points = PointSet(std::move(P));
    out.points.set_normals(std::move(N));
    if (C.cols() > 0) out.points.set_colours(std::move(C));
    if (I.size() > 0) out.points.set_intensity(std::move(I));
    if (faces.cols() > 0) out.points.set_faces(std::move(faces));
    out.origin = std::move(origin);
    out.label = std::move(label);
    return out;
  }
};

// How many random surface points copy_surface makes of `target`: 0 when it is used as it is.
Index copy_surface_points(const PointSet& target, Index exemplar_points, Index exemplar_samples, Index target_samples) {
  if (!target.has_faces() || exemplar_samples <= 0) return 0;
  const double per_sample = std::max(1.0, double(exemplar_points) / double(exemplar_samples));
  const auto wanted = Index(std::ceil(per_sample * double(target_samples)));
  return target.size() >= wanted ? 0 : wanted;
}

}  // namespace

PointSet copy_surface(const PointSet& target, Index exemplar_points, Index exemplar_samples, Index target_samples) {
  const Index wanted = copy_surface_points(target, exemplar_points, exemplar_samples, target_samples);
  return wanted > 0 ? random_surface_points(target, wanted, 1) : target;
}

bool plan_copies_target(const TransferPlan& plan) {
  return uses(plan, true);
}

TransferCounts stream_plan(const TransferPlan& plan, const PointSet* exemplar, const PointSet* copies,
                           Index chunk_points, const TransferSink& sink, const ProgressFn& progress) {
  if (chunk_points <= 0) throw InvariantError("stream_plan: chunk_points must be positive");
  if (!exemplar || !uses(plan, false)) exemplar = nullptr;
  if (!copies || !uses(plan, true)) copies = nullptr;
  if (exemplar && ((plan.colours && !exemplar->has_colours()) || (plan.intensity && !exemplar->has_intensity())))
    throw InvariantError("apply_plan: the plan's exemplar had colours or intensity that these points lack");
  const auto made = carried_of(plan);
  const auto exemplar_nearest = exemplar ? nearest_samples(*exemplar, plan.exemplar_samples) : std::vector<int>{};
  report(progress, 0.2);
  const auto target_nearest = copies ? nearest_samples(*copies, plan.target_samples) : std::vector<int>{};
  report(progress, 0.4);
  const size_t np = plan.patches.size();
  std::vector<PatchInput> inputs(np);
  TransferCounts counts;
  for (size_t p = 0; p < np; ++p) {
    const bool t = plan.patches[p].from_target;
    inputs[p] = {t ? copies : exemplar, t ? &target_nearest : &exemplar_nearest, &made[p]};
    const auto [points, faces] = patch_counts(inputs[p], plan.mesh_output);
    counts.points += points;
    counts.faces += faces;
    counts.by_origin[int(plan.patches[p].origin)] += points;
  }
  if (sink.begin) sink.begin(counts);
  // Patch by patch in the plan's order, each input's points in their order: the order apply_plan always had.
  std::vector<Index> rows;
  std::vector<std::int32_t> slot;
  std::vector<Eigen::Vector3i> tris;
  Index written = 0;
  for (size_t p = 0; p < np; ++p) {
    const PatchInput& in = inputs[p];
    if (!in.full) continue;
    for (Index begin = 0; begin < in.full->size(); begin += chunk_points) {
      TransferResult run = emit_run(plan, p, in, begin, std::min(in.full->size(), begin + chunk_points), rows);
      if (run.points.size() > 0) sink.points(std::move(run));
    }
    if (counts.faces > 0 && in.full->has_faces()) {
      slots_of(in, written, slot);
      add_triangles(*in.full, slot, plan.patches[p].whole.rotation.determinant() < 0, tris);
    }
    written += patch_counts(in, false).first;
    report(progress, 0.4 + 0.6 * double(p + 1) / double(np));
  }
  if (counts.faces > 0) {
    Matrix3Xi F(3, Index(tris.size()));
    for (size_t t = 0; t < tris.size(); ++t) F.col(Index(t)) = tris[t];
    sink.faces(F);
  }
  return counts;
}

TransferCounts stream_plan_chunks(const TransferPlan& plan, PointChunks& exemplar, Index exemplar_points,
                                  const PointSet* copies, Index chunk_points, const TransferSink& sink,
                                  const ProgressFn& progress) {
  if (chunk_points <= 0) throw InvariantError("stream_plan: chunk_points must be positive");
  if (!copies || !uses(plan, true)) copies = nullptr;
  if (uses(plan, false) && (plan.colours || plan.intensity || plan.mesh_output))
    throw InvariantError("stream_plan_chunks: the plan's exemplar had colours, intensity or triangles, runs have none");
  const auto made = carried_of(plan);
  // Pass 1: every exemplar point's nearest sample (one int32 a point), and what each patch will emit.
  std::vector<std::int32_t> exemplar_nearest(static_cast<size_t>(exemplar_points));
  {
    KdTree tree;
    tree.build(plan.exemplar_samples);
    PointSet run;
    Index at = 0;
    exemplar.rewind();
    while (exemplar.next(chunk_points, run)) {
      if (at + run.size() > exemplar_points) throw InvariantError("stream_plan_chunks: more points than announced");
      nearest_into(tree, run.positions(), exemplar_nearest.data() + at);
      at += run.size();
    }
    if (at != exemplar_points) throw InvariantError("stream_plan_chunks: fewer points than announced");
  }
  report(progress, 0.2);
  const auto target_nearest = copies ? nearest_samples(*copies, plan.target_samples) : std::vector<int>{};
  report(progress, 0.4);
  const size_t np = plan.patches.size();
  TransferCounts counts;
  for (size_t p = 0; p < np; ++p) {
    Index points = 0;
    if (plan.patches[p].from_target) {
      points = copies ? patch_counts({copies, &target_nearest, &made[p]}, false).first : 0;
    } else {
      for (const std::int32_t k : exemplar_nearest) points += made[p][size_t(k)] >= 0;
    }
    counts.points += points;
    counts.by_origin[int(plan.patches[p].origin)] += points;
  }
  if (sink.begin) sink.begin(counts);
  // Pass 2, one per exemplar patch: patch by patch in the plan's order, each input's points in their order.
  std::vector<Index> rows;
  PointSet run;
  for (size_t p = 0; p < np; ++p) {
    if (plan.patches[p].from_target) {
      if (!copies) continue;
      const PatchInput in{copies, &target_nearest, &made[p]};
      for (Index begin = 0; begin < copies->size(); begin += chunk_points) {
        TransferResult out = emit_run(plan, p, in, begin, std::min(copies->size(), begin + chunk_points), rows);
        if (out.points.size() > 0) sink.points(std::move(out));
      }
    } else {
      Index at = 0;
      exemplar.rewind();
      while (exemplar.next(chunk_points, run)) {
        const PatchInput in{&run, &exemplar_nearest, &made[p], at};
        TransferResult out = emit_run(plan, p, in, 0, run.size(), rows);
        if (out.points.size() > 0) sink.points(std::move(out));
        at += run.size();
      }
    }
    report(progress, 0.4 + 0.6 * double(p + 1) / double(np));
  }
  return counts;
}

void EveryKth::add(const TransferResult& chunk) {
  std::vector<std::int32_t> rows;
  for (Index first = (stride_ - seen_ % stride_) % stride_; first < chunk.points.size(); first += stride_)
    rows.push_back(std::int32_t(first));
  seen_ += chunk.points.size();
  if (rows.empty()) return;
  TransferResult part;
  part.points = subset(chunk.points, rows);
  for (const auto r : rows) {
    part.origin.push_back(chunk.origin[size_t(r)]);
    part.label.push_back(chunk.label[size_t(r)]);
  }
  parts_.push_back(std::move(part));
}

TransferResult EveryKth::take() {
  Index total = 0;
  for (const auto& p : parts_) total += p.points.size();
  Gathered g;
  const bool colours = !parts_.empty() && parts_[0].points.has_colours();
  const bool intensity = !parts_.empty() && parts_[0].points.has_intensity();
  TransferPlan shape;  // only its colours and intensity flags
  shape.colours = colours;
  shape.intensity = intensity;
  TransferCounts counts;
  counts.points = total;
  g.begin(shape, counts);
  for (const auto& p : parts_) g.add(p);
  parts_.clear();
  return g.result({});
}

TransferResult apply_plan(const TransferPlan& plan, const PointSet* exemplar, const PointSet* copies,
                          const ProgressFn& progress) {
  Gathered g;
  Matrix3Xi faces;
  const TransferSink sink{[&](const TransferCounts& c) { g.begin(plan, c); },
                          [&](const TransferResult& chunk) { g.add(chunk); }, [&](const Matrix3Xi& f) { faces = f; }};
  const Index most = std::max<Index>({Index(1), exemplar ? exemplar->size() : 0, copies ? copies->size() : 0});
  stream_plan(plan, exemplar, copies, most, sink, progress);
  return g.result(std::move(faces));
}

namespace {

// Where a triangle's points have their nearest target sample: all among the copied samples, none, or to be looked up
// point by point.
enum class FaceCopies : std::uint8_t { kNone, kAll, kLookUp };

// The columns of `samples` where `copied` is `value`.
Eigen::Matrix3Xd samples_where(const Eigen::Matrix3Xd& samples, const std::vector<char>& copied, bool value) {
  std::vector<Index> columns;
  for (Index i = 0; i < samples.cols(); ++i)
    if ((copied[size_t(i)] != 0) == value) columns.push_back(i);
  return samples(Eigen::all, columns);
}

// Distance from q to the nearest point of `tree` (infinite for an empty tree).
double nearest_distance(const KdTree& tree, Index size, const Eigen::Vector3d& q) {
  if (size == 0) return std::numeric_limits<double>::infinity();
  std::int32_t index = 0;
  double d2 = 0;
  tree.knn(q, 1, &index, &d2);
  return std::sqrt(d2);
}

// Per triangle of `target`, from the ball about its centroid through its farthest corner (radius r): when the nearest
// copied sample is farther from the centroid than the nearest other sample by more than 2r (and a rounding margin),
// every point of the triangle is nearer to an uncopied sample, and the other way round. Only the triangles along the
// copied region's border need a lookup per point.
std::vector<FaceCopies> face_copies(const PointSet& target, const Eigen::Matrix3Xd& samples,
                                    const std::vector<char>& copied) {
  const Eigen::Matrix3Xd in = samples_where(samples, copied, true), out = samples_where(samples, copied, false);
  KdTree in_tree, out_tree;
  if (in.cols() > 0) in_tree.build(in);
  if (out.cols() > 0) out_tree.build(out);
  const Eigen::Matrix3Xd& P = target.positions();
  const Matrix3Xi& F = target.faces();
  std::vector<FaceCopies> kind(size_t(F.cols()));
  tbb::parallel_for(tbb::blocked_range<Index>(0, F.cols(), 1024), [&](const tbb::blocked_range<Index>& r) {
    for (Index f = r.begin(); f != r.end(); ++f) {
      const Eigen::Vector3d c = (P.col(F(0, f)) + P.col(F(1, f)) + P.col(F(2, f))) / 3;
      double radius = 0;
      for (int k = 0; k < 3; ++k) radius = std::max(radius, (P.col(F(k, f)) - c).norm());
      const double d_in = nearest_distance(in_tree, in.cols(), c), d_out = nearest_distance(out_tree, out.cols(), c);
      const double margin = 2 * radius + 1e-9 * (radius + std::min(d_in, d_out));
      kind[size_t(f)] = d_in - d_out > margin   ? FaceCopies::kNone
                        : d_out - d_in > margin ? FaceCopies::kAll
                                                : FaceCopies::kLookUp;
    }
  });
  return kind;
}

}  // namespace

PointSet copied_points(const TransferPlan& plan, const PointSet& target) {
  if (!plan_copies_target(plan)) return {};
  std::vector<char> copied(size_t(plan.target_samples.cols()), 0);
  for (size_t k = 0; k < plan.patch.size(); ++k)
    if (plan.patches[size_t(plan.patch[k])].from_target) copied[size_t(plan.base[k])] = 1;
  const Index exemplar_samples = plan.exemplar_samples.cols(), target_samples = plan.target_samples.cols();
  const Index wanted = copy_surface_points(target, plan.exemplar_points, exemplar_samples, target_samples);
  // The target as it is (with its triangles, which copies may carry) is already in memory.
  if (wanted <= 0) return target;
  KdTree tree;
  tree.build(plan.target_samples);
  const std::vector<FaceCopies> faces = face_copies(target, plan.target_samples, copied);
  // A point is copied when its nearest target sample is; most triangles answer that for all their points at once.
  const auto keep = [&](const Eigen::Vector3d& p, std::int32_t face) {
    if (faces[size_t(face)] != FaceCopies::kLookUp) return faces[size_t(face)] == FaceCopies::kAll;
    std::int32_t nearest = 0;
    double d2 = 0;
    tree.knn(p, 1, &nearest, &d2);
    return copied[size_t(nearest)] != 0;
  };
  return random_surface_points_where(target, wanted, 1, keep);
}

TransferResult transfer_planned(const TransferPlan& plan, const PointSet* exemplar, const PointSet* target,
                                const ProgressFn& progress) {
  if (!target || !plan_copies_target(plan)) return apply_plan(plan, exemplar, nullptr, progress);
  // Copies come from the target's surface at the exemplar's density, not from a low-poly template's few vertices.
  const PointSet copies = copied_points(plan, *target);
  return apply_plan(plan, exemplar, &copies, progress);
}

TransferResult transfer(const TransferInputs& in, const ProgressFn& progress) {
  return transfer_planned(plan_transfer(in), &in.exemplar, &in.target, progress);
}

}  // namespace scanfill
