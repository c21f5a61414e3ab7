// The up of a template whose symmetry does not tell it, read from the scan (DESIGN section 9).
//
// The upright terms of the label node, its cap rule and the upright turns all need the object's up. A body of
// revolution or a box with a square footprint gives it (upright_axis); a box with three different sides has three
// half-turn axes alike, and the engine then assumed +z, which is wrong for a model drawn y-up: the ribbed box drawn
// y-up took quarter turns about its front-back axis, tipped over, as the "upright" ones (mean F over the six views
// 0.952 z-up, 0.873 y-up).
//
// A box-like object with style carries it on its sides, and its lid and floor are plain (a ribbed or panelled crate, a
// pillar, a cabinet): so of the template's axes, up is the one whose faces the registered scan shows plainest, when it
// is clearly the plainest. A scan sample counts for the axis its nearest template sample faces along (within 30
// degrees), and is plain when it lies within half an alpha of that sample's plane and faces its way (within 20
// degrees). Ours, not the paper's (the paper's examples are upright).
#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "nodes/core/point_set.h"
#include "nodes/core/similarity.h"
#include "nodes/symmetry/symmetry.h"

namespace scanfill {

// Per axis: the scan samples near the faces that face along it, how many of them face along it too (within 30
// degrees), and how many lie plain on those faces.
struct FaceTally {
  Index near = 0;
  Index facing = 0;
  Index plain = 0;
  Index raised = 0;  // of the near ones, those facing that sample's way but standing 1.5 alpha off its plane (relief)
};

// The tallies of the scan (`exemplar`, with normals, moved onto the template by `exemplar_to_target`) against the
// template `target` (with normals), one per axis of `axes`. Deterministic.
std::vector<FaceTally> plain_face_tallies(const PointSet& exemplar, const Similarity& exemplar_to_target,
                                          const PointSet& target, const std::vector<SymmetryAxis>& axes,
                                          double spacing);

// The axis (its direction, signed so that its largest coordinate is positive) whose faces the scan shows plainest:
// of the axes the scan sees (samples facing along it: at least 2% of all tallied, and 30; not only the relief's walls
// near the face's edge), at least two; the plainest has at least 40%
// of its samples plain, and a share 0.25 above every other seen axis' (the ribbed box: 0.52-0.98 on its lid or floor,
// 0.20-0.55 on its sides, seen from the sweep's views), and under 5% raised: a lid is plain. None otherwise (the scan
// sees one side only, or the object's sides are as plain as its lid, or its plainest faces carry relief). The ribbed
// box seen nearly square to its long side, (-0.22, -0.97, 0.07), a short side at a graze and its lid unseen: the long
// side (its ribs cover a third of it) was plainer than the grazed side, and up along its depth took quarter turns
// about that axis as upright, the short side's ribs on the lid and floor (F 0.877, template blending 0.907). Raised
// shares seen on the sweep's views: the ribbed box's sides 8.7-14%, its lid and floor 0; the scanned square pillar's
// sides 3-70%, its lid and floor 0-1.2% (samples off the plane that face elsewhere, its capital's mouldings, are
// many).
std::optional<Eigen::Vector3d> plainest_face_axis(const PointSet& exemplar, const Similarity& exemplar_to_target,
                                                  const PointSet& target, const std::vector<SymmetryAxis>& axes,
                                                  double spacing);
// The same from the tallies of `plain_face_tallies`.
std::optional<Eigen::Vector3d> plainest_face_axis(const std::vector<FaceTally>& tallies,
                                                  const std::vector<SymmetryAxis>& axes);

// The axis (signed as above) whose faces a scan taken from around the object does not show: of three axes, the scan
// sees two, each with at least 10% of the tallied samples facing along it, and the third not at all (under 2%, or 30
// samples). A scan taken at the height of a box's sides sees two of them at their shared edge, and neither its lid nor
// its floor: the scanned square pillar seen level with a corner, where its lid is unseen, its bounding box is not
// square (0.20 by 0.24 across) and it is drawn y-up, took +z for up and laid its sides' relief on its lid and floor (F
// 0.47-0.53, under the scan alone's 0.53-0.56). A view from above towards one side shows that side and the lid and not
// the third axis either, so this is asked only after the plain lid (plainest_face_axis): ours, a prior that scans are
// taken from around an object rather than from above one of its sides.
std::optional<Eigen::Vector3d> unseen_face_axis(const std::vector<FaceTally>& tallies,
                                                const std::vector<SymmetryAxis>& axes);

}  // namespace scanfill
