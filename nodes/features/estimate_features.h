// features node (DESIGN section 4): normals, signed principal curvatures and directions, per point.
//
// Normals: PCA of the k nearest neighbours (smallest eigenvector of the covariance), oriented
//   - kInput: to agree with normals the input already has (mesh samples, clouds with normals);
//   - kViewpoint: towards the sensor position (single-view scans);
//   - kPropagate: over a minimum spanning tree of the kNN graph with edge cost 1 - |n_i . n_j| (Hoppe et al. 1992),
//     each component's sign chosen so that normals point away from the centroid on balance (closed models);
//   - kAuto: kInput if the input has normals, else kViewpoint if it has a viewpoint, else kPropagate.
// Curvature: the shape operator S (2x2 symmetric, 3 unknowns) fitted by least squares to dn = S dp over the
//   neighbours, dp and dn the position and normal differences projected on the tangent plane; its eigenvalues are the
//   signed principal curvatures (positive where the surface bends away from the normal, e.g. 1/r on a sphere with
//   outward normals), |k1| >= |k2|, and d1 the eigenvector of k1. PCL's PrincipalCurvaturesEstimation is not used
//   (unsigned, unitless, not thread-safe per instance).
// Directions are unreliable near umbilics (|k2/k1| > umbilic_ratio) and on flat parts (|k1| h < flat_threshold, h the
//   neighbourhood radius). There they are replaced by a smooth 4-fold cross field (Hertzmann and Zorin 2000): with
//   z_i = exp(4 i theta_i) in a local tangent frame, minimise sum_ij |z_i - r_ij z_j|^2 + lambda sum |z_i - z0_i|^2
//   over the kNN graph, r_ij the frame transport of j to i, reliable neighbours soft-constrained to their own
//   direction with weight `reliable_weight`, every unknown lightly (`regularization`) to its raw estimate. Solved by
//   Jacobi-preconditioned conjugate gradients, parallel and deterministic.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "nodes/core/point_set.h"
#include "nodes/core/progress.h"

namespace scanfill {

enum class NormalOrientation { kAuto, kInput, kViewpoint, kPropagate };

struct FeaturesOptions {
  int k = 16;  // neighbours for normals and the shape-operator fit; [6, 128]
  NormalOrientation orientation = NormalOrientation::kAuto;  // see above
  std::optional<Eigen::Vector3d> viewpoint;  // sensor position for kViewpoint; overrides the input's own
  double umbilic_ratio = 0.75;               // |k2/k1| above this: k1 direction unreliable; (0, 1]
  double flat_threshold = 0.02;              // |k1| h below this: direction unreliable (dimensionless); >= 0
  bool smooth_directions = true;             // replace unreliable directions by the cross field
  double reliable_weight = 10.0;             // soft-constraint weight of reliable directions; > 0
  double regularization = 1e-3;              // pull of every unknown to its raw direction; > 0
  int max_iterations = 300;                  // conjugate-gradient iterations; >= 1
  double tolerance = 1e-3;                   // relative residual to stop at (angles need no more); (0, 1)
};

struct FeaturesResult {
  PointSet points;                  // the input plus normals, curvatures, directions
  Index unreliable_directions = 0;  // points whose direction came from the cross field
  int iterations = 0;               // conjugate-gradient iterations run
  double residual = 0.0;            // final relative residual of the cross-field solve
  bool converged = true;
  NormalOrientation orientation_used = NormalOrientation::kAuto;
  std::vector<std::string> warnings;
};

// Throws InputError if the input has fewer than k + 1 points.
FeaturesResult estimate_features(const PointSet& input, const FeaturesOptions& options,
                                 const ProgressFn& progress = {});

}  // namespace scanfill
