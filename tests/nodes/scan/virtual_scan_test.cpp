#include "nodes/scan/virtual_scan.h"

#include <gtest/gtest.h>

#include "nodes/core/errors.h"
#include "nodes/procedural/shapes.h"

namespace scanfill {
namespace {

ScanOptions from_z(double distance) {
  ScanOptions o;
  o.eye = Eigen::Vector3d(0, 0, distance);
  o.up = Eigen::Vector3d::UnitY();
  return o;
}

TEST(VirtualScan, SphereFrontOnlyOnTheSurfaceFacingTheEye) {
  const double r = 0.5, d = 3.0;
  const ScanResult s = virtual_scan(make_sphere(r, 256), from_z(d));
  const PointSet& p = s.points;
  ASSERT_GT(p.size(), 1000);
  for (Index i = 0; i < p.size(); ++i) {
    ASSERT_NEAR(p.positions().col(i).norm(), r, 2e-4);  // on the sphere (chord error of 256 segments)
    // Visible from the eye: the silhouette is where the ray grazes, at z = r^2 / d.
    ASSERT_GT(p.positions()(2, i), r * r / d - 1e-3);
    ASSERT_GT(p.normals().col(i).dot(Eigen::Vector3d(0, 0, d) - p.positions().col(i)), 0);
  }
  // One point per pixel inside the projected disc: pi (rho H / (2 tan(fov / 2)))^2, rho = r / sqrt(d^2 - r^2).
  const double rho = r / std::sqrt(d * d - r * r), radius_px = rho * 240 / std::tan(M_PI / 8);
  EXPECT_NEAR(double(p.size()), M_PI * radius_px * radius_px, 0.02 * M_PI * radius_px * radius_px);
  ASSERT_TRUE(p.viewpoint());
  EXPECT_EQ(*p.viewpoint(), Eigen::Vector3d(0, 0, d));
}

TEST(VirtualScan, OccludedSurfacesAreMissing) {
  Similarity behind;
  behind.translation = Eigen::Vector3d(0, 0, -1.5);
  const PointSet two = merged(make_sphere(0.5, 128), transformed(make_sphere(0.5, 128), behind));
  const ScanResult s = virtual_scan(two, from_z(3.0));
  for (Index i = 0; i < s.points.size(); ++i) ASSERT_GT(s.points.positions()(2, i), 0.0);  // the rear sphere is hidden
}

TEST(VirtualScan, NoiseAlongTheRayHasTheGivenSigmaAndIsSeeded) {
  ScanOptions o = from_z(3.0);
  o.noise = 0.002;
  const PointSet sphere = make_sphere(0.5, 256);
  const ScanResult a = virtual_scan(sphere, o), b = virtual_scan(sphere, o);
  EXPECT_EQ(a.points.positions(), b.points.positions());
  // Near the disc centre the ray is radial: the radial error is the noise itself.
  double sum = 0, sum2 = 0;
  Index n = 0;
  for (Index i = 0; i < a.points.size(); ++i) {
    const Eigen::Vector3d p = a.points.positions().col(i);
    if (p.head<2>().norm() > 0.1) continue;
    const double e = p.norm() - 0.5;
    sum += e;
    sum2 += e * e;
    ++n;
  }
  ASSERT_GT(n, 500);
  const double mean = sum / double(n), sigma = std::sqrt(sum2 / double(n) - mean * mean);
  EXPECT_NEAR(sigma, 0.002, 0.0002);
  EXPECT_NEAR(mean, 0.0, 0.0003);
  o.seed = 2;
  EXPECT_NE(virtual_scan(sphere, o).points.positions(), a.points.positions());
}

TEST(VirtualScan, RefusesCloudsAndEmptyViews) {
  EXPECT_THROW(virtual_scan(PointSet(make_sphere(0.5, 16).positions()), from_z(3)), InputError);
  ScanOptions away = from_z(3);
  away.target = Eigen::Vector3d(0, 0, 10);  // looking away from the sphere
  EXPECT_THROW(virtual_scan(make_sphere(0.5, 16), away), InputError);
}

TEST(VirtualScan, DefaultCameraLooksAtTheBoxCentreWithZUpUnlessLookingAlongZ) {
  const PointSet box = make_box(Eigen::Vector3d(2, 2, 4));  // centred at the origin
  const ScanOptions side = default_camera(transformed(box, {Eigen::Matrix3d::Identity(), {1, 2, 3}, 1}),
                                          Eigen::Vector3d(1, -5, 3), std::nullopt, std::nullopt);
  EXPECT_TRUE(side.target.isApprox(Eigen::Vector3d(1, 2, 3)));
  EXPECT_EQ(side.up, Eigen::Vector3d::UnitZ());
  // Within about 8 degrees of the z axis (|forward.z| > 0.99) +z would leave the image frame ill-defined: +y.
  EXPECT_EQ(default_camera(box, {0, 0.1, 5}, Eigen::Vector3d::Zero(), std::nullopt).up, Eigen::Vector3d::UnitY());
  EXPECT_EQ(default_camera(box, {0, 1, 5}, Eigen::Vector3d::Zero(), std::nullopt).up, Eigen::Vector3d::UnitZ());
  // What the config gives is kept.
  const ScanOptions given = default_camera(box, {0, 0, 5}, Eigen::Vector3d(0, 0, 1), Eigen::Vector3d::UnitX());
  EXPECT_EQ(given.target, Eigen::Vector3d(0, 0, 1));
  EXPECT_EQ(given.up, Eigen::Vector3d::UnitX());
}

}  // namespace
}  // namespace scanfill
