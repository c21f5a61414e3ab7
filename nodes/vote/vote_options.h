// The config section `vote` (nodes/core/options.h): key, doc line and range of each VoteOptions field.
#pragma once

#include "nodes/core/options.h"
#include "nodes/vote/vote.h"

namespace scanfill {

OptionTable option_table(VoteOptions& v);

}  // namespace scanfill
