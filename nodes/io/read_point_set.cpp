#include "nodes/io/read_point_set.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

#include "nodes/core/kdtree.h"
#include "nodes/io/orient_faces.h"
#include "nodes/io/raw_mesh.h"

namespace scanfill {
namespace io {

std::string read_file(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) fail(path, "no such file");
  if (std::filesystem::is_directory(path, ec)) fail(path, "is a directory, expected a point cloud or mesh file");
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, "cannot be opened for reading");
  std::string data;
  in.seekg(0, std::ios::end);
  const auto size = in.tellg();
  if (size < 0) fail(path, "cannot determine the file size");
  data.resize(static_cast<size_t>(size));
  in.seekg(0);
  in.read(data.data(), size);
  if (!in) fail(path, "read error");
  if (data.empty()) fail(path, "file is empty");
  return data;
}

std::string read_head(const std::filesystem::path& path, bool (*complete)(std::string_view), std::uint64_t& file_size) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) fail(path, "no such file");
  if (std::filesystem::is_directory(path, ec)) fail(path, "is a directory, expected a point cloud or mesh file");
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, "cannot be opened for reading");
  in.seekg(0, std::ios::end);
  const auto size = in.tellg();
  if (size < 0) fail(path, "cannot determine the file size");
  if (size == 0) fail(path, "file is empty");
  file_size = std::uint64_t(size);
  in.seekg(0);
  std::string head;
  constexpr size_t kBlock = 1 << 16;
  while (head.size() < file_size && !complete(head)) {
    const size_t at = head.size();
    head.resize(std::min<std::uint64_t>(file_size, at + kBlock));
    in.read(head.data() + at, std::streamsize(head.size() - at));
    if (!in) fail(path, "read error");
  }
  return head;
}

void Tokenizer::skip_space() {
  while (p_ < end_ && (*p_ == ' ' || *p_ == '\t' || *p_ == '\r' || *p_ == '\n' || *p_ == '\f' || *p_ == '\v')) {
    if (*p_ == '\n') ++line_;
    ++p_;
  }
}

std::string_view Tokenizer::next() {
  skip_space();
  const char* start = p_;
  while (p_ < end_ && !(*p_ == ' ' || *p_ == '\t' || *p_ == '\r' || *p_ == '\n' || *p_ == '\f' || *p_ == '\v')) ++p_;
  return {start, static_cast<size_t>(p_ - start)};
}

bool Tokenizer::at_end() {
  skip_space();
  return p_ >= end_;
}

void Tokenizer::skip_line() {
  while (p_ < end_ && *p_ != '\n') ++p_;
  if (p_ < end_) {
    ++p_;
    ++line_;
  }
}

bool parse_double(std::string_view t, double& out) {
  if (t.empty()) return false;
  const char* b = t.data();
  if (*b == '+') ++b;
  const auto [ptr, ec] = std::from_chars(b, t.data() + t.size(), out);
  if (ec == std::errc::result_out_of_range) {  // denormals and overflow: take strtod's answer (inf or tiny)
    out = std::strtod(std::string(t).c_str(), nullptr);
    return true;
  }
  return ec == std::errc() && ptr == t.data() + t.size();
}

bool parse_int(std::string_view t, std::int64_t& out) {
  if (t.empty()) return false;
  const char* b = t.data();
  if (*b == '+') ++b;
  const auto [ptr, ec] = std::from_chars(b, t.data() + t.size(), out);
  return ec == std::errc() && ptr == t.data() + t.size();
}

}  // namespace io

std::string lower_extension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext;
}

