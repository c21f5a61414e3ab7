// The main run (DESIGN section 2): one tbb::flow graph per mode, built by build_completion, build_transfer or
// build_analogy (pipeline.cpp), whose nodes are the stages of stages.h; the outputs are written by outputs.cpp once
// the whole graph has succeeded, each atomically, so a failed run leaves no output file.
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

// Builds and runs the graph of config.mode, then writes the outputs. Throws Error (with the failing node's name).
RunOutcome run(const RunConfig& config);

// Peak resident memory of this process so far, in MiB.
double peak_rss_mb();

}  // namespace scanfill
