#include "nodes/io/read_pp.h"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <sstream>

#include "nodes/core/errors.h"

namespace scanfill {
namespace {

// The value of attribute `name` in one XML tag's text, or nothing.
std::optional<std::string> attribute(const std::string& tag, const std::string& name) {
  for (size_t at = tag.find(name); at != std::string::npos; at = tag.find(name, at + 1)) {
    const bool starts = at > 0 && std::isspace(static_cast<unsigned char>(tag[at - 1]));
    size_t i = at + name.size();
    while (i < tag.size() && std::isspace(static_cast<unsigned char>(tag[i]))) ++i;
    if (!starts || i >= tag.size() || tag[i] != '=') continue;
    ++i;
    while (i < tag.size() && std::isspace(static_cast<unsigned char>(tag[i]))) ++i;
    if (i >= tag.size() || (tag[i] != '"' && tag[i] != '\'')) return std::nullopt;
    const size_t end = tag.find(tag[i], i + 1);
    if (end == std::string::npos) return std::nullopt;
    return tag.substr(i + 1, end - i - 1);
  }
  return std::nullopt;
}

NamedPoint parse_point(const std::string& tag, const std::filesystem::path& path, int index) {
  const std::string where = path.string() + ": point " + std::to_string(index + 1);
  NamedPoint p;
  const char* axes[3] = {"x", "y", "z"};
  for (int k = 0; k < 3; ++k) {
    const auto text = attribute(tag, axes[k]);
    char* end = nullptr;
    const double v = text ? std::strtod(text->c_str(), &end) : NAN;
    if (!text || text->empty() || end != text->c_str() + text->size() || !std::isfinite(v))
      throw IoError(where + ": expected a finite " + axes[k] + "=\"...\"");
    p.position(k) = v;
  }
  const auto name = attribute(tag, "name");
  if (!name || name->empty()) throw IoError(where + ": expected a name=\"...\"");
  p.name = *name;
  return p;
}

}  // namespace

std::vector<NamedPoint> read_picked_points(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path.string() + ": no such file");
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string xml = buffer.str();
  if (xml.find("<PickedPoints") == std::string::npos)
    throw IoError(path.string() + ": not a MeshLab picked-points file (no <PickedPoints>)");
  std::vector<NamedPoint> points;
  int index = 0;
  for (size_t at = xml.find("<point"); at != std::string::npos; at = xml.find("<point", at + 1)) {
    const size_t end = xml.find('>', at);
    if (end == std::string::npos) throw IoError(path.string() + ": a <point> tag is not closed");
    const std::string tag = xml.substr(at, end - at);
    if (tag.size() > 6 && !std::isspace(static_cast<unsigned char>(tag[6]))) continue;  // <points...> or the like
    const NamedPoint p = parse_point(tag, path, index++);
    if (attribute(tag, "active").value_or("1") != "0") points.push_back(p);
  }
  return points;
}

}  // namespace scanfill
