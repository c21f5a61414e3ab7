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

#include "nodes/align/align.h"
#include "nodes/correspond/correspond.h"
#include "nodes/features/estimate_features.h"
#include "nodes/io/read_point_set.h"
#include "nodes/label/label.h"
#include "nodes/modes/modes.h"
#include "nodes/sample/sample.h"
#include "nodes/scan/virtual_scan.h"
#include "nodes/support/support.h"
#include "nodes/symmetry/symmetry.h"
#include "nodes/synthesize/synthesize.h"
#include "nodes/vote/vote.h"

namespace scanfill {

// One input of the run: a file, or a procedural shape written as "procedural:NAME".
struct InputSpec {
  std::string role;            // scan, template, source, target, exemplar
  std::string text;            // as written in the config
  std::filesystem::path path;  // resolved against the config file's folder (empty for procedural inputs)
  std::string procedural;      // shape name for "procedural:NAME"
  bool revolution = false;     // "revolution:PATH": the body of revolution about z of the model at PATH (a template)
};

// Replaces the scan input (completion) by a single-view virtual range scan of it: the paper's synthetic scanner, so
// that a complete model (or a procedural shape) can be completed and scored against itself.
struct VirtualScanConfig {
  std::optional<Eigen::Vector3d> eye;     // camera position; ~ = no virtual scan
  std::optional<Eigen::Vector3d> target;  // looked-at point; ~ = the input's bounding-box centre
  std::optional<Eigen::Vector3d> up;      // image up; ~ = +z (or +y when looking along z)
  int width = 640;
  int height = 480;
  double fov_deg = 45.0;
  double noise = 0.0;
  std::uint64_t seed = 1;
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
  SymmetryOptions symmetry;
  LabelOptions label;
  CorrespondOptions correspond;
  double cover_distance = 2.0;  // completion: template samples within this many alpha of the registered scan are S
  SynthesisOptions synthesize;
  AlignOptions align;
  VirtualScanConfig virtual_scan;
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
