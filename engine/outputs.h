// The outputs of a run (DESIGN section 5), written after the whole graph has succeeded: samples_ROLE.ply per input,
// output.ply (completion, transfer), analogy.ply with a colour per transform, report.json last; and the summary shown
// to the user. Every file is written atomically.
#pragma once

#include "engine/pipeline.h"
#include "engine/stages.h"

namespace scanfill {

RunOutcome write_outputs(RunState& state);

}  // namespace scanfill
