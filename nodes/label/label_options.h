// The config section `label` (nodes/core/options.h): key, doc line and range of each LabelOptions field.
#pragma once

#include "nodes/core/options.h"
#include "nodes/label/label.h"

namespace scanfill {

OptionTable option_table(LabelOptions& l);

// The paper's values (section 5.2, eq. 5-9): sigma_n = 0.1 pi/2, mu = 0.5 (pairwise_cap 0.5 with it, so that V stays
// a metric), its label costs (eq. 8 and 9 as printed) and MRF neighbours in the 5-alpha ring with normals within 90
// degrees.
void use_paper_parameters(LabelOptions& l);

}  // namespace scanfill
