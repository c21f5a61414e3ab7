// load node: reads the point clouds and meshes users have (DESIGN section 4, load).
//
// Formats, chosen by the file extension (case-insensitive):
//   .ply  ASCII and binary (either endianness), CRLF headers, extra elements (range_grid, camera...), n-gon faces
//   .pcd  ascii, binary, binary_compressed (our own checked reader; 64-bit integer fields too); organised clouds with
//         NaN holes
//   .obj  v / vn / f with any index form (v, v/vt, v//vn, v/vt/vn, negative), n-gons
//   .off  OFF, NOFF, COFF; .stl ASCII and binary (vertices welded); .xyz x y z [nx ny nz]
// N-gons are split into triangle fans. Non-finite points are dropped, with their faces, and counted. Anything empty,
// truncated, with wrong counts or out-of-range face indices, or without a finite point throws IoError naming the file.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "nodes/core/point_set.h"

namespace scanfill {

struct LoadOptions {
  // Reorder points by Morton code (DESIGN section 7: 2.5-3x faster kd-tree queries); source_index keeps the way back.
  bool morton_sort = true;
  // A scan (or exemplar) given as one binary PLY of more points than this is read in chunks, never held whole: sampled
  // by per-chunk grid thinning and carried by the transfer a run at a time, in file order (issue 13). 0 = never.
  Index stream_above = 0;
};

struct LoadResult {
  PointSet points;
  std::string format;                 // "ply", "pcd", "obj", "off", "stl", "xyz"
  std::string encoding;               // "ascii", "binary_little_endian", "binary_compressed", ...
  Index file_points = 0;              // points (vertices) declared in the file, before dropping non-finite ones
  Index dropped_nonfinite = 0;        // points dropped because a coordinate was NaN or infinite
  std::vector<std::string> warnings;  // one line each, ready to show
};

LoadResult read_point_set(const std::filesystem::path& path, const LoadOptions& options = {});

// What the header of a PLY or PCD file says, read without its body (as `pdal info --summary` does).
struct FileHeader {
  std::string format;                        // "ply", "pcd"
  std::string encoding;                      // as LoadResult::encoding
  Index points = 0;                          // vertices (PLY) or POINTS (PCD) declared, non-finite ones included
  Index faces = 0;                           // PLY face element records (polygons, before they are split), 0 for PCD
  std::vector<std::string> elements;         // PLY: every element with its count, "vertex 40256"; PCD: "WIDTH x HEIGHT"
  std::vector<std::string> properties;       // PLY: "vertex.x float", "face.vertex_indices list uchar int"; PCD: "x F4"
  std::optional<Eigen::Vector3d> viewpoint;  // PCD VIEWPOINT origin
  Index header_bytes = 0;                    // the bytes read
};

// The header of a PLY or PCD file, read and checked as read_point_set checks it (the counts against the file's size
// included), without reading the points: a few kilobytes whatever the file's size. Nothing for formats without a
// header (OBJ, OFF, STL, XYZ). Throws IoError naming the file.
std::optional<FileHeader> read_header(const std::filesystem::path& path);

// True for the extensions read_point_set accepts.
bool is_supported_extension(const std::filesystem::path& path);

// The path's extension in lower case, with its dot (".ply"; "" for none).
std::string lower_extension(const std::filesystem::path& path);

}  // namespace scanfill
