// A run fails whole (issue 11): its outputs are written to a staging folder beside the output folder and moved into
// place only after every file is written and flushed to disk; a failed, interrupted (SIGINT, SIGTERM) or crashed
// run leaves no file of its own in the output folder. The staging folder is made before any work, so an output
// folder that cannot be made or written is refused first, not after the computing.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "engine/config.h"

namespace scanfill {

class Staging {
 public:
  // Makes `<parent of output_dir>/.<name of output_dir>.scanfill-<pid>`. Throws IoError naming the folder when the
  // output folder is a file, or its parent cannot be made or written.
  explicit Staging(const std::filesystem::path& output_dir);
  ~Staging();  // removes the staging folder unless committed
  Staging(const Staging&) = delete;
  Staging& operator=(const Staging&) = delete;

  const std::filesystem::path& folder() const { return folder_; }
  // Flushes every file of the staging folder to disk, moves them into the output folder (made if missing) and
  // removes the staging folder. Returns the files' final paths, in the order given.
  std::vector<std::filesystem::path> commit(const std::vector<std::string>& names);

 private:
  std::filesystem::path output_dir_, folder_;
  bool committed_ = false;
};

// Refuses (ConfigError) a run that would overwrite one of its own inputs: an input file at a path the run writes.
void check_outputs_spare_inputs(const RunConfig& config);

// SIGINT and SIGTERM remove the staging folder of the run in progress, then end the process (exit 130 / 143).
void remove_staging_on_signals();

}  // namespace scanfill
