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
// Appearance: when the exemplar has colours or intensity, every output point has them. A point moved from the
// exemplar (kept or synthesised) keeps its exemplar point's exactly; a point copied from the target, which has no
// measured appearance in the exemplar, gets kCopiedColour (mid grey) and kCopiedIntensity (0, a scanner's "no
// return"); its `origin` tells it apart.
#pragma once

#include <cstdint>
#include <vector>

#include "nodes/align/align.h"
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

struct TransferResult {
  PointSet points;                  // positions, normals, faces when the exemplar is a mesh; colours, intensity when
                                    // the exemplar has them
  std::vector<Origin> origin;       // per point
  std::vector<std::int32_t> label;  // per point
};

TransferResult transfer(const TransferInputs& in, const ProgressFn& progress = {});

// The target's points that copies are made of (DESIGN section 9: a copy is sampled at the output's density, never
// reduced to a template's own vertices): the target itself when it is a cloud or a mesh with at least as many
// vertices per sample as the exemplar has points per sample; otherwise that many area-uniform points on its triangles
// (seeded; copied regions then carry no triangles).
PointSet copy_surface(const PointSet& target, Index exemplar_points, Index exemplar_samples, Index target_samples);

}  // namespace scanfill
