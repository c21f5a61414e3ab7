// modes node: mean shift on the 13-D vote embedding (paper section 5.1).
//
// Flat kernel of radius `bandwidth`, FLANN radius search (exact single kd-tree). Seeds are the centroids of the most
// populated grid bins (bin side = bandwidth), run in parallel; converged modes closer than the bandwidth are merged and
// ranked by support (votes within the bandwidth); the averaged rotation is projected back to SO(3).
#pragma once

#include <vector>

#include "nodes/core/analogy.h"

namespace scanfill {

struct ModesOptions {
  double bandwidth = 0.25;  // kernel radius in the embedding; > 0
  int max_seeds = 1500;     // most populated bins used as seeds; >= 1
  int max_iterations = 40;  // mean-shift steps per seed; >= 1
  int max_modes = 40;       // modes kept, by support; >= 1
  Index min_votes = 8;      // modes with fewer votes are dropped; >= 1
};

struct ModesResult {
  std::vector<Mode> modes;  // by decreasing votes
  Index seeds = 0;
};

// How far (model units) a mode's transform may be from the truth: the bandwidth, in translation units.
double mode_accuracy(const VoteResult& votes, const ModesOptions& options);

ModesResult find_modes(const VoteResult& votes, const ModesOptions& options);

}  // namespace scanfill
