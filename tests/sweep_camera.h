// The virtual scanner as bench/robustness.py places it, for tests that scan a model as the sweep sees it.
#pragma once

#include <Eigen/Core>
#include <optional>

#include "nodes/core/point_set.h"
#include "nodes/scan/virtual_scan.h"

namespace scanfill::test {

// The sweep's eye for a model bounded by `bounds`, seen along `view`: 2.6 diagonals from its centre.
inline Eigen::Vector3d sweep_eye(const BoundingBox& bounds, const Eigen::Vector3d& view) {
  return (bounds.min + bounds.max) / 2 + 2.6 * bounds.diagonal() * view.normalized();
}

// The sweep's camera at `eye`, looking at `target`: 480 by 480 rays at 30 degrees, up as default_camera takes it.
inline ScanOptions sweep_camera(const PointSet& model, const Eigen::Vector3d& eye, const Eigen::Vector3d& target) {
  ScanOptions camera = default_camera(model, eye, target, std::nullopt);
  camera.width = camera.height = 480;
  camera.fov_deg = 30;
  return camera;
}

// The sweep's camera for `model` seen along `view`, looking at the centre of its bounding box.
inline ScanOptions sweep_camera(const PointSet& model, const Eigen::Vector3d& view) {
  const BoundingBox bounds = bounding_box(model.positions());
  return sweep_camera(model, sweep_eye(bounds, view), (bounds.min + bounds.max) / 2);
}

// Seed 6565's eye 3.4 degrees above edge-on to the procedural gear (`--random-views 6 --view-seed 6565`'s (-0.99,
// 0.11, 0.06)), and the centre it looks at, as bench/robustness.py puts them (the gear's bounding box from 2000
// samples, not its exact one).
inline const Eigen::Vector3d kGearEdgeOnEye(-3.742046092104117, 0.40418135506173797, 0.2999147885238472);
inline const Eigen::Vector3d kSweepGearCentre(-3.275275230407715e-05, -2.3871660232543945e-05, 0.07500000298023224);

}  // namespace scanfill::test
