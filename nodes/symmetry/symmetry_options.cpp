#include "nodes/symmetry/symmetry_options.h"

namespace scanfill {

OptionTable option_table(SymmetryOptions& sm) {
  using namespace checks;
  return {
      "symmetry",
      "global rotational symmetries: the source's continuous ones are quotiented out of the votes, the target's "
      "are composed with the transforms found (DESIGN section 9)",
      {{"enabled", &sm.enabled, "find symmetries and compose candidates (false = plain voting)", any()},
       {"distance", &sm.distance, "a rotated sample must land this close (alpha) to a sample; > 0",
        positive(&sm.distance)},
       {"normal_angle_deg", &sm.normal_angle_deg, "with normals within this angle; (0, 180]",
        range(&sm.normal_angle_deg, 0.0, 180.0, true, "a number in (0, 180]")},
       {"min_overlap", &sm.min_overlap, "share of samples that must land on the shape; (0, 1]",
        range(&sm.min_overlap, 0.0, 1.0, true, "a number in (0, 1]")},
       {"max_order", &sm.max_order, "largest discrete order n tried per axis; [2, 64]",
        range(&sm.max_order, 2, 64, false, "an integer in [2, 64]")},
       {"continuous_steps", &sm.continuous_steps,
        "a continuous axis offers rotations every 360 / this degrees; [2, 360]",
        range(&sm.continuous_steps, 2, 360, false, "an integer in [2, 360]")},
       {"max_group", &sm.max_group, "most discrete symmetries kept; [1, 1000]",
        range(&sm.max_group, 1, 1000, false, "an integer in [1, 1000]")},
       {"test_samples", &sm.test_samples, "samples each rotation is scored on (an even subsample); >= 10",
        range<Index>(&sm.test_samples, 10, Index(1) << 40, false, "an integer >= 10")},
       {"max_base_transforms", &sm.max_base_transforms,
        "found transforms composed with the target's symmetries, strongest first; [0, 1000]",
        range(&sm.max_base_transforms, 0, 1000, false, "an integer in [0, 1000]")},
       {"parts", &sm.parts, "also the turns of each part of the target about its own continuous axis (a leg)", any()},
       {"part_normal_angle_deg", &sm.part_normal_angle_deg,
        "neighbouring samples are in one part when their normals agree within this; (0, 180]",
        range(&sm.part_normal_angle_deg, 0.0, 180.0, true, "a number in (0, 180]")},
       {"part_min_samples", &sm.part_min_samples, "smaller parts are not searched; >= 10",
        range<Index>(&sm.part_min_samples, 10, Index(1) << 40, false, "an integer >= 10")},
       {"part_turns", &sm.part_turns, "a part's axis offers turns by multiples of 360 / this degrees; [2, 360]",
        range(&sm.part_turns, 2, 360, false, "an integer in [2, 360]")},
       {"face_turns", &sm.face_turns,
        "also the quarter turns about the up axis between flat faces of the target that its symmetries do not relate "
        "(a box that is not square)",
        any()}}};
}

}  // namespace scanfill
