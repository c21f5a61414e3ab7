// XYZ reader: one point per line, "x y z" or "x y z nx ny nz", separated by spaces, tabs or commas; '#' comments.
// Every data line must have the same number of columns. Columns 4-6 are taken as normals when they are unit vectors;
// otherwise as colours "r g b" (as CloudCompare and MeshLab export them) when every value lies in [0, 255]: [0, 1]
// floats when none exceeds 1 (scaled by 255), else [0, 255] (rounded); anything else is ignored with a warning.
#include <algorithm>
#include <cmath>

#include "nodes/io/raw_mesh.h"

namespace scanfill::io {

RawMesh read_xyz(const std::filesystem::path& path) {
  std::string data = read_file(path);
  RawMesh mesh;
  mesh.encoding = "ascii";
  for (char& c : data)
    if (c == ',' || c == ';') c = ' ';
  size_t pos = 0;
  int line_no = 0, columns = -1;
  std::vector<double> extra;
  while (pos < data.size()) {
    size_t eol = data.find('\n', pos);
    if (eol == std::string::npos) eol = data.size();
    Tokenizer tok(data.data() + pos, data.data() + eol);
    pos = eol + 1;
    ++line_no;
    double v[6];
    int n = 0;
    for (std::string_view t = tok.next(); !t.empty(); t = tok.next()) {
      if (t[0] == '#') break;
      if (n == 6) fail(path, "line " + std::to_string(line_no) + ": more than 6 columns (expected x y z [nx ny nz])");
      if (!parse_double(t, v[n]))
        fail(path, "line " + std::to_string(line_no) + ": '" + std::string(t) + "' is not a number");
      ++n;
    }
    if (n == 0) continue;
    if (n != 3 && n != 6)
      fail(path, "line " + std::to_string(line_no) + ": " + std::to_string(n) + " columns (expected x y z [nx ny nz])");
    if (columns < 0) columns = n;
    if (n != columns)
      fail(path, "line " + std::to_string(line_no) + ": " + std::to_string(n) + " columns where earlier lines have " +
                     std::to_string(columns));
    mesh.xyz.insert(mesh.xyz.end(), v, v + 3);
    if (n == 6) extra.insert(extra.end(), v + 3, v + 6);
  }
  if (columns == 6) {
    bool unit = true;
    for (size_t i = 0; i + 2 < extra.size() && unit; i += 3)
      unit = std::abs(std::sqrt(extra[i] * extra[i] + extra[i + 1] * extra[i + 1] + extra[i + 2] * extra[i + 2]) - 1) <
             0.1;
    bool colour_range = true;
    double largest = 0;
    for (const double v : extra) {
      colour_range = colour_range && v >= 0 && v <= 255;  // false for NaN too
      largest = std::max(largest, v);
    }
    if (unit) {
      mesh.normals = std::move(extra);
    } else if (colour_range) {
      const double scale = largest <= 1 ? 255.0 : 1.0;
      mesh.colours.reserve(extra.size());
      for (const double v : extra) mesh.colours.push_back(std::uint8_t(std::round(v * scale)));
    } else {
      mesh.warnings.push_back(path.string() +
                              ": columns 4-6 are neither unit normals nor colours in [0, 255] and were ignored");
    }
  }
  return mesh;
}

}  // namespace scanfill::io
