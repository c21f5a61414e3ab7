// One ICP loop for the registrations that need one: correspond's rigid registration of the scan and support's
// refinement of a mode (synthesize's refinement steps along a subspace of motions, its own loop). Each caller finds
// its own pairs (its trimming, normal and distance rules); the loop fits them, point-to-point while far (robust) and
// point-to-plane after (precise, and it slides along flat faces), and stops on too few pairs or convergence.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <vector>

#include "nodes/core/similarity.h"

namespace scanfill {

// The pairs of one iteration: moved = q(from) for the current estimate q, their partners, and the partners' normals
// (read by point-to-plane steps only). rms: the pairs' RMS distance, for the convergence test.
// trusted (optional, one flag per pair): the pairs whose own normals agree with their partners'. When given, a
// point-to-plane step still fits every pair, but moves only along the motions the trusted pairs constrain.
struct IcpPairs {
  Eigen::Matrix3Xd moved, to, normals;
  std::vector<char> trusted;
  double rms = 0;
};

struct IcpOptions {
  int iterations = 10;
  int point_to_point_iterations = 0;  // the first this many steps are point-to-point, the rest point-to-plane
  bool allow_scale = false;           // similarity (true) or rigid (false) steps
  Eigen::Index min_pairs = 3;         // fewer pairs end the loop
  double converged_change = 0;  // stop once rotation change (rad) + translation change / rms falls below; 0 = never
};

// Fills the pairs for estimate q at iteration `iteration`.
using IcpPairFinder = std::function<void(const Similarity& q, int iteration, IcpPairs& pairs)>;
// Called after each accepted step with the new estimate (a caller's own bookkeeping, e.g. regrowing a support).
using IcpStepDone = std::function<void(const Similarity& q)>;

// One step from the pairs, composed after q: D q, D the least-squares point-to-point (Umeyama) or linearised
// point-to-plane fit of moved to to; the rotation is re-projected onto SO(3).
Similarity icp_step(const Similarity& q, const IcpPairs& pairs, bool point_to_plane, bool allow_scale);

// Iterates from `q`; returns the last estimate.
Similarity icp(Similarity q, const IcpPairFinder& find_pairs, const IcpOptions& options,
               const IcpStepDone& step_done = {});

}  // namespace scanfill
