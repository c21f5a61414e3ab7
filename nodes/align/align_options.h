// The config section `align` (nodes/core/options.h): key, doc line and range of each AlignOptions field.
#pragma once

#include "nodes/align/align.h"
#include "nodes/core/options.h"

namespace scanfill {

OptionTable option_table(AlignOptions& al);

}  // namespace scanfill
