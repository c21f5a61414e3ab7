// transfer node: the sample-level result carried to every original point or triangle (paper section 6's
// post-processing, generalised; DESIGN sections 2 and 4).
//
// Each patch of the synthesis applies one transform to one input (the exemplar, or the target for copies). Every
// original point of that input follows the patch of its nearest sample: it is emitted, moved by the patch's transform,
// exactly when its nearest sample was (and survived the align node's thinning), and the alignment offset of that
// sample is applied along the sample's normal. Where the inputs are meshes, every triangle whose three corners are
// emitted by a patch is emitted with them, so the output keeps the exemplar's full resolution and connectivity. Memory
// is linear in the output: one index per input point and patch, no dense tables. Finally the working frame is mapped
// to the output frame (in completion, back to the scan's own frame).
//
// The transfer runs in two steps (DESIGN section 10). plan_transfer keeps what it needs of the sample-level run: the
// samples' positions, each patch's whole transform and each kept synthesis sample's patch, base sample, offset and
// normal, a few MB whatever the scan's size. apply_plan carries points through a plan; it needs nothing else, so the
// exemplar can be carried in tiles, each by its own process (`scanfill apply`), and their outputs are disjoint: a
// point's output depends only on the point and its nearest sample. transfer() is plan_transfer then apply_plan on
// the whole exemplar and the target's copy surface: the one-process run uses the same code as the tiles.
//
// Appearance: when the exemplar has colours or intensity, every output point has them (the plan says so, so that a
// tile's output and the plan-level copies agree). A point moved from the exemplar (kept or synthesised) keeps its
// exemplar point's exactly; a point copied from the target, which has no measured appearance in the exemplar, gets
// kCopiedColour (mid grey) and kCopiedIntensity (0, a scanner's "no return"); its `origin` tells it apart.
#pragma once

#include <algorithm>
#include <cstdint>
#include <functional>
#include <vector>

#include "nodes/align/align.h"
#include "nodes/core/point_chunks.h"
#include "nodes/core/progress.h"
#include "nodes/synthesize/synthesize.h"

namespace scanfill {

struct TransferInputs {
  const PointSet& exemplar;          // the exemplar as loaded (input frame)
  const PointSet& exemplar_samples;  // its samples (input frame)
  const PointSet& target;            // the target as loaded (working frame)
  const PointSet& target_samples;    // its samples
  const Similarity& exemplar_to_working;
  const Synthesis& synthesis;
  const AlignResult& alignment;
  const Similarity& working_to_output;
};

inline const Eigen::Matrix<std::uint8_t, 3, 1> kCopiedColour{128, 128, 128};
constexpr float kCopiedIntensity = 0.0f;

// A patch of the plan: which input it carries, what its points are, and where they go.
struct PlanPatch {
  int label = -1;                     // as Patch::label
  Origin origin = Origin::kExemplar;  // as Patch::origin
  bool from_target = false;           // base input: the target's copy surface (true) or the exemplar
  Similarity whole;                   // base input's frame -> output frame (working_to_output o transform o to_working)
};

// Everything the full-resolution transfer needs of the sample-level run (DESIGN section 10).
struct TransferPlan {
  Eigen::Matrix3Xd exemplar_samples;  // 3 by Se, input frame: every exemplar point follows its nearest one
  Eigen::Matrix3Xd target_samples;    // 3 by St, working frame: every copy-surface point follows its nearest one
  Index exemplar_points = 0;          // points of the whole exemplar (sets the copy surface's density)
  BoundingBox exemplar_bounds;        // of the whole exemplar, input frame: points carried must lie inside
  bool mesh_output = false;           // the exemplar is a mesh: triangles whose corners a patch emits come along
  bool colours = false;               // the exemplar has colours: every output point has them (copies kCopiedColour)
  bool intensity = false;             // the exemplar has intensity: every output point has it (copies kCopiedIntensity)
  std::vector<PlanPatch> patches;
  // Per carried sample: the synthesis points the align node kept, in synthesis order (K of them).
  std::vector<std::int32_t> patch;  // K: index into patches
  std::vector<std::int32_t> base;   // K: the exemplar or target sample the synthesis point came from
  std::vector<double> shift;        // K: the alignment offset, output units, along `normal`
  Eigen::Matrix3Xd normal;          // 3 by K: the synthesis point's normal, output frame
};

struct TransferResult {
  PointSet points;                  // positions, normals, faces when the exemplar is a mesh; colours, intensity when
                                    // the exemplar has them
  std::vector<Origin> origin;       // per point
  std::vector<std::int32_t> label;  // per point
};

// What a streamed transfer will give, known before its first point (the PLY header's counts).
struct TransferCounts {
  Index points = 0;                // output points
  Index faces = 0;                 // output triangles
  Index by_origin[3] = {0, 0, 0};  // points by Origin
};

// Where a streamed transfer's output goes, in output order: the counts first, then consecutive runs of output points
// (positions, normals, colours and intensity when the plan has them; `origin` and `label` per point; no faces), then
// every triangle (indices into the whole output; only when counts.faces > 0).
struct TransferSink {
  std::function<void(const TransferCounts&)> begin;
  std::function<void(TransferResult)> points;  // each run is handed over: the sink may keep it
  std::function<void(const Matrix3Xi&)> faces;
};

// apply_plan as a stream (DESIGN section 10: memory bounded by the samples plus one chunk): the same points in the
// same order, given to `sink` in runs of at most `chunk_points` input points' worth. Holds one int32 per input point
// (its nearest sample) and, for a mesh exemplar, its triangles; never the whole output.
TransferCounts stream_plan(const TransferPlan& plan, const PointSet* exemplar, const PointSet* copies,
                           Index chunk_points, const TransferSink& sink, const ProgressFn& progress = {});

// stream_plan with the exemplar read a run at a time (issue 13: a scan too large to hold), `exemplar_points` points in
// all: the points stream_plan gives for those points held whole, in the same order. The exemplar is a cloud without
// colours or intensity (InvariantError otherwise). Holds one int32 per exemplar point and one run; every exemplar
// patch is one more pass over the runs.
TransferCounts stream_plan_chunks(const TransferPlan& plan, PointChunks& exemplar, Index exemplar_points,
                                  const PointSet* copies, Index chunk_points, const TransferSink& sink,
                                  const ProgressFn& progress = {});

// Every stride-th point of a stream (output index a multiple of `stride`), gathered: a bounded picture of an output too
// large to hold (the preview's input). Points in stream order, with their attributes.
class EveryKth {
 public:
  explicit EveryKth(Index stride) : stride_(std::max<Index>(stride, 1)) {}
  void add(const TransferResult& chunk);
  TransferResult take();  // the gathered points (the object is empty afterwards)

