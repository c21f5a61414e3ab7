// sample node: Poisson-disk sampling by weighted sample elimination (Yuksel 2015; paper section 3; DESIGN section 4).
//
// Candidates are the input points of a cloud, or `oversampling` x N area-weighted random points on a mesh's triangles.
// A cloud with more than 40 N points is first thinned to about 16 N candidates (neighbour lists grow with the ratio):
// one point per grid cell (and normal octant), the one nearest the cell centre, so sparse regions keep all points.
// Each candidate i has weight w_i = sum_j (1 - d_ij / d_max)^weight_exponent over neighbours j within d_max = 2 r_max,
// r_max = sqrt(A / (2 sqrt(3) N)); candidates are eliminated heaviest first, their neighbours' weights updated, until N
// remain. A neighbour counts only if its normal agrees within normal_angle_deg, so both sides of thin parts survive.
//
// Deviation from the paper's sequential max-heap: elimination runs in parallel rounds. A round removes every candidate
// that is a local maximum of (weight, index) among its live neighbours and whose weight is at least the excess-th
// largest live weight; the sequential greedy would also remove each such candidate before any of its neighbours, so
// the rounds follow the greedy closely, and the result does not depend on the thread count.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "nodes/core/point_chunks.h"
#include "nodes/core/point_set.h"
#include "nodes/core/progress.h"

namespace scanfill {

struct SampleOptions {
  double spacing = 0.0;            // target mean nearest-neighbour distance (alpha), model units; 0 = use count; >= 0
  Index count = 20000;             // number of samples when spacing is 0; >= 1
  double oversampling = 6.0;       // mesh candidates per output sample (Yuksel recommends 5-10); [2, 100]
  double normal_angle_deg = 60.0;  // neighbours with normals further apart than this do not repel; (0, 180]
  double weight_exponent = 8.0;    // exponent of (1 - d/d_max) in the elimination weight; (0, 64]
  std::uint64_t seed = 1;          // seed of the mesh candidate generator
  bool all_points_when_sparse = false;  // a cloud sparser than `spacing` gives all its points (else InputError)
};

struct SampleResult {
  PointSet samples;      // positions, normals (when known), provenance (face + barycentrics, or source_index)
  Index candidates = 0;  // candidates the elimination started from
  double area = 0.0;     // surface area used for r_max (exact for meshes, estimated for clouds)
  double r_max = 0.0;    // Poisson-disk radius bound of the paper
  double spacing = 0.0;  // mean nearest-neighbour distance of the samples (alpha)
  int rounds = 0;        // parallel elimination rounds
  std::vector<std::string> warnings;
};

// Throws InputError when the input cannot give what is asked (fewer cloud points than samples, a mesh of zero area).
SampleResult sample(const PointSet& input, const SampleOptions& options, const ProgressFn& progress = {});

// n area-weighted random points on a mesh's triangles (the sampler's candidates): positions, normals (interpolated
// vertex normals when the mesh has them, else face normals) and face provenance, in Morton order; the same points on
// any thread count for a seed. Throws InputError for a mesh of zero area.
PointSet random_surface_points(const PointSet& mesh, Index n, std::uint64_t seed);

// The points of random_surface_points(mesh, n, seed) that `keep` accepts (called in parallel with each point's position
// and triangle), positions and normals, in the same order, made block by block: memory for the kept points only, never
// all n.
PointSet random_surface_points_where(const PointSet& mesh, Index n, std::uint64_t seed,
                                     const std::function<bool(const Eigen::Vector3d&, std::int32_t)>& keep);

// `mesh`'s triangles each split into four at its edges' midpoints as often as it takes for its own longest edge to be
// at most `longest_edge` (so its points spread as evenly as the mesh's area), all of them once fewer while that would
// make more than `most_faces` triangles. Each split triangle is split apart from its neighbours: a surface to sample
// (its vertices are not merged, and neighbours split differently meet at T-junctions); triangles left whole keep the
// mesh's shared vertices. Positions and triangles only. Throws InputError for a cloud.
PointSet subdivided_mesh(const PointSet& mesh, double longest_edge, Index most_faces);

// Sampling a cloud too large to hold (issue 13), from a PointChunks source in two passes.
//
// summarize_chunks is the first pass: the points' count and bounding box, and every stride-th point (about
// `kept_points` of them), on which the cloud's area is estimated (cloud_area's estimate follows the local spacing, not
// the density, so an even subsample gives the whole cloud's area). sample_chunks is the second: a cloud of more than
// 40 points per requested sample is thinned on the grid a run at a time (GridThinner: the same points as the
// whole-cloud thinning, holding only the grid's candidates), and the candidates are sampled as sample() samples a
// cloud; a smaller cloud is read whole and given to sample(). Deviations from sample() on the whole cloud, by
// necessity: exact duplicates are not merged (that needs a sort of every point), the points keep their file order (no
// Morton sort), and a thinned cloud's spacing-derived count comes from the subsample's area.
struct ChunksSummary {
  Index points = 0;    // finite points in all
  BoundingBox bounds;  // of every point
  Index stride = 1;    // every_kth holds points 0, stride, 2 stride, ...
  PointSet every_kth;  // positions (and normals when known), source_index
};
ChunksSummary summarize_chunks(PointChunks& chunks, Index chunk_points, Index kept_points);
SampleResult sample_chunks(PointChunks& chunks, const ChunksSummary& summary, const SampleOptions& options,
                           Index chunk_points, const ProgressFn& progress = {});

// One point per cell of a grid of spacing h anchored at `lo` (and per normal octant when the points have normals),
// the one nearest the cell centre, ties to the lower index: the thinning of sample(), fed a run at a time. Holds one
// entry per occupied cell, never the whole cloud.
class GridThinner {
 public:
  GridThinner(const Eigen::Vector3d& lo, double h) : lo_(lo), h_(h) {}
  // The next run of points (indices continue from the previous runs).
  void add(const PointSet& run);
  // The kept points in index order: positions, normals when the runs had them, source_index (the run's, or the index).
  PointSet take();

  struct Cell {
    std::int64_t key;
    double d2;
    Index index;
    std::int64_t source;
    Eigen::Vector3d p, n;
  };

 private:
  Eigen::Vector3d lo_;
  double h_;
  Index seen_ = 0;
  bool normals_ = false;
  std::vector<Cell> cells_, run_, merged_;  // cells_: the best point of each cell so far, by key
};

// Indices (ascending) of the points sample() keeps when it thins a cloud on a grid of spacing h anchored at the
// points' minimum: what GridThinner must reproduce.
std::vector<Index> thin_on_grid(const Eigen::Matrix3Xd& positions, const Eigen::Matrix3Xd& normals, double h);

// Sample count that gives a mean nearest-neighbour distance of `spacing` on a surface of `area` (measured on WSE
// output, see tests/nodes/sample_test.cpp).
Index count_for_spacing(double area, double spacing);

}  // namespace scanfill
