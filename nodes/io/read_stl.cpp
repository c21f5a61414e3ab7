// STL reader, ASCII and binary. STL is a triangle soup: identical corner positions are welded into one vertex so the
// result is an indexed mesh whose point count is the number of distinct corners.
#include <cstring>
#include <unordered_map>

#include "nodes/io/raw_mesh.h"

namespace scanfill::io {
namespace {

struct KeyHash {
  size_t operator()(const std::array<double, 3>& k) const {
    size_t h = 0;
    for (double d : k) {
      std::uint64_t u;
      std::memcpy(&u, &d, 8);
      h ^= std::hash<std::uint64_t>()(u) + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2);
    }
    return h;
  }
};

class Welder {
 public:
  explicit Welder(RawMesh& mesh) : mesh_(mesh) {}
  std::int64_t add(double x, double y, double z) {
    const std::array<double, 3> key{x == 0 ? 0.0 : x, y == 0 ? 0.0 : y, z == 0 ? 0.0 : z};  // -0 == +0
    const auto [it, inserted] = index_.try_emplace(key, std::int64_t(mesh_.xyz.size() / 3));
    if (inserted) mesh_.xyz.insert(mesh_.xyz.end(), key.begin(), key.end());
    return it->second;
  }

 private:
  RawMesh& mesh_;
  std::unordered_map<std::array<double, 3>, std::int64_t, KeyHash> index_;
};

}  // namespace

RawMesh read_stl(const std::filesystem::path& path) {
  const std::string data = read_file(path);
  RawMesh mesh;
  Welder weld(mesh);
  std::uint32_t count = 0;
  if (data.size() >= 84) std::memcpy(&count, data.data() + 80, 4);
  const bool binary = data.size() >= 84 && data.size() == 84 + 50 * std::uint64_t(count);
  if (binary) {
    mesh.encoding = "binary";
    for (std::uint32_t t = 0; t < count; ++t) {
      const char* rec = data.data() + 84 + 50 * size_t(t) + 12;  // skip the facet normal
      for (int c = 0; c < 3; ++c) {
        float v[3];
        std::memcpy(v, rec + 12 * c, 12);
        mesh.faces.push_back(weld.add(v[0], v[1], v[2]));
      }
    }
    return mesh;
  }
  if (data.compare(0, 5, "solid") != 0) {
    if (data.size() >= 84)
      fail(path, "binary STL declares " + std::to_string(count) + " triangles (" +
                     std::to_string(84 + 50 * std::uint64_t(count)) + " bytes) but the file has " +
                     std::to_string(data.size()) + " bytes (truncated?)");
    fail(path, "not an STL file (too short for binary, does not start with 'solid')");
  }
  mesh.encoding = "ascii";
  Tokenizer tok(data.data(), data.data() + data.size());
  int corner = 0;
  for (std::string_view t = tok.next(); !t.empty(); t = tok.next()) {
    if (t == "vertex") {
      double v[3];
      for (double& x : v) {
        const std::string_view n = tok.next();
        if (!parse_double(n, x))
          fail(path, "line " + std::to_string(tok.line()) + ": expected a coordinate, got '" + std::string(n) + "'");
      }
      mesh.faces.push_back(weld.add(v[0], v[1], v[2]));
      ++corner;
    } else if (t == "endfacet") {
      if (corner != 3)
        fail(path,
             "line " + std::to_string(tok.line()) + ": facet with " + std::to_string(corner) + " vertices, expected 3");
      corner = 0;
    }
  }
  if (corner != 0) fail(path, "truncated: the last facet is incomplete");
  if (mesh.faces.empty()) fail(path, "ASCII STL with no facets");
  return mesh;
}

}  // namespace scanfill::io
