// One object cut out of a scanned scene (`scanfill crop`). A real range scan or stereo cloud holds the table the
// object stands on and whatever else the sensor saw (PCL's table_scene_mug: a mug, its table, a wall and a chair);
// completion needs the object alone. Three steps, each optional, in this order: keep the points inside a box given in
// the scan's own coordinates; drop the largest plane among them (the support, found by seeded RANSAC and refitted by
// least squares); keep the largest connected part (points joined across gaps smaller than `gap`). Every per-point
// attribute is kept; a mesh's faces are not (the result is a point cloud).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <optional>

#include "nodes/core/point_set.h"

namespace scanfill {

struct CropOptions {
  std::optional<BoundingBox> box;  // keep the points inside (bounds included); none: every point
  bool drop_plane = false;         // drop the largest plane (the table an object stands on)
  bool largest_part = false;       // keep the largest connected part
  double plane_distance = 0;       // a plane's inliers lie closer than this; 0: 2 x the points' median spacing
  double gap = 0;                  // parts are joined across gaps shorter than this; 0: 4 x the median spacing
  int plane_trials = 500;          // RANSAC's random triples; >= 1
  std::uint64_t seed = 1;
};

struct CropResult {
  PointSet points;
  Index in_box = 0;        // points inside the box (all of them without one)
  Index plane_points = 0;  // dropped as the plane
  Eigen::Vector3d plane_normal = Eigen::Vector3d::Zero();
  double plane_offset = 0;  // the plane: plane_normal . x + plane_offset = 0
  Index parts = 0;          // connected parts found (largest_part)
  double spacing = 0;       // the median nearest-neighbour spacing the defaults scale with
};

// Throws InputError when no point is left after a step (naming the step), ConfigError for a bad option.
CropResult crop(const PointSet& points, const CropOptions& options);

}  // namespace scanfill
