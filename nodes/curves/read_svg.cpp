// SVG reader of nodes/curves/curves.h: a minimal tag and attribute tokenizer (no XML library), path data with every
// command of SVG 1.1, transforms, and the basic shapes. Arcs follow the SVG implementation notes (F.6.5 and F.6.6:
// endpoint to centre parameterisation, radii scaled up when too small).
#include <Eigen/Geometry>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <map>
#include <set>

#include "nodes/core/errors.h"
#include "nodes/curves/curves.h"

namespace scanfill {
namespace {

using Affine = Eigen::Matrix<double, 2, 3>;  // x -> A.leftCols<2>() x + A.col(2)

Affine identity_affine() {
  return (Affine() << 1, 0, 0, 0, 1, 0).finished();
}

Affine compose(const Affine& a, const Affine& b) {  // a o b
  Affine out;
  out.leftCols<2>() = a.leftCols<2>() * b.leftCols<2>();
  out.col(2) = a.leftCols<2>() * b.col(2) + a.col(2);
  return out;
}

[[noreturn]] void fail(const std::string& name, const std::string& what) {
  throw IoError(name + ": " + what);
}

// Numbers of a path's data, a points list or a transform's arguments: separators are spaces and commas; "1.5.5" is
// two numbers, "-1-2" too. Arc flags may be written without a separator ("a1 1 0 11 2 3"): flag() reads one digit.
class NumberReader {
 public:
  NumberReader(std::string_view text, const std::string& name, const std::string& what)
      : s_(text), name_(name), what_(what) {}  // keeps a copy: callers pass temporaries
  void skip() {
    while (pos_ < s_.size() && (std::isspace(static_cast<unsigned char>(s_[pos_])) || s_[pos_] == ',')) ++pos_;
  }
  bool at_number() {
    skip();
    if (pos_ >= s_.size()) return false;
    const char c = s_[pos_];
    return std::isdigit(static_cast<unsigned char>(c)) || c == '-' || c == '+' || c == '.';
  }
  bool done() {
    skip();
    return pos_ >= s_.size();
  }
  char peek() {
    skip();
    return pos_ < s_.size() ? s_[pos_] : '\0';
  }
  char take() { return s_[pos_++]; }
  double number() {
    if (!at_number()) fail(name_, what_ + ": expected a number at '" + rest() + "'");
    size_t end = pos_;
    if (s_[end] == '-' || s_[end] == '+') ++end;
    bool dot = false, digits = false;
    for (; end < s_.size(); ++end) {
      const char c = s_[end];
      if (std::isdigit(static_cast<unsigned char>(c))) {
        digits = true;
      } else if (c == '.' && !dot) {
        dot = true;
      } else {
        break;
      }
    }
    if (digits && end < s_.size() && (s_[end] == 'e' || s_[end] == 'E')) {
      size_t e = end + 1;
      if (e < s_.size() && (s_[e] == '-' || s_[e] == '+')) ++e;
      if (e < s_.size() && std::isdigit(static_cast<unsigned char>(s_[e]))) {
        while (e < s_.size() && std::isdigit(static_cast<unsigned char>(s_[e]))) ++e;
        end = e;
      }
    }
    if (!digits) fail(name_, what_ + ": expected a number at '" + rest() + "'");
    const double v = std::stod(s_.substr(pos_, end - pos_));
    pos_ = end;
    if (!std::isfinite(v)) fail(name_, what_ + ": a number is not finite");
    return v;
  }
  bool flag() {
    skip();
    if (pos_ >= s_.size() || (s_[pos_] != '0' && s_[pos_] != '1'))
      fail(name_, what_ + ": expected an arc flag 0 or 1 at '" + rest() + "'");
    return s_[pos_++] == '1';
  }
  Eigen::Vector2d point() {
    const double x = number();
    return {x, number()};
  }
  std::string rest() const { return s_.substr(pos_, 20); }

