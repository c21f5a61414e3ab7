// Writers. Every output is written atomically: to a temporary file in the same folder, then renamed, so that a failed
// run never leaves a partial file behind.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "nodes/core/point_set.h"

namespace scanfill {

// One extra per-vertex property for write_ply, N values.
struct PlyProperty {
  enum class Type { kUint8, kInt32, kFloat32 };
  std::string name;
  Type type = Type::kFloat32;
  std::vector<double> values;
};

// The type of the coordinates, normals, curvatures and directions in a written PLY.
enum class PlyReal {
  kFloat32,  // half the size; what every output uses
  kFloat64,  // exact: the tiles of `scanfill split`, which must carry the points as the run has them
};

// Binary little-endian PLY: x y z, then nx ny nz, k1 k2, d1x d1y d1z when present, the extra properties, red green
// blue (uchar) and intensity (float) when present, and the faces when present. Colours and intensity are written as
// stored whatever `real` is. Throws IoError naming the file on failure (and leaves no file); InvariantError when an
// extra property repeats one of the point set's (colours are set on the point set).
void write_ply(const std::filesystem::path& path, const PointSet& points, const std::vector<PlyProperty>& extra = {},
               PlyReal real = PlyReal::kFloat32);

// Writes `content` to `path` atomically (temp file + rename). Throws IoError naming the file.
void write_file_atomic(const std::filesystem::path& path, const std::string& content);

}  // namespace scanfill
