#include "nodes/procedural/castle.h"

#include "nodes/procedural/shapes.h"

namespace scanfill {
namespace {

// Closed box between two corners.
PointSet corner_box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  return make_lowpoly_box(hi - lo, (lo + hi) / 2);
}

void append(PointSet& mesh, const PointSet& more) {
  mesh = mesh.empty() ? more : merged(mesh, more);
}

// Breakpoints of [lo, hi] cut into `cells` equal cells, each with an opening of `open` of its width at its centre:
// lo, o0, c0, o1, c1, ..., hi; the odd intervals are openings.
std::vector<double> opening_breaks(double lo, double hi, int cells, double open) {
  std::vector<double> out{lo};
  const double cell = (hi - lo) / cells;
  for (int c = 0; c < cells; ++c) {
    const double mid = lo + (c + 0.5) * cell;
    out.push_back(mid - open * cell / 2);
    out.push_back(mid + open * cell / 2);
  }
  out.push_back(hi);
  return out;
}

// A slab between lo and hi whose face is spanned by axis b and z, pierced by a rows x cols grid of windows.
void add_pierced_slab(PointSet& mesh, Eigen::Vector3d lo, Eigen::Vector3d hi, int b, int rows, int cols,
                      const CastleStyle& style) {
  const std::vector<double> along = opening_breaks(lo(b), hi(b), cols, cols > 0 ? style.window_width : 0);
  const std::vector<double> up = opening_breaks(lo(2), hi(2), rows, rows > 0 ? style.window_height : 0);
  for (size_t i = 0; i + 1 < along.size(); ++i)
    for (size_t k = 0; k + 1 < up.size(); ++k) {
      if (i % 2 == 1 && k % 2 == 1) continue;  // a window
      if (along[i + 1] <= along[i] || up[k + 1] <= up[k]) continue;
      Eigen::Vector3d a = lo, c = hi;
      a(b) = along[i], c(b) = along[i + 1], a(2) = up[k], c(2) = up[k + 1];
      append(mesh, corner_box(a, c));
    }
}

// `count` merlons along axis b from lo to hi, with gaps as wide as merlons, the first and last at the ends.
void add_merlons(PointSet& mesh, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, int b, int count) {
  const double width = (hi(b) - lo(b)) / std::max(1, 2 * count - 1);
  for (int m = 0; m < count; ++m) {
    Eigen::Vector3d a = lo, c = hi;
    a(b) = lo(b) + 2 * m * width;
    c(b) = a(b) + width;
    append(mesh, corner_box(a, c));
  }
}

// Tower: four pierced sides of thickness shell x size, a roof under the parapet, merlons on each side.
PointSet make_tower(const PartBox& box, const CastleStyle& s) {
  PointSet mesh;
  const Eigen::Vector3d size = box.size();
  const double top = box.max.z() - s.merlon_height * size.z();
  const double roof = 0.05 * size.z();
  append(mesh, corner_box(Eigen::Vector3d(box.min.x(), box.min.y(), top - roof),
                          Eigen::Vector3d(box.max.x(), box.max.y(), top)));
  for (int a = 0; a < 2; ++a)
    for (const int side : {-1, 1}) {
      const int b = 1 - a;
      Eigen::Vector3d lo = box.min, hi = box.max;
      if (side < 0)
        hi(a) = box.min(a) + s.shell * size(a);
      else
        lo(a) = box.max(a) - s.shell * size(a);
      Eigen::Vector3d body_hi = hi;
      body_hi.z() = top;
      add_pierced_slab(mesh, lo, body_hi, b, s.tower_window_rows, s.tower_window_cols, s);
      Eigen::Vector3d merlon_lo = lo;
      merlon_lo.z() = top;
      add_merlons(mesh, merlon_lo, hi, b, s.tower_merlons);
    }
  return mesh;
}

// Wall: one solid slab pierced through its long faces, merlons along its length, full thickness.
PointSet make_wall(const PartBox& box, const CastleStyle& s) {
  PointSet mesh;
  const Eigen::Vector3d size = box.size();
  const int along = size.x() >= size.y() ? 0 : 1;
  const double top = box.max.z() - s.merlon_height * size.z();
  Eigen::Vector3d body_hi = box.max, merlon_lo = box.min;
  body_hi.z() = top;
  merlon_lo.z() = top;
  add_pierced_slab(mesh, box.min, body_hi, along, s.wall_window_rows, s.wall_window_cols, s);
  add_merlons(mesh, merlon_lo, box.max, along, s.wall_merlons);
  return mesh;
}

CastlePart part(bool tower, Eigen::Vector3d lo, Eigen::Vector3d hi) {
  return {{lo, hi}, tower};
}

// The layouts: two exemplars' (keep, fort) and two targets' (gate, bastion) of other part sizes, a wall turned 90
// degrees and another number of towers. Parts touch and do not overlap.
std::optional<std::vector<CastlePart>> castle_layout(const std::string& name) {
  using V = Eigen::Vector3d;
  if (name == "keep")  // two towers and a wall along x
    return std::vector<CastlePart>{part(true, V(-6, -1, 0), V(-4, 1, 6)), part(false, V(-4, -0.5, 0), V(4, 0.5, 4)),
                                   part(true, V(4, -1, 0), V(6, 1, 6))};
  if (name == "fort")  // three towers, walls along x and y
    return std::vector<CastlePart>{part(true, V(-5, -1.5, 0), V(-2, 1.5, 5)),
                                   part(false, V(-2, -0.6, 0), V(4, 0.6, 3.5)), part(true, V(4, -1.5, 0), V(7, 1.5, 5)),
                                   part(false, V(4.9, 1.5, 0), V(6.1, 7.5, 3.5)),
                                   part(true, V(4, 7.5, 0), V(7, 10.5, 5))};
  if (name == "gate")  // three towers of another size, a wall along x and one turned to y
    return std::vector<CastlePart>{
        part(true, V(-5, -1.25, 0), V(-2.5, 1.25, 7)), part(false, V(-2.5, -0.6, 0), V(3.5, 0.6, 4.5)),
        part(true, V(3.5, -1.25, 0), V(6, 1.25, 7)), part(false, V(4.2, 1.25, 0), V(5.3, 8.25, 4.5)),
        part(true, V(3.5, 8.25, 0), V(6, 10.75, 7))};
  if (name == "bastion")  // one broad tower and a long wall along y
    return std::vector<CastlePart>{part(true, V(-2, -2, 0), V(2, 2, 5)), part(false, V(-0.7, 2, 0), V(0.7, 12, 3))};
  return std::nullopt;
}

std::optional<CastleStyle> castle_style(const std::string& name) {
  if (name == "a") return CastleStyle{};
  if (name == "b") {
    CastleStyle b;
    b.tower_window_rows = 1, b.tower_window_cols = 2, b.tower_merlons = 2;
    b.wall_window_rows = 2, b.wall_window_cols = 2, b.wall_merlons = 7;
    b.merlon_height = 0.2, b.shell = 0.2, b.window_width = 0.4, b.window_height = 0.6;
    return b;
  }
  return std::nullopt;
}

const std::vector<std::string>& layout_names() {
  static const std::vector<std::string> names{"keep", "fort", "gate", "bastion"};
  return names;
}

// castle_LAYOUT[_STYLE] split; false when `name` is not of that form.
bool split_castle_name(const std::string& name, std::vector<CastlePart>& layout, std::optional<CastleStyle>& style) {
  if (name.rfind("castle_", 0) != 0) return false;
  const std::string rest = name.substr(7);
  const size_t cut = rest.find('_');
  const auto found = castle_layout(rest.substr(0, cut));
  if (!found) return false;
  layout = *found;
  style.reset();
  if (cut == std::string::npos) return true;
  style = castle_style(rest.substr(cut + 1));
  return bool(style);
}

}  // namespace

