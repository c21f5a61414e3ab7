#include "nodes/align/align_options.h"

namespace scanfill {

OptionTable option_table(AlignOptions& al) {
  using namespace checks;
  return {
      "align",
      "seam removal, paper eq. 10 (Ceres)",
      {{"neighbors", &al.neighbors, "kNN graph of the synthesised samples; [2, 32]",
        range(&al.neighbors, 2, 32, false, "an integer in [2, 32]")},
       {"pair_distance", &al.pair_distance, "seam pairs closer than this, in alpha; > 0", positive(&al.pair_distance)},
       {"gap_weight", &al.gap_weight, "weight of the normal gap across patches; >= 0", non_negative(&al.gap_weight)},
       {"keep_weight", &al.keep_weight, "weight keeping each patch's shape; >= 0", non_negative(&al.keep_weight)},
       {"pull", &al.pull, "v of eq. 10, the pull to the start; > 0", positive(&al.pull)},
       {"thin_distance", &al.thin_distance,
        "overlap-ring samples this close (alpha) to another patch are dropped; >= 0 (0 = keep)",
        non_negative(&al.thin_distance)}}};
}

}  // namespace scanfill
