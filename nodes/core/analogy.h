// The messages of the analogy chain vote -> modes -> support -> label (paper section 5, DESIGN section 5), kept here
// so that the four stages are siblings sharing these types rather than an include chain.
//
// A vote is a similarity embedded without angle wrap-around as the 13-vector
//   [w_R vec(R), w_t (t - c) / diag, w_s log s]
// (chordal rotation distance; c and diag the centre and diagonal of the source and target boxes together); the
// weights travel with the votes, so that modes and symmetry read the embedding without the vote stage's options.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "nodes/core/point_set.h"
#include "nodes/core/similarity.h"

namespace scanfill {

using VoteMatrix = Eigen::Matrix<double, 13, Eigen::Dynamic>;

struct EmbeddingWeights {
  double rotation = 1.0;     // w_R
  double translation = 8.0;  // w_t (translation in units of the bounding-box diagonal)
  double scale = 2.0;        // w_s (log scale)
};

// The votes of the vote stage (target -> source transforms, paper eq. 2 direction).
struct VoteResult {
  VoteMatrix embedding;             // 13 by V
  std::vector<std::int32_t> voter;  // target sample of each vote
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  double diagonal = 1.0;
  EmbeddingWeights weights;
  Index pairs = 0;
};

// Embedding of a transform in the frame of `votes`, and back (rotation projected to SO(3)).
Eigen::Matrix<double, 13, 1> embed(const Similarity& q, const VoteResult& frame);
Similarity unembed(const Eigen::Matrix<double, 13, 1>& x, const VoteResult& frame);

// A mode of the votes (the modes stage).
struct Mode {
  Similarity transform;
  Index votes = 0;                   // votes within the bandwidth
  std::vector<std::int32_t> voters;  // distinct target samples whose votes are within the bandwidth
};

// A transform with the target samples it explains (the support stage, paper eq. 2); the label stage's labels.
struct SupportedTransform {
  Similarity transform;
  std::vector<std::int32_t> support;  // target samples explained, ascending
  double rms = 0;                     // RMS distance of the support to the source after refinement
};

}  // namespace scanfill
