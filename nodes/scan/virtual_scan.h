// A virtual single-view range scanner (the paper's "synthetic scanner"; DESIGN section 5, `scanfill scan`).
//
// A pinhole camera at `eye` looking at `target` renders the mesh into a width x height depth buffer (perspective
// z-buffer rasterisation, perspective-correct depth); every pixel that sees the surface gives one point, so occluded
// surfaces and back faces (facing away from the camera) are missing, as in a real scan. Optional Gaussian noise of
// standard deviation `noise` (model units) moves each point along its viewing ray. Points carry the normal of the face
// they hit (towards the camera) and the scanner position as viewpoint. Deterministic for a seed.
#pragma once

#include <cstdint>
#include <optional>

#include "nodes/core/point_set.h"
#include "nodes/io/read_point_set.h"

namespace scanfill {

struct ScanOptions {
  Eigen::Vector3d eye = Eigen::Vector3d(0, -3, 0);   // camera position
  Eigen::Vector3d target = Eigen::Vector3d::Zero();  // point the camera looks at; != eye
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();     // image up; parallel to the view: default_up of the view
  int width = 640;                                   // image columns; [1, 16384]
  int height = 480;                                  // image rows; [1, 16384]
  double fov_deg = 45.0;                             // vertical field of view; (0, 180)
  double noise = 0.0;                                // Gaussian sigma along the ray, model units; >= 0
  std::uint64_t seed = 1;
};

// The config's virtual scan (section virtual_scan): completion's scan input replaced by a single-view range scan of
// it, the paper's synthetic scanner, so that a complete model (or a procedural shape) can be completed and scored
// against itself. What it leaves open (~), default_camera decides.
struct VirtualScanOptions {
  std::optional<Eigen::Vector3d> eye;     // camera position; ~ = no virtual scan
  std::optional<Eigen::Vector3d> target;  // looked-at point; ~ = the centre of the input's bounding box
  std::optional<Eigen::Vector3d> up;      // image up; ~ = default_up: +z, or +y when looking within 8 degrees of z
  int width = 640;                        // image columns; [1, 16384]
  int height = 480;                       // image rows; [1, 16384]
  double fov_deg = 45.0;                  // vertical field of view; (0, 180)
  double noise = 0.0;                     // Gaussian sigma along the ray, model units; >= 0
  std::uint64_t seed = 1;                 // seed of the noise
};

struct ScanResult {
  PointSet points;  // positions, normals, viewpoint
  Index pixels_hit = 0;
};

// The camera's up when none is given: +z, or +y when the view direction is within about 8 degrees of the z axis
// (|forward.z| > 0.99), where +z would leave the image frame ill-defined.
Eigen::Vector3d default_up(const Eigen::Vector3d& forward);

// The camera at `eye`, looking at `target` (~ = the centre of the mesh's bounding box) with `up` (~ = default_up):
// the scanner's defaults for what a config leaves open. The image and noise options keep their defaults.
ScanOptions default_camera(const PointSet& mesh, const Eigen::Vector3d& eye,
                           const std::optional<Eigen::Vector3d>& target, const std::optional<Eigen::Vector3d>& up);

// Throws InputError for a point cloud (no faces) or when no pixel sees the mesh.
ScanResult virtual_scan(const PointSet& mesh, const ScanOptions& options);

// The config's virtual scan of a loaded input (completion's scan): the input as it is when options.eye is ~, else its
// range scan seen by default_camera, with " (virtual scan)" added to the format. `name` names the input in the error
// for a point cloud.
LoadResult virtual_scan_input(LoadResult load, const VirtualScanOptions& options, const std::string& name);

}  // namespace scanfill
