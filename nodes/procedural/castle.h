// Procedural castles for style exchange (issue 12, configs/exchange_castles.yaml): a layout is a list of parts (towers
// and walls), each an axis-aligned box; a style says how a part is detailed (window grid, merlons, shell thickness),
// every length relative to the part's own box, so that the box map of a styled part onto another box is that part
// styled in the other box. The styled target of an exchange is therefore the same generator on the target's layout:
// the known answer. Every detail stays inside its part's box, so the bounding box of a part's geometry is its box.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "nodes/core/point_set.h"
#include "nodes/exchange/part_box.h"

namespace scanfill {

struct CastlePart {
  PartBox box;
  bool tower = false;  // a tower (windows on four sides, a roof) or a wall (windows through its long faces)
};

struct CastleStyle {
  int tower_window_rows = 2, tower_window_cols = 1, tower_merlons = 3;  // per side of a tower
  int wall_window_rows = 1, wall_window_cols = 3, wall_merlons = 5;     // along each long side of a wall
  double merlon_height = 0.15;  // share of the part's height taken by the merlons
  double shell = 0.15;          // a tower's side thickness, share of its size across the side
  double window_width = 0.5;    // share of a window cell's width that is open
  double window_height = 0.5;   // share of a window cell's height that is open
};

// A part detailed in `style`: a mesh of closed boxes inside part.box.
PointSet make_castle_part(const CastlePart& part, const CastleStyle& style);
// Every part detailed in `style`, or (without a style) each part a plain box.
PointSet make_castle(const std::vector<CastlePart>& layout, const std::optional<CastleStyle>& style);

// The bundled castles, by procedural name: castle_LAYOUT (plain boxes) or castle_LAYOUT_STYLE, LAYOUT one of keep,
// fort, gate, bastion and STYLE a or b. Nothing when `name` is none of them.
std::optional<PointSet> make_named_castle(const std::string& name);
// The part boxes of a named castle (its layout), or nothing.
std::optional<PartBoxes> castle_part_boxes(const std::string& name);
// Every named castle.
std::vector<std::string> castle_names();

}  // namespace scanfill
