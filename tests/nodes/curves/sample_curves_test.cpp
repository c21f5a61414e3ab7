#include "nodes/curves/sample_curves.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "nodes/core/errors.h"

namespace scanfill {
namespace {

Polyline circle(double r, int n, bool clockwise, Eigen::Vector2d centre = Eigen::Vector2d::Zero()) {
  Polyline c;
  c.closed = true;
  c.points.resize(2, n);
  for (int i = 0; i < n; ++i) {
    const double a = (clockwise ? -2 : 2) * M_PI * i / n;
    c.points.col(i) = centre + r * Eigen::Vector2d(std::cos(a), std::sin(a));
  }
  return c;
}

TEST(SampleCurves, CircleHasCurvatureOneOverRadiusAndOutwardNormals) {
  for (const bool clockwise : {false, true}) {
    const double r = 2.0, spacing = 0.05;
    const CurveSamples s = sample_curves({circle(r, 2000, clockwise, {3, 1})}, spacing, {});
    EXPECT_NEAR(double(s.samples.size()), 2 * M_PI * r / spacing, 1.0);
    for (Index i = 0; i < s.samples.size(); ++i) {
      const Eigen::Vector3d radial = (s.samples.positions().col(i) - Eigen::Vector3d(3, 1, 0)).normalized();
      EXPECT_GT(s.samples.normals().col(i).dot(radial), 0.9999) << i;
      EXPECT_NEAR(s.samples.curvatures()(0, i), 1 / r, 0.01) << i;
      EXPECT_EQ(s.samples.curvatures()(1, i), 0.0);
      EXPECT_EQ(s.samples.positions()(2, i), 0.0);
      // Frame (d1, n x d1, n) = (d1, z, n): d1 = z x n.
      EXPECT_TRUE(s.samples.normals().col(i).cross(s.samples.directions().col(i)).isApprox(Eigen::Vector3d::UnitZ()));
    }
  }
}

TEST(SampleCurves, EqualArcLengthStepsOnASquare) {
  Polyline sq;
  sq.closed = true;
  sq.points.resize(2, 4);
  sq.points << 0, 1, 1, 0, 0, 0, 1, 1;
  const CurveSamples s = sample_curves({sq}, 0.01, {});
  ASSERT_EQ(s.samples.size(), 400);
  for (Index i = 1; i < s.samples.size(); ++i)
    EXPECT_NEAR((s.samples.positions().col(i) - s.samples.positions().col(i - 1)).norm(), 0.01, 1e-9);
  // Mid-edge samples are straight with outward normals; samples at a corner turn by a quarter over the stencil.
  EXPECT_NEAR(s.samples.curvatures()(0, 50), 0.0, 1e-9);
  EXPECT_TRUE(s.samples.normals().col(50).isApprox(Eigen::Vector3d(0, -1, 0)));
  EXPECT_NEAR(s.samples.curvatures()(0, 100), M_PI / 2 / 0.01, 1e-6);
  EXPECT_EQ(s.curve.size(), 400u);
  EXPECT_NEAR(s.arc[200], 2.0, 1e-12);
}

TEST(SampleCurves, OpenCurveNormalsPointAwayFromTheDrawing) {
  Polyline arc;  // upper half circle, open; its normals should point up and out
  arc.points.resize(2, 181);
  for (int i = 0; i <= 180; ++i)
    arc.points.col(i) = Eigen::Vector2d(std::cos(i * M_PI / 180), std::sin(i * M_PI / 180));
  const CurveSamples s = sample_curves({arc}, 0.02, {});
  EXPECT_EQ(s.samples.size(), Index(std::llround(M_PI / 0.02)) + 1);  // both ends sampled
  EXPECT_GT(s.samples.normals()(1, s.samples.size() / 2), 0.99);
  // The input is a polygon of 1-degree chords, shorter than the stencil: its turning is measured to ~2%.
  EXPECT_NEAR(s.samples.curvatures()(0, s.samples.size() / 2), 1.0, 0.03);
  EXPECT_THROW(sample_curves({arc}, 1.0, {}), InputError);  // 4 samples
}

TEST(OrderIntoCurves, ShuffledSamplesComeBackAsTheirCurves) {
  Polyline line;
  line.points.resize(2, 2);
  line.points << 5, 8, 0, 0;
  const CurveSamples target = sample_curves({circle(1, 720, false), line}, 0.05, {});
  Eigen::Matrix3Xd shuffled = target.samples.positions();
  std::mt19937 rng(3);
  for (Index i = shuffled.cols() - 1; i > 0; --i) shuffled.col(i).swap(shuffled.col(Index(rng() % (i + 1))));
  const Curves out = order_into_curves(shuffled, target, {});
  ASSERT_EQ(out.size(), 2u);
  EXPECT_TRUE(out[0].closed);
  EXPECT_FALSE(out[1].closed);
  EXPECT_NEAR(curve_length(out[0]), curve_length(circle(1, 720, false)), 0.01);
  EXPECT_NEAR(curve_length(out[1]), 3.0, 1e-9);
  // A hole in the circle cuts it open: one open polyline.
  Eigen::Matrix3Xd holed(3, shuffled.cols());
  Index n = 0;
  for (Index i = 0; i < target.samples.size(); ++i)
    if (target.curve[size_t(i)] == 0 && (target.arc[size_t(i)] < 1 || target.arc[size_t(i)] > 1.5))
      holed.col(n++) = target.samples.positions().col(i);
  const Curves cut = order_into_curves(holed.leftCols(n), target, {});
  ASSERT_EQ(cut.size(), 1u);  // after the hole, across the start point, up to the hole
  EXPECT_FALSE(cut[0].closed);
  EXPECT_NEAR(curve_length(cut[0]), 2 * M_PI - 0.5, 0.06);
}

}  // namespace
}  // namespace scanfill
