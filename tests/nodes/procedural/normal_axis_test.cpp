#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "nodes/core/point_set.h"
#include "nodes/core/surface_elements.h"
#include "nodes/io/read_point_set.h"
#include "nodes/procedural/normal_axis.h"
#include "nodes/procedural/shapes.h"
#include "nodes/scan/virtual_scan.h"
#include "test_util.h"

namespace scanfill {
namespace {

// The distance of `p` from the line of `axis`.
double off_axis(const RevolutionAxis& axis, const Eigen::Vector3d& p) {
  const Eigen::Vector3d d = p - axis.centre;
  return (d - d.dot(axis.direction) * axis.direction).norm();
}

double degrees_between(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::min(1.0, std::abs(a.normalized().dot(b.normalized())))) * 180 / M_PI;
}

// One view of the procedural vase (axis z through the origin) from its front.
PointSet front_view_of_the_vase() {
  ScanOptions o;
  o.eye = Eigen::Vector3d(0, -3, 0.8);
  o.target = Eigen::Vector3d(0, 0, 0.5);
  return virtual_scan(make_vase(), o).points;
}

TEST(NormalAxis, FindsATurnedCylindersAxisFromItsFaces) {
  // A cylinder's normals all lie in one plane (the singular case of the solve).
  Similarity q;
  q.rotation = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  q.translation = Eigen::Vector3d(0.4, -0.2, 1.5);
  const PointSet cylinder = transformed(make_cylinder(0.3, 1.0, 128), q);
  const SurfaceElements faces = surface_elements(cylinder);
  const RevolutionAxis axis = axis_from_normals(faces);
  EXPECT_LT(degrees_between(axis.direction, q.rotation.col(2)), 0.01);
  EXPECT_LT(off_axis(axis, q.translation), 1e-6);
  // A triangle's centroid is a sixth of a facet (of 128) off the angle its normal faces: sine 0.008.
  EXPECT_LT(normal_axis_misfit(faces, axis), 0.01);
  EXPECT_GT(normal_axis_misfit(faces, RevolutionAxis{q.translation, q.rotation.col(0)}), 0.3);
}

TEST(NormalAxis, OneViewOfAVaseIsRevolvedAboutTheVasesAxis) {
  const PointSet scan = front_view_of_the_vase();
  ASSERT_TRUE(scan.has_normals());
  // Its bounding box's centre is half the radius in front of the axis, and the view direction fits its rings best: the
  // template was a disk about y.
  const RevolutionAxis axis = revolution_axis(scan);
  EXPECT_LT(degrees_between(axis.direction, Eigen::Vector3d::UnitZ()), 0.5);
  EXPECT_LT(off_axis(axis, Eigen::Vector3d(0, 0, 0.5)), 0.005);
  const RevolutionFit fit = fit_revolution(scan);
  // The body lies on the vase's own body of revolution: its extent across the axis is the vase's.
  const BoundingBox body = bounding_box(fit.body.positions()), vase = bounding_box(make_vase_template().positions());
  EXPECT_NEAR(body.max.x() - body.min.x(), vase.max.x() - vase.min.x(), 0.03);
  EXPECT_NEAR(body.max.y() - body.min.y(), vase.max.y() - vase.min.y(), 0.03);
  // Scored only where the view saw the vase, the body lies on the scan: no warning that it is no body of revolution.
  EXPECT_LT(fit.misfit, 0.1);
}

TEST(NormalAxis, TheSameScanWithoutNormalsGivesTheSameAxis) {
  const PointSet scan = front_view_of_the_vase();
  const PointSet bare(scan.positions());
  const RevolutionAxis axis = revolution_axis(bare);
  EXPECT_LT(degrees_between(axis.direction, Eigen::Vector3d::UnitZ()), 1.0);
  EXPECT_LT(off_axis(axis, Eigen::Vector3d(0, 0, 0.5)), 0.01);
}

// One view of a real model drawn y-up, from `direction` (model units, normalised) at 2.5 diagonals.
PointSet view_of(const PointSet& model, const Eigen::Vector3d& direction) {
  const BoundingBox box = bounding_box(model.positions());
  ScanOptions o;
  o.target = (box.min + box.max) / 2;
  o.eye = o.target + 2.5 * (box.max - box.min).norm() * direction.normalized();
  o.up = Eigen::Vector3d::UnitY();
  return virtual_scan(model, o).points;
}

TEST(NormalAxis, ViewsOfTheRealVaseFromItsSidesAreRevolvedAboutItsAxis) {
  SCANFILL_REQUIRE_SHARED_DATA();
  const PointSet vase = read_point_set(test::shared_data() / "models" / "text2mesh_vase.obj").points;
  const RevolutionAxis own = revolution_axis(vase);
  ASSERT_LT(degrees_between(own.direction, Eigen::Vector3d::UnitY()), 0.01);
  const double diagonal = (bounding_box(vase.positions()).max - bounding_box(vase.positions()).min).norm();
  // From its profile (the axes through its bounding box's centre), the front and side views took axes 78 degrees off.
  for (const Eigen::Vector3d& d :
       {Eigen::Vector3d(0, 0.2, -1), Eigen::Vector3d(1, 0.25, 0), Eigen::Vector3d(0.6, 0.4, -0.8)}) {
    const RevolutionAxis axis = revolution_axis(view_of(vase, d));
    EXPECT_LT(degrees_between(axis.direction, Eigen::Vector3d::UnitY()), 0.01) << d.transpose();
    EXPECT_LT(off_axis(own, axis.centre), 0.01 * diagonal) << d.transpose();
  }
}

TEST(NormalAxis, TheTeapotSeenFromItsSpoutKeepsItsUprightAxis) {
  SCANFILL_REQUIRE_SHARED_DATA();
  // Its spout and handle pull the normals' free axis to x; the profile's y is kept.
  const PointSet teapot = read_point_set(test::shared_data() / "models" / "teapot.obj").points;
  for (const Eigen::Vector3d& d : {Eigen::Vector3d(0, 0.2, -1), Eigen::Vector3d(0.6, 0.4, -0.8)})
    EXPECT_LT(degrees_between(revolution_axis(view_of(teapot, d)).direction, Eigen::Vector3d::UnitY()), 0.01)
        << d.transpose();
}

}  // namespace
}  // namespace scanfill
