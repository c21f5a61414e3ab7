// The run configuration: one YAML file, one key per option field (CONVENTIONS, configuration).
//
// Each Options struct of a node is described once by a field table (fields.cpp): key, reference, one-line doc and
// range check. The same table reads YAML, validates, and prints --print-defaults, so they cannot drift apart.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "nodes/features/estimate_features.h"
#include "nodes/io/read_point_set.h"
#include "nodes/label/label.h"
#include "nodes/modes/modes.h"
#include "nodes/sample/sample.h"
#include "nodes/support/support.h"
#include "nodes/vote/vote.h"

namespace scanfill {

// One input of the run: a file, or a procedural shape written as "procedural:NAME".
struct InputSpec {
  std::string role;            // scan, template, source, target, exemplar
  std::string text;            // as written in the config
  std::filesystem::path path;  // resolved against the config file's folder (empty for procedural inputs)
  std::string procedural;      // shape name for "procedural:NAME"
};

struct RunConfig {
  std::string mode = "completion";           // completion | transfer | analogy
  std::vector<InputSpec> inputs;             // in the mode's role order
  std::filesystem::path output_dir = "out";  // created if missing; relative to the working directory
  int threads = 0;                           // 0 = all cores
  LoadOptions load;
  SampleOptions sample;
  FeaturesOptions features;
  VoteOptions vote;
  ModesOptions modes;
  SupportOptions support;  // support.allow_scale follows vote.allow_scale
  LabelOptions label;
  std::filesystem::path config_path;  // the file it was read from
};

// Roles each mode requires, in order.
const std::vector<std::string>& mode_names();
const std::vector<std::string>& roles_for_mode(const std::string& mode);

// Reads and validates a config file. Throws ConfigError whose message lists every problem, one per line, each as
// "FILE:LINE:COLUMN: dotted.key: problem".
RunConfig load_config(const std::filesystem::path& path);

// Pure validation of a config (ranges, mode, inputs). Returns (dotted key, problem) pairs; empty when valid.
std::vector<std::pair<std::string, std::string>> validate(const RunConfig& config);

// A complete, valid config with every option, its default and its meaning (for --print-defaults).
std::string default_config_yaml();

}  // namespace scanfill
