// Graph assembly per mode and the main run (DESIGN section 2).
//
// Every input has a branch load -> sample -> features; the branches run concurrently in one tbb::flow graph, with
// immutable std::shared_ptr<const T> messages. Each node body is a call of a pure function of nodes/; the engine
// adds timing, progress, logging and the node's name to any error. Outputs are written only after the whole graph
// has succeeded, each atomically, so a failed run leaves no output file.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "engine/config.h"

namespace scanfill {

struct NodeTiming {
  std::string name;
  double wall_s = 0;
};

struct RunOutcome {
  std::vector<std::filesystem::path> outputs;  // files written, report.json last
  std::vector<NodeTiming> nodes;
  std::vector<std::string> warnings;
  std::string summary;  // what was made and where, for the user (several lines)
};

// Runs the graph for config.mode. Throws Error (with the failing node's name) on failure.
RunOutcome run_pipeline(const RunConfig& config);

// Peak resident memory of this process so far, in MiB.
double peak_rss_mb();

// Loads one input: a file, or a procedural shape.
LoadResult load_input(const InputSpec& spec, const LoadOptions& options);

}  // namespace scanfill
