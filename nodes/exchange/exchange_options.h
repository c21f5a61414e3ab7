// Mode exchange's options (nodes/exchange/exchange.h says what each weighs), and the config section `exchange`
// (nodes/core/options.h): key, doc line and range of each field. Apart from exchange.h so that the config, which
// holds them, does not depend on the algorithm's header.
#pragma once

#include <string>

#include "nodes/core/options.h"

namespace scanfill {

struct ExchangeOptions {
  // PLY vertex property holding each point's part (an integer; negative = no part); auto = the first present of
  // part, part_id, segment, segment_id, label, scalar_part, scalar_label. Used when the config gives no boxes.
  std::string part_property = "auto";
  double box_spacing = 0.02;      // T's box samples: grid step, share of T's bounding-box diagonal; (0, 0.1]
  double match_tolerance = 0.01;  // A(box k) explains box j when every corner is within this share of j's diagonal
  double label_cost = 10;         // h of a transform (eq. 8), in unary units (a sample's unary is <= 1); >= 0
  double rotation_cost = 1;       // weight of (1 - cos angle) / 2 in h; >= 0
  double distortion_cost = 4;     // weight of the variance of log d_k (the stretch) in h; >= 0
  double scale_cost = 1;          // weight of the squared mean of log d_k (the uniform scale) in h; >= 0
  double smoothness = 1;          // Potts weight between neighbouring samples; >= 0
  int max_cycles = 10;            // alpha-expansion sweeps; [1, 100]
};

OptionTable option_table(ExchangeOptions& e);

}  // namespace scanfill
