#include "nodes/core/icp.h"

#include <algorithm>

namespace scanfill {

Similarity icp_step(const Similarity& q, const IcpPairs& pairs, bool point_to_plane, bool allow_scale) {
  if (point_to_plane) return point_to_plane_step(q, pairs.moved, pairs.to, pairs.normals, allow_scale);
  const Similarity d = fit_similarity(pairs.moved, pairs.to, allow_scale);
  Similarity next = d.compose(q);
  next.rotation = nearest_rotation(next.rotation);
  return next;
}

Similarity icp(Similarity q, const IcpPairFinder& find_pairs, const IcpOptions& o, const IcpStepDone& step_done) {
  IcpPairs pairs;
  for (int it = 0; it < o.iterations; ++it) {
    find_pairs(q, it, pairs);
    if (pairs.moved.cols() < o.min_pairs) break;
    const Similarity next = icp_step(q, pairs, it >= o.point_to_point_iterations, o.allow_scale);
    const double change = rotation_angle(next.rotation * q.rotation.transpose()) +
                          (next.translation - q.translation).norm() / std::max(pairs.rms, 1e-300);
    q = next;
    if (step_done) step_done(q);
    if (change < o.converged_change) break;
  }
  return q;
}

}  // namespace scanfill
