#include "nodes/support/support_options.h"

namespace scanfill {

OptionTable option_table(SupportOptions& su) {
  using namespace checks;
  return {
      "support",
      "target samples each transform explains (paper eq. 2), with similarity ICP",
      {{"distance", &su.distance, "explained within this many alpha of a source sample; > 0", positive(&su.distance)},
       {"normal_angle_deg", &su.normal_angle_deg, "and with normals within this angle; (0, 180]",
        range(&su.normal_angle_deg, 0.0, 180.0, true, "a number in (0, 180]")},
       {"graph_k", &su.graph_k, "neighbours of the target graph the support grows over; [2, 64]",
        range(&su.graph_k, 2, 64, false, "an integer in [2, 64]")},
       {"icp_iterations", &su.icp_iterations, "similarity ICP steps per transform; >= 0",
        range(&su.icp_iterations, 0, 1000, false, "an integer in [0, 1000]")},
       {"icp_samples", &su.icp_samples, "ICP uses at most this many support samples (an even subsample); >= 3",
        range<Index>(&su.icp_samples, 3, Index(1) << 40, false, "an integer >= 3")},
       {"min_support", &su.min_support, "transforms explaining fewer samples are dropped; >= 1",
        range<Index>(&su.min_support, 1, Index(1) << 40, false, "an integer >= 1")},
       {"duplicate_angle_deg", &su.duplicate_angle_deg, "transforms this close in rotation ...; >= 0",
        non_negative(&su.duplicate_angle_deg)},
       {"duplicate_distance", &su.duplicate_distance,
        "... and moving the support less than this (alpha) are merged; >= 0", non_negative(&su.duplicate_distance)},
       {"redundant_overlap", &su.redundant_overlap,
        "a transform whose support lies this much inside a stronger one's is dropped; (0, 1]",
        range(&su.redundant_overlap, 0.0, 1.0, true, "a number in (0, 1]")}}};
}

void use_paper_parameters(SupportOptions& su) {
  su.normal_angle_deg = 90.0;
}

}  // namespace scanfill
