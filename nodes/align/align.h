// align node: removes the seams between patches (paper eq. 10, DESIGN section 4).
//
// Every synthesised or copied sample i may move along its normal by an offset d_i; exemplar samples of a completion
// (the scan itself) stay fixed. Eq. 10 as solved here, all distances in alpha:
//   sum over seam pairs (i, j) of different patches, closer than `pair_distance` alpha with normals within 60 degrees:
//       gap_weight ((p_i + d_i n_i - p_j - d_j n_j) . m_ij)^2,   m_ij the mean normal;
//   sum over neighbours (i, j) of the same patch: keep_weight (d_i - d_j)^2   (each patch keeps its shape);
//   sum over i: pull (d_i)^2                                                  (v = 0.01 of the paper: stay near the
//   start).
// The problem is linear: Ceres (sparse normal Cholesky) converges in one step. Afterwards, an extension-ring sample
// that lies within `thin_distance` alpha of another patch's non-ring sample is dropped, so overlaps do not double the
// density.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "nodes/core/solver_summary.h"
#include "nodes/synthesize/synthesize.h"

namespace scanfill {

struct AlignOptions {
  int neighbors = 8;            // kNN graph of the synthesis; [2, 32]
  double pair_distance = 2.0;   // seam pairs closer than this, in alpha; > 0
  double gap_weight = 1.0;      // >= 0
  double keep_weight = 1.0;     // >= 0
  double pull = 0.01;           // v of eq. 10; > 0
  double thin_distance = 0.75;  // alpha; >= 0 (0 = keep every ring sample)
};

struct AlignResult {
  std::vector<double> offset;      // per synthesis point: displacement along its normal, model units
  std::vector<std::uint8_t> keep;  // per synthesis point: 0 when thinned out
  Index seam_pairs = 0;
  double gap_before = 0, gap_after = 0;  // RMS normal gap over the seam pairs, model units
  std::optional<SolverSummary> solver;   // Ceres' summary of the solve; none without seam pairs (nothing to solve)
};

// Which synthesis points survive the thinning of the overlaps (1) when each point is moved by its offset (model
// units) along its normal: an extension-ring sample goes when a non-ring sample of another patch lies within
// `thin_distance` alpha with a normal within 60 degrees (none goes when thin_distance is 0). align's `keep` is this at
// its offsets; at zero offsets it is the synthesis as the output will have it, before the seams are closed.
std::vector<std::uint8_t> thinned_overlaps(const Synthesis& s, const std::vector<double>& offset, double spacing,
                                           double thin_distance);

AlignResult align(const Synthesis& synthesis, double spacing, const AlignOptions& options);

}  // namespace scanfill
