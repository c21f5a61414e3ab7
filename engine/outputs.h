// The outputs of a run (DESIGN section 5), written after the whole graph has succeeded: samples_ROLE.ply per input,
// output.ply (completion, transfer), output_mesh.ply (when output.surface makes one), analogy.ply with a colour per
// transform, report.json last; and the summary shown to the user. The run fails whole: files are staged beside the
// output folder and moved in together (engine/staging.h).
#pragma once

#include "engine/pipeline.h"
#include "engine/stages.h"
#include "nodes/io/write_ply.h"

namespace scanfill {

class Staging;

// output.ply's per-point properties beside positions and normals: origin, label and RGB (by origin, or by label).
// `scanfill apply` writes its tiles with the same, so that their points are output.ply's own.
std::vector<PlyProperty> output_properties(const TransferResult& output, int self_label, bool by_label);

// Writes into the staging folder (state.write_dir), then commits it: the files appear in output.dir together.
RunOutcome write_outputs(RunState& state, Staging& staging);

}  // namespace scanfill
