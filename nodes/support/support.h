// support node: the target samples each candidate transform explains (paper eq. 2), refined (DESIGN section 4).
//
// A target sample t is explained by Q when Q p_t lies within `distance` alpha of a source sample s and their normals
// agree within `normal_angle_deg` (R n_t . n_s). The support grows from the mode's voters over the target kNN graph,
// never testing every mode against every sample. A mode is only as accurate as the mean-shift bandwidth allows
// (`mode_accuracy`, model units), often several alpha at high density, so growth and ICP (point-to-point, then
// point-to-plane, on an even subsample of at most `icp_samples` of the support) start at that distance and halve it
// each step down to `distance` alpha, re-growing the support at each (the label node's sigma_p = 0.1 alpha is far
// tighter than mean-shift accuracy); the support is then re-grown at `distance` alpha. Transforms that
// explain (nearly) the same samples as a stronger one add nothing to the analogy but labels: the symmetric equivalents
// of a box or a cylinder, or a part slid along a flat face. They are dropped (`redundant_overlap`), keeping the largest
// support, then the lowest RMS distance. Transforms whose support falls below `min_support` samples, or that end up
// within tolerance of a stronger one, are dropped, and so are transforms whose refined scale left the voted range
// [min_scale, max_scale] (ICP collapsing a transform onto a few source samples, which are then near every target
// sample: such a transform would "explain" most of the target and push the real ones out as redundant).
#pragma once

#include <vector>

#include "nodes/core/analogy.h"
#include "nodes/core/point_set.h"
#include "nodes/core/similarity.h"

namespace scanfill {

struct SupportOptions {
  double distance = 2.0;             // explained when within this many alpha of a source sample; > 0
  double normal_angle_deg = 90.0;    // and normals agree within this; (0, 180]
  int graph_k = 8;                   // target kNN graph for growing; [2, 64]
  int icp_iterations = 5;            // similarity ICP steps per transform; >= 0
  Index icp_samples = 4096;          // ICP uses at most this many support samples (an even subsample); >= 3
  Index min_support = 30;            // transforms explaining fewer samples are dropped; >= 1
  bool allow_scale = true;           // refine as similarity (true) or rigid motion
  double min_scale = 0.25;           // refined transforms whose scale leaves [min_scale, max_scale] are dropped: ICP
  double max_scale = 4.0;            // can shrink a transform onto a few source samples, which then "explain" any
                                     // target sample (the engine sets both from vote's range, as allow_scale)
  double duplicate_angle_deg = 2.0;  // transforms closer than this in rotation ...
  double duplicate_distance = 1.0;   // ... and moving the support centre less than this many alpha are merged
  double redundant_overlap = 0.9;    // a transform whose support lies this much inside a stronger one's is dropped
                                     // (a symmetric equivalent, or a slid part); (0, 1], 1 = only exact subsets
};

struct SupportResult {
  std::vector<SupportedTransform> transforms;  // by decreasing support
};

SupportResult grow_supports(const PointSet& source, const PointSet& target, const std::vector<Mode>& modes,
                            double spacing, double mode_accuracy, const SupportOptions& options);

// `found` plus the transforms grown from `extra` modes (composed candidates, DESIGN section 9), all selected together
// by the rules above: an extra transform that explains what a found one does is dropped like any duplicate, and one
// that explains fewer than min_support samples no found transform explains is not kept (the extras are for coverage:
// where voting already explains the target, its own transforms are kept as they are). The extras
// are grown at `distance` alpha without ICP: they are exact compositions, and ICP would slide them along the free
// motions of a symmetric target. `preferred` modes are grown alike but kept whatever they add, and are selected before
// the found and extra ones, so that a near duplicate of one gives way to it (the exact quarter turns eq. 9 prefers,
// symmetry.h's axis_quarter_turns, over a voted turn a degree or two off).
SupportResult extend_supports(const PointSet& source, const PointSet& target, const SupportResult& found,
                              const std::vector<Mode>& extra, double spacing, double accuracy,
                              const SupportOptions& options, const std::vector<Mode>& preferred = {});

}  // namespace scanfill
