// Similarity transforms (nodes/core/similarity.h): known rotations, composition and inversion against the formulas,
// the rotation helpers on the 24 axis rotations, and the Umeyama and point-to-plane fits recovering a known transform.
#include "nodes/core/similarity.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

namespace scanfill {
namespace {

using Eigen::Index;

constexpr double kEps = 1e-12;

Eigen::Matrix3d rot(double angle, const Eigen::Vector3d& axis) {
  return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
}

// A generic similarity: no axis rotation, a scale other than 1, a translation off every axis.
Similarity generic() {
  return Similarity{rot(0.7, Eigen::Vector3d(1, 2, 3)), Eigen::Vector3d(0.3, -0.2, 0.5), 1.7};
}

Eigen::Matrix3Xd random_points(Index n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  Eigen::Matrix3Xd p(3, n);
  for (Index i = 0; i < n; ++i) p.col(i) = Eigen::Vector3d(u(rng), u(rng), u(rng));
  return p;
}

TEST(Similarity, AQuarterTurnAboutZMapsXToYAndYToMinusX) {
  const Similarity q{rot(M_PI / 2, Eigen::Vector3d::UnitZ()), Eigen::Vector3d::Zero(), 1};
  EXPECT_LT((q.apply(Eigen::Vector3d::UnitX()) - Eigen::Vector3d::UnitY()).norm(), kEps);
  EXPECT_LT((q.apply(Eigen::Vector3d::UnitY()) + Eigen::Vector3d::UnitX()).norm(), kEps);
  EXPECT_LT((q.apply(Eigen::Vector3d::UnitZ()) - Eigen::Vector3d::UnitZ()).norm(), kEps);
}

TEST(Similarity, ApplyScalesAndRotatesThenTranslatesAndNormalsOnlyRotate) {
  // x -> 2 Rz(90) x + (1, 0, 0): (1, 0, 0) -> (0, 2, 0) + (1, 0, 0).
  const Similarity q{rot(M_PI / 2, Eigen::Vector3d::UnitZ()), Eigen::Vector3d(1, 0, 0), 2};
  EXPECT_LT((q.apply(Eigen::Vector3d(1, 0, 0)) - Eigen::Vector3d(1, 2, 0)).norm(), kEps);
  EXPECT_LT((q.apply(Eigen::Vector3d::Zero()) - Eigen::Vector3d(1, 0, 0)).norm(), kEps);
  // A normal is a direction: no scale, no translation, still unit.
  const Eigen::Vector3d n = q.apply_normal(Eigen::Vector3d::UnitX());
  EXPECT_LT((n - Eigen::Vector3d::UnitY()).norm(), kEps);
}

TEST(Similarity, ComposeAppliesTheRightOperandFirst) {
  const Similarity a{rot(M_PI / 2, Eigen::Vector3d::UnitZ()), Eigen::Vector3d::Zero(), 1};
  const Similarity b{Eigen::Matrix3d::Identity(), Eigen::Vector3d(1, 0, 0), 1};
  // a(b(0)) = Rz(90) (1, 0, 0) = (0, 1, 0); b(a(0)) = (1, 0, 0).
  EXPECT_LT((a.compose(b).apply(Eigen::Vector3d::Zero()) - Eigen::Vector3d(0, 1, 0)).norm(), kEps);
  EXPECT_LT((b.compose(a).apply(Eigen::Vector3d::Zero()) - Eigen::Vector3d(1, 0, 0)).norm(), kEps);
  const Similarity g = generic(), h{rot(-1.2, Eigen::Vector3d(0, 1, -1)), Eigen::Vector3d(-2, 0.1, 4), 0.4};
  const Eigen::Matrix3Xd p = random_points(50, 1);
  for (Index i = 0; i < p.cols(); ++i)
    EXPECT_LT((g.compose(h).apply(p.col(i)) - g.apply(h.apply(p.col(i)))).norm(), 1e-12);
  EXPECT_NEAR(g.compose(h).scale, 1.7 * 0.4, kEps);
}

TEST(Similarity, InverseUndoesTheTransformFromEitherSide) {
  const Similarity g = generic();
  const Similarity gi = g.inverse();
  EXPECT_NEAR(gi.scale, 1 / 1.7, kEps);
  for (const Similarity& id : {g.compose(gi), gi.compose(g)}) {
    EXPECT_LT((id.rotation - Eigen::Matrix3d::Identity()).norm(), 1e-12);
    EXPECT_LT(id.translation.norm(), 1e-12);
    EXPECT_NEAR(id.scale, 1.0, kEps);
  }
  const Eigen::Matrix3Xd p = random_points(50, 2);
  for (Index i = 0; i < p.cols(); ++i) EXPECT_LT((gi.apply(g.apply(p.col(i))) - p.col(i)).norm(), 1e-12);
  // The inverse of the inverse is the transform itself.
  const Similarity gii = gi.inverse();
  EXPECT_LT((gii.rotation - g.rotation).norm(), 1e-12);
  EXPECT_LT((gii.translation - g.translation).norm(), 1e-12);
  EXPECT_NEAR(gii.scale, g.scale, kEps);
}

TEST(Similarity, LogScalesAddUnderComposition) {
  // The vote embedding measures scale as log s: composing similarities adds their log scales.
  const Similarity a{Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero(), 2.0};
  const Similarity b{rot(0.3, Eigen::Vector3d::UnitX()), Eigen::Vector3d(1, 1, 1), 0.125};
  EXPECT_NEAR(std::log(a.compose(b).scale), std::log(2.0) + std::log(0.125), kEps);
  EXPECT_NEAR(std::log(a.inverse().scale), -std::log(2.0), kEps);
}

TEST(Similarity, RotationAngleAndAxisOfKnownRotations) {
  EXPECT_NEAR(rotation_angle(Eigen::Matrix3d::Identity()), 0.0, 1e-7);
  EXPECT_NEAR(rotation_angle(rot(M_PI / 2, Eigen::Vector3d::UnitZ())), M_PI / 2, 1e-12);
  EXPECT_NEAR(rotation_angle(rot(M_PI, Eigen::Vector3d(1, 1, 0))), M_PI, 1e-7);
  // Angles are in [0, pi]: a turn by -0.4 is a turn by 0.4 about the opposite axis.
  EXPECT_NEAR(rotation_angle(rot(-0.4, Eigen::Vector3d(1, 2, 3))), 0.4, 1e-12);
  const Eigen::Vector3d axis = Eigen::Vector3d(1, 2, 3).normalized();
  EXPECT_LT((rotation_axis(rot(0.4, axis)) - axis).norm(), 1e-12);
  EXPECT_LT((rotation_axis(rot(-0.4, axis)) + axis).norm(), 1e-12);
  EXPECT_LT((rotation_axis(Eigen::Matrix3d::Identity()) - Eigen::Vector3d::UnitZ()).norm(), kEps);
}

TEST(Similarity, NearestRotationKeepsARotationAndNeverReturnsAReflection) {
  const Eigen::Matrix3d R = rot(0.9, Eigen::Vector3d(-1, 0.5, 2));
  EXPECT_LT((nearest_rotation(R) - R).norm(), 1e-12);
  // A scaled, slightly perturbed rotation projects back onto it.
  Eigen::Matrix3d M = 3.0 * R;
  M(0, 1) += 1e-4;
  EXPECT_LT((nearest_rotation(M) - R).norm(), 1e-4);
  // A reflection (det -1) goes to a proper rotation.
  const Eigen::Matrix3d F = Eigen::Vector3d(1, 1, -1).asDiagonal();
  const Eigen::Matrix3d P = nearest_rotation(F * R);
  EXPECT_NEAR(P.determinant(), 1.0, 1e-12);
  EXPECT_LT((P.transpose() * P - Eigen::Matrix3d::Identity()).norm(), 1e-12);
}

TEST(Similarity, ExactlyTheTwentyFourAxisRotationsAreAxisRotations) {
  // All signed permutation matrices: 48, of which the 24 with det +1 are rotations mapping axes to axes.
  int proper = 0, accepted = 0;
  const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (const auto& perm : perms)
    for (int signs = 0; signs < 8; ++signs) {
      Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
      for (int r = 0; r < 3; ++r) A(r, perm[r]) = (signs >> r & 1) ? -1 : 1;
      if (A.determinant() < 0) continue;
      ++proper;
      accepted += is_axis_rotation(A, 1e-9);
      // Within tolerance: a 1 degree wobble passes at 2 degrees, fails at half a degree.
      const Eigen::Matrix3d W = A * rot(M_PI / 180, Eigen::Vector3d(1, 1, 1));
      EXPECT_TRUE(is_axis_rotation(W, 2 * M_PI / 180));
      EXPECT_FALSE(is_axis_rotation(W, 0.5 * M_PI / 180));
    }
  EXPECT_EQ(proper, 24);
  EXPECT_EQ(accepted, 24);
  EXPECT_FALSE(is_axis_rotation(rot(M_PI / 4, Eigen::Vector3d::UnitZ()), 0.1));
  EXPECT_FALSE(is_axis_rotation(rot(0.7, Eigen::Vector3d(1, 2, 3)), 0.1));
}

TEST(Similarity, UmeyamaFitRecoversAKnownSimilarityAndRigidMotion) {
  const Eigen::Matrix3Xd from = random_points(40, 3);
  const Similarity g = generic();
  Eigen::Matrix3Xd to(3, from.cols());
  for (Index i = 0; i < from.cols(); ++i) to.col(i) = g.apply(from.col(i));
  const Similarity q = fit_similarity(from, to, true);
  EXPECT_LT((q.rotation - g.rotation).norm(), 1e-9);
  EXPECT_LT((q.translation - g.translation).norm(), 1e-9);
  EXPECT_NEAR(q.scale, 1.7, 1e-9);
  EXPECT_NEAR(q.rotation.determinant(), 1.0, 1e-12);

  // Rigid: the same data without scale gives scale 1 exactly; with an unscaled g the fit is exact too.
  EXPECT_EQ(fit_similarity(from, to, false).scale, 1.0);
  Similarity rigid = g;
  rigid.scale = 1;
  for (Index i = 0; i < from.cols(); ++i) to.col(i) = rigid.apply(from.col(i));
  const Similarity r = fit_similarity(from, to, false);
  EXPECT_LT((r.rotation - rigid.rotation).norm(), 1e-9);
  EXPECT_LT((r.translation - rigid.translation).norm(), 1e-9);
}

TEST(Similarity, UmeyamaFitOfTooFewOrMismatchedPointsIsTheIdentity) {
  const Eigen::Matrix3Xd two = random_points(2, 4), three = random_points(3, 5);
  for (const Similarity& q :
       {fit_similarity(two, (two.array() + 1.0).matrix(), true), fit_similarity(three, two, true)}) {
    EXPECT_EQ(q.rotation, Eigen::Matrix3d::Identity());
    EXPECT_EQ(q.translation, Eigen::Vector3d::Zero());
    EXPECT_EQ(q.scale, 1.0);
  }
}

// Points on the six faces of a cube (every motion is constrained by some face) with their normals.
void cube_samples(Eigen::Matrix3Xd& points, Eigen::Matrix3Xd& normals) {
  std::mt19937_64 rng(6);
  std::uniform_real_distribution<double> u(-0.5, 0.5);
  const int per_face = 40;
  points.resize(3, 6 * per_face);
  normals.resize(3, 6 * per_face);
  for (int f = 0; f < 6; ++f)
    for (int k = 0; k < per_face; ++k) {
      Eigen::Vector3d n = Eigen::Vector3d::Zero();
      n(f / 2) = f % 2 ? -1 : 1;
      Eigen::Vector3d p(u(rng), u(rng), u(rng));
      p(f / 2) = 0.5 * n(f / 2);
      points.col(f * per_face + k) = p;
      normals.col(f * per_face + k) = n;
    }
}

TEST(Similarity, PointToPlaneStepsConvergeToAKnownSmallMotion) {
  Eigen::Matrix3Xd to, normals;
  cube_samples(to, normals);
  // from = truth^-1(to): the exact correspondences of the cube under a small known similarity.
  const Similarity truth{rot(0.05, Eigen::Vector3d(1, -2, 0.5)), Eigen::Vector3d(0.02, -0.01, 0.03), 1.03};
  const Similarity inv = truth.inverse();
  Eigen::Matrix3Xd from(3, to.cols());
  for (Index i = 0; i < to.cols(); ++i) from.col(i) = inv.apply(to.col(i));
  Similarity q;  // identity start
  for (int it = 0; it < 8; ++it) {
    Eigen::Matrix3Xd moved(3, from.cols());
    for (Index i = 0; i < from.cols(); ++i) moved.col(i) = q.apply(from.col(i));
    q = point_to_plane_step(q, moved, to, normals, true);
  }
  EXPECT_LT(rotation_angle(q.rotation.transpose() * truth.rotation), 1e-6);
  EXPECT_LT((q.translation - truth.translation).norm(), 1e-6);
  EXPECT_NEAR(q.scale, truth.scale, 1e-6);
}

TEST(Similarity, PointToPlaneStepAtTheSolutionStaysAndWithTooFewPointsDoesNothing) {
  Eigen::Matrix3Xd to, normals;
  cube_samples(to, normals);
  const Similarity start{rot(0.2, Eigen::Vector3d::UnitY()), Eigen::Vector3d(1, 2, 3), 0.5};
  // Already aligned: the step is the identity, so q comes back unchanged.
  const Similarity same = point_to_plane_step(start, to, to, normals, true);
  EXPECT_LT((same.rotation - start.rotation).norm(), 1e-9);
  EXPECT_LT((same.translation - start.translation).norm(), 1e-9);
  EXPECT_NEAR(same.scale, start.scale, 1e-12);
  // Fewer than 7 correspondences: q is returned as it is, whatever the residuals.
  const Similarity few =
      point_to_plane_step(start, to.leftCols(6), (to.leftCols(6).array() + 0.1).matrix(), normals.leftCols(6), true);
  EXPECT_EQ(few.rotation, start.rotation);
  EXPECT_EQ(few.translation, start.translation);
  EXPECT_EQ(few.scale, start.scale);
}

TEST(Similarity, RigidPointToPlaneStepsKeepTheScale) {
  Eigen::Matrix3Xd to, normals;
  cube_samples(to, normals);
  const Similarity truth{rot(0.03, Eigen::Vector3d(0, 1, 1)), Eigen::Vector3d(-0.02, 0.01, 0.0), 1.0};
  const Similarity inv = truth.inverse();
  Eigen::Matrix3Xd from(3, to.cols());
  for (Index i = 0; i < to.cols(); ++i) from.col(i) = inv.apply(to.col(i));
  Similarity q;
  q.scale = 1.0;
  for (int it = 0; it < 8; ++it) {
    Eigen::Matrix3Xd moved(3, from.cols());
    for (Index i = 0; i < from.cols(); ++i) moved.col(i) = q.apply(from.col(i));
    q = point_to_plane_step(q, moved, to, normals, false);
    EXPECT_EQ(q.scale, 1.0);
  }
  EXPECT_LT(rotation_angle(q.rotation.transpose() * truth.rotation), 1e-6);
  EXPECT_LT((q.translation - truth.translation).norm(), 1e-6);
}

}  // namespace
}  // namespace scanfill
