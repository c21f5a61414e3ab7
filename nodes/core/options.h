// One description per Options struct (CONVENTIONS, configuration): each field's key, where it lives, one doc line and
// its range check, kept next to the struct it describes (nodes/STAGE/STAGE_options.h).
//
// The engine turns the tables into YAML reading, validation messages with file:line:column and --print-defaults
// (engine/config.cpp); the nodes check their own options at entry with check_options, so a caller that skips the
// config (a test, a benchmark) gets the same checks. No YAML here: a table only points at fields.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "nodes/core/point_set.h"

namespace scanfill {

enum class NormalOrientation;  // nodes/features
struct Landmark;               // nodes/correspond
struct LandmarkFiles;          // nodes/correspond

using FieldRef = std::variant<double*, int*, Index*, std::uint64_t*, bool*, NormalOrientation*,
                              std::optional<Eigen::Vector3d>*, std::vector<Landmark>*, LandmarkFiles*, std::string*>;

struct Field {
  std::string key;                                    // the YAML key, = the field's name
  FieldRef ref;                                       // the field
  std::string doc;                                    // meaning, unit, valid range
  std::function<std::optional<std::string>()> check;  // "expected ..." when the value is out of range
};

struct OptionTable {
  std::string key;  // the config section: "sample", "features", ...
  std::string doc;
  std::vector<Field> fields;
};

// Throws ConfigError naming every field out of range, one per line: "vote.min_scale: expected a number > 0".
void check_options(const OptionTable& table);

// The same for an Options struct that has a table (option_table(Options&) beside it).
template <class Options>
void check_options(const Options& options) {
  Options copy = options;  // tables point at mutable fields; checking only reads
  check_options(option_table(copy));
}

// Range checks for tables.
namespace checks {

inline std::function<std::optional<std::string>()> any() {
  return [] { return std::optional<std::string>(); };
}

template <class T>
std::function<std::optional<std::string>()> range(const T* v, T lo, T hi, bool lo_open, const std::string& what) {
  return [=]() -> std::optional<std::string> {
    const bool ok = (lo_open ? *v > lo : *v >= lo) && *v <= hi;
    if (ok) return std::nullopt;
    return "expected " + what;
  };
}

inline std::function<std::optional<std::string>()> positive(const double* p) {
  return [p]() -> std::optional<std::string> {
    if (*p > 0 && std::isfinite(*p)) return std::nullopt;
    return "expected a number > 0";
  };
}

inline std::function<std::optional<std::string>()> non_negative(const double* p) {
  return [p]() -> std::optional<std::string> {
    if (*p >= 0 && std::isfinite(*p)) return std::nullopt;
    return "expected a number >= 0";
  };
}

inline constexpr double kInf = std::numeric_limits<double>::infinity();

}  // namespace checks
}  // namespace scanfill