 private:
  std::string s_;
  size_t pos_ = 0;
  std::string name_, what_;
};

// ---- transforms ----

Affine one_transform(const std::string& op, const std::vector<double>& a, const std::string& name) {
  const auto need = [&](std::initializer_list<size_t> counts) {
    if (std::find(counts.begin(), counts.end(), a.size()) == counts.end())
      fail(name, "transform " + op + "() with " + std::to_string(a.size()) + " arguments");
  };
  Affine m = identity_affine();
  const double deg = M_PI / 180.0;
  if (op == "matrix") {
    need({6});
    m << a[0], a[2], a[4], a[1], a[3], a[5];
  } else if (op == "translate") {
    need({1, 2});
    m.col(2) = Eigen::Vector2d(a[0], a.size() > 1 ? a[1] : 0.0);
  } else if (op == "scale") {
    need({1, 2});
    m(0, 0) = a[0];
    m(1, 1) = a.size() > 1 ? a[1] : a[0];
  } else if (op == "rotate") {
    need({1, 3});
    const double c = std::cos(a[0] * deg), s = std::sin(a[0] * deg);
    m.leftCols<2>() << c, -s, s, c;
    if (a.size() == 3) {
      const Eigen::Vector2d p(a[1], a[2]);
      m.col(2) = p - m.leftCols<2>() * p;
    }
  } else if (op == "skewX") {
    need({1});
    m(0, 1) = std::tan(a[0] * deg);
  } else if (op == "skewY") {
    need({1});
    m(1, 0) = std::tan(a[0] * deg);
  } else {
    fail(name, "unknown transform '" + op + "' (expected matrix, translate, scale, rotate, skewX or skewY)");
  }
  return m;
}

// "translate(10 20) rotate(45)": the product, leftmost outermost.
Affine parse_transform(const std::string& text, const std::string& name) {
  Affine m = identity_affine();
  size_t pos = 0;
  while (true) {
    while (pos < text.size() && (std::isspace(static_cast<unsigned char>(text[pos])) || text[pos] == ',')) ++pos;
    if (pos >= text.size()) break;
    const size_t open = text.find('(', pos), close = text.find(')', pos);
    if (open == std::string::npos || close == std::string::npos || close < open)
      fail(name, "malformed transform '" + text + "'");
    std::string op = text.substr(pos, open - pos);
    op.erase(std::remove_if(op.begin(), op.end(), [](char c) { return std::isspace(static_cast<unsigned char>(c)); }),
             op.end());
    NumberReader r(std::string_view(text).substr(open + 1, close - open - 1), name, "transform " + op);
    std::vector<double> args;
    while (!r.done()) args.push_back(r.number());
    m = compose(m, one_transform(op, args, name));
    pos = close + 1;
  }
  return m;
}

// ---- flattening ----

// Number of segments that keeps a Bezier of these control points within tol of its chords (Wang's formula).
int bezier_segments(const std::vector<Eigen::Vector2d>& c, double tolerance) {
  const double degree = double(c.size() - 1);
  double second = 0, polygon = 0;
  for (size_t i = 0; i + 2 < c.size(); ++i) second = std::max(second, (c[i + 2] - 2 * c[i + 1] + c[i]).norm());
  for (size_t i = 0; i + 1 < c.size(); ++i) polygon += (c[i + 1] - c[i]).norm();
  const double tol = std::max(tolerance * polygon, 1e-12);
  const double n = std::ceil(std::sqrt(degree * (degree - 1) / 8.0 * second / tol));
  return std::clamp(int(n), 1, 4096);
}

Eigen::Vector2d bezier_point(const std::vector<Eigen::Vector2d>& c, double t) {
  std::vector<Eigen::Vector2d> p = c;  // de Casteljau
  for (size_t level = p.size() - 1; level > 0; --level)
    for (size_t i = 0; i < level; ++i) p[i] = (1 - t) * p[i] + t * p[i + 1];
  return p[0];
}

// Appends the Bezier's points after its first control point (the current point).
void flatten_bezier(const std::vector<Eigen::Vector2d>& c, double tolerance, std::vector<Eigen::Vector2d>& out) {
  const int n = bezier_segments(c, tolerance);
  for (int i = 1; i <= n; ++i) out.push_back(bezier_point(c, double(i) / n));
}

// Arc from p0 to p1 with radii r, x-axis rotation phi (degrees) and the two flags (SVG F.6.5); appends the points after
// p0. Degenerate radii give a line.
void flatten_arc(const Eigen::Vector2d& p0, Eigen::Vector2d r, double phi_deg, bool large, bool sweep,
                 const Eigen::Vector2d& p1, std::vector<Eigen::Vector2d>& out) {
  r = r.cwiseAbs();
  if (r.x() == 0 || r.y() == 0 || p0 == p1) {
    if (p0 != p1) out.push_back(p1);
    return;
  }
  const double phi = phi_deg * M_PI / 180.0;
  const Eigen::Matrix2d R = Eigen::Rotation2Dd(phi).toRotationMatrix();
  const Eigen::Vector2d q = R.transpose() * (0.5 * (p0 - p1));
  const double lambda = (q.x() * q.x()) / (r.x() * r.x()) + (q.y() * q.y()) / (r.y() * r.y());
  if (lambda > 1) r *= std::sqrt(lambda);
  const double rx2 = r.x() * r.x(), ry2 = r.y() * r.y();
  const double num = rx2 * ry2 - rx2 * q.y() * q.y() - ry2 * q.x() * q.x();
  const double den = rx2 * q.y() * q.y() + ry2 * q.x() * q.x();
  double k = std::sqrt(std::max(0.0, num / den));
  if (large == sweep) k = -k;
  const Eigen::Vector2d cq(k * r.x() * q.y() / r.y(), -k * r.y() * q.x() / r.x());
  const Eigen::Vector2d centre = R * cq + 0.5 * (p0 + p1);
  const auto angle = [&](const Eigen::Vector2d& v) { return std::atan2(v.y() / r.y(), v.x() / r.x()); };
  const double a0 = angle(q - cq);
  double delta = angle(-q - cq) - a0;
  if (sweep && delta < 0) delta += 2 * M_PI;
  if (!sweep && delta > 0) delta -= 2 * M_PI;
  const int n = std::max(1, int(std::ceil(std::abs(delta) / (M_PI / 90))));  // 2-degree steps
  for (int i = 1; i < n; ++i) {
    const double a = a0 + delta * i / n;
    out.push_back(R * Eigen::Vector2d(r.x() * std::cos(a), r.y() * std::sin(a)) + centre);
  }
  out.push_back(p1);
}

// ---- path data ----

class PathBuilder {
 public:
  PathBuilder(const std::string& name, double tolerance) : name_(name), tolerance_(tolerance) {}
  Curves run(const std::string& d);

