#include "nodes/eval/evaluate.h"

#include <gtest/gtest.h>

#include "nodes/core/errors.h"
#include "nodes/procedural/shapes.h"

namespace scanfill {
namespace {

TEST(Eval, IdenticalSurfacesScorePerfectly) {
  const PointSet sphere = make_sphere(0.5, 96);
  const EvalResult r = evaluate(sphere, sphere, {.surface_samples = 50000});
  // Two independent random samplings of one surface: distances of the order of the sampling gap only.
  EXPECT_LT(r.chamfer_l1, 0.004);
  EXPECT_DOUBLE_EQ(r.fscore, 1.0);
  EXPECT_GT(r.normal_consistency, 0.99);
  EXPECT_FALSE(r.unseen_detail_recall.has_value());
}

TEST(Eval, ConcentricSpheresAreTheirRadiusGapApart) {
  const double gap = 0.03;
  Similarity grow;
  grow.scale = (0.5 + gap) / 0.5;
  const PointSet inner = make_sphere(0.5, 128), outer = transformed(inner, grow);
  const EvalResult r = evaluate(outer, inner, {.threshold = 0.01, .surface_samples = 100000});
  EXPECT_NEAR(r.chamfer_l1, gap, 0.1 * gap);
  EXPECT_NEAR(r.chamfer_l2, gap * gap, 0.2 * gap * gap);
  EXPECT_NEAR(r.hausdorff, gap, 0.3 * gap);
  EXPECT_NEAR(r.tau, 0.01 * std::sqrt(3.0), 0.01 * 0.05);  // 1% of the unit sphere box diagonal, 0.0173 < gap
  EXPECT_DOUBLE_EQ(r.fscore, 0.0);
  const EvalResult loose = evaluate(outer, inner, {.threshold = 0.03, .surface_samples = 100000});  // tau 0.052
  EXPECT_DOUBLE_EQ(loose.fscore, 1.0);
}

TEST(Eval, UnseenDetailRecallSeparatesStyleFromTemplateFilling) {
  // The fluted vase seen from +x only; the template is its plain body. A template-filling completion (scan where seen,
  // template elsewhere) must score 0 on unseen detail; the complete vase scores 1.
  const PointSet vase = make_vase(), plain = make_vase_template();
  auto half = [](const PointSet& mesh, bool positive) {
    Eigen::Matrix3Xd keep(3, mesh.size());
    Index n = 0;
    for (Index i = 0; i < mesh.size(); ++i)
      if ((mesh.positions()(0, i) > 0) == positive) keep.col(n++) = mesh.positions().col(i);
    return PointSet(Eigen::Matrix3Xd(keep.leftCols(n)));
  };
  const PointSet scan = half(vase, true);
  const PointSet filled = merged(scan, half(plain, false));
  const EvalOptions o{.threshold = 0.005, .surface_samples = 150000};
  const EvalResult baseline = evaluate(filled, vase, o, &scan, &plain);
  ASSERT_TRUE(baseline.unseen_detail_recall.has_value());
  EXPECT_GT(baseline.unseen_detail_points, 1000);
  EXPECT_LT(*baseline.unseen_detail_recall, 0.05);
  const EvalResult perfect = evaluate(vase, vase, o, &scan, &plain);
  EXPECT_GT(*perfect.unseen_detail_recall, 0.95);
}

TEST(Eval, RefusesHalfTheUnseenDetailInputs) {
  const PointSet sphere = make_sphere(0.5, 32);
  EXPECT_THROW(evaluate(sphere, sphere, {}, &sphere, nullptr), InputError);
  EXPECT_THROW(evaluate(PointSet(), sphere, {}), InputError);
}

}  // namespace
}  // namespace scanfill
