// vote node: candidate similarity transforms by pair voting (paper section 5.1, after Mitra, Guibas, Pauly 2006).
//
// A target sample t and a source sample s of similar curvature signature vote for the transform Q mapping target to
// source (paper eq. 2 direction): R = F_s F_t^T with frames F = [d1, n x d1, n], s = k1_t / k1_s (1 where the surface
// is too flat to tell, or when scale is not allowed), t = p_s - s R p_t. The k1 direction has a sign ambiguity, so
// each pair votes twice (d1 and -d1); near umbilics, where d1 and d2 may swap, four times. Frames are proper rotations:
// no reflections. Not all pairs vote: `target_samples` target points chosen by a seeded generator each match their
// `matches_per_point` nearest source points in signature k2/k1 (flat points form a class of their own).
// Flat target points (|k1| alpha < flat_curvature) pair with any flat source point under any in-plane slide, so they
// flood the vote space with sliding transforms (as Mitra et al. note, pruning low-curvature points): they vote only
// when fewer than `min_curved_fraction` of the target points are curved. Each vote is embedded as the 13-vector of
// nodes/core/analogy.h, with the weights rotation_weight, translation_weight and scale_weight.
// `planar` (mode curves: samples of 2D curves at z = 0, k2 = 0, d1 = z x n, nodes/curves/sample_curves.h): the 2D
// similarity group only (rotation about z, translation in the plane, scale): one vote per pair, from the frame itself,
// and the signature is k1 alpha, the curve's one curvature; each voter pairs with its curve_matches nearest.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "nodes/core/analogy.h"
#include "nodes/core/point_set.h"
#include "nodes/core/similarity.h"

namespace scanfill {

struct VoteOptions {
  Index target_samples = 4000;        // target points that vote; >= 1
  int matches_per_point = 12;         // source points each voting target point pairs with; [1, 256]
  int curve_matches = 48;             // the same on curves (planar): their signature k1 alpha is not scale-free, so
                                      // a scaled partner lies further off in it; [1, 1024]
  bool allow_scale = true;            // similarity (true) or rigid (false) transforms
  double min_scale = 0.25;            // scales outside [min_scale, max_scale] are not voted for; > 0
  double max_scale = 4.0;             // >= min_scale
  double completion_scale = 1.5;      // completion narrows the range to [1 / this, this]: one object's parts, and a
                                      // flat face takes any shrunk copy of itself (the engine narrows vote's and
                                      // support's range; vote() reads only min_scale, max_scale); > 1
  double flat_curvature = 0.02;       // |k1| alpha below this: too flat for a scale or a signature; >= 0
  double umbilic_ratio = 0.75;        // |k2/k1| above this: four rotations per pair; (0, 1]
  double min_curved_fraction = 0.05;  // flat target points vote only if fewer curved points than this; [0, 1]
  double rotation_weight = 1.0;       // w_R; > 0
  double translation_weight = 8.0;    // w_t (translation in units of the bounding-box diagonal); > 0
  double scale_weight = 2.0;          // w_s (log scale); > 0
  std::uint64_t seed = 1;
  bool planar = false;                  // the z = 0 plane (mode curves; set by the engine, no key): see below
  std::optional<Eigen::Matrix3d> axes;  // the target's own axes (columns; set by the engine, no key): the vote space's
                                        // translations are in units of the bounding box's diagonal in these axes, the
                                        // same for a shape standing turned in the world's frame; unset: the world's
};

// source and target need normals, curvatures and directions (the features node). `spacing` is the sample spacing
// alpha. Throws InputError when either has no features.
VoteResult vote(const PointSet& source, const PointSet& target, double spacing, const VoteOptions& options);

}  // namespace scanfill