 private:
  void command(char cmd, NumberReader& r);
  void move_to(const Eigen::Vector2d& p) {
    finish(false);
    current_ = start_ = p;
    points_ = {p};
  }
  void line_to(const Eigen::Vector2d& p) {
    start_if_needed();
    points_.push_back(p);
    current_ = p;
  }
  void start_if_needed() {
    if (points_.empty()) points_ = {current_};
  }
  void finish(bool closed);

  std::string name_;
  double tolerance_;
  Curves curves_;
  std::vector<Eigen::Vector2d> points_;
  Eigen::Vector2d current_ = Eigen::Vector2d::Zero(), start_ = Eigen::Vector2d::Zero();
  Eigen::Vector2d last_control_ = Eigen::Vector2d::Zero();
  char last_ = 0;
};

void PathBuilder::finish(bool closed) {
  std::vector<Eigen::Vector2d> p;
  for (const auto& q : points_)
    if (p.empty() || (q - p.back()).norm() > 0) p.push_back(q);
  if (closed && p.size() > 1 && (p.back() - p.front()).norm() == 0) p.pop_back();
  if (p.size() >= 2) {
    Polyline c;
    c.points.resize(2, Eigen::Index(p.size()));
    for (size_t i = 0; i < p.size(); ++i) c.points.col(Eigen::Index(i)) = p[i];
    c.closed = closed && p.size() >= 3;
    curves_.push_back(std::move(c));
  }
  points_.clear();
}

void PathBuilder::command(char cmd, NumberReader& r) {
  const bool rel = std::islower(static_cast<unsigned char>(cmd));
  const char up = char(std::toupper(static_cast<unsigned char>(cmd)));
  const Eigen::Vector2d base = rel ? current_ : Eigen::Vector2d::Zero();
  const auto pt = [&] { return Eigen::Vector2d(r.point() + base); };
  // The reflected control point of S and T: only after a command of the same family.
  const bool cubic_before = last_ == 'C' || last_ == 'S', quad_before = last_ == 'Q' || last_ == 'T';
  const Eigen::Vector2d reflected = ((up == 'S' && cubic_before) || (up == 'T' && quad_before))
                                        ? Eigen::Vector2d(2 * current_ - last_control_)
                                        : current_;
  switch (up) {
    case 'M':
      move_to(pt());
      break;
    case 'L':
      line_to(pt());
      break;
    case 'H':
      line_to({r.number() + base.x(), current_.y()});
      break;
    case 'V':
      line_to({current_.x(), r.number() + base.y()});
      break;
    case 'C':
    case 'S': {
      const Eigen::Vector2d c1 = up == 'C' ? pt() : reflected, c2 = pt(), p = pt();
      start_if_needed();
      flatten_bezier({current_, c1, c2, p}, tolerance_, points_);
      last_control_ = c2;
      current_ = p;
      break;
    }
    case 'Q':
    case 'T': {
      const Eigen::Vector2d c1 = up == 'Q' ? pt() : reflected, p = pt();
      start_if_needed();
      flatten_bezier({current_, c1, p}, tolerance_, points_);
      last_control_ = c1;
      current_ = p;
      break;
    }
    case 'A': {
      const Eigen::Vector2d radii = r.point();
      const double phi = r.number();
      const bool large = r.flag(), sweep = r.flag();
      const Eigen::Vector2d p = pt();
      start_if_needed();
      flatten_arc(current_, radii, phi, large, sweep, p, points_);
      current_ = p;
      break;
    }
    default:
      fail(name_, std::string("path data: unknown command '") + cmd + "'");
  }
  last_ = up;
}

Curves PathBuilder::run(const std::string& d) {
  NumberReader r(d, name_, "path data");
  char cmd = 0;
  while (!r.done()) {
    if (std::isalpha(static_cast<unsigned char>(r.peek()))) {
      const bool first = cmd == 0;
      cmd = r.take();
      if (first && cmd != 'M' && cmd != 'm')
        fail(name_, std::string("path data must start with a moveto (M or m), got '") + cmd + "'");
      if (cmd == 'Z' || cmd == 'z') {
        if (!points_.empty()) points_.push_back(start_);
        finish(true);
        current_ = start_;
        last_ = 'Z';
        continue;
      }
    } else if (cmd == 0) {
      fail(name_, "path data must start with a moveto (M or m), got '" + r.rest() + "'");
    } else if (cmd == 'M' || cmd == 'm') {
      cmd = cmd == 'M' ? 'L' : 'l';  // further pairs after a moveto are linetos
    } else if (cmd == 'Z' || cmd == 'z') {
      fail(name_, "path data: numbers after Z at '" + r.rest() + "'");
    }
    command(cmd, r);
  }
  finish(false);
  return std::move(curves_);
}

// ---- elements ----

struct Tag {
  std::string name;
  std::map<std::string, std::string> attributes;
  bool closing = false, self_closing = false;
};

double length_attribute(const Tag& tag, const std::string& key, const std::string& name, double fallback) {
  const auto it = tag.attributes.find(key);
  if (it == tag.attributes.end()) return fallback;
  std::string v = it->second;
  if (v.size() > 2 && v.substr(v.size() - 2) == "px") v.resize(v.size() - 2);
  NumberReader r(v, name, "<" + tag.name + "> " + key);
  const double x = r.number();
  if (!r.done()) fail(name, "<" + tag.name + "> " + key + "='" + it->second + "': only plain numbers and px are read");
  return x;
}

std::string attribute(const Tag& tag, const std::string& key) {
  const auto it = tag.attributes.find(key);
  return it == tag.attributes.end() ? std::string() : it->second;
}

Polyline polygon_of(const std::vector<Eigen::Vector2d>& p, bool closed) {
  Polyline c;
  c.points.resize(2, Eigen::Index(p.size()));
  for (size_t i = 0; i < p.size(); ++i) c.points.col(Eigen::Index(i)) = p[i];
  c.closed = closed;
  return c;
}

std::vector<Eigen::Vector2d> ellipse_points(const Eigen::Vector2d& centre, double rx, double ry, double a0, double a1,
                                            int steps) {
  std::vector<Eigen::Vector2d> p;
  for (int i = 0; i < steps; ++i) {
    const double a = a0 + (a1 - a0) * i / steps;
    p.push_back(centre + Eigen::Vector2d(rx * std::cos(a), ry * std::sin(a)));
  }
  return p;
}

Curves rect_curves(const Tag& t, const std::string& name) {
  const double x = length_attribute(t, "x", name, 0), y = length_attribute(t, "y", name, 0);
  const double w = length_attribute(t, "width", name, 0), h = length_attribute(t, "height", name, 0);
  if (!(w > 0 && h > 0)) return {};  // SVG: a zero-size rect is not rendered
  double rx = length_attribute(t, "rx", name, -1), ry = length_attribute(t, "ry", name, -1);
  if (rx < 0) rx = ry;
  if (ry < 0) ry = rx;
  rx = std::clamp(rx, 0.0, w / 2);
  ry = std::clamp(ry, 0.0, h / 2);
  if (rx == 0 || ry == 0) return {polygon_of({{x, y}, {x + w, y}, {x + w, y + h}, {x, y + h}}, true)};
  std::vector<Eigen::Vector2d> p;  // quarter ellipses at the corners, clockwise on screen from the top right
  const std::pair<Eigen::Vector2d, double> corners[4] = {{{x + w - rx, y + ry}, -M_PI / 2},
                                                         {{x + w - rx, y + h - ry}, 0},
                                                         {{x + rx, y + h - ry}, M_PI / 2},
                                                         {{x + rx, y + ry}, M_PI}};
  for (const auto& [c, a] : corners)
    for (const auto& q : ellipse_points(c, rx, ry, a, a + M_PI / 2, 45)) p.push_back(q);
  return {polygon_of(p, true)};
}

Curves points_curves(const Tag& t, const std::string& name, bool closed) {
  NumberReader r(attribute(t, "points"), name, "<" + t.name + "> points");
  std::vector<Eigen::Vector2d> p;
  while (!r.done()) p.push_back(r.point());
  if (p.size() < 2) return {};
  return {polygon_of(p, closed && p.size() >= 3)};
}

// The curves one drawing element makes, in its own coordinates.
Curves element_curves(const Tag& t, const std::string& name, double tolerance) {
  const auto len = [&](const char* key) { return length_attribute(t, key, name, 0); };
  if (t.name == "path") return PathBuilder(name, tolerance).run(attribute(t, "d"));
  if (t.name == "polyline") return points_curves(t, name, false);
  if (t.name == "polygon") return points_curves(t, name, true);
  if (t.name == "line") return {polygon_of({{len("x1"), len("y1")}, {len("x2"), len("y2")}}, false)};
  if (t.name == "rect") return rect_curves(t, name);
  if (t.name == "circle" || t.name == "ellipse") {
    const double rx = t.name == "circle" ? len("r") : len("rx"), ry = t.name == "circle" ? rx : len("ry");
    if (!(rx > 0 && ry > 0)) return {};
    return {polygon_of(ellipse_points({len("cx"), len("cy")}, rx, ry, 0, 2 * M_PI, 180), true)};
  }
  return {};
}

// ---- tokenizer ----

class TagReader {
 public:
  TagReader(const std::string& text, const std::string& name) : s_(text), name_(name) {}
  // The next element tag; false at the end. Comments, declarations, processing instructions and text are skipped.
  bool next(Tag& tag);

