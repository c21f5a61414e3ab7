#include "nodes/io/write_ply.h"

#include <unistd.h>

#include <atomic>
#include <bit>
#include <cstring>
#include <fstream>
#include <sstream>

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

void write_ply(const std::filesystem::path& path, const PointSet& points, const std::vector<PlyProperty>& extra,
               PlyReal real) {
  const bool exact = real == PlyReal::kFloat64;
  const std::string r = exact ? "property double " : "property float ";
  const auto put_real = [exact](std::string& buf, double v) { exact ? put(buf, v) : put(buf, float(v)); };
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
  std::ostringstream header;
  header << "ply\nformat binary_little_endian 1.0\ncomment written by scanfill\n";
  header << "element vertex " << n << "\n" << r << "x\n" << r << "y\n" << r << "z\n";
  if (points.has_normals()) header << r << "nx\n" << r << "ny\n" << r << "nz\n";
  if (points.has_curvatures()) header << r << "k1\n" << r << "k2\n";
  if (points.has_directions()) header << r << "d1x\n" << r << "d1y\n" << r << "d1z\n";
  for (const PlyProperty& p : extra) {
    const char* type = p.type == PlyProperty::Type::kUint8   ? "uchar"
                       : p.type == PlyProperty::Type::kInt32 ? "int"
                                                             : "float";
    header << "property " << type << " " << p.name << "\n";
  }
  if (points.has_colours()) header << "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  if (points.has_intensity()) header << "property float intensity\n";
  if (points.has_faces())
    header << "element face " << points.faces().cols() << "\nproperty list uchar int vertex_indices\n";
  header << "end_header\n";

  write_atomic(path, [&](std::ofstream& out) {
    const std::string h = header.str();
    out.write(h.data(), std::streamsize(h.size()));
    std::string buf;
    constexpr Index kChunk = 1 << 16;
    for (Index start = 0; start < n; start += kChunk) {
      buf.clear();
      for (Index i = start; i < std::min(n, start + kChunk); ++i) {
        for (int k = 0; k < 3; ++k) put_real(buf, points.positions()(k, i));
        if (points.has_normals())
          for (int k = 0; k < 3; ++k) put_real(buf, points.normals()(k, i));
        if (points.has_curvatures())
          for (int k = 0; k < 2; ++k) put_real(buf, points.curvatures()(k, i));
        if (points.has_directions())
          for (int k = 0; k < 3; ++k) put_real(buf, points.directions()(k, i));
        for (const PlyProperty& p : extra) {
          const double v = p.values[size_t(i)];
          switch (p.type) {
            case PlyProperty::Type::kUint8:
              put(buf, std::uint8_t(v));
              break;
            case PlyProperty::Type::kInt32:
              put(buf, std::int32_t(v));
              break;
            case PlyProperty::Type::kFloat32:
              put(buf, float(v));
              break;
          }
        }
        if (points.has_colours())
          for (int k = 0; k < 3; ++k) put(buf, points.colours()(k, i));
        if (points.has_intensity()) put(buf, points.intensity()(i));
      }
      out.write(buf.data(), std::streamsize(buf.size()));
    }
    buf.clear();
    for (Eigen::Index f = 0; f < points.faces().cols(); ++f) {
      put(buf, std::uint8_t(3));
      for (int k = 0; k < 3; ++k) put(buf, std::int32_t(points.faces()(k, f)));
      if (buf.size() > (1u << 20)) {
        out.write(buf.data(), std::streamsize(buf.size()));
        buf.clear();
      }
    }
    out.write(buf.data(), std::streamsize(buf.size()));
  });
}

}  // namespace scanfill
