// Wavefront OBJ reader: v, vn and f (any of v, v/vt, v//vn, v/vt/vn; negative indices count back from the end).
// Other statements (vt, g, o, s, usemtl, mtllib, l, p...) are read past. A vertex gets the normal of the first face
// corner that names one; normals are kept only when every vertex gets one. Vertex colours "v x y z r g b" (the
// extension MeshLab and CloudCompare write, [0, 1] floats) are kept when every vertex has them.
#include <algorithm>
#include <cmath>

#include "nodes/io/raw_mesh.h"

namespace scanfill::io {

RawMesh read_obj(const std::filesystem::path& path) {
  const std::string data = read_file(path);
  RawMesh mesh;
  mesh.encoding = "ascii";
  std::vector<double> vn;
  std::vector<std::int64_t> vertex_normal;  // per vertex: index into vn, or -1
  std::vector<std::int64_t> corners, corner_normals;
  std::int64_t skipped_faces = 0, coloured = 0;
  size_t pos = 0;
  int line_no = 0;
  while (pos < data.size()) {
    size_t eol = data.find('\n', pos);
    if (eol == std::string::npos) eol = data.size();
    const char* b = data.data() + pos;
    const char* e = data.data() + eol;
    pos = eol + 1;
    ++line_no;
    Tokenizer tok(b, e);
    const std::string_view key = tok.next();
    auto where = [&] { return "line " + std::to_string(line_no) + ": "; };
    if (key == "v" || key == "vn") {
      double c[3];
      for (double& x : c) {
        const std::string_view t = tok.next();
        if (!parse_double(t, x))
          fail(path, where() + "expected 3 numbers after '" + std::string(key) + "', got '" + std::string(t) + "'");
      }
      auto& dst = key == "v" ? mesh.xyz : vn;
      dst.insert(dst.end(), c, c + 3);
      if (key == "v") {
        vertex_normal.push_back(-1);
        // Three more numbers are a colour; one more (a homogeneous w) or none is not.
        double rgb[3];
        int n = 0;
        for (std::string_view t = tok.next(); !t.empty() && n < 4; t = tok.next())
          n += n < 3 && parse_double(t, rgb[n]) ? 1 : 4;
        const bool colour = n == 3;
        if (colour && coloured == std::int64_t(mesh.xyz.size() / 3) - 1) {
          for (const double c : rgb)
            mesh.colours.push_back(std::isfinite(c) ? std::uint8_t(std::clamp(std::round(255 * c), 0.0, 255.0)) : 0);
          ++coloured;
        }
      }
    } else if (key == "f") {
      corners.clear();
      corner_normals.clear();
      const auto nv = std::int64_t(mesh.xyz.size() / 3), nn = std::int64_t(vn.size() / 3);
      for (std::string_view t = tok.next(); !t.empty(); t = tok.next()) {
        const size_t s1 = t.find('/');
        std::int64_t v = 0, n = 0;
        if (!parse_int(t.substr(0, s1), v) || v == 0) fail(path, where() + "bad face corner '" + std::string(t) + "'");
        if (s1 != std::string_view::npos) {
          const size_t s2 = t.find('/', s1 + 1);
          if (s2 != std::string_view::npos && s2 + 1 < t.size() && !parse_int(t.substr(s2 + 1), n))
            fail(path, where() + "bad normal index in face corner '" + std::string(t) + "'");
        }
        v = v > 0 ? v - 1 : nv + v;  // 1-based, or relative to the vertices read so far
        n = n > 0 ? n - 1 : n < 0 ? nn + n : -1;
        if (v < 0 || v >= nv)
          fail(path, where() + "face corner '" + std::string(t) + "' names vertex " + std::to_string(v + 1) +
                         ", but only " + std::to_string(nv) + " vertices are defined before it");
        if (n >= nn) fail(path, where() + "face corner '" + std::string(t) + "' names a missing normal");
        corners.push_back(v);
        corner_normals.push_back(n);
      }
      if (!add_polygon(mesh.faces, corners.data(), corners.size())) ++skipped_faces;
      for (size_t k = 0; k < corners.size(); ++k)
        if (corner_normals[k] >= 0 && vertex_normal[size_t(corners[k])] < 0)
          vertex_normal[size_t(corners[k])] = corner_normals[k];
    }
  }
  const bool all_normals = !vertex_normal.empty() && !vn.empty() &&
                           std::none_of(vertex_normal.begin(), vertex_normal.end(), [](auto i) { return i < 0; });
  if (all_normals) {
    mesh.normals.reserve(mesh.xyz.size());
    for (const auto i : vertex_normal)
      mesh.normals.insert(mesh.normals.end(), &vn[size_t(3 * i)], &vn[size_t(3 * i + 3)]);
  }
  if (coloured != std::int64_t(mesh.xyz.size() / 3)) mesh.colours.clear();
  if (skipped_faces > 0)
    mesh.warnings.push_back(std::to_string(skipped_faces) + " faces with fewer than 3 vertices were skipped");
  return mesh;
}

}  // namespace scanfill::io