 private:
  void skip_past(const char* end) {
    const size_t e = s_.find(end, pos_);
    if (e == std::string::npos) fail(name_, std::string("unterminated markup (no '") + end + "')");
    pos_ = e + std::strlen(end);
  }
  std::string word() {
    const size_t b = pos_;
    while (pos_ < s_.size() && !std::isspace(static_cast<unsigned char>(s_[pos_])) && s_[pos_] != '>' &&
           s_[pos_] != '/' && s_[pos_] != '=')
      ++pos_;
    return s_.substr(b, pos_ - b);
  }
  void spaces() {
    while (pos_ < s_.size() && std::isspace(static_cast<unsigned char>(s_[pos_]))) ++pos_;
  }
  void attributes(Tag& tag);
  const std::string& s_;
  std::string name_;
  size_t pos_ = 0;
};

void TagReader::attributes(Tag& tag) {
  while (true) {
    spaces();
    if (pos_ >= s_.size()) fail(name_, "unterminated tag <" + tag.name + ">");
    if (s_[pos_] == '>') {
      ++pos_;
      return;
    }
    if (s_.compare(pos_, 2, "/>") == 0) {
      tag.self_closing = true;
      pos_ += 2;
      return;
    }
    const std::string key = word();
    spaces();
    if (key.empty() || pos_ >= s_.size() || s_[pos_] != '=') fail(name_, "malformed attribute in <" + tag.name + ">");
    ++pos_;
    spaces();
    const char quote = pos_ < s_.size() ? s_[pos_] : '\0';
    if (quote != '"' && quote != '\'') fail(name_, "<" + tag.name + "> " + key + ": expected a quoted value");
    const size_t end = s_.find(quote, pos_ + 1);
    if (end == std::string::npos) fail(name_, "<" + tag.name + "> " + key + ": unterminated value");
    tag.attributes[key] = s_.substr(pos_ + 1, end - pos_ - 1);
    pos_ = end + 1;
  }
}

bool TagReader::next(Tag& tag) {
  while (true) {
    pos_ = s_.find('<', pos_);
    if (pos_ == std::string::npos) return false;
    if (s_.compare(pos_, 4, "<!--") == 0) {
      skip_past("-->");
    } else if (s_.compare(pos_, 9, "<![CDATA[") == 0) {
      skip_past("]]>");
    } else if (s_.compare(pos_, 2, "<?") == 0) {
      skip_past("?>");
    } else if (s_.compare(pos_, 2, "<!") == 0) {
      skip_past(">");
    } else {
      break;
    }
  }
  tag = Tag();
  ++pos_;
  if (pos_ < s_.size() && s_[pos_] == '/') {
    tag.closing = true;
    ++pos_;
  }
  tag.name = word();
  if (tag.name.empty()) fail(name_, "malformed tag at offset " + std::to_string(pos_));
  if (tag.closing) {
    skip_past(">");
    return true;
  }
  attributes(tag);
  return true;
}

const std::set<std::string>& drawing_elements() {
  static const std::set<std::string> names{"path", "polyline", "polygon", "line", "rect", "circle", "ellipse"};
  return names;
}

// Elements skipped with everything inside them: they draw nothing themselves.
bool skipped_element(const std::string& n) {
  static const std::set<std::string> names{"defs",           "title",          "desc",   "metadata", "style",
                                           "clipPath",       "mask",           "marker", "pattern",  "symbol",
                                           "linearGradient", "radialGradient", "filter", "script"};
  return names.count(n) || n.find(':') != std::string::npos;
}

}  // namespace

Curves parse_svg(const std::string& text, const std::string& name, double tolerance) {
  TagReader reader(text, name);
  std::vector<std::pair<std::string, Affine>> open;  // containers: name and transform to the root
  Curves curves;
  int skipping = 0;  // depth inside a skipped element
  bool seen_svg = false;
  Tag tag;
  while (reader.next(tag)) {
    if (tag.closing) {
      if (skipping > 0) {
        --skipping;
      } else if (!open.empty()) {
        open.pop_back();
      }
      continue;
    }
    if (skipping > 0 || skipped_element(tag.name)) {
      if (!tag.self_closing) ++skipping;
      continue;
    }
    if (!seen_svg && tag.name != "svg")
      fail(name, "not an SVG file (the first element is <" + tag.name + ">, not <svg>)");
    const Affine parent = open.empty() ? identity_affine() : open.back().second;
    const std::string tr = attribute(tag, "transform");
    const Affine m = tr.empty() ? parent : compose(parent, parse_transform(tr, name));
    if (tag.name == "svg" || tag.name == "g") {
      seen_svg |= tag.name == "svg";
      if (!tag.self_closing) open.push_back({tag.name, m});
      continue;
    }
    if (!drawing_elements().count(tag.name))
      fail(name, "unsupported SVG element <" + tag.name +
                     "> (curves are read from path, polyline, polygon, line, rect, circle and ellipse)");
    for (Polyline& c : element_curves(tag, name, tolerance)) {
      c.points = (m.leftCols<2>() * c.points).colwise() + m.col(2);
      curves.push_back(std::move(c));
    }
    if (!tag.self_closing) open.push_back({tag.name, m});
  }
  if (!seen_svg) fail(name, "not an SVG file (no <svg> element)");
  if (curves.empty())
    fail(name, "no paths: the SVG has no path, polyline, polygon, line, rect, circle or ellipse with a length");
  return curves;
}

}  // namespace scanfill
