// The config's sections, one per node's options, each described once by the table beside its Options struct
// (nodes/STAGE/STAGE_options.h); config reading, validation and --print-defaults all use them. Internal to the engine.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "engine/config.h"
#include "nodes/core/options.h"

namespace scanfill {

// A config section: a node's option table (nodes/core/options.h).
using Section = OptionTable;

std::vector<Section> option_sections(RunConfig& config);

// The paper's parameters (preset: paper) in place of ours, in every section that has them.
void use_paper_parameters(RunConfig& config);

// String tables of enums for YAML.
const std::vector<std::pair<std::string, NormalOrientation>>& orientation_names();
std::string to_string(NormalOrientation o);

}  // namespace scanfill
