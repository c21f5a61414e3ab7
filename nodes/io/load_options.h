// The config section `load` (nodes/core/options.h): key, doc line and range of each LoadOptions field.
#pragma once

#include "nodes/core/options.h"
#include "nodes/io/read_point_set.h"

namespace scanfill {

OptionTable option_table(LoadOptions& load);

}  // namespace scanfill
