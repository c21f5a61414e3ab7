// The config section `symmetry` (nodes/core/options.h): key, doc line and range of each SymmetryOptions field.
#pragma once

#include "nodes/core/options.h"
#include "nodes/symmetry/symmetry.h"

namespace scanfill {

OptionTable option_table(SymmetryOptions& sm);

}  // namespace scanfill
