// One input of a run, as a user writes it (a config's inputs, `scanfill sample --input`, `scan --input`, `eval`):
//
//   FILE                  a point cloud or mesh (.ply .pcd .obj .off .stl .xyz), relative to `base`; or a .conf
//                         (scan_alignment.h): its range scans, each moved by its pose, as one point set
//   procedural:NAME       a procedural shape (nodes/procedural/shapes.h)
//   revolution:INPUT      the body of revolution of INPUT (a FILE or procedural:NAME) about its own axis: a template
//   box:INPUT             the axis-aligned bounding box of INPUT, 8 vertices: the plain template of a box-like model
//
// This file is the one owner of that syntax: parse_input reads it, check_input says why it cannot be loaded, and
// load_input loads it.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "nodes/io/read_point_set.h"

namespace scanfill {

struct InputSpec {
  std::string text;            // as written by the user
  std::filesystem::path path;  // the file, resolved against `base` (empty for a procedural input)
  std::string procedural;      // shape name of "procedural:NAME"
  bool revolution = false;     // "revolution:...": the body of revolution of the model about its axis
  bool box = false;            // "box:...": the model's axis-aligned bounding box
};

// Parses `text`; a relative file path is resolved against `base` (the config file's folder; empty = as written).
InputSpec parse_input(const std::string& text, const std::filesystem::path& base = {});

// Why `spec` cannot be loaded (unknown shape, missing file, unknown format), or nothing when it can be tried.
std::optional<std::string> check_input(const InputSpec& spec);

// Why `spec` cannot be read as a drawing of mode curves (procedural, missing file, not .svg / .txt / .polyline), or
// nothing.
std::optional<std::string> check_drawing_input(const InputSpec& spec);

// What to call the input in messages: the resolved path, or the text of a procedural input.
std::string input_name(const InputSpec& spec);

// The bounding box of a loaded input, as the report shows it.
BoundingBox input_bounds(const LoadResult& load);

// Reads the file or makes the shape. Throws IoError (files) or InputError (unknown shape).
LoadResult load_input(const InputSpec& spec, const LoadOptions& options = {});

// Loads the fragments of one scan (given in one frame, as a hand-held scanner's software exports them) and joins them
// into one point set, in order: positions; normals, colours and intensity each when every fragment has them; faces
// when every fragment is a mesh.
// Each warning names its fragment. The registration to the template then moves them together.
LoadResult load_fragments(const std::vector<InputSpec>& specs, const LoadOptions& options = {});

}  // namespace scanfill
