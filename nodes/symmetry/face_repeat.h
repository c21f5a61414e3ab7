// The exemplar's own repeat along a flat face (DESIGN section 9: the exemplar's repeats, for coverage).
//
// A box that is not square takes its short side's relief on its long sides by a quarter turn, centre onto centre
// (composed_candidates' face turns); the turned side covers the middle of a long side and leaves its ends. A shift
// along the face carries the short side onto an end, in phase with the middle only when the shift is a multiple of the
// relief's period (ribs every 10 cm: a shift of 15 cm puts them between the middle's). So the exemplar says which
// shifts are right: shifted along the face by each step, the fraction of its samples there that land on the exemplar
// (within half an alpha of a sample's plane, facing its way) peaks at the period.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <vector>

#include "nodes/core/point_set.h"

namespace scanfill {

class KdTree;

struct FaceRepeat {
  double period = 0;  // the smallest shift that lands the face's relief on itself; 0: the face is plain (every shift
                      // lands on it)
};

// The repeat along `direction` (unit, in the face's plane) of the exemplar samples `near` (indices into `exemplar`, the
// samples on one face, with normals; `tree` holds all of the exemplar's positions), tried at every half alpha
// (`spacing`) up to `max_shift`. A sample counts at a shift when its shifted position stays within the samples' own
// extent along the direction. None when fewer than 30 samples count at the shortest shift, or no shift fits: the
// relief does not repeat within `max_shift`. Deterministic.
std::optional<FaceRepeat> repeat_along(const PointSet& exemplar, const KdTree& tree,
                                       const std::vector<std::int32_t>& near, const Eigen::Vector3d& direction,
                                       double spacing, double max_shift);

}  // namespace scanfill
