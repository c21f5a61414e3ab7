// What every format reader produces before the shared clean-up in read_point_set.cpp. Internal to nodes/io.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "nodes/core/errors.h"
#include "nodes/io/read_point_set.h"

namespace scanfill::io {

struct RawMesh {
  std::vector<double> xyz;            // 3 per vertex
  std::vector<double> normals;        // 3 per vertex, or empty
  std::vector<std::uint8_t> colours;  // 3 per vertex (red, green, blue in [0, 255]), or empty
  std::vector<float> intensity;       // 1 per vertex, or empty
  std::vector<std::int64_t> faces;    // 3 per triangle, as written in the file (checked later)
  std::optional<Eigen::Vector3d> viewpoint;
  std::string encoding;
  std::vector<std::string> warnings;
};

RawMesh read_ply(const std::filesystem::path& path);
RawMesh read_pcd(const std::filesystem::path& path);
RawMesh read_obj(const std::filesystem::path& path);
RawMesh read_off(const std::filesystem::path& path);
RawMesh read_stl(const std::filesystem::path& path);
RawMesh read_xyz(const std::filesystem::path& path);
FileHeader read_ply_header(const std::filesystem::path& path);
FileHeader read_pcd_header(const std::filesystem::path& path);

// "<path>: <what>" as an IoError.
[[noreturn]] inline void fail(const std::filesystem::path& path, const std::string& what) {
  throw IoError(path.string() + ": " + what);
}

// The whole file in memory; IoError if it cannot be opened or is empty.
std::string read_file(const std::filesystem::path& path);

// The file's first bytes, read in blocks until `complete(bytes)` or the end of the file, and the file's size; the same
// IoErrors as read_file.
std::string read_head(const std::filesystem::path& path, bool (*complete)(std::string_view), std::uint64_t& file_size);

// Appends a polygon as a triangle fan; returns false (and appends nothing) for fewer than 3 corners.
inline bool add_polygon(std::vector<std::int64_t>& faces, const std::int64_t* corners, size_t n) {
  if (n < 3) return false;
  for (size_t i = 1; i + 1 < n; ++i) {
    faces.push_back(corners[0]);
    faces.push_back(corners[i]);
    faces.push_back(corners[i + 1]);
  }
  return true;
}

// A whitespace tokenizer over a text buffer that tracks line numbers; '\r' is whitespace.
class Tokenizer {
 public:
  Tokenizer(const char* begin, const char* end) : p_(begin), end_(end) {}
  // Next token, or an empty view at end of input.
  std::string_view next();
  bool at_end();
  // Rest of the current line (for comments), consuming the newline.
  void skip_line();
  int line() const { return line_; }
  // Bytes not yet consumed.
  size_t remaining() const { return size_t(end_ - p_); }

 private:
  void skip_space();
  const char* p_;
  const char* end_;
  int line_ = 1;
};

// A number for a message: %g, not std::to_string's 300 digits of 1e300.
inline std::string short_number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

// Parses a number token; false if it is not entirely a number.
bool parse_double(std::string_view token, double& out);
bool parse_int(std::string_view token, std::int64_t& out);

}  // namespace scanfill::io
