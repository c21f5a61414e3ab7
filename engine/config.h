// The run configuration: one YAML file, one key per option field (CONVENTIONS, configuration).
//
// Each Options struct of a node is described once by the option table beside it (nodes/STAGE/STAGE_options.h): key,
// reference, one-line doc and range check. The same table reads YAML, validates, prints --print-defaults and is
// checked by the node at entry, so they cannot drift apart.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "nodes/align/align.h"
#include "nodes/correspond/correspond.h"
#include "nodes/curves/sample_curves.h"
#include "nodes/exchange/exchange_options.h"
#include "nodes/exchange/part_box.h"
#include "nodes/features/estimate_features.h"
#include "nodes/input/input.h"
#include "nodes/label/label.h"
#include "nodes/modes/modes.h"
#include "nodes/sample/sample.h"
#include "nodes/scan/virtual_scan.h"
#include "nodes/support/support.h"
#include "nodes/surface/surface.h"
#include "nodes/symmetry/symmetry.h"
#include "nodes/synthesize/synthesize.h"
#include "nodes/vote/vote.h"

namespace scanfill {

// What a run makes (DESIGN section 1); each mode has its own graph builder (pipeline.cpp).
enum class RunMode { kCompletion, kTransfer, kAnalogy, kCurves, kExchange };

// The part an input plays: completion takes scan + template, transfer and curves source + target + exemplar, analogy
// source + target, exchange one or more exemplars and targets.
enum class Role { kScan, kTemplate, kSource, kTarget, kExemplar };

// One input of the run: its role and what the config wrote for it (a file, procedural:NAME, revolution:...).
struct Input {
  Role role = Role::kScan;
  InputSpec spec;
  std::vector<InputSpec> fragments;  // further fragments of a scan or exemplar given as a list (after `spec`)
  // Mode exchange: the input's name in output file names, and its parts as boxes when the config gives them (else
  // from a per-vertex part property of its PLY, or a procedural castle's layout). A target may be boxes alone
  // (spec.text empty).
  std::string name;
  std::optional<PartBoxes> boxes;
};

// Whether an input of this role may be a list of fragments (scan and exemplar: the paper's vase, Figure 13, was
// completed from two hand-held fragments).
bool takes_fragments(Role role);

// Every file or shape of an input: `spec`, then its further fragments.
std::vector<InputSpec> all_specs(const Input& input);

// output.surface: whether output_mesh.ply, a surface of the completed shape, is made. auto: poisson in completion
// (a scan's points are a cloud), none in transfer (a mesh exemplar's output keeps its triangles); analogy has no
// output.ply to mesh.
enum class SurfaceChoice { kAuto, kNone, kPoisson };
const std::vector<std::pair<std::string, SurfaceChoice>>& surface_choice_names();

// output.colour: output.ply's RGB. origin: scan (or exemplar) grey, synthesised orange, copied blue; label: one colour
// per transform, as analogy.ply; scan: the scan's (or exemplar's) own colours, carried with its points through the
// transfer (copied points mid grey); auto: scan when the scan has colours, origin otherwise.
enum class ColourChoice { kAuto, kOrigin, kLabel, kScan };
const std::vector<std::pair<std::string, ColourChoice>>& colour_choice_names();

struct RunConfig {
  RunMode mode = RunMode::kCompletion;
  std::vector<Input> inputs;                         // in the mode's role order
  std::filesystem::path output_dir = "out";          // created if missing; relative to the working directory
  ColourChoice output_colour = ColourChoice::kAuto;  // output.colour: output.ply's RGB (see ColourChoice)
  int threads = 0;                                   // 0 = all cores
  std::string preset = "scanfill";                   // the parameter set the sections start from: scanfill | paper
  // output.surface: output_mesh.ply or not; the mesh's options are the section `surface` (below)
  SurfaceChoice output_surface = SurfaceChoice::kAuto;
  LoadOptions load;
  SampleOptions sample;
  FeaturesOptions features;
  VoteOptions vote;
  ModesOptions modes;
  SupportOptions support;  // allow_scale is vote.allow_scale's (the engine passes it on); no key of its own
  SymmetryOptions symmetry;
  LabelOptions label;
  CorrespondOptions correspond;
  CoverOptions cover;  // completion: which template samples the registered scan covers (keys correspond.cover_*)
  SynthesisOptions synthesize;
  AlignOptions align;
  VirtualScanOptions virtual_scan;
  SurfaceOptions surface;
  CurveSampleOptions curves;          // mode curves: the drawings' samples and the output's polylines
  ExchangeOptions exchange;           // mode exchange: part boxes and the box-wise analogy
  std::filesystem::path config_path;  // the file it was read from
};

// Names as the config and the report write them.
const std::vector<std::pair<std::string, RunMode>>& mode_names();
std::string mode_name(RunMode mode);
std::string role_name(Role role);

// Whether the run makes output_mesh.ply (output.surface resolved for the mode).
bool makes_surface(const RunConfig& config);

// Roles each mode requires, in order.
const std::vector<Role>& roles_for_mode(RunMode mode);

// Every input playing `role`, in config order (mode exchange has several exemplars and targets).
std::vector<const Input*> inputs_for(const RunConfig& config, Role role);

// The input playing `role`; throws InvariantError when the config has none.
const Input& input_for(const RunConfig& config, Role role);

// Reads and validates a config file. Throws ConfigError whose message lists every problem, one per line, each as
// "FILE:LINE:COLUMN: dotted.key: problem".
// `overrides`: KEY=VALUE texts (the command line's --set), applied over the file's keys before any check.
RunConfig load_config(const std::filesystem::path& path, const std::vector<std::string>& overrides = {});

// Pure validation of a config (ranges, mode, inputs). Returns (dotted key, problem) pairs; empty when valid.
std::vector<std::pair<std::string, std::string>> validate(const RunConfig& config);

// A complete, valid config with every option, its default and its meaning (for --print-defaults).
std::string default_config_yaml();

}  // namespace scanfill
