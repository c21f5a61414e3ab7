// nodes/exchange: the box maps (24 rotations, the non-uniform scale that makes A(box i) = box j) and the box-wise
// analogy's choices (an exact map over a distorting one, a quarter turn for a turned wall, few transforms).
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <set>

#include "nodes/exchange/exchange.h"

namespace scanfill {
namespace {

PartBox box(double x0, double y0, double z0, double x1, double y1, double z1) {
  return {Eigen::Vector3d(x0, y0, z0), Eigen::Vector3d(x1, y1, z1)};
}

TEST(BoxTransform, TwentyFourDistinctProperRotationsIdentityFirst) {
  const auto& rotations = axis_rotations();
  ASSERT_EQ(rotations.size(), 24u);
  EXPECT_TRUE(rotations[0].isIdentity());
  std::set<std::vector<double>> distinct;
  for (const Eigen::Matrix3d& R : rotations) {
    EXPECT_NEAR(R.determinant(), 1.0, 1e-12);
    EXPECT_TRUE((R * R.transpose()).isIdentity(1e-12));
    distinct.insert(std::vector<double>(R.data(), R.data() + 9));
  }
  EXPECT_EQ(distinct.size(), 24u);
}

TEST(BoxTransform, EveryRotationMapsTheSourceBoxOntoTheTargetBox) {
  const PartBox s = box(-1, 0, 2, 3, 1, 4), t = box(5, 5, 0, 6, 9, 3);
  for (int r = 0; r < 24; ++r) {
    const BoxTransform a = box_transform(s, 0, t, 0, r);
    const PartBox image = a.apply(s);
    EXPECT_TRUE(image.min.isApprox(t.min, 1e-12) && image.max.isApprox(t.max, 1e-12)) << r;
    EXPECT_TRUE((a.scales.array() > 0).all());
    // Normals by the inverse transpose: a face normal of s becomes the matching face normal of t.
    const Eigen::Vector3d n = a.apply_normal(Eigen::Vector3d::UnitX());
    EXPECT_NEAR(n.cwiseAbs().maxCoeff(), 1.0, 1e-12);
  }
}

TEST(BoxTransform, DepthIsPositiveInsideAndTheSurfaceDistanceIsItsSize) {
  const PartBox b = box(0, 0, 0, 2, 4, 6);
  EXPECT_NEAR(depth_in_box(b, Eigen::Vector3d(1, 1, 3)), 1.0, 1e-12);
  EXPECT_NEAR(depth_in_box(b, Eigen::Vector3d(5, 4, 6)), -3.0, 1e-12);
  EXPECT_NEAR(distance_to_box_surface(b, Eigen::Vector3d(3, 5, 6)), std::sqrt(2.0), 1e-12);
}

TEST(BoxAnalogy, ATurnedWallTakesTheWallByAQuarterTurnAndTheTowerTakesTheTower) {
  // Source: a tower and a wall along x. Target: a taller tower and a wall along y, in the other order.
  const PartBoxes source{box(0, 0, 0, 2, 2, 6), box(2, 0.5, 0, 10, 1.5, 4)};
  const PartBoxes target{box(0, 2, 0, 1, 9, 4), box(-1, -1, 0, 2, 2, 8)};
  const BoxAnalogy a = label_box_analogy(source, target, {});
  ASSERT_EQ(a.box_source.size(), 2u);
  EXPECT_EQ(a.box_source[0], 1);
  EXPECT_EQ(a.box_source[1], 0);
  const BoxTransform& wall = a.transforms[size_t(a.box_label[0])];
  EXPECT_NEAR(wall.angle(), M_PI / 2, 1e-12);
  EXPECT_NEAR(std::abs(wall.rotation_matrix(2, 2)), 1.0, 1e-12);  // about z: the wall stays upright
  EXPECT_TRUE(wall.scales.isApprox(Eigen::Vector3d(1, 7.0 / 8, 1), 1e-12));
  const BoxTransform& tower = a.transforms[size_t(a.box_label[1])];
  EXPECT_EQ(tower.rotation, 0);
  EXPECT_GT(a.candidates, 24);
  EXPECT_EQ(a.sample_label.size(), size_t(a.samples.points.size()));
}

TEST(BoxAnalogy, OneTranslationServesTwoBoxesWhenTheLayoutRepeats) {
  // Two equal towers 4 apart in both: one map (the shift) explains both target towers.
  const PartBoxes source{box(0, 0, 0, 1, 1, 3), box(4, 0, 0, 5, 1, 3)};
  const PartBoxes target{box(10, 0, 0, 11, 1, 3), box(14, 0, 0, 15, 1, 3)};
  const BoxAnalogy a = label_box_analogy(source, target, {});
  EXPECT_EQ(a.transforms.size(), 1u);
  EXPECT_TRUE(a.transforms[0].translation.isApprox(Eigen::Vector3d(10, 0, 0), 1e-9));
}

TEST(Exchange, SynthesisCarriesEachPartsPointsOntoItsTargetBox) {
  const PartBoxes source{box(0, 0, 0, 1, 1, 1), box(1, 0, 0, 3, 1, 1)};
  const PartBoxes target{box(0, 0, 0, 2, 2, 2)};
  Eigen::Matrix3Xd p(3, 3);
  p << 0.5, 2.0, 1.0, 0.5, 0.5, 0.5, 0.25, 0.5, 0.5;  // part 0, part 1, the shared face (part 0, the lower box)
  PointSet exemplar(p);
  exemplar.set_normals(Eigen::Matrix3Xd::Constant(3, 3, 1.0 / std::sqrt(3.0)));
  const Exchange x = exchange_style(exemplar, source, target, {});
  EXPECT_EQ(assign_parts(p, source), (std::vector<int>{0, 1, 0}));
  ASSERT_EQ(x.analogy.box_source.size(), 1u);
  EXPECT_EQ(x.analogy.box_source[0], 0);  // the unit cube scales uniformly onto the target: no distortion
  ASSERT_EQ(x.output.size(), 2);
  EXPECT_TRUE(x.output.positions().col(0).isApprox(Eigen::Vector3d(1, 1, 0.5), 1e-12));
  EXPECT_NEAR(x.output.normals().col(0).norm(), 1.0, 1e-12);
}

// A source box with none of the exemplar in it would carry nothing: maps start only from boxes that hold some.
TEST(Exchange, ABoxWithoutExemplarPointsIsNoSource) {
  const PartBoxes source{box(100, 100, 100, 101, 101, 101), box(0, 0, 0, 1, 1, 1)};  // equal sizes: a tie on cost
  Eigen::Matrix3Xd p(3, 2);
  p << 0.5, 0.25, 0.5, 0.25, 0.5, 0.25;
  const Exchange x = exchange_style(PointSet(p), source, {box(5, 5, 5, 6, 6, 6)}, {});
  EXPECT_EQ(x.analogy.box_source, std::vector<int>{1});
  EXPECT_EQ(x.output.size(), 2);
}

}  // namespace
}  // namespace scanfill