PointSet make_castle_part(const CastlePart& part, const CastleStyle& style) {
  return part.tower ? make_tower(part.box, style) : make_wall(part.box, style);
}

PointSet make_castle(const std::vector<CastlePart>& layout, const std::optional<CastleStyle>& style) {
  PointSet mesh;
  for (const CastlePart& p : layout)
    append(mesh, style ? make_castle_part(p, *style) : corner_box(p.box.min, p.box.max));
  return mesh;
}

std::optional<PointSet> make_named_castle(const std::string& name) {
  std::vector<CastlePart> layout;
  std::optional<CastleStyle> style;
  if (!split_castle_name(name, layout, style)) return std::nullopt;
  return make_castle(layout, style);
}

std::optional<PartBoxes> castle_part_boxes(const std::string& name) {
  std::vector<CastlePart> layout;
  std::optional<CastleStyle> style;
  if (!split_castle_name(name, layout, style)) return std::nullopt;
  PartBoxes boxes;
  for (const CastlePart& p : layout) boxes.push_back(p.box);
  return boxes;
}

std::vector<std::string> castle_names() {
  std::vector<std::string> names;
  for (const std::string& layout : layout_names())
    for (const char* suffix : {"", "_a", "_b"}) names.push_back("castle_" + layout + suffix);
  return names;
}

}  // namespace scanfill
