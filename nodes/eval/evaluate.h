// eval: accuracy of an output against a complete reference (DESIGN section 5, `scanfill eval`).
//
// Surfaces are compared as point sets: a mesh contributes `surface_samples` area-uniform random points (seeded) with
// face normals, a cloud its own points (normals estimated by PCA where missing). With d(x, Y) the distance from x to
// the nearest point of Y, O the output and R the reference:
//   chamfer_l1 = (mean_o d(o, R) + mean_r d(r, O)) / 2       chamfer_l2 = (mean_o d(o, R)^2 + mean_r d(r, O)^2) / 2
//   precision = share of O within tau of R, recall = share of R within tau of O, fscore = 2 P R / (P + R)
//   hausdorff = max(max_o d(o, R), max_r d(r, O)), normal_consistency = mean of |n . n_nearest| over both directions
// tau = threshold x the reference's bounding-box diagonal. Given the scan and the template, unseen_detail_recall is
// the share, within tau of O, of the reference points farther than tau from the template (style detail) and from the
// scan (unseen): the one number that says whether style reached what the scanner never saw.
#pragma once

#include <cstdint>
#include <optional>

#include "nodes/core/point_set.h"

namespace scanfill {

struct EvalOptions {
  double threshold = 0.01;         // tau as a fraction of the reference's bounding-box diagonal; > 0
  Index surface_samples = 200000;  // random points drawn on a mesh; >= 1
  std::uint64_t seed = 1;
};

struct EvalResult {
  double tau = 0;  // absolute threshold
  double chamfer_l1 = 0, chamfer_l2 = 0, precision = 0, recall = 0, fscore = 0, hausdorff = 0;
  double normal_consistency = 0;
  std::optional<double> unseen_detail_recall;
  Index unseen_detail_points = 0;  // reference points that are style detail and unseen
};

// scan and template_shape are optional (both or neither).
EvalResult evaluate(const PointSet& output, const PointSet& reference, const EvalOptions& options,
                    const PointSet* scan = nullptr, const PointSet* template_shape = nullptr);

// The classic template-blending completion, a baseline for completion results: the scan's points plus the template's
// points (`surface_samples` random points of a mesh, or its own points) farther than `gap` from the scan. Both inputs
// are taken as they are (roughly aligned, as scanfill's inputs are).
PointSet template_blend(const PointSet& scan, const PointSet& template_shape, double gap, const EvalOptions& options);

}  // namespace scanfill
