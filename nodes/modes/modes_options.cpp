#include "nodes/modes/modes_options.h"

namespace scanfill {

OptionTable option_table(ModesOptions& m) {
  using namespace checks;
  return {"modes",
          "mean shift on the votes",
          {{"bandwidth", &m.bandwidth, "flat kernel radius in the vote embedding; > 0", positive(&m.bandwidth)},
           {"max_seeds", &m.max_seeds, "most populated bins used as seeds; >= 1",
            range(&m.max_seeds, 1, 1 << 30, false, "an integer >= 1")},
           {"max_iterations", &m.max_iterations, "mean-shift steps per seed; >= 1",
            range(&m.max_iterations, 1, 1 << 20, false, "an integer >= 1")},
           {"max_modes", &m.max_modes, "modes kept, by support; >= 1",
            range(&m.max_modes, 1, 1 << 20, false, "an integer >= 1")},
           {"min_votes", &m.min_votes, "modes with fewer votes are dropped; >= 1",
            range<Index>(&m.min_votes, 1, Index(1) << 40, false, "an integer >= 1")}}};
}

}  // namespace scanfill
