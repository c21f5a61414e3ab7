// The config section `correspond` (nodes/core/options.h): key, doc line and range of each CorrespondOptions field.
#pragma once

#include "nodes/core/options.h"
#include "nodes/correspond/correspond.h"

namespace scanfill {

OptionTable option_table(CorrespondOptions& co);

// The correspond section's keys of completion's coverage (cover_template): cover_distance, cover_relief,
// cover_min_samples.
OptionTable option_table(CoverOptions& cover);

}  // namespace scanfill
