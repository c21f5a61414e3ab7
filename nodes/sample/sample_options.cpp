#include "nodes/sample/sample_options.h"

namespace scanfill {

OptionTable option_table(SampleOptions& s) {
  using namespace checks;
  return {"sample",
          "Poisson-disk sampling by weighted sample elimination (Yuksel 2015)",
          {{"spacing", &s.spacing, "target mean nearest-neighbour distance (alpha), model units; 0 = use count; >= 0",
            range(&s.spacing, 0.0, kInf, false, "a number >= 0")},
           {"count", &s.count, "number of samples per input when spacing is 0; >= 1",
            range<Index>(&s.count, 1, Index(1) << 40, false, "an integer >= 1")},
           {"oversampling", &s.oversampling, "mesh candidates per output sample; [2, 100]",
            range(&s.oversampling, 2.0, 100.0, false, "a number in [2, 100]")},
           {"normal_angle_deg", &s.normal_angle_deg,
            "neighbours whose normals differ by more than this do not repel (keeps both sides of thin parts); (0, 180]",
            range(&s.normal_angle_deg, 0.0, 180.0, true, "a number in (0, 180]")},
           {"weight_exponent", &s.weight_exponent, "exponent of (1 - d/d_max) in the elimination weight; (0, 64]",
            range(&s.weight_exponent, 0.0, 64.0, true, "a number in (0, 64]")},
           {"seed", &s.seed, "seed of the random mesh candidates; any non-negative integer",
            [] { return std::optional<std::string>(); }}}};
}

}  // namespace scanfill
