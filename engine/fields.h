// Field tables: the single description of each options struct used by config reading, validation and
// --print-defaults. Internal to the engine.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "engine/config.h"

namespace scanfill {

using FieldRef = std::variant<double*, int*, Index*, std::uint64_t*, bool*, NormalOrientation*,
                              std::optional<Eigen::Vector3d>*, std::vector<Landmark>*>;

struct Field {
  std::string key;
  FieldRef ref;
  std::string doc;                                    // meaning, unit, valid range
  std::function<std::optional<std::string>()> check;  // "expected ..." when the value is out of range
};

struct Section {
  std::string key;  // "sample", "features", "load"
  std::string doc;
  std::vector<Field> fields;
};

std::vector<Section> option_sections(RunConfig& config);

// String tables of enums for YAML.
const std::vector<std::pair<std::string, NormalOrientation>>& orientation_names();
std::string to_string(NormalOrientation o);

}  // namespace scanfill
