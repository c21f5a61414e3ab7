// Polyline text reading and the writers of nodes/curves/curves.h; read_curves picks the reader by extension.
#include "nodes/curves/curves.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "nodes/core/errors.h"
#include "nodes/io/read_point_set.h"
#include "nodes/io/write_ply.h"

namespace scanfill {
namespace {

std::string slurp(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path.string() + ": cannot open");
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// One "x y" line; false for a line that is not two finite numbers.
bool parse_pair(std::string line, Eigen::Vector2d& p) {
  std::replace(line.begin(), line.end(), ',', ' ');
  std::istringstream s(line);
  std::string extra;
  if (!(s >> p.x() >> p.y()) || (s >> extra)) return false;
  return p.allFinite();
}

void end_curve(std::vector<Eigen::Vector2d>& p, Curves& curves, const std::string& name, int line) {
  if (p.empty()) return;
  if (p.size() < 2) throw IoError(name + ":" + std::to_string(line) + ": a curve needs at least 2 points, got 1");
  Polyline c;
  c.closed = p.size() >= 4 && p.front() == p.back();
  if (c.closed) p.pop_back();
  c.points.resize(2, Eigen::Index(p.size()));
  for (size_t i = 0; i < p.size(); ++i) c.points.col(Eigen::Index(i)) = p[i];
  curves.push_back(std::move(c));
  p.clear();
}

// A number as %g with `digits` significant digits: the same text on every platform and locale-free.
std::string num(double v, int digits = 6) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return buf;
}

std::string path_data(const Polyline& c) {
  std::string d;
  for (Eigen::Index i = 0; i < c.points.cols(); ++i)
    d += (i == 0 ? "M" : " L") + num(c.points(0, i)) + " " + num(c.points(1, i));
  if (c.closed) d += " Z";
  return d;
}

}  // namespace

double curve_length(const Polyline& curve) {
  const Eigen::Index n = curve.points.cols();
  double length = 0;
  for (Eigen::Index i = 0; i + 1 < n; ++i) length += (curve.points.col(i + 1) - curve.points.col(i)).norm();
  if (curve.closed && n > 1) length += (curve.points.col(0) - curve.points.col(n - 1)).norm();
  return length;
}

double drawing_length(const Curves& curves) {
  double length = 0;
  for (const Polyline& c : curves) length += curve_length(c);
  return length;
}

bool is_curve_extension(const std::filesystem::path& path) {
  const std::string ext = lower_extension(path);
  return ext == ".svg" || ext == ".txt" || ext == ".polyline";
}

Curves read_curves(const std::filesystem::path& path) {
  if (!is_curve_extension(path))
    throw IoError(path.string() + ": unknown drawing format '" + path.extension().string() +
                  "' (expected .svg, .txt or .polyline)");
  const std::string text = slurp(path);
  return lower_extension(path) == ".svg" ? parse_svg(text, path.string()) : parse_polylines(text, path.string());
}

Curves parse_polylines(const std::string& text, const std::string& name) {
  Curves curves;
  std::vector<Eigen::Vector2d> points;
  std::istringstream in(text);
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (const size_t hash = line.find('#'); hash != std::string::npos) line.resize(hash);
    if (std::all_of(line.begin(), line.end(), [](unsigned char c) { return std::isspace(c); })) {
      end_curve(points, curves, name, number - 1);
      continue;
    }
    Eigen::Vector2d p;
    if (!parse_pair(line, p))
      throw IoError(name + ":" + std::to_string(number) + ": expected 'x y' (two finite numbers), got '" + line + "'");
    points.push_back(p);
  }
  end_curve(points, curves, name, number);
  if (curves.empty()) throw IoError(name + ": no curves (expected 'x y' lines, a blank line between curves)");
  return curves;
}

void write_polylines(const std::filesystem::path& path, const Curves& curves) {
  std::string out;
  for (size_t k = 0; k < curves.size(); ++k) {
    if (k) out += "\n";
    const Polyline& c = curves[k];
    for (Eigen::Index i = 0; i < c.points.cols(); ++i)
      out += num(c.points(0, i), 9) + " " + num(c.points(1, i), 9) + "\n";
    if (c.closed) out += num(c.points(0, 0), 9) + " " + num(c.points(1, 0), 9) + "\n";
  }
  write_file_atomic(path, out);
}

void write_svg(const std::filesystem::path& path, const std::vector<SvgStroke>& strokes,
               const std::vector<SvgDot>& dots, double dot_radius) {
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(1e300), hi = -lo;
  double width = 0;
  for (const auto& s : strokes) {
    lo = lo.cwiseMin(s.curve.points.rowwise().minCoeff());
    hi = hi.cwiseMax(s.curve.points.rowwise().maxCoeff());
    width = std::max(width, s.width);
  }
  for (const auto& d : dots) lo = lo.cwiseMin(d.at), hi = hi.cwiseMax(d.at);
  if (!(lo.x() <= hi.x())) lo = hi = Eigen::Vector2d::Zero();
  const double margin = 0.05 * std::max((hi - lo).maxCoeff(), 1e-9) + width + dot_radius;
  lo.array() -= margin;
  hi.array() += margin;
  const Eigen::Vector2d size = hi - lo;
  std::string out = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"" +
                    num(lo.x()) + " " + num(lo.y()) + " " + num(size.x()) + " " + num(size.y()) +
                    "\" width=\"800\" height=\"" + num(std::round(800 * size.y() / size.x())) + "\">\n";
  for (const auto& s : strokes)
    out += "<path d=\"" + path_data(s.curve) + "\" fill=\"none\" stroke=\"" + s.colour + "\" stroke-width=\"" +
           num(s.width) + "\" stroke-linejoin=\"round\"/>\n";
  for (const auto& d : dots)
    out += "<circle cx=\"" + num(d.at.x()) + "\" cy=\"" + num(d.at.y()) + "\" r=\"" + num(dot_radius) + "\" fill=\"" +
           d.colour + "\"/>\n";
  out += "</svg>\n";
  write_file_atomic(path, out);
}

}  // namespace scanfill