namespace {

// Drops non-finite points (and faces that use them), checks face indices, builds the PointSet.
LoadResult finish(const std::filesystem::path& path, io::RawMesh raw, const std::string& format,
                  const LoadOptions& options) {
  LoadResult result;
  result.format = format;
  result.encoding = raw.encoding;
  result.warnings = std::move(raw.warnings);
  const Index n_file = Index(raw.xyz.size() / 3);
  result.file_points = n_file;
  if (n_file == 0) io::fail(path, "contains no points");
  const bool has_normals = raw.normals.size() == raw.xyz.size();
  const bool has_colours = raw.colours.size() == raw.xyz.size();
  const bool has_intensity = Index(raw.intensity.size()) == n_file;

  for (size_t f = 0; f < raw.faces.size(); ++f) {
    if (raw.faces[f] < 0 || raw.faces[f] >= n_file)
      io::fail(path, "face " + std::to_string(f / 3) + " uses vertex index " + std::to_string(raw.faces[f]) +
                         ", outside [0, " + std::to_string(n_file) + ")");
  }

  std::vector<std::int64_t> remap(static_cast<size_t>(n_file), -1);
  Index kept = 0;
  for (Index i = 0; i < n_file; ++i) {
    const double* p = &raw.xyz[size_t(3 * i)];
    if (std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2])) remap[size_t(i)] = kept++;
  }
  if (kept == 0) io::fail(path, "has no point with finite coordinates (" + std::to_string(n_file) + " points read)");
  result.dropped_nonfinite = n_file - kept;

  Eigen::Matrix3Xd positions(3, kept);
  Eigen::Matrix3Xd normals(3, has_normals ? kept : 0);
  Matrix3Xu8 colours(3, has_colours ? kept : 0);
  Eigen::VectorXf intensity(has_intensity ? kept : 0);
  VectorXi64 source_index(kept);
  Index bad_normals = 0;
  for (Index i = 0; i < n_file; ++i) {
    const Index j = remap[size_t(i)];
    if (j < 0) continue;
    positions.col(j) = Eigen::Vector3d(raw.xyz[size_t(3 * i)], raw.xyz[size_t(3 * i + 1)], raw.xyz[size_t(3 * i + 2)]);
    source_index(j) = i;
    if (has_colours) colours.col(j) = Eigen::Map<const Eigen::Matrix<std::uint8_t, 3, 1>>(&raw.colours[size_t(3 * i)]);
    if (has_intensity) intensity(j) = raw.intensity[size_t(i)];
    if (has_normals) {
      Eigen::Vector3d n(raw.normals[size_t(3 * i)], raw.normals[size_t(3 * i + 1)], raw.normals[size_t(3 * i + 2)]);
      const double len = n.norm();
      if (!(len > 1e-12) || !std::isfinite(len)) {
        ++bad_normals;
        n.setZero();
      } else if (std::abs(len - 1) > 1e-12) {
        n /= len;  // normals unit to rounding are kept as stored: a tile scanfill wrote reads back bit for bit
      }
      normals.col(j) = n;
    }
  }

  std::vector<std::int32_t> tris;
  tris.reserve(raw.faces.size());
  Index dropped_faces = 0;
  for (size_t f = 0; f + 2 < raw.faces.size(); f += 3) {
    const auto a = remap[size_t(raw.faces[f])], b = remap[size_t(raw.faces[f + 1])],
               c = remap[size_t(raw.faces[f + 2])];
    if (a < 0 || b < 0 || c < 0) {
      ++dropped_faces;
      continue;
    }
    tris.insert(tris.end(), {std::int32_t(a), std::int32_t(b), std::int32_t(c)});
  }

  if (const Index turned = orient_faces(positions, tris); turned > 0)
    result.warnings.push_back(std::to_string(turned) + " of " + std::to_string(tris.size() / 3) +
                              " faces were wound against their neighbours or faced into their closed part, and were "
                              "turned");
  if (result.dropped_nonfinite > 0)
    result.warnings.push_back(std::to_string(result.dropped_nonfinite) + " of " + std::to_string(n_file) +
                              " points have non-finite coordinates and were dropped");
  if (dropped_faces > 0)
    result.warnings.push_back(std::to_string(dropped_faces) + " faces used dropped points and were dropped");
  // A few broken normals (some writers emit zeros) keep the rest; many mean the normals are not to be trusted.
  const bool keep_normals = has_normals && bad_normals * 100 <= kept;
  if (bad_normals > 0)
    result.warnings.push_back(std::to_string(bad_normals) + " points have zero or non-finite normals; " +
                              (keep_normals ? "kept as zero vectors" : "all normals ignored"));

  PointSet& ps = result.points;
  ps.set_positions(std::move(positions));
  if (keep_normals) ps.set_normals(std::move(normals));
  if (has_colours) ps.set_colours(std::move(colours));
  if (has_intensity) ps.set_intensity(std::move(intensity));
  if (!tris.empty()) ps.set_faces(Eigen::Map<const Matrix3Xi>(tris.data(), 3, Eigen::Index(tris.size() / 3)));
  ps.set_source_index(std::move(source_index));
  ps.set_viewpoint(raw.viewpoint);

  if (options.morton_sort && kept > 1) {
    const std::vector<Index> order = morton_order(ps.positions());
    std::vector<std::int32_t> inverse(order.size()), sorted(order.size());
    for (Index i = 0; i < kept; ++i) {
      sorted[size_t(i)] = std::int32_t(order[size_t(i)]);
      inverse[size_t(order[size_t(i)])] = std::int32_t(i);
    }
    // Every per-point attribute in the new order; the faces renumbered, the viewpoint kept.
    PointSet reordered = subset(ps, sorted);
    if (ps.has_faces()) {
      Matrix3Xi faces = ps.faces();
      for (Eigen::Index k = 0; k < faces.size(); ++k) faces.data()[k] = inverse[size_t(faces.data()[k])];
      reordered.set_faces(std::move(faces));
    }
    reordered.set_viewpoint(ps.viewpoint());
    ps = std::move(reordered);
  }
  ps.check();
  return result;
}

}  // namespace

std::optional<FileHeader> read_header(const std::filesystem::path& path) {
  const std::string ext = lower_extension(path);
  if (ext == ".ply") return io::read_ply_header(path);
  if (ext == ".pcd") return io::read_pcd_header(path);
  if (!is_supported_extension(path))
    io::fail(path, "unknown format '" + ext + "' (expected .ply, .pcd, .obj, .off, .stl or .xyz)");
  return std::nullopt;
}

bool is_supported_extension(const std::filesystem::path& path) {
  const std::string ext = lower_extension(path);
  return ext == ".ply" || ext == ".pcd" || ext == ".obj" || ext == ".off" || ext == ".stl" || ext == ".xyz";
}

LoadResult read_point_set(const std::filesystem::path& path, const LoadOptions& options) {
  const std::string ext = lower_extension(path);
  if (ext == ".ply") return finish(path, io::read_ply(path), "ply", options);
  if (ext == ".pcd") return finish(path, io::read_pcd(path), "pcd", options);
  if (ext == ".obj") return finish(path, io::read_obj(path), "obj", options);
  if (ext == ".off") return finish(path, io::read_off(path), "off", options);
  if (ext == ".stl") return finish(path, io::read_stl(path), "stl", options);
  if (ext == ".xyz") return finish(path, io::read_xyz(path), "xyz", options);
  io::fail(path, "unknown format '" + ext + "' (expected .ply, .pcd, .obj, .off, .stl or .xyz)");
}

}  // namespace scanfill
