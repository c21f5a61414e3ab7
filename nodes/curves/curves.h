// 2D drawings for mode curves (issue 12; the paper's Figures 2, 6 and 8): polylines in the plane, as read from SVG
// files or plain polyline text, and written back the same ways.
//
// Coordinates are the file's own (SVG user units, y pointing down); the drawing becomes the z = 0 plane of the 3D
// point set the analogy nodes work on (nodes/curves/sample_curves.h).
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

namespace scanfill {

struct Polyline {
  Eigen::Matrix2Xd points;  // 2 by P vertices, P >= 2
  bool closed = false;      // the last vertex joins the first
};
using Curves = std::vector<Polyline>;

// Arc length of a polyline, including the closing segment of a closed one.
double curve_length(const Polyline& curve);
// The total arc length of a drawing.
double drawing_length(const Curves& curves);

// Reads a drawing: .svg (read_svg) or .txt / .polyline (read_polylines), by extension (case-insensitive).
// Throws IoError naming the file for anything unreadable, an unknown extension or a drawing with no curve.
Curves read_curves(const std::filesystem::path& path);

// True for the extensions read_curves accepts.
bool is_curve_extension(const std::filesystem::path& path);

// SVG: <path> (M L H V C S Q T A Z, absolute and relative), <polyline>, <polygon>, <line>, <rect> (rounded corners
// too), <circle>, <ellipse>; `transform` on elements and groups (matrix, translate, scale, rotate, skewX, skewY).
// Curves are flattened to within `tolerance` of the exact curve, relative to each segment's control-polygon length.
// <defs>, <title>, <desc>, <metadata>, <style> and namespaced editor elements are skipped with their content. Any other
// element (<text>, <image>, <use>, ...) throws IoError naming the element and `name`; so does a drawing with no curve.
Curves parse_svg(const std::string& text, const std::string& name, double tolerance = 1e-5);

// Plain polylines: one "x y" pair a line (spaces, tabs or a comma between), a blank line between curves, '#' starts a
// comment. A curve whose last vertex repeats its first is closed. Throws IoError naming `name` and the line.
Curves parse_polylines(const std::string& text, const std::string& name);

// Writers, atomic (a temporary file renamed into place). Throw IoError naming the file.
// write_polylines: the format parse_polylines reads (a closed curve repeats its first vertex at the end).
void write_polylines(const std::filesystem::path& path, const Curves& curves);

// An SVG that opens in any browser: each curve a <path> in its colour, framed by a viewBox around all curves plus a
// margin; `dots` (optional) adds a small disc per point, in its own colour (analogy.svg's coloured samples).
struct SvgStroke {
  Polyline curve;
  std::string colour = "#000000";  // CSS colour
  double width = 1.0;              // stroke width, model units
};
struct SvgDot {
  Eigen::Vector2d at;
  std::string colour;
};
void write_svg(const std::filesystem::path& path, const std::vector<SvgStroke>& strokes,
               const std::vector<SvgDot>& dots, double dot_radius);

}  // namespace scanfill
