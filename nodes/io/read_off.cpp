// OFF reader: OFF, NOFF (normals after each vertex), COFF/CNOFF (colours, ignored); counts on the keyword line or the
// next; '#' comments; n-gon faces with optional trailing colour.
#include <cmath>

#include "nodes/io/raw_mesh.h"

namespace scanfill::io {

RawMesh read_off(const std::filesystem::path& path) {
  std::string data = read_file(path);
  // Strip comments so the tokenizer sees only numbers after the keyword.
  for (size_t i = 0; i < data.size(); ++i) {
    if (data[i] == '#')
      while (i < data.size() && data[i] != '\n') data[i++] = ' ';
  }
  RawMesh mesh;
  mesh.encoding = "ascii";
  Tokenizer tok(data.data(), data.data() + data.size());
  const std::string key(tok.next());
  if (key.size() < 3 || key.compare(key.size() - 3, 3, "OFF") != 0)
    fail(path, "not an OFF file (expected the keyword OFF, got '" + key + "')");
  if (key.find("4") != std::string::npos || key.find("n") == 0)
    fail(path, "OFF variant '" + key + "' (4-D or n-D) is not supported");
  const bool normals = key.find('N') != std::string::npos;
  const bool colours = key.find('C') != std::string::npos;
  if (key.find("ST") != std::string::npos)
    fail(path, "OFF variant '" + key + "' (texture coordinates) is not supported");
  std::int64_t counts[3];
  for (auto& c : counts) {
    const std::string_view t = tok.next();
    if (!parse_int(t, c) || c < 0) fail(path, "expected vertex, face and edge counts, got '" + std::string(t) + "'");
  }
  auto number = [&](const char* what, std::int64_t index) {
    const std::string_view t = tok.next();
    double v;
    if (t.empty())
      fail(path, std::string("truncated: ") + what + " " + std::to_string(index) + " of " +
                     std::to_string(what[0] == 'v' ? counts[0] : counts[1]) + " is missing");
    if (!parse_double(t, v))
      fail(path, "line " + std::to_string(tok.line()) + ": '" + std::string(t) + "' is not a number");
    return v;
  };
  // The counts against the bytes left, before anything is allocated: a value takes at least one character and a
  // separator (the last may lack it); a vertex has 3, 6, 7 or 10 values, a face at least its size.
  const std::uint64_t values = 3 + (normals ? 3 : 0) + (colours ? 4 : 0);
  const std::uint64_t room = (tok.remaining() + 1) / 2;  // values the rest of the file can hold
  if (std::uint64_t(counts[0]) > room / values)
    fail(path, "truncated: the header declares " + std::to_string(counts[0]) + " vertices, more than the " +
                   std::to_string(tok.remaining()) + " bytes after it can hold");
  if (std::uint64_t(counts[1]) > room - std::uint64_t(counts[0]) * values)
    fail(path, "truncated: the header declares " + std::to_string(counts[1]) + " faces, more than the " +
                   std::to_string(tok.remaining()) + " bytes after it can hold");
  mesh.xyz.reserve(size_t(counts[0]) * 3);
  for (std::int64_t i = 0; i < counts[0]; ++i) {
    for (int k = 0; k < 3; ++k) mesh.xyz.push_back(number("vertex", i));
    if (normals)
      for (int k = 0; k < 3; ++k) mesh.normals.push_back(number("vertex", i));
    if (colours)
      for (int k = 0; k < 4; ++k) number("vertex", i);  // RGBA, ignored
  }
  std::vector<std::int64_t> corners;
  std::int64_t skipped = 0;
  for (std::int64_t f = 0; f < counts[1]; ++f) {
    const std::string_view size_token = tok.next();
    const int line = tok.line();
    std::int64_t n = 0;
    if (size_token.empty())
      fail(path, "truncated: face " + std::to_string(f) + " of " + std::to_string(counts[1]) + " is missing");
    if (!parse_int(size_token, n) || n < 0)
      fail(path, "line " + std::to_string(line) + ": invalid face size '" + std::string(size_token) + "'");
    if (std::uint64_t(n) > (tok.remaining() + 1) / 2)
      fail(path, "line " + std::to_string(line) + ": face " + std::to_string(f) + " declares " + std::to_string(n) +
                     " vertices, more than the rest of the file holds");
    corners.resize(static_cast<size_t>(n));
    for (auto& c : corners) {
      const double v = number("face", f);
      if (!(v >= -9e15 && v <= 9e15) || v != std::floor(v))  // NaN, fractions and the unrepresentable
        fail(path, "line " + std::to_string(tok.line()) + ": face " + std::to_string(f) + " has a vertex index '" +
                       short_number(v) + "' that is not an integer");
      c = std::int64_t(v);
    }
    // A face may carry a colour on the same line: skip to the end of that line.
    while (!tok.at_end() && tok.line() == line) tok.next();
    if (!add_polygon(mesh.faces, corners.data(), corners.size())) ++skipped;
  }
  if (skipped) mesh.warnings.push_back(std::to_string(skipped) + " faces with fewer than 3 vertices were skipped");
  return mesh;
}

}  // namespace scanfill::io
