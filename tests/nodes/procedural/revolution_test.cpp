#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "nodes/core/point_set.h"
#include "nodes/io/read_point_set.h"
#include "nodes/procedural/shapes.h"
#include "test_util.h"

namespace scanfill {
namespace {

// The flat faces of a body of revolution at one end along `axis`: the area of those facing out of the body (along
// -axis at the bottom, +axis at the top), of those facing in, and the radius of the end's outermost vertex.
struct EndFaces {
  double outward = 0, inward = 0, ring = 0;
};

EndFaces end_faces(const PointSet& mesh, const Eigen::Vector3d& axis, const Eigen::Vector3d& centre, bool top) {
  const Eigen::Matrix3Xd& p = mesh.positions();
  const double end = top ? (axis.transpose() * p).maxCoeff() : (axis.transpose() * p).minCoeff();
  const auto at_end = [&](Index i) { return std::abs(axis.dot(p.col(i)) - end) < 1e-9; };
  EndFaces e;
  for (Index i = 0; i < p.cols(); ++i)
    if (at_end(i)) {
      const Eigen::Vector3d d = p.col(i) - centre;
      e.ring = std::max(e.ring, (d - d.dot(axis) * axis).norm());
    }
  for (Index j = 0; j < mesh.faces().cols(); ++j) {
    const auto f = mesh.faces().col(j);
    if (!at_end(f(0)) || !at_end(f(1)) || !at_end(f(2))) continue;
    const Eigen::Vector3d n = (p.col(f(1)) - p.col(f(0))).cross(p.col(f(2)) - p.col(f(0)));
    const double out = (top ? 1 : -1) * n.dot(axis);
    (out > 0 ? e.outward : e.inward) += n.norm() / 2;
  }
  return e;
}

// The end is capped: a disk out to its ring (no gap between the cap and the wall), facing out of the body.
void expect_capped(const EndFaces& e) {
  EXPECT_GT(e.ring, 0);
  EXPECT_NEAR(e.outward, M_PI * e.ring * e.ring, 0.01 * M_PI * e.ring * e.ring);
  EXPECT_EQ(e.inward, 0);
}

void expect_open(const EndFaces& e) {
  EXPECT_EQ(e.outward, 0);
  EXPECT_EQ(e.inward, 0);
}

// A disk of points (no faces) of `radius` at height z about the z axis: the floor of a cup.
PointSet disk_points(double radius, double z) {
  std::vector<Eigen::Vector3d> q;
  for (int i = 0; i <= 24; ++i)
    for (int k = 0; k < 96; ++k) {
      const double r = radius * i / 24, phi = 2 * M_PI * k / 96;
      q.emplace_back(r * std::cos(phi), r * std::sin(phi), z);
    }
  Eigen::Matrix3Xd m(3, Index(q.size()));
  for (size_t i = 0; i < q.size(); ++i) m.col(Index(i)) = q[i];
  return PointSet(std::move(m));
}

const Eigen::Vector3d kZ = Eigen::Vector3d::UnitZ(), kOrigin = Eigen::Vector3d::Zero();

// The cup (the vase as a vessel) is a closed shell facing out: its outer wall, rim and underside face away from the
// wall's material, its inner wall and the floor's top face into the cup. The volume its faces enclose (divergence
// theorem) is the wall's and the floor's, about 2 pi 0.32 x 0.03 x 1 + pi 0.3^2 x 0.03 = 0.069, positive only if every
// face is wound outward.
TEST(ProceduralCup, ItsShellFacesOutAndItsInsideFacesTheAxis) {
  const int segments = 96;
  const PointSet cup = make_cup(segments);
  const Eigen::Matrix3Xd& P = cup.positions();
  // The inner wall's faces follow the vase's (make_cup appends it first): a grid of segments x segments quads.
  const Eigen::Index inner_begin = make_vase(12, 16, segments).faces().cols(),
                     inner_end = inner_begin + 2 * segments * segments;
  double volume = 0;
  Eigen::Index facing_in = 0;
  for (Eigen::Index f = 0; f < cup.faces().cols(); ++f) {
    const Eigen::Vector3d a = P.col(cup.faces()(0, f)), b = P.col(cup.faces()(1, f)), c = P.col(cup.faces()(2, f));
    volume += a.dot(b.cross(c)) / 6;
    const Eigen::Vector3d centre = (a + b + c) / 3, n = (b - a).cross(c - a);
    if (f >= inner_begin && f < inner_end) facing_in += n.head<2>().dot(centre.head<2>()) < 0;
  }
  EXPECT_NEAR(volume, 0.069, 0.015);
  EXPECT_EQ(facing_in, inner_end - inner_begin);
}

TEST(ProceduralRevolution, AClosedCylinderGetsBothCaps) {
  // The column's template: a finely tessellated closed cylinder; and the same drawn low-poly, whose caps are single
  // fans of 24 triangles with no vertex inside the disk but the centre.
  // (About z given: revolution_axis needs more than a low-poly model's few vertices to tell its axis.)
  for (const PointSet& model : {make_column_template(), make_lowpoly_cylinder(0.3, 0.0, 1.2, 24)}) {
    const PointSet body = make_revolution(model, RevolutionAxis{});
    expect_capped(end_faces(body, kZ, kOrigin, false));
    expect_capped(end_faces(body, kZ, kOrigin, true));
    EXPECT_NEAR(end_faces(body, kZ, kOrigin, false).ring, 0.3, 0.003);  // the wall, not pulled in by the floor
  }
}

TEST(ProceduralRevolution, AnOpenTubeGetsNoCap) {
  const PointSet body = make_revolution(make_cylinder(0.3, 1.0, 128));
  expect_open(end_faces(body, kZ, kOrigin, false));
  expect_open(end_faces(body, kZ, kOrigin, true));
  // The procedural vase is a tube too: neither its foot nor its mouth is closed.
  const PointSet vase = make_revolution(make_vase());
  EXPECT_EQ(vase.faces().cols(), make_revolution(make_cylinder(0.3, 1.0, 128)).faces().cols());
  expect_open(end_faces(vase, kZ, kOrigin, false));
  expect_open(end_faces(vase, kZ, kOrigin, true));
}

TEST(ProceduralRevolution, ACupGetsItsFloorButKeepsItsMouthOpen) {
  // The floor as points only: a model need not be a mesh.
  const PointSet cup = merged(make_cylinder(0.3, 1.0, 128), disk_points(0.3, -0.5));
  const PointSet body = make_revolution(cup);
  expect_capped(end_faces(body, kZ, kOrigin, false));
  expect_open(end_faces(body, kZ, kOrigin, true));
  EXPECT_NEAR(end_faces(body, kZ, kOrigin, false).ring, 0.3, 0.003);
  // Upside down: the floor is now the top.
  const Similarity flip{Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()).toRotationMatrix(), kOrigin, 1.0};
  const PointSet bowl = make_revolution(transformed(cup, flip));
  expect_open(end_faces(bowl, kZ, kOrigin, false));
  expect_capped(end_faces(bowl, kZ, kOrigin, true));
}

// A teapot-like model: a tube of radius 0.3 with a spout standing out at +x, drawn with many more vertices than the
// tube. The body of revolution is fitted to the surface, not to the vertices (whose median radius the spout pulled out
// to its own at its height), about the tube's axis, not the bounding box's centre (which the spout moves to +x).
TEST(ProceduralRevolution, ASpoutDrawnFinelyWidensNeitherTheBodyNorMovesItsAxis) {
  const Similarity along_x{Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY()).toRotationMatrix(),
                           Eigen::Vector3d(0.4, 0, 0), 1.0};
  const PointSet spout = transformed(make_cylinder(0.06, 0.2, 1024), along_x);
  const PointSet teapot = merged(make_cylinder(0.3, 1.0, 64), spout);
  ASSERT_GT(spout.size(), 4 * (teapot.size() - spout.size()));
  const RevolutionAxis axis = revolution_axis(teapot);
  EXPECT_GT(std::abs(axis.direction.z()), 0.999);
  EXPECT_LT(axis.centre.head<2>().norm(), 0.01);
  const PointSet body = make_revolution(teapot, axis);
  for (Index i = 0; i < body.size(); ++i) {
    const Eigen::Vector3d x = body.positions().col(i);
    if (std::abs(x.z()) < 0.05) {
      EXPECT_NEAR(x.head<2>().norm(), 0.3, 0.015) << "at height " << x.z();
    }
  }
}

