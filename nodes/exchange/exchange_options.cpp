#include "nodes/exchange/exchange_options.h"

namespace scanfill {

OptionTable option_table(ExchangeOptions& e) {
  using namespace checks;
  return {"exchange",
          "mode exchange: part boxes, the maps between them, the box-wise analogy's costs",
          {{"part_property", &e.part_property,
            "PLY vertex property with each point's part (integer, < 0 = none); auto = part, part_id, segment, "
            "segment_id, label, scalar_part or scalar_label",
            any()},
           {"box_spacing", &e.box_spacing,
            "grid step of the target's box samples, share of its bounding-box diagonal; "
            "(0, 0.1]",
            range(&e.box_spacing, 0.0, 0.1, true, "a number in (0, 0.1]")},
           {"match_tolerance", &e.match_tolerance,
            "a mapped source box explains a target box when each corner is within this share of its diagonal; "
            "(0, 0.5]",
            range(&e.match_tolerance, 0.0, 0.5, true, "a number in (0, 0.5]")},
           {"label_cost", &e.label_cost, "cost of each transform used (eq. 8), in unary units; >= 0",
            non_negative(&e.label_cost)},
           {"rotation_cost", &e.rotation_cost, "weight of (1 - cos angle) / 2 in a transform's cost; >= 0",
            non_negative(&e.rotation_cost)},
           {"distortion_cost", &e.distortion_cost,
            "weight of the stretch (variance of log scale_k over x, y, z) in a transform's cost; >= 0",
            non_negative(&e.distortion_cost)},
           {"scale_cost", &e.scale_cost, "weight of the uniform scale (mean of log scale_k, squared) in its cost; >= 0",
            non_negative(&e.scale_cost)},
           {"smoothness", &e.smoothness, "Potts weight between neighbouring box samples; >= 0",
            non_negative(&e.smoothness)},
           {"max_cycles", &e.max_cycles, "alpha-expansion sweeps over the labels; [1, 100]",
            range(&e.max_cycles, 1, 100, false, "an integer in [1, 100]")}}};
}

}  // namespace scanfill
