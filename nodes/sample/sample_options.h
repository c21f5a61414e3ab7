// The config section `sample` (nodes/core/options.h): key, doc line and range of each SampleOptions field.
#pragma once

#include "nodes/core/options.h"
#include "nodes/sample/sample.h"

namespace scanfill {

OptionTable option_table(SampleOptions& s);

}  // namespace scanfill
