// Procedural meshes with known geometry: test fixtures with known answers (curvature of a sphere, a cylinder, a
// plane) and the bundled default example (an ornamented vase and its plain cylinder template), so that scanfill runs
// without downloaded data.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "nodes/core/point_set.h"
#include "nodes/core/similarity.h"

namespace scanfill {

// Square in the z = 0 plane, side `size`, centred at the origin, normals +z; `segments` quads per side.
PointSet make_plane(double size, int segments);
// Sphere of `radius` at the origin, latitude-longitude triangulation, outward winding.
PointSet make_sphere(double radius, int segments);
// Open cylinder of `radius` and `height` along z, centred at the origin, outward winding.
PointSet make_cylinder(double radius, double height, int segments);
// Ornamented vase, axis z, base at z = 0, height 1: a body of revolution with `flutes` vertical grooves, a rolled rim,
// and a ring of `beads` spheres around the foot. The structure the analogy finds: repeated flutes and beads.
PointSet make_vase(int flutes = 12, int beads = 16, int segments = 192);
// The vase as a vessel: its ornamented outer wall, an inner wall 3 cm in (a plain body of revolution, faces turned to
// the axis), a rim joining them at the top, a floor 3 cm thick closing the foot, and the beads. Seen from above, a
// scanner sees its inside through the mouth, as it does a real vase's; the vase itself is one open sheet.
PointSet make_cup(int segments = 192);
// The vase's structural template: its body of revolution without flutes or beads.
PointSet make_vase_template(int segments = 192);
// The vase's plainest template: a closed cylinder of its height standing on z = 0, radius 0.33 (the vase's profile
// runs 0.28-0.40 about it), drawn with `segments` sides.
PointSet make_vase_cylinder(int segments = 128);

// Closed axis-aligned box with the given side lengths, centred at the origin, outward winding; `segments` quads per
// unit length along each side (at least 1 per side).
PointSet make_box(const Eigen::Vector3d& size, int segments_per_unit = 32);
// A sphere of radius 0.5 with `bumps` Gaussian bumps of random size in random directions (seeded): a shape without
// symmetry, with curvature that varies everywhere, for tests whose transform must be unique.
PointSet make_blob(int bumps = 8, std::uint64_t seed = 3, int segments = 128);

// Closed prism along z from z = z0 to z0 + height whose cross-section has radius r(phi) (wall plus two caps): the
// building block of the end-to-end fixtures below.
PointSet make_prism(const std::function<double(double)>& radius, double z0, double height, int segments);
// A fluted column (radius 0.3, height 1.2, base at z = 0, `flutes` grooves along its whole height, closed), and its
// template: the plain closed cylinder.
PointSet make_column(int flutes = 16);
PointSet make_column_template();
// A gear (radius 0.45 with `teeth` teeth 0.06 high, 0.15 thick, base at z = 0), and its template: the plain disk.
PointSet make_gear(int teeth = 20);
PointSet make_gear_template();
// A table (top 1 x 0.6 x 0.06 at height 0.7, four turned legs with beads and rings), and its template: the same top
// on four plain cylindrical legs.
PointSet make_table();
PointSet make_table_template();
// A long table (top 1.8 x 0.6, six turned legs) and its plain template: the structurally different target of the
// furniture transfer example.
PointSet make_bench();
PointSet make_bench_template();

// Low-poly templates as users draw them: a box of 8 vertices and 12 triangles, and a closed cylinder with `sides`
// wall quads and fan caps (base at z0).
PointSet make_lowpoly_box(const Eigen::Vector3d& size, const Eigen::Vector3d& centre);
PointSet make_lowpoly_cylinder(double radius, double z0, double height, int sides);
// A crate (0.6 x 0.6 x 0.8, base at z = 0) with the same relief on its four sides (a raised frame and a diamond), and
// its template: the plain box of 8 vertices. Only quarter turns about z carry one side's relief to another.
PointSet make_crate();
PointSet make_crate_template();
// A box that is not square (0.8 x 0.5 x 0.6, base at z = 0) whose four sides carry raised vertical ribs every 0.1,
// centred on each side, above a raised plinth band; top and bottom plain. Its template is the plain 8-vertex box.
PointSet make_ribbed_box();
PointSet make_ribbed_box_template();
// A ring lying on z = 0 (a torus, radius 0.3 about z, tube radius 0.06) with 20 round beads on its outer equator, and
// with `beads` false its template: the plain torus. Its unseen underside is the seen top turned end over end.
PointSet make_beaded_ring(bool beads);
// A triangular prism standing on z = 0 (circumradius 0.4, height 0.9, a vertex at +x) with a round medallion and two
// bands on each side, and with `relief` false its template, the 6-vertex prism: its turns by a third (about its
// centroid, not its bounding box's centre) carry a side onto the others. With `sides` 6, a hexagonal prism (shape
// names medallion_prism6 and prism_template6): a polygon that is the object's own shape, not a drawing of a round one.
PointSet make_medallion_prism(bool relief, int sides = 3);
// A barrel standing on z = 0 (height 1, radius 0.4 at its ends and 0.5 at mid-height) with a round medallion at each
// quarter turn, and with `relief` false its template, the plain barrel. Its scan does not repeat about its axis from
// below, where the medallions' upper halves go unseen; only quarter turns carry one medallion onto another.
PointSet make_medallion_barrel(bool relief);
// Two plain disks (the gear's template) side by side, the second scaled by `second_scale`: the target of the two-body
// transfers (S = one disk, E = the gear); with `gears`, the two gears: the styled target those transfers should give.
PointSet make_disk_pair(double second_scale, bool gears);

// The axis of a body of revolution: a point on it and its unit direction.
struct RevolutionAxis {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction = Eigen::Vector3d::UnitZ();
};

// The axis about which a model is most nearly a body of revolution: of z, x, y and the model's principal axes, each
// through the centre of its bounding box, the one whose rings' radii vary least (z where it fits within 5% of the
// best, as the procedural shapes and the virtual scanner assume). Many meshes are drawn y-up. The axis the model's
// normals meet (normal_axis.h) instead where they meet it more than twice as nearly, or where the model is seen from
// one side (fewer than 3/4 of 64 sectors about that axis hold a quarter of an even share of its points) and they meet
// it no more than 25% worse: one view of a vase, whose bounding box's centre lies off its axis.
RevolutionAxis revolution_axis(const PointSet& model, int rings = 128);

// The body of revolution about the model's revolution_axis that best fits it: per height, the median distance of its
// points from the axis, smoothed; a tube from the lowest to the highest point along the axis, closed at an end by a
// flat cap (outward normal along the axis) where the model is closed there: where its surface in the last 2% of the
// height covers the end's disk (a candle's bottom, a vase's floor), not at a vase's mouth. The plain structural
// template of a vase-like scan (relief, beads and handles averaged away).
PointSet make_revolution(const PointSet& model, int rings = 128, int segments = 256);
// The same about a given axis.
PointSet make_revolution(const PointSet& model, const RevolutionAxis& axis, int rings = 128, int segments = 256);

// make_revolution's body, its axis, and how far the body is from the model: the mean distance of the body's vertices
// from the model's nearest point, relative to the model's mean distance from the axis; only the vertices in the
// sectors about the axis (of 64) where the model has points, so that one view's body is not scored on the side it
// did not see. Where the model is round, the
// body lies on it: 0.01 for the teapot and the gear, 0.03-0.04 for the text2mesh vase and candle, 0.10 for the
// Vase-Lion (not round in section, 0.73 by 0.60). Where it is not, the body spreads over space the model leaves empty:
// 0.50 for the text2mesh lamp (three arms), 0.28 for the bunny, 0.21 for the four-legged table. (The model's points'
// distance from the body does not tell these apart: the lamp's is 0.15, the Vase-Lion's 0.12.) The profile points are
// drawn once.
struct RevolutionFit {
  PointSet body;
  RevolutionAxis axis;
  double misfit = 0;
};
RevolutionFit fit_revolution(const PointSet& model, int rings = 128, int segments = 256);

// The mesh moved by q (faces kept), and two meshes as one.
PointSet transformed(const PointSet& mesh, const Similarity& q);
PointSet merged(const PointSet& a, const PointSet& b);

// Shape by name ("plane", "sphere", "cylinder", "blob", "vase", "vase_template"), with default sizes; throws InputError
// for an unknown name, listing the valid ones.
PointSet make_shape(const std::string& name);
const std::vector<std::string>& shape_names();

}  // namespace scanfill
