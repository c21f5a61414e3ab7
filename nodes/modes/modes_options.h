// The config section `modes` (nodes/core/options.h): key, doc line and range of each ModesOptions field.
#pragma once

#include "nodes/core/options.h"
#include "nodes/modes/modes.h"

namespace scanfill {

OptionTable option_table(ModesOptions& m);

}  // namespace scanfill
