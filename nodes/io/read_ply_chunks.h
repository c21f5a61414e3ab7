// Chunked reading of a large binary PLY (issue 13): a scan of 10^8 points is read a bounded run of vertices at a time,
// never held whole (read_point_set holds the file and the point set at once, about 48 bytes a point and more).
//
// The vertices come in file order (no Morton sort: that needs them all), each run as read_point_set(path,
// {.morton_sort = false}) gives those rows: positions, normals when the file has nx ny nz (normalised as read_point_set
// does; a zero or non-finite normal is kept as zero, since the whole-file decision to drop every normal when more than
// 1% are broken cannot be made a run at a time), source_index = the vertex's row in the file. Points with a
// non-finite coordinate are dropped and counted. Colours, intensity and other properties are read past.
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <vector>

#include "nodes/core/point_chunks.h"

namespace scanfill {

class PlyChunkReader : public PointChunks {
 public:
  // Reads and checks the header (as read_point_set does, the counts against the file's size included). Throws IoError
  // naming the file when it is not a binary PLY whose first element is `vertex`, without list properties, with x y z.
  explicit PlyChunkReader(const std::filesystem::path& path);

  Index rows() const override { return rows_; }  // vertices declared in the file
  bool has_normals() const { return normals_; }
  Index dropped_nonfinite() const { return dropped_; }  // so far
  const std::filesystem::path& path() const { return path_; }

  // Back to the first vertex (a new pass over the file).
  void rewind() override;
  // The next at most `max_points` vertices' finite points (positions, normals when the file has them, source_index);
  // false once every vertex has been read. Throws IoError naming the file if the data ends early.
  bool next(Index max_points, PointSet& out) override;

 private:
  std::filesystem::path path_;
  std::ifstream in_;
  std::uint64_t body_ = 0;  // byte offset of the first vertex
  Index rows_ = 0, row_ = 0, dropped_ = 0;
  size_t record_ = 0;  // bytes per vertex
  bool swap_ = false, normals_ = false;
  std::vector<int> offset_, type_;  // per value slot x y z nx ny nz: byte offset in the record and scalar type
  std::vector<char> buffer_;
};

}  // namespace scanfill
