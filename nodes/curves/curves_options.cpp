#include "nodes/curves/curves_options.h"

namespace scanfill {

OptionTable option_table(CurveSampleOptions& c) {
  using namespace checks;
  return {
      "curves",
      "mode curves: equal arc-length samples of the drawings, their frames, and the output's polylines",
      {{"spacing", &c.spacing, "arc length between samples (alpha), model units; 0 = from count; >= 0",
        non_negative(&c.spacing)},
       {"count", &c.count, "samples over the whole target drawing when spacing is 0; [16, 10000000]",
        range<Index>(&c.count, 16, 10000000, false, "an integer in [16, 10000000]")},
       {"curvature_window", &c.curvature_window,
        "half-width of the tangent and curvature stencil along the curve, in alpha; [0.25, 10]",
        range(&c.curvature_window, 0.25, 10.0, false, "a number in [0.25, 10]")},
       {"gap", &c.gap, "output points farther apart than this (alpha) start a new polyline; > 0", positive(&c.gap)}}};
}

}  // namespace scanfill
