// label node: the label costs of eq. 9 (ours and the paper's, as printed), and the MRF of the paper's 5-alpha ring.
#include "nodes/label/label.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
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

}  // namespace
}  // namespace scanfill
