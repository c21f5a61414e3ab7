// A virtual single-view range scanner (the paper's "synthetic scanner"; DESIGN section 5, `scanfill scan`).
//
// A pinhole camera at `eye` looking at `target` renders the mesh into a width x height depth buffer (perspective
// z-buffer rasterisation, perspective-correct depth); every pixel that sees the surface gives one point, so occluded
// surfaces and back faces (facing away from the camera) are missing, as in a real scan. Optional Gaussian noise of
// standard deviation `noise` (model units) moves each point along its viewing ray. Points carry the normal of the face
// they hit (towards the camera) and the scanner position as viewpoint. Deterministic for a seed.
#pragma once

#include <cstdint>

#include "nodes/core/point_set.h"

namespace scanfill {

struct ScanOptions {
  Eigen::Vector3d eye = Eigen::Vector3d(0, -3, 0);   // camera position
  Eigen::Vector3d target = Eigen::Vector3d::Zero();  // point the camera looks at; != eye
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();     // image up (any vector not parallel to the view direction)
  int width = 640;                                   // image columns; [1, 16384]
  int height = 480;                                  // image rows; [1, 16384]
  double fov_deg = 45.0;                             // vertical field of view; (0, 180)
  double noise = 0.0;                                // Gaussian sigma along the ray, model units; >= 0
  std::uint64_t seed = 1;
};

struct ScanResult {
  PointSet points;  // positions, normals, viewpoint
  Index pixels_hit = 0;
};

// Throws InputError for a point cloud (no faces) or when no pixel sees the mesh.
ScanResult virtual_scan(const PointSet& mesh, const ScanOptions& options);

}  // namespace scanfill