 private:
  Index stride_, seen_ = 0;
  std::vector<TransferResult> parts_;
};

// The target's copy surface (copy_surface) reduced to the points a patch of the plan copies, in the same order: what
// stream_plan emits of it. A random copy surface is made in blocks and filtered as it is made, so that only the copied
// points are ever held (a 10^7-point scan's copy surface has 10^7 points, of which the copies are a few percent).
PointSet copied_points(const TransferPlan& plan, const PointSet& target);

// plan_transfer then apply_plan on the whole exemplar and, when a patch copies the target, its copy surface.
TransferResult transfer(const TransferInputs& in, const ProgressFn& progress = {});

// The plan of a transfer. Throws InvariantError when the alignment does not match the synthesis.
TransferPlan plan_transfer(const TransferInputs& in);

// The points of `exemplar` (input frame; null: none) and of `copies` (the target's copy surface, working frame; null:
// none) carried through the plan's patches, patch by patch in the plan's order, each input's points in their order.
// A mesh's triangles whose corners one patch emits come along. The exemplar may be any subset of the planned one; it
// must have colours and intensity where the plan says the exemplar had them (InvariantError otherwise).
TransferResult apply_plan(const TransferPlan& plan, const PointSet* exemplar, const PointSet* copies,
                          const ProgressFn& progress = {});

// apply_plan on `exemplar` (null: none) and, when a patch copies the target and `target` is given (as loaded, working
// frame), on its copy surface. transfer() is transfer_planned(plan_transfer(in), &in.exemplar, &in.target).
TransferResult transfer_planned(const TransferPlan& plan, const PointSet* exemplar, const PointSet* target,
                                const ProgressFn& progress = {});

// Whether a patch of the plan copies the target (then the run has plan-level points: its copy surface carried).
bool plan_copies_target(const TransferPlan& plan);

// The first of `points` outside the plan's exemplar bounds (a point of another scan), or -1 when all lie inside.
Index first_point_outside(const TransferPlan& plan, const PointSet& points);

// The plan's internal consistency (indices in range, sizes that agree), as one line naming what is wrong; empty when
// consistent. A plan read from a file is checked before use.
std::string plan_inconsistency(const TransferPlan& plan);

// `tiles` consecutive runs of indices into `n` points, as equal as they can be (the first n % tiles one longer): the
// tile splitter's chunks. Loaded points are Morton-ordered, so consecutive runs are compact in space.
std::vector<std::pair<Index, Index>> tile_ranges(Index n, Index tiles);

// The points [range.first, range.second) of `points` with their per-point attributes, as a cloud: one tile.
PointSet tile_points(const PointSet& points, std::pair<Index, Index> range);

// The target's points that copies are made of (DESIGN section 9: a copy is sampled at the output's density, never
// reduced to a template's own vertices): the target itself when it is a cloud or a mesh with at least as many
// vertices per sample as the exemplar has points per sample; otherwise that many area-uniform points on its triangles
// (seeded; copied regions then carry no triangles).
PointSet copy_surface(const PointSet& target, Index exemplar_points, Index exemplar_samples, Index target_samples);

}  // namespace scanfill
