#include "nodes/io/write_ply.h"

#include <unistd.h>

#include <atomic>
#include <bit>
#include <cstring>
#include <fstream>
#include <sstream>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "nodes/core/errors.h"

namespace scanfill {
namespace {

std::filesystem::path temp_path(const std::filesystem::path& path) {
  static std::atomic<int> counter{0};
  std::string name = ".";  // built with += : GCC 12 warns falsely on "." + string (PR 105329)
  name += path.filename().string();
  name += ".tmp" + std::to_string(::getpid()) + "_" + std::to_string(counter++);
  return path.parent_path() / name;
}

// Calls write(std::ofstream&) on a temporary file, then renames it over `path`; removes the temporary on failure.
template <class Write>
void write_atomic(const std::filesystem::path& path, Write&& write) {
  const std::filesystem::path tmp = temp_path(path);
  try {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw IoError(path.string() + ": cannot be opened for writing");
    write(out);
    out.flush();
    if (!out) throw IoError(path.string() + ": write failed (disk full?)");
    out.close();
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    if (ec) throw IoError(path.string() + ": cannot be written (" + ec.message() + ")");
  } catch (...) {
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    throw;
  }
}

template <class T>
void put(std::string& buf, T v) {
  static_assert(std::endian::native == std::endian::little, "big-endian hosts would need byte swapping here");
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  buf.append(b, sizeof(T));
}

}  // namespace

void write_file_atomic(const std::filesystem::path& path, const std::string& content) {
  write_atomic(path, [&](std::ofstream& out) { out.write(content.data(), std::streamsize(content.size())); });
}

PlyLayout ply_layout(const PointSet& points, const std::vector<PlyProperty>& extra, PlyReal real) {
  PlyLayout layout;
  layout.vertices = points.size();
  layout.faces = points.faces().cols();
  layout.normals = points.has_normals();
  layout.curvatures = points.has_curvatures();
  layout.directions = points.has_directions();
  layout.colours = points.has_colours();
  layout.intensity = points.has_intensity();
  for (const PlyProperty& p : extra) layout.extra.emplace_back(p.name, p.type);
  layout.real = real;
  layout.viewpoint = points.viewpoint();
  return layout;
}

namespace {

std::string header_of(const PlyLayout& layout) {
  const std::string r = layout.real == PlyReal::kFloat64 ? "property double " : "property float ";
  std::ostringstream header;
  header << "ply\nformat binary_little_endian 1.0\ncomment written by scanfill\n";
  header << "element vertex " << layout.vertices << "\n" << r << "x\n" << r << "y\n" << r << "z\n";
  if (layout.normals) header << r << "nx\n" << r << "ny\n" << r << "nz\n";
  if (layout.curvatures) header << r << "k1\n" << r << "k2\n";
  if (layout.directions) header << r << "d1x\n" << r << "d1y\n" << r << "d1z\n";
  for (const auto& [name, type] : layout.extra) {
    const char* t = type == PlyProperty::Type::kUint8 ? "uchar" : type == PlyProperty::Type::kInt32 ? "int" : "float";
    header << "property " << t << " " << name << "\n";
  }
  if (layout.colours) header << "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  if (layout.intensity) header << "property float intensity\n";
  if (layout.faces > 0) header << "element face " << layout.faces << "\nproperty list uchar int vertex_indices\n";
  if (layout.viewpoint) header << "element camera 1\n" << r << "view_px\n" << r << "view_py\n" << r << "view_pz\n";
  header << "end_header\n";
  return header.str();
}

// Throws InvariantError unless `points` and `extra` carry exactly the layout's attributes.
void check_matches(const PlyLayout& layout, const PointSet& points, const std::vector<PlyProperty>& extra) {
  points.check();
  const Index n = points.size();
  for (const PlyProperty& p : extra) {
    if ((points.has_colours() && (p.name == "red" || p.name == "green" || p.name == "blue")) ||
        (points.has_intensity() && p.name == "intensity"))
      throw InvariantError("write_ply: property '" + p.name + "' is the point set's own: set it there");
    if (Index(p.values.size()) != n)
      throw InvariantError("write_ply: property '" + p.name + "' has " + std::to_string(p.values.size()) +
                           " values for " + std::to_string(n) + " points");
  }
  if (n == 0) return;
  bool same = layout.normals == points.has_normals() && layout.curvatures == points.has_curvatures() &&
              layout.directions == points.has_directions() && layout.colours == points.has_colours() &&
              layout.intensity == points.has_intensity() && layout.extra.size() == extra.size();
  for (size_t k = 0; same && k < extra.size(); ++k)
    same = layout.extra[k].first == extra[k].name && layout.extra[k].second == extra[k].type;
  if (!same) throw InvariantError("write_ply: points whose attributes differ from the file's layout");
}

}  // namespace

PlyWriter::PlyWriter(const std::filesystem::path& path, PlyLayout layout)
    : path_(path), tmp_(temp_path(path)), layout_(std::move(layout)) {
  out_.open(tmp_, std::ios::binary | std::ios::trunc);
  if (!out_) throw IoError(path_.string() + ": cannot be opened for writing");
  const std::string h = header_of(layout_);
  out_.write(h.data(), std::streamsize(h.size()));
}

PlyWriter::~PlyWriter() {
  if (committed_) return;
  out_.close();
  std::error_code ec;
  std::filesystem::remove(tmp_, ec);
}

namespace {

// Bytes of one vertex record of `layout` (every property has a fixed width).
size_t record_bytes(const PlyLayout& layout) {
  const size_t real = layout.real == PlyReal::kFloat64 ? 8 : 4;
  size_t reals = 3 + (layout.normals ? 3 : 0) + (layout.curvatures ? 2 : 0) + (layout.directions ? 3 : 0);
  size_t bytes = reals * real + (layout.colours ? 3 : 0) + (layout.intensity ? 4 : 0);
  for (const auto& [name, type] : layout.extra) bytes += type == PlyProperty::Type::kUint8 ? 1 : 4;
  return bytes;
}

template <class T>
char* put_at(char* dst, T v) {
  static_assert(std::endian::native == std::endian::little, "big-endian hosts would need byte swapping here");
  std::memcpy(dst, &v, sizeof(T));
  return dst + sizeof(T);
}

// Vertex i's record at dst, in the layout's order.
void encode_vertex(const PlyLayout& layout, const PointSet& points, const std::vector<PlyProperty>& extra, Index i,
                   char* dst) {
  const bool exact = layout.real == PlyReal::kFloat64;
  const auto real = [&](double v) { dst = exact ? put_at(dst, v) : put_at(dst, float(v)); };
  for (int k = 0; k < 3; ++k) real(points.positions()(k, i));
  if (layout.normals)
    for (int k = 0; k < 3; ++k) real(points.normals()(k, i));
  if (layout.curvatures)
    for (int k = 0; k < 2; ++k) real(points.curvatures()(k, i));
  if (layout.directions)
    for (int k = 0; k < 3; ++k) real(points.directions()(k, i));
  for (const PlyProperty& p : extra) {
    const double v = p.values[size_t(i)];
    switch (p.type) {
      case PlyProperty::Type::kUint8:
        dst = put_at(dst, std::uint8_t(v));
        break;
      case PlyProperty::Type::kInt32:
        dst = put_at(dst, std::int32_t(v));
        break;
      case PlyProperty::Type::kFloat32:
        dst = put_at(dst, float(v));
        break;
    }
  }
  if (layout.colours)
    for (int k = 0; k < 3; ++k) dst = put_at(dst, points.colours()(k, i));
  if (layout.intensity) put_at(dst, points.intensity()(i));
}

}  // namespace

void PlyWriter::append(const PointSet& points, const std::vector<PlyProperty>& extra) {
  check_matches(layout_, points, extra);
  const Index n = points.size();
  if (faces_ > 0 || vertices_ + n > layout_.vertices)
    throw InvariantError("write_ply: more vertices than the " + std::to_string(layout_.vertices) + " declared");
  // Records have a fixed width: each block is encoded in parallel into place, then written at once.
  const size_t record = record_bytes(layout_);
  constexpr Index kChunk = 1 << 18;
  for (Index start = 0; start < n; start += kChunk) {
    const Index m = std::min(n - start, kChunk);
    buf_.resize(size_t(m) * record);
    tbb::parallel_for(tbb::blocked_range<Index>(0, m, 4096), [&](const tbb::blocked_range<Index>& r) {
      for (Index j = r.begin(); j != r.end(); ++j)
        encode_vertex(layout_, points, extra, start + j, buf_.data() + size_t(j) * record);
    });
    out_.write(buf_.data(), std::streamsize(buf_.size()));
  }
  vertices_ += n;
}

void PlyWriter::append_faces(const Matrix3Xi& faces) {
  if (vertices_ != layout_.vertices || faces_ + faces.cols() > layout_.faces)
    throw InvariantError("write_ply: triangles before every vertex, or more than the " + std::to_string(layout_.faces) +
                         " declared");
  buf_.clear();
  for (Eigen::Index f = 0; f < faces.cols(); ++f) {
    put(buf_, std::uint8_t(3));
    for (int k = 0; k < 3; ++k) put(buf_, std::int32_t(faces(k, f)));
    if (buf_.size() > (1u << 20)) {
      out_.write(buf_.data(), std::streamsize(buf_.size()));
      buf_.clear();
    }
  }
  out_.write(buf_.data(), std::streamsize(buf_.size()));
  faces_ += faces.cols();
}

void PlyWriter::commit() {
  if (vertices_ != layout_.vertices || faces_ != layout_.faces)
    throw InvariantError("write_ply: " + std::to_string(vertices_) + " vertices and " + std::to_string(faces_) +
                         " triangles written, " + std::to_string(layout_.vertices) + " and " +
                         std::to_string(layout_.faces) + " declared");
  if (layout_.viewpoint) {
    buf_.clear();
    for (int k = 0; k < 3; ++k) {
      const double v = (*layout_.viewpoint)(k);
      layout_.real == PlyReal::kFloat64 ? put(buf_, v) : put(buf_, float(v));
    }
    out_.write(buf_.data(), std::streamsize(buf_.size()));
  }
  out_.flush();
  if (!out_) throw IoError(path_.string() + ": write failed (disk full?)");
  out_.close();
  std::error_code ec;
  std::filesystem::rename(tmp_, path_, ec);
  if (ec) throw IoError(path_.string() + ": cannot be written (" + ec.message() + ")");
  committed_ = true;
}

void write_ply(const std::filesystem::path& path, const PointSet& points, const std::vector<PlyProperty>& extra,
               PlyReal real) {
  PlyWriter writer(path, ply_layout(points, extra, real));
  writer.append(points, extra);
  writer.append_faces(points.faces());
  writer.commit();
}

}  // namespace scanfill
