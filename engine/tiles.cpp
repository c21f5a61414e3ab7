#include "engine/tiles.h"

#include <cstdio>

#include "engine/outputs.h"
#include "engine/stages.h"
#include "nodes/core/errors.h"
#include "nodes/io/plan_file.h"
#include "nodes/io/read_point_set.h"
#include "nodes/io/write_ply.h"
#include "nodes/transfer/transfer.h"

namespace scanfill {
namespace {

// The input the transfer carries: completion's scan, transfer's exemplar.
const Input& exemplar_input(const RunConfig& config, const std::string& command) {
  if (config.mode == RunMode::kAnalogy || config.mode == RunMode::kExchange)
    throw ConfigError(config.config_path.string() + ": mode: " + mode_name(config.mode) +
                      " has no transfer for scanfill " + command + " (completion or transfer)");
  return input_for(config, config.mode == RunMode::kCompletion ? Role::kScan : Role::kExemplar);
}

void make_parent(const std::filesystem::path& file) {
  std::error_code ec;
  if (!file.parent_path().empty()) std::filesystem::create_directories(file.parent_path(), ec);
  if (ec) throw IoError(file.parent_path().string() + ": cannot be made (" + ec.message() + ")");
}

void require_ply(const std::filesystem::path& path) {
  if (path.extension() != ".ply") throw ConfigError(path.string() + ": the output must be a .ply file");
}

// True when a and b name the same existing file.
bool same_file(const std::filesystem::path& a, const std::filesystem::path& b) {
  std::error_code ec;
  return std::filesystem::equivalent(a, b, ec);
}

// A plan run writes its two files, not output.dir's: neither may be one of the run's inputs.
void refuse_overwriting_inputs(const RunConfig& config, const std::vector<std::filesystem::path>& written) {
  for (const auto& input : config.inputs)
    for (const InputSpec& spec : all_specs(input))
      for (const auto& out : written)
        if (!spec.path.empty() && same_file(spec.path, out))
          throw ConfigError("inputs." + role_name(input.role) + ": " + spec.path.string() +
                            " would be overwritten by scanfill plan's " + out.string());
}

// The name of a tile_*.ply file in dir, or empty.
std::string a_tile_in(const std::filesystem::path& dir) {
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.starts_with("tile_") && entry.path().extension() == ".ply") return name;
  }
  return "";
}

// output.colour in the plan file and back (resolved: never auto).
PlanColour plan_colour(ColourChoice c) {
  return c == ColourChoice::kScan    ? PlanColour::kScan
         : c == ColourChoice::kLabel ? PlanColour::kLabel
                                     : PlanColour::kOrigin;
}
ColourChoice choice_of(PlanColour c) {
  return c == PlanColour::kScan    ? ColourChoice::kScan
         : c == PlanColour::kLabel ? ColourChoice::kLabel
                                   : ColourChoice::kOrigin;
}

}  // namespace

PlanPaths plan_paths(const RunConfig& config, const std::string& plan, const std::string& points) {
  PlanPaths p;
  p.plan = plan.empty() ? config.output_dir / "scanfill.plan" : std::filesystem::path(plan);
  p.points = points.empty() ? p.plan.parent_path() / "plan_points.ply" : std::filesystem::path(points);
  return p;
}

PlanOutcome make_plan(const RunConfig& config, const PlanPaths& paths) {
  exemplar_input(config, "plan");
  require_ply(paths.points);
  if (paths.plan == paths.points) throw ConfigError(paths.plan.string() + ": the plan and its points need two files");
  refuse_overwriting_inputs(config, {paths.plan, paths.points});
  make_parent(paths.plan);
  make_parent(paths.points);
  RunState state(config);
  state.plan_only = true;
  run_graph(state);
  const Planned& planned = *state.plan();
  const Synthesized& syn = *planned.aligned->synthesized;
  PlanFile file{planned.plan, syn.analogy->labels.self_label,
                plan_colour(resolved_colour(config.output_colour, planned.plan.colours))};
  const PointSet& target = syn.analogy->votes().target()->sampled->loaded->load.points;
  const TransferResult copies = transfer_planned(file.plan, nullptr, &target);
  write_output_ply(paths.points, copies, choice_of(file.colour), file.self_label);
  write_plan(paths.plan, file);
  return {Index(file.plan.patches.size()), Index(file.plan.patch.size()), copies.points.size(),
          std::filesystem::file_size(paths.plan)};
}

ApplyOutcome apply_tile(const std::filesystem::path& plan, const std::filesystem::path& tile,
                        const std::filesystem::path& output) {
  require_ply(output);
  if (same_file(output, plan) || same_file(output, tile))
    throw ConfigError(output.string() + ": the output would overwrite an input of scanfill apply");
  const PlanFile file = read_plan(plan);
  if (!is_supported_extension(tile))
    throw IoError(tile.string() + ": unknown format (expected .ply, .pcd, .obj, .off, .stl or .xyz)");
  const LoadResult loaded = read_point_set(tile);
  const PointSet& points = loaded.points;
  if (const Index i = first_point_outside(file.plan, points); i >= 0) {
    const Eigen::Vector3d p = points.positions().col(i);
    char where[96];
    std::snprintf(where, sizeof(where), "(%.6g, %.6g, %.6g)", p.x(), p.y(), p.z());
    throw InputError(tile.string() + ": point " + where + " lies outside the bounds of the scan " + plan.string() +
                     " was made for: a tile of another scan?");
  }
  if ((file.plan.colours && !points.has_colours()) || (file.plan.intensity && !points.has_intensity()))
    throw InputError(tile.string() + ": has no " +
                     (file.plan.colours && !points.has_colours() ? "colours" : "intensity") + " but the scan " +
                     plan.string() + " was made for has: split it with scanfill split");
  const TransferResult out = apply_plan(file.plan, &points, nullptr);
  make_parent(output);
  write_output_ply(output, out, choice_of(file.colour), file.self_label);
  return {points.size(), out.points.size()};
}

PointSet exemplar_of(const RunConfig& config) {
  return load_as_run(config, exemplar_input(config, "split")).points;
}

std::vector<std::filesystem::path> split_into_tiles(const PointSet& points, Index tiles,
                                                    const std::filesystem::path& dir) {
  if (tiles > points.size())
    throw InputError("split: " + std::to_string(tiles) + " tiles of " + std::to_string(points.size()) +
                     " points would leave some empty");
  const auto name = [&](Index t) {
    char n[32];
    std::snprintf(n, sizeof(n), "tile_%04lld.ply", static_cast<long long>(t));
    return dir / n;
  };
  if (const std::string old = a_tile_in(dir); !old.empty())
    throw IoError(dir.string() + ": already holds tiles (" + old + "); remove them or choose another folder");
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw IoError(dir.string() + ": cannot be made (" + ec.message() + ")");
  std::vector<std::filesystem::path> written;
  try {
    for (const auto& range : tile_ranges(points.size(), tiles)) {
      written.push_back(name(Index(written.size())));
      write_ply(written.back(), tile_points(points, range), {}, PlyReal::kFloat64);
    }
  } catch (...) {
    for (const auto& f : written) std::filesystem::remove(f, ec);
    throw;
  }
  return written;
}

}  // namespace scanfill
