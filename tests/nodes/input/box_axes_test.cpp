#include "nodes/input/box_axes.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "nodes/input/input.h"
#include "nodes/io/write_ply.h"
#include "nodes/procedural/shapes.h"
#include "nodes/sample/sample.h"
#include "test_util.h"

namespace scanfill {
namespace {

const Eigen::Matrix3d kTurned =
    (Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()) * Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX()))
        .toRotationMatrix();

// The largest angle, in degrees, between an axis of `found` and the nearest axis of `truth` (either sign).
double worst_axis_angle(const Eigen::Matrix3d& found, const Eigen::Matrix3d& truth) {
  double worst = 0;
  for (int c = 0; c < 3; ++c) {
    const double cosine = (truth.transpose() * found.col(c)).cwiseAbs().maxCoeff();
    worst = std::max(worst, std::acos(std::min(1.0, cosine)) * 180 / M_PI);
  }
  return worst;
}

// A carton's surface points, turned as a sensor would see it, and only its side towards the sensor (three faces from
// a corner): as the Kinect's milk carton (../shared/data/scans/pcl_kinect/milk.pcd) comes.
PointSet turned_carton_seen_from_a_corner() {
  const PointSet box = transformed(make_lowpoly_box(Eigen::Vector3d(0.07, 0.07, 0.2), Eigen::Vector3d::Zero()),
                                   Similarity{kTurned, Eigen::Vector3d(0.1, -0.2, 0.9), 1});
  const Eigen::Vector3d towards = kTurned * Eigen::Vector3d(1, 1, 1);
  const auto& P = box.positions();
  return random_surface_points_where(box, 30000, 5, [&](const Eigen::Vector3d&, std::int32_t f) {
    const auto& v = box.faces().col(f);
    return (P.col(v(1)) - P.col(v(0))).cross(P.col(v(2)) - P.col(v(0))).dot(towards) > 0;  // a face seen
  });
}

TEST(BoxAxes, FindsTheFacesOfATurnedBoxMesh) {
  const PointSet box = transformed(make_lowpoly_box(Eigen::Vector3d(1, 2, 3), Eigen::Vector3d::Zero()),
                                   Similarity{kTurned, Eigen::Vector3d::Zero(), 1});
  EXPECT_LT(worst_axis_angle(box_axes(box), kTurned), 0.1);
}

TEST(BoxAxes, FindsTheFacesOfACartonSeenFromACorner) {
  PointSet cloud = turned_carton_seen_from_a_corner();
  cloud.set_normals(Eigen::Matrix3Xd(3, 0));  // a scan without normals: each point's comes from its neighbours
  EXPECT_LT(worst_axis_angle(box_axes(cloud), kTurned), 1.0);
}

// A model drawn square to its axes keeps them exactly, relief and all (the crate's frames and diamonds), so its
// template is its axis-aligned bounding box, as before.
TEST(BoxAxes, KeepsTheAxesOfAModelDrawnSquare) {
  EXPECT_TRUE(box_axes(make_crate()).isIdentity(0));
  EXPECT_TRUE(box_axes(make_lowpoly_box(Eigen::Vector3d(1, 2, 3), Eigen::Vector3d::Zero())).isIdentity(0));
}

// `box:` of the turned carton's scan: eight corners square to its faces, each within 2 mm of the carton's (the scan
// sees three faces, so all three extents); its axis-aligned bounding box is turned and larger.
TEST(BoxAxes, ABoxTemplateOfATurnedScanLiesOnItsFaces) {
  const test::TempDir dir;
  write_ply(dir / "carton.ply", turned_carton_seen_from_a_corner());
  const LoadResult l = load_input(parse_input("box:" + (dir / "carton.ply").string()));
  ASSERT_EQ(l.points.size(), 8);
  EXPECT_NE(l.format.find("square to the faces"), std::string::npos) << l.format;
  for (Index i = 0; i < 8; ++i) {
    const Eigen::Vector3d local = kTurned.transpose() * (l.points.positions().col(i) - Eigen::Vector3d(0.1, -0.2, 0.9));
    EXPECT_LT((local.cwiseAbs() - Eigen::Vector3d(0.035, 0.035, 0.1)).cwiseAbs().maxCoeff(), 0.002) << local;
  }
}

}  // namespace
}  // namespace scanfill
