// label node: the label costs of eq. 9 (ours and the paper's, as printed), and the MRF of the paper's 5-alpha ring.
#include "nodes/label/label.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <array>
#include <cmath>

#include "nodes/features/estimate_features.h"
#include "nodes/procedural/shapes.h"
#include "nodes/sample/sample.h"

namespace scanfill {
namespace {

struct Box {
  PointSet samples;
  double spacing = 0;
};

const Box& box() {
  static const Box b = [] {
    const SampleResult s = sample(make_shape("box"), {.count = 1500});
    return Box{estimate_features(s.samples, {}).points, s.spacing};
  }();
  return b;
}

SupportedTransform about(const Eigen::Vector3d& axis, double deg, double scale = 1.0) {
  SupportedTransform t;
  t.transform.rotation = Eigen::AngleAxisd(deg * M_PI / 180, axis.normalized()).toRotationMatrix();
  t.transform.scale = scale;
  t.support = {0, 1, 2};
  return t;
}

TEST(Label, ThePapersLabelCostsAreZeroForTheIdentityAndNLn2ForAxisRotations) {
  LabelOptions o;
  o.paper_label_costs = true;
  const std::vector<SupportedTransform> transforms{
      about(Eigen::Vector3d::UnitZ(), 0),   about(Eigen::Vector3d::UnitZ(), 90),
      about(Eigen::Vector3d::UnitX(), 180), about(Eigen::Vector3d::UnitY(), 270),
      about(Eigen::Vector3d::UnitZ(), 30),  about(Eigen::Vector3d::UnitZ(), 0, 1.5)};
  const LabelResult r = label_target(box().samples, box().samples, transforms, box().spacing, o);
  const double n = double(box().samples.size());
  ASSERT_EQ(r.label_costs.size(), transforms.size());
  EXPECT_DOUBLE_EQ(r.label_costs[0], 0.0);
  for (int l = 1; l <= 3; ++l) EXPECT_NEAR(r.label_costs[size_t(l)], n * std::log(2.0), 1e-6 * n) << l;
  // 30 degrees about z: -log of exp(cos 120 deg - 1) on top of ln 2.
  EXPECT_NEAR(r.label_costs[4], n * (std::log(2.0) + 1 - std::cos(4 * M_PI / 6)), 1e-6 * n);
  EXPECT_NEAR(r.label_costs[5], n * (std::log(2.0) + 0.25), 1e-6 * n);  // (s - 1)^2 at s = 1.5
}

TEST(Label, OurLabelCostsPreferAQuarterTurnAboutTheVerticalToTurningOver) {
  const LabelOptions o;
  const std::vector<SupportedTransform> transforms{
      about(Eigen::Vector3d::UnitZ(), 0), about(Eigen::Vector3d::UnitZ(), 90), about(Eigen::Vector3d::UnitX(), 180),
      about(Eigen::Vector3d::UnitZ(), 30)};
  const LabelResult r = label_target(box().samples, box().samples, transforms, box().spacing, o);
  const double base = o.label_cost_per_sample * double(box().samples.size());
  EXPECT_DOUBLE_EQ(r.label_costs[0], base);
  EXPECT_DOUBLE_EQ(r.label_costs[1], base);                          // an axis rotation about the vertical
  EXPECT_DOUBLE_EQ(r.label_costs[2], base * (1 + o.upright_prior));  // upside down
  EXPECT_NEAR(r.label_costs[3], base * (1 + o.rotation_prior * 30.0 / 45), 1e-9 * base);
}

TEST(Label, TheUprightPriorFollowsTheUpDirection) {
  // A model drawn y-up: with up = +y, the quarter turn about y is the upright one, and one about z turns it over.
  LabelOptions o;
  o.up = Eigen::Vector3d(0, 2, 0);  // any length
  const std::vector<SupportedTransform> transforms{
      about(Eigen::Vector3d::UnitY(), 90), about(Eigen::Vector3d::UnitZ(), 180), about(Eigen::Vector3d::UnitZ(), 90)};
  const LabelResult r = label_target(box().samples, box().samples, transforms, box().spacing, o);
  const double base = o.label_cost_per_sample * double(box().samples.size());
  EXPECT_DOUBLE_EQ(r.label_costs[0], base);
  EXPECT_NEAR(r.label_costs[1], base * (1 + o.upright_prior), 1e-9 * base);
  EXPECT_NEAR(r.label_costs[2], base * (1 + o.upright_prior / 2), 1e-9 * base);
}

TEST(Label, TheRingMrfLabelsAnIdentityAnalogyAsTheIdentity) {
  // S = T: the identity, supported everywhere, explains every sample, with either neighbourhood.
  SupportedTransform identity_everywhere = about(Eigen::Vector3d::UnitZ(), 0);
  identity_everywhere.support.resize(size_t(box().samples.size()));
  for (size_t t = 0; t < identity_everywhere.support.size(); ++t) identity_everywhere.support[t] = std::int32_t(t);
  for (const double radius : {0.0, 5.0}) {
    LabelOptions o;
    o.mrf_radius = radius;
    const LabelResult r = label_target(box().samples, box().samples, {identity_everywhere}, box().spacing, o);
    Index identity = 0;
    for (const int l : r.labels) identity += l == 0;
    EXPECT_EQ(identity, box().samples.size()) << "mrf_radius " << radius;
    EXPECT_LT(r.energy_after, r.energy_before);
  }
}

// A 0.6 cube's samples with features, and its +x, +y and +z faces (the seen ones) as a source.
struct SeenCube {
  PointSet cube, source;
  std::vector<std::int32_t> seen;
  double spacing = 0;
};

SeenCube seen_cube() {
  const SampleResult s = sample(make_box(Eigen::Vector3d(0.6, 0.6, 0.6)), {.count = 3000});
  SeenCube c{estimate_features(s.samples, {}).points, {}, {}, s.spacing};
  for (Index t = 0; t < c.cube.size(); ++t)
    if (c.cube.normals().col(t).maxCoeff() > 0.9) c.seen.push_back(std::int32_t(t));
  c.source = subset(c.cube, c.seen);
  return c;
}

// A cube seen from the +x, +y and +z sides (the source) against the whole cube (the target), with three candidates:
// the identity, the flip about the horizontal diagonal (1, -1, 0) (-x, -y and the bottom onto +y, +x and the top) and
// the half turn about z (-x, -y onto +x, +y), expanded in that order. The flip alone covers all three unseen faces, so
// label costs alone pick it for the side faces too, turning their style upside down; the per-sample upright unary makes
// each side-face sample prefer the half turn, and leaves the flip the bottom, where nothing upright fits.
TEST(Label, EachSampleOnAnUnseenSideFacePrefersTheHalfTurnAboutTheVerticalToAFlip) {
  const SeenCube c = seen_cube();
  const PointSet &cube = c.cube, &source = c.source;
  std::vector<SupportedTransform> transforms{about(Eigen::Vector3d::UnitZ(), 0), about(Eigen::Vector3d(1, -1, 0), 180),
                                             about(Eigen::Vector3d::UnitZ(), 180)};
  for (auto& q : transforms) {
    q.support.resize(size_t(cube.size()));
    for (size_t t = 0; t < q.support.size(); ++t) q.support[t] = std::int32_t(t);
  }
  auto side_and_bottom_labels = [&](double upright_unary) {
    LabelOptions o;
    o.upright_unary = upright_unary;
    const LabelResult r = label_target(source, cube, transforms, c.spacing, o);
    std::array<Index, 3> side{}, bottom{};  // per label, on the -x / -y faces and on the bottom
    for (Index t = 0; t < cube.size(); ++t) {
      const int l = r.labels[size_t(t)];
      if (l > 2) continue;
      if (cube.normals().col(t).z() < -0.9) ++bottom[size_t(l)];
      if (cube.normals().col(t).head<2>().minCoeff() < -0.9) ++side[size_t(l)];
    }
    return std::pair{side, bottom};
  };
  const auto [side, bottom] = side_and_bottom_labels(LabelOptions{}.upright_unary);
  const Index sides = side[0] + side[1] + side[2];
  EXPECT_GT(side[2], 95 * sides / 100) << "the half turn about z on the unseen side faces";
  EXPECT_GT(bottom[1], 95 * (bottom[0] + bottom[1] + bottom[2]) / 100) << "the flip on the bottom";
  const auto [side0, bottom0] = side_and_bottom_labels(0.0);
  EXPECT_GT(side0[1], 95 * sides / 100) << "without it, label costs alone let the flip take the side faces";
}

// The same cube with the identity supported on its seen faces only: on the bottom, away from its edges, no upright
// transform is feasible, and the flip is the only one that carries the seen top there. The upright unary is then no
// cost to it: even at a weight far above the plain copy's (self_cost 8), the bottom takes the flip, not a copy.
TEST(Label, WhereNoUprightTransformIsFeasibleTheFlipPaysNoUprightUnary) {
  const SeenCube c = seen_cube();
  const PointSet &cube = c.cube, &source = c.source;
  std::vector<SupportedTransform> transforms{about(Eigen::Vector3d::UnitZ(), 0), about(Eigen::Vector3d(1, -1, 0), 180)};
  transforms[0].support = c.seen;
  for (Index t = 0; t < cube.size(); ++t)
    if (cube.normals().col(t).maxCoeff() < 0.9) transforms[1].support.push_back(std::int32_t(t));
  LabelOptions o;
  o.upright_unary = 20;
  const LabelResult r = label_target(source, cube, transforms, c.spacing, o);
  Index bottom = 0, flipped = 0;
  for (Index t = 0; t < cube.size(); ++t)
    if (cube.normals().col(t).z() < -0.9 && cube.positions().col(t).head<2>().cwiseAbs().maxCoeff() < 0.2) {
      ++bottom;
      flipped += r.labels[size_t(t)] == 1;
    }
  ASSERT_GT(bottom, 100);
  EXPECT_GT(flipped, 95 * bottom / 100);
}

// The cube seen on its +x side only, with the quarter turn about y that tips that side onto the bottom (the cube on its
// side) and the quarter turn about z that carries it onto the +y side, each supported on the face it fills. The tip
// is not feasible on the bottom where caps do not take tips (completion), and the bottom stays a plain copy; where
// they do (analogy and transfer, the default here) the tip takes the bottom.
TEST(Label, ATransformThatTipsTheObjectOverIsNotFeasibleOnItsCaps) {
  const SeenCube c = seen_cube();
  std::vector<std::int32_t> plus_x;
  for (Index t = 0; t < c.cube.size(); ++t)
    if (c.cube.normals().col(t).x() > 0.9) plus_x.push_back(std::int32_t(t));
  const PointSet source = subset(c.cube, plus_x);
  std::vector<SupportedTransform> transforms{about(Eigen::Vector3d::UnitY(), -90),
                                             about(Eigen::Vector3d::UnitZ(), -90)};
  for (Index t = 0; t < c.cube.size(); ++t) {
    if (c.cube.normals().col(t).z() < -0.9) transforms[0].support.push_back(std::int32_t(t));
    if (c.cube.normals().col(t).y() > 0.9) transforms[1].support.push_back(std::int32_t(t));
  }
  const auto tipped_on_bottom = [&](bool caps_take_tips) {
    LabelOptions o;
    o.caps_take_tips = caps_take_tips;
    const LabelResult r = label_target(source, c.cube, transforms, c.spacing, o);
    Index bottom = 0, tipped = 0, turned = 0, plus_y = 0;
    for (Index t = 0; t < c.cube.size(); ++t) {
      const int l = r.labels[size_t(t)];
      if (c.cube.normals().col(t).z() < -0.9) ++bottom, tipped += l == 0;
      if (c.cube.normals().col(t).y() > 0.9) ++plus_y, turned += l == 1;
    }
    EXPECT_GT(turned, 9 * plus_y / 10) << "the quarter turn about the vertical fills the +y side";
    return double(tipped) / double(bottom);
  };
  EXPECT_EQ(tipped_on_bottom(false), 0.0);
  EXPECT_GT(tipped_on_bottom(true), 0.9);
}

// A closed cylinder (z axis) seen over 165 degrees of its side (from -70 to 95 degrees about z) as the source, against
// the whole cylinder, with the turns about z every 30 degrees as candidates, as composed_candidates offers them for a
// body of revolution. Each turn is supported where it carries a sample onto the seen arc. Every turn fits the template
// alike, so label costs and the pairwise term alone leave the back to whichever turns the expansion reached first
// (turns of 30, 60, 120 and 150 degrees). The quarter unary lets each sample prefer the quarter and half turns, which
// carry a relief facing front (a vase's knob) onto the back's middle, not 30 degrees beside it.
TEST(Label, OnABodyOfRevolutionEachSamplePrefersQuarterAndHalfTurnsToOtherTurns) {
  const SampleResult s = sample(make_shape("cylinder"), {.count = 4000});
  const PointSet cylinder = estimate_features(s.samples, {}).points;
  const auto angle_of = [](const Eigen::Vector3d& p) {  // degrees about z from +x, in (-180, 180]
    return std::atan2(p.y(), p.x()) * 180 / M_PI;
  };
  const auto seen = [&](const Eigen::Vector3d& p) { return angle_of(p) > -70 && angle_of(p) < 95; };
  std::vector<std::int32_t> front;
  for (Index t = 0; t < cylinder.size(); ++t)
    if (seen(cylinder.positions().col(t))) front.push_back(std::int32_t(t));
  const PointSet source = subset(cylinder, front);
  std::vector<SupportedTransform> transforms;
  for (int k = 0; k < 12; ++k) {
    SupportedTransform q = about(Eigen::Vector3d::UnitZ(), 30.0 * k);
    q.support.clear();
    for (Index t = 0; t < cylinder.size(); ++t)
      if (seen(q.transform.apply(cylinder.positions().col(t)))) q.support.push_back(std::int32_t(t));
    transforms.push_back(q);
  }
  const auto quarter_share = [&](double quarter_unary) {  // on the back's middle, within 45 degrees of 192.5
    LabelOptions o;
    o.quarter_unary = quarter_unary;
    const LabelResult r = label_target(source, cylinder, transforms, s.spacing, o);
    Index middle = 0, quarter = 0;
    for (Index t = 0; t < cylinder.size(); ++t) {
      const double a = angle_of(cylinder.positions().col(t));
      if (std::abs(cylinder.normals()(2, t)) > 0.1 || std::abs(std::remainder(a - 192.5, 360.0)) > 45) continue;
      ++middle;
      quarter += r.labels[size_t(t)] < 12 && r.labels[size_t(t)] % 3 == 0;
    }
    return double(quarter) / double(std::max<Index>(middle, 1));
  };
  EXPECT_GT(quarter_share(LabelOptions{}.quarter_unary), 0.95);
  EXPECT_LT(quarter_share(0.0), 0.8) << "without it, other turns take part of the back's middle";
}

}  // namespace
}  // namespace scanfill
