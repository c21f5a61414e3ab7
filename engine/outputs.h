// The outputs of a run (DESIGN section 5), written after the whole graph has succeeded: samples_ROLE.ply per input,
// output_mesh.ply (when output.surface makes one), analogy.ply with a colour per transform, report.json last; and the
// summary shown to the user. output.ply (completion, transfer) is streamed into the staging folder by the transfer node
// (OutputPlyWriter), too large to hold whole. The run fails whole: files are staged beside the output folder and moved
// in together (engine/staging.h).
#pragma once

#include <filesystem>

#include "engine/pipeline.h"
#include "engine/stages.h"
#include "nodes/io/write_ply.h"

namespace scanfill {

class Staging;

// output.colour as it applies to an output: auto is the scan's own colours when the transfer carried them (the scan,
// or exemplar, has colours), by origin otherwise; the other choices as they are.
ColourChoice resolved_colour(ColourChoice configured, bool carried_colours);

// Writes `output` as output.ply: positions and normals, per point its origin and label, RGB as `colour` (resolved, not
// auto) says, the scan's own colours as carried or by origin or label, and the intensity when carried. `scanfill
// plan` and `scanfill apply` write their points with it, so that they are output.ply's own.
void write_output_ply(const std::filesystem::path& path, const TransferResult& output, ColourChoice colour,
                      int self_label);

// output.ply written as the transfer streams it: the header from the counts, then each run of points coloured as
// `colour` (resolved) says, then the triangles; the file appears at commit(). write_output_ply is one of these.
class OutputPlyWriter {
 public:
  OutputPlyWriter(const std::filesystem::path& path, const TransferCounts& counts, bool intensity, ColourChoice colour,
                  int self_label);
  void append(const TransferResult& run);
  void append_faces(const Matrix3Xi& faces) { ply_.append_faces(faces); }
  void commit() { ply_.commit(); }

 private:
  PlyWriter ply_;
  ColourChoice colour_;
  int self_label_;
};

// Writes into the staging folder (state.write_dir), then commits it: the files appear in output.dir together.
RunOutcome write_outputs(RunState& state, Staging& staging);

}  // namespace scanfill
