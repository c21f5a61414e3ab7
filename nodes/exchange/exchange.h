// Style exchange with box proxies (paper section 7, "Style Exchange", Figure 14): no source model is given; each part
// of the exemplar and of the target is replaced by its axis-aligned box, the exemplar's boxes are the source S and the
// target's boxes T, and the analogy S -> T is assembled from the maps between pairs of boxes (box_transform.h).
//
//   candidates  every (source box i, target box j, axis rotation R): A x = c_j + D R (x - c_i); equal maps merged.
//               A explains target box j when it carries some source box k onto it (corners within match_tolerance).
//   unary       on T's box samples (a grid on each box face): the distance from the sample to the surface of A(box_k)
//               over the tolerance, squared and capped at 1; a label is feasible only where it explains the box. The
//               paper applies each candidate to S's samples and measures the fit; for boxes that fit is the box-surface
//               distance, computed exactly here instead of by a nearest-neighbour search.
//   label cost  eq. 8 with eq. 9's preferences: h_l = label_cost (1 + rotation_cost (1 - cos angle) / 2 +
//               distortion_cost var_k(log d_k) + scale_cost mean_k(log d_k)^2). Eq. 9 gives every axis rotation the
//               same cost; small rotations are preferred here so that a part keeps its upright orientation when
//               nothing asks it to turn. Eq. 9's (s - 1)^2 has one scale; with three, the stretch (the spread of the
//               log scales) and the uniform part (their mean) are weighed apart, so that a box map that only scales
//               wins over one that stretches (a tower's box onto a tower, not onto a wall).
//   pairwise    Potts, smoothness, between grid neighbours of a face.
//   solved by   alpha-expansion with label costs (nodes/graphcut/expansion.h); each target box then takes the label
//               of most of its samples (ties: the lower label).
//   synthesis   each target box j with its map A, which carries source box k onto j: the exemplar's points of part k
//               (the box they lie deepest in) are moved by A, normals by the inverse transpose; the union is the
//               output. A mesh exemplar keeps its triangles (a triangle belongs to the part of its centroid), so the
//               output is a mesh at the exemplar's own resolution however much a map stretches; a cloud gives its
//               points.
#pragma once

#include <string>
#include <vector>

#include "nodes/core/point_set.h"
#include "nodes/exchange/box_transform.h"
#include "nodes/exchange/exchange_options.h"
#include "nodes/exchange/part_box.h"

namespace scanfill {

// The PLY vertex properties that commonly hold a segmentation, in the order part_property auto tries them.
const std::vector<std::string>& common_part_properties();

// T's box samples: a grid on every face of every box.
struct BoxSamples {
  PointSet points;                                           // positions and face normals
  std::vector<int> box;                                      // per sample, its target box
  std::vector<std::pair<std::int32_t, std::int32_t>> edges;  // grid neighbours on a face
};

BoxSamples sample_boxes(const PartBoxes& boxes, double spacing);

struct BoxAnalogy {
  std::vector<BoxTransform> transforms;  // the labels used, in order of first use by a target box
  std::vector<int> box_label;            // per target box, its transform (index in transforms)
  std::vector<int> box_source;           // per target box, the source box its transform carries onto it
  BoxSamples samples;                    // T's box samples
  std::vector<int> sample_label;         // per sample, its transform (index in transforms)
  Index candidates = 0;                  // distinct maps between pairs of boxes
  double energy_before = 0, energy_after = 0;
  bool converged = false;
};

// The box-wise analogy S -> T; `usable`: per source box, whether maps may start from it (empty = all; a box that holds
// none of the exemplar would carry nothing). Throws InvariantError for an empty or degenerate box list, or no usable
// source box.
BoxAnalogy label_box_analogy(const PartBoxes& source, const PartBoxes& target, const ExchangeOptions& options,
                             const std::vector<bool>& usable = {});

struct Exchange {
  BoxAnalogy analogy;
  PointSet output;                // the exemplar carried by each target box's map (a mesh when it is one)
  std::vector<int> output_label;  // per output point, its transform (index in analogy.transforms)
};

// The bounding box of each part: labels >= 0 in increasing order (their labels in `parts`); negative labels are no
// part.
PartBoxes boxes_of_parts(const std::vector<Eigen::Vector3d>& positions, const std::vector<int>& labels,
                         std::vector<int>& parts);

// Each exemplar point's part: the source box it lies deepest in (ties: the lower box).
std::vector<int> assign_parts(const Eigen::Matrix3Xd& points, const PartBoxes& boxes);

// Per source box, the exemplar's points (or triangles, by their centroids) of that part.
std::vector<std::vector<Index>> points_by_part(const PointSet& exemplar, const PartBoxes& source);
std::vector<std::vector<Index>> triangles_by_part(const PointSet& exemplar, const PartBoxes& source);

// The output: for every target box, the exemplar's points (or triangles) of the source box its map carries onto it,
// moved by the map.
// `members`: per source box, its points or triangles (points_by_part or triangles_by_part).
Exchange synthesize_exchange(const PointSet& exemplar, const std::vector<std::vector<Index>>& members,
                             BoxAnalogy analogy);

// label_box_analogy from the source boxes that hold some of the exemplar, then synthesize_exchange.
Exchange exchange_style(const PointSet& exemplar, const PartBoxes& source, const PartBoxes& target,
                        const ExchangeOptions& options);

}  // namespace scanfill
