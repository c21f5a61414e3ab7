// The config section `curves` (nodes/core/options.h): key, doc line and range of each CurveSampleOptions field.
#pragma once

#include "nodes/core/options.h"
#include "nodes/curves/sample_curves.h"

namespace scanfill {

OptionTable option_table(CurveSampleOptions& c);

}  // namespace scanfill
