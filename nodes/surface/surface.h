// surface node: a triangle mesh through a completion's points (issue 14; the engine gives it the synthesis' samples),
// by Poisson surface reconstruction (Kazhdan, Bolitho, Hoppe 2006) as PCL's surface module implements it (pcl::Poisson,
// BSD; not CGAL's GPL parts).
//
// 1. The points are thinned to about `max_points` on a voxel grid (per voxel the point nearest its centre): Poisson's
//    cost grows with the points and the octree, while its accuracy is set by `depth`; a completion's output has
//    10^5 - 10^6 points (its samples 2-5x10^4) and the mesh needs far fewer to be as close to the surface.
//    The defaults (depth 6, 10^4 points) are the cheapest that keep the vase example's F-score: measured on it, the
//    surface scores F 0.980 against the vase as its 168 k points do (0.980), in 0.7-1 s; depth 7 with 2.5x10^4
//    points scores 0.986 in 2.5-3.5 s, more than the example's 10 s budget leaves (README, Performance).
// 2. pcl::Poisson<PointNormal> at `depth` with `samples_per_node`, on one thread: PCL's Poisson parallelises with
//    OpenMP, and scanfill keeps one threading runtime (TBB, DESIGN section 6); one thread also makes the mesh the same
//    bytes whatever the run's thread count. It is not reentrant (PoissonRecon keeps static state), so calls are
//    serialised. PoissonRecon 4 reports iso-surface edges it cannot pair with printf on stdout ("Vertex pair not in
//    list 2 ..." from GetMCIsoEdges, compiled into libpcl_surface; the branch prints when the pair *is* in its map, the
//    mirror of branch 1's test, and then leaves that iso-curve unclosed). It happens on some inputs only (points whose
//    normals disagree: tens of lines; on clean inputs a few lines or none, and which ones varies from machine to
//    machine), is unconditional inside PCL and cannot be switched off, so stdout (fd 1) is captured around the call
//    (StdoutCapture in surface.cpp): PoissonRecon's lines become `diagnostics` and a warning, anything else written
//    meanwhile is passed on to the real stdout after the call.
// 3. Trimming: Poisson returns a closed surface and closes every hole (an open top, an unseen underside) with a smooth
//    blob. A triangle is dropped when one of its corners lies farther than `trim_distance` spacings from the nearest
//    thinned point; the vertices no triangle uses go too. A point's spacing is the side of the patch of surface it
//    stands for, sqrt(pi r^2 / 8) with r the distance to its 8th nearest neighbour, floored at the median spacing
//    (clustered points, as in merged patches, do not trim the surface around them). A distance test rather than
//    PoissonRecon's density trimming: PCL 1.13's Poisson (PoissonRecon 4) reports no per-vertex density.
// 4. Vertex normals: area-weighted face normals, the whole mesh flipped when they disagree with the points' normals.
#pragma once

#include <string>
#include <vector>

#include "nodes/core/point_set.h"

namespace scanfill {

struct SurfaceOptions {
  int depth = 6;                  // Poisson octree depth: the grid is at most 2^depth cells a side; [4, 12]
  double samples_per_node = 1.5;  // least points per octree leaf: more smooths noise, less follows detail; [1, 20]
  Index max_points = 10000;       // the points are voxel-thinned to about this many before meshing; >= 100
  double trim_distance = 2.5;     // drop triangles with a corner farther than this, in spacings, from the points; > 0
};

struct SurfaceResult {
  PointSet mesh;               // positions, normals, faces (3 by F triangles)
  Index points_meshed = 0;     // points given to Poisson after thinning
  double spacing = 0;          // their median spacing (sqrt of the surface area per point), model units
  Index poisson_vertices = 0;  // Poisson's mesh before trimming
  Index poisson_faces = 0;
  Index trimmed_faces = 0;  // triangles dropped as too far from the points
  Index diagnostics = 0;    // lines PoissonRecon printed about edges it could not pair (see 2. above)
  std::vector<std::string> warnings;
};

// points  N points with normals (N >= 3). Throws InvariantError without normals, ConfigError on options out of range.
SurfaceResult poisson_surface(const PointSet& points, const SurfaceOptions& options);

// The points of `points` (with every per-point attribute) nearest the centres of the cells of a voxel grid sized so
// that about `max_points` remain, in their input order; all of them when there are no more than max_points.
PointSet thin_to_budget(const PointSet& points, Index max_points);

}  // namespace scanfill
