// The config section `support` (nodes/core/options.h): key, doc line and range of each SupportOptions field.
#pragma once

#include "nodes/core/options.h"
#include "nodes/support/support.h"

namespace scanfill {

OptionTable option_table(SupportOptions& su);

// The paper's value (eq. 2): delta_n = 0, normals within 90 degrees.
void use_paper_parameters(SupportOptions& su);

}  // namespace scanfill
