#include "nodes/input/input.h"

#include <algorithm>

#include "nodes/procedural/shapes.h"

namespace scanfill {
namespace {

constexpr std::string_view kProcedural = "procedural:";
constexpr std::string_view kRevolution = "revolution:";

bool starts_with(const std::string& s, std::string_view prefix) {
  return s.rfind(prefix, 0) == 0;
}

}  // namespace

InputSpec parse_input(const std::string& text, const std::filesystem::path& base) {
  InputSpec spec;
  spec.text = text;
  std::string rest = text;
  if (starts_with(rest, kRevolution)) {
    spec.revolution = true;
    rest = rest.substr(kRevolution.size());
  }
  if (starts_with(rest, kProcedural))
    spec.procedural = rest.substr(kProcedural.size());
  else
    spec.path = std::filesystem::path(rest).is_absolute() ? std::filesystem::path(rest) : base / rest;
  return spec;
}

std::optional<std::string> check_input(const InputSpec& spec) {
  if (!spec.procedural.empty()) {
    const auto& names = shape_names();
    if (std::find(names.begin(), names.end(), spec.procedural) != names.end()) return std::nullopt;
    std::string valid;
    for (const auto& n : names) valid += (valid.empty() ? "" : ", ") + n;
    return "unknown procedural shape '" + spec.procedural + "' (valid: " + valid + ")";
  }
  std::error_code ec;
  if (!std::filesystem::exists(spec.path, ec)) return "no such file: " + spec.path.string();
  if (!std::filesystem::is_regular_file(spec.path, ec)) return "not a regular file: " + spec.path.string();
  if (!is_supported_extension(spec.path))
    return "unknown format '" + spec.path.extension().string() + "' of " + spec.path.string() +
           " (expected .ply, .pcd, .obj, .off, .stl or .xyz)";
  return std::nullopt;
}

std::string input_name(const InputSpec& spec) {
  return spec.procedural.empty() ? spec.path.string() : spec.text;
}

BoundingBox input_bounds(const LoadResult& load) {
  return bounding_box(load.points.positions());
}

LoadResult load_input(const InputSpec& spec, const LoadOptions& options) {
  if (spec.revolution) {
    InputSpec model = spec;
    model.revolution = false;
    LoadResult r = load_input(model, options);
    r.points = make_revolution(r.points);
    r.format += " (body of revolution)";
    r.file_points = r.points.size();
    return r;
  }
  if (spec.procedural.empty()) return read_point_set(spec.path, options);
  LoadResult r;
  r.points = make_shape(spec.procedural);
  r.format = "procedural";
  r.encoding = spec.procedural;
  r.file_points = r.points.size();
  return r;
}

}  // namespace scanfill
