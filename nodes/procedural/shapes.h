// Procedural meshes with known geometry: test fixtures with known answers (curvature of a sphere, a cylinder, a
// plane) and the bundled default example (an ornamented vase and its plain cylinder template), so that scanfill runs
// without downloaded data.
#pragma once

#include <cstdint>
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
// The vase's structural template: its body of revolution without flutes or beads.
PointSet make_vase_template(int segments = 192);

// Closed axis-aligned box with the given side lengths, centred at the origin, outward winding; `segments` quads per
// unit length along each side (at least 1 per side).
PointSet make_box(const Eigen::Vector3d& size, int segments_per_unit = 32);
// A sphere of radius 0.5 with `bumps` Gaussian bumps of random size in random directions (seeded): a shape without
// symmetry, with curvature that varies everywhere, for tests whose transform must be unique.
PointSet make_blob(int bumps = 8, std::uint64_t seed = 3, int segments = 128);

// The mesh moved by q (faces kept), and two meshes as one.
PointSet transformed(const PointSet& mesh, const Similarity& q);
PointSet merged(const PointSet& a, const PointSet& b);

// Shape by name ("plane", "sphere", "cylinder", "blob", "vase", "vase_template"), with default sizes; throws InputError
// for an unknown name, listing the valid ones.
PointSet make_shape(const std::string& name);
const std::vector<std::string>& shape_names();

}  // namespace scanfill
