// Plan, apply and tiles (DESIGN section 10): the commands that let another engine (Dask, a Slurm job array) carry a
// large scan in tiles.
//
//   scanfill plan   the run up to the plan node; writes the plan file (nodes/io/plan_file.h) and the plan-level
//                   points: the target's copies carried (empty when nothing is copied). Neither depends on a tile.
//   scanfill apply  one tile of the exemplar carried through a plan, written with output.ply's properties (RGB as
//                   output.colour resolved when planning; the scan's colours and intensity ride along as in the run).
//   scanfill split  the exemplar, as the run loads it, in tiles of consecutive (Morton-ordered) points, written
//   exactly.
// The union of every tile's output and the plan-level points is output.ply's points, each once: a point's output
// depends only on the point and the plan.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "engine/config.h"
#include "nodes/core/point_set.h"

namespace scanfill {

struct PlanPaths {
  std::filesystem::path plan;    // the plan file
  std::filesystem::path points;  // the plan-level points (.ply)
};

// `plan`: the given path, or <output.dir>/scanfill.plan; `points`: the given path, or plan_points.ply beside the plan.
PlanPaths plan_paths(const RunConfig& config, const std::string& plan, const std::string& points);

struct PlanOutcome {
  Index patches = 0, carried_samples = 0, plan_points = 0;
  std::uintmax_t plan_bytes = 0;
};

// Runs config's graph up to the plan node and writes both files (each atomically; the points first, so that a plan
// file is there only when its points are). Throws ConfigError for a mode without a transfer (analogy).
PlanOutcome make_plan(const RunConfig& config, const PlanPaths& paths);

struct ApplyOutcome {
  Index tile_points = 0, output_points = 0;
};

// Carries the tile's points through the plan file and writes them to `output` (.ply). Throws IoError naming the file
// for a plan or tile that cannot be read, InputError for a tile outside the plan's scan.
ApplyOutcome apply_tile(const std::filesystem::path& plan, const std::filesystem::path& tile,
                        const std::filesystem::path& output);

// The exemplar of config's run as the run loads it (completion: the scan, through the virtual scanner when
// configured). Throws ConfigError for a mode without an exemplar (analogy).
PointSet exemplar_of(const RunConfig& config);

// Writes `points` as `tiles` files <dir>/tile_NNNN.ply (consecutive runs, x y z and normals in double precision, the
// scan's colours and intensity as loaded, no triangles) and returns their paths. Refuses a folder that already holds
// tiles, and more tiles than points; a failed split leaves no tile behind.
std::vector<std::filesystem::path> split_into_tiles(const PointSet& points, Index tiles,
                                                    const std::filesystem::path& dir);

}  // namespace scanfill
