// Writers. Every output is written atomically: to a temporary file in the same folder, then renamed, so that a failed
// run never leaves a partial file behind.
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <utility>
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
// blue (uchar) and intensity (float) when present, the faces when present, and the point set's viewpoint as a camera
// element when it has one. Colours and intensity are written as
// stored whatever `real` is. Throws IoError naming the file on failure (and leaves no file); InvariantError when an
// extra property repeats one of the point set's (colours are set on the point set).
void write_ply(const std::filesystem::path& path, const PointSet& points, const std::vector<PlyProperty>& extra = {},
               PlyReal real = PlyReal::kFloat32);

// The record layout of a binary PLY as write_ply writes it: which point-set attributes and extra properties each
// vertex has, and how many vertices and triangles the file declares.
struct PlyLayout {
  Index vertices = 0;
  Index faces = 0;
  bool normals = false, curvatures = false, directions = false, colours = false, intensity = false;
  std::vector<std::pair<std::string, PlyProperty::Type>> extra;  // after the directions, before the colours
  PlyReal real = PlyReal::kFloat32;
  // The sensor position of a single-view scan: after the faces, one camera record (view_px view_py view_pz, of the
  // coordinates' type), as PCL's PLY writer gives it.
  std::optional<Eigen::Vector3d> viewpoint;
};

// A binary PLY written in pieces: the header first (the counts declared up front), then the vertices in any number of
// append() calls, then the triangles. The file appears (atomically, by rename) only at commit(), which checks that
// exactly the declared counts were written; a writer destroyed before commit() leaves no file. Memory is one piece's
// buffer, whatever the file's size. write_ply is one PlyWriter with one append.
class PlyWriter {
 public:
  PlyWriter(const std::filesystem::path& path, PlyLayout layout);
  ~PlyWriter();
  PlyWriter(const PlyWriter&) = delete;
  PlyWriter& operator=(const PlyWriter&) = delete;

  // The next points.size() vertices: the layout's attributes of `points`, and `extra` in the layout's order (same
  // names, one value per point). Throws InvariantError when they do not match the layout or exceed its count.
  void append(const PointSet& points, const std::vector<PlyProperty>& extra = {});
  // The next triangles (vertex indices into the whole file), after every vertex.
  void append_faces(const Matrix3Xi& faces);
  // Throws InvariantError unless the declared counts were written, IoError naming the file when it cannot be.
  void commit();

 private:
  std::filesystem::path path_, tmp_;
  PlyLayout layout_;
  std::ofstream out_;
  std::string buf_;
  Index vertices_ = 0, faces_ = 0;
  bool committed_ = false;
};

// The layout write_ply gives `points` with `extra`.
PlyLayout ply_layout(const PointSet& points, const std::vector<PlyProperty>& extra, PlyReal real = PlyReal::kFloat32);

// Writes `content` to `path` atomically (temp file + rename). Throws IoError naming the file.
void write_file_atomic(const std::filesystem::path& path, const std::string& content);

}  // namespace scanfill
