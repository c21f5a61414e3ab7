// The config section `label` (nodes/core/options.h): key, doc line and range of each LabelOptions field.
#pragma once

#include "nodes/core/options.h"
#include "nodes/label/label.h"

namespace scanfill {

OptionTable option_table(LabelOptions& l);

}  // namespace scanfill
