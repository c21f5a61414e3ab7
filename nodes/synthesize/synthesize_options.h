// The config section `synthesize` (nodes/core/options.h): key, doc line and range of each SynthesisOptions field.
#pragma once

#include "nodes/core/options.h"
#include "nodes/synthesize/synthesize.h"

namespace scanfill {

OptionTable option_table(SynthesisOptions& sy);

}  // namespace scanfill
