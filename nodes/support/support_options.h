// The config section `support` (nodes/core/options.h): key, doc line and range of each SupportOptions field.
#pragma once

#include "nodes/core/options.h"
#include "nodes/support/support.h"

namespace scanfill {

OptionTable option_table(SupportOptions& su);

}  // namespace scanfill
