// The config section `features` (nodes/core/options.h): key, doc line and range of each FeaturesOptions field.
#pragma once

#include "nodes/core/options.h"
#include "nodes/features/estimate_features.h"

namespace scanfill {

OptionTable option_table(FeaturesOptions& f);

}  // namespace scanfill