// A lamp with three arms is round about no axis. The axis is centred by the points' spread about their rings, not
// relative to the mean radius, which an axis moved off the model makes ever larger: with that ratio the search ran
// away for minutes. Pushed to its bound of a tenth of the diagonal, the search keeps the bounding box's centre.
TEST(ProceduralRevolution, TheCentringOfALampRoundAboutNoAxisStaysNearIt) {
  SCANFILL_REQUIRE_SHARED_DATA();
  const PointSet lamp = read_point_set(test::shared_data() / "models" / "text2mesh_lamp.obj").points;
  const RevolutionAxis axis = revolution_axis(lamp);
  const BoundingBox box = bounding_box(lamp.positions());
  const Eigen::Vector3d off = axis.centre - (box.min + box.max) / 2;
  EXPECT_LT((off - off.dot(axis.direction) * axis.direction).norm(), 0.01);  // (the centre of its surface samples' box)
}

// How far real models' bodies of revolution are from them (fit_revolution's misfit): the vase's, candle's, teapot's and
// Vase-Lion's, which complete them better than the scan alone, under the 0.2 above which loading warns (0.01-0.10);
// the lamp's (whose template scores F 0.21-0.27 against 0.61-0.73 for the scan alone) and the bunny's over it.
TEST(ProceduralRevolution, TheMisfitSetsRoundModelsApartFromOthers) {
  SCANFILL_REQUIRE_SHARED_DATA();
  const auto misfit = [](const char* file) {
    return fit_revolution(read_point_set(test::shared_data() / "models" / file).points).misfit;
  };
  for (const char* round : {"text2mesh_vase.obj", "text2mesh_candle.obj", "teapot.obj", "vaselion.obj"})
    EXPECT_LT(misfit(round), 0.15) << round;
  for (const char* other : {"text2mesh_lamp.obj", "stanford-bunny.obj"}) EXPECT_GT(misfit(other), 0.25) << other;
  EXPECT_LT(fit_revolution(make_gear()).misfit, 0.05);  // a disk's faces lie on its body's caps
}

TEST(ProceduralRevolution, TheRealCandleIsClosedAtItsFootOnly) {
  SCANFILL_REQUIRE_SHARED_DATA();
  // Drawn y-up: a flat round foot, and a wick that ends in a point.
  const PointSet candle = read_point_set(test::shared_data() / "models" / "text2mesh_candle.obj").points;
  const RevolutionAxis axis = revolution_axis(candle);
  ASSERT_GT(std::abs(axis.direction.y()), 0.999);
  const PointSet body = make_revolution(candle, axis);
  const Eigen::Vector3d up = axis.direction.y() > 0 ? axis.direction : Eigen::Vector3d(-axis.direction);
  const EndFaces foot = end_faces(body, up, axis.centre, false), wick = end_faces(body, up, axis.centre, true);
  expect_capped(foot);
  EXPECT_GT(foot.ring, 0.55);  // the foot's edge (0.6), not the floor's median distance (0.42)
  expect_open(wick);
}

}  // namespace
}  // namespace scanfill
