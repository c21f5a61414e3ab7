#include "nodes/synthesize/synthesize_options.h"

namespace scanfill {

OptionTable option_table(SynthesisOptions& sy) {
  using namespace checks;
  return {
      "synthesize",
      "A* = M A M^-1: the exemplar carried by each region's transform",
      {{"reach", &sy.reach, "a mapped source sample belongs to a region within this many alpha; > 0",
        positive(&sy.reach)},
       {"ring_k", &sy.ring_k, "kNN graph defining each region's overlap ring; [0, 32]",
        range(&sy.ring_k, 0, 32, false, "an integer in [0, 32]")},
       {"refine_iterations", &sy.refine_iterations,
        "ICP steps refining each transform against the exemplar's overlapping images (0 = no refinement); >= 0",
        range(&sy.refine_iterations, 0, 1000, false, "an integer in [0, 1000]")},
       {"refine_distance", &sy.refine_distance, "refinement pairs closer than this, in alpha; > 0",
        positive(&sy.refine_distance)},
       {"search_distance", &sy.search_distance,
        "each slippable motion of the template is searched this far (alpha) for the exemplar's phase; >= 0",
        non_negative(&sy.search_distance)},
       {"repeats", &sy.repeats,
        "completion: turn each image to the scan's own repeats about the axis, and fill with its turned copies", any()},
       {"mirror", &sy.mirror,
        "completion: where the scan does not repeat about the template's axis but mirrors onto itself about a plane "
        "through it, its mirror image replaces the images where it lands",
        any()},
       {"seen_through", &sy.seen_through,
        "completion: the template is not copied where the scanner saw the scan through it (needs the sensor's "
        "position: features.viewpoint, a PCD's VIEWPOINT or a PLY's camera element)",
        any()},
       {"gap_distance", &sy.gap_distance,
        "a target sample no landed source sample or output point comes this close to (alpha, along its normal) is "
        "copied, but not over a relief that faces its way sunk up to three times this; > 0",
        positive(&sy.gap_distance)},
       {"overlay_distance", &sy.overlay_distance, "... and this close across its normal (alpha); > 0",
        positive(&sy.overlay_distance)}}};
}

}  // namespace scanfill
