// vote node: known answers on shapes whose features are given exactly. T is S moved by a known similarity g, every
// feature (position, normal, k1 direction, curvatures) carried with it, so the pair of a target sample and its own
// source sample votes for exactly Q = g^-1 (target -> source), and nothing else concentrates there. Also: the
// embedding's metric and round trip, the scale range and the rigid rule, the flat-point rule, the voter sample.
#include "nodes/vote/vote.h"
#include "nodes/curves/sample_curves.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>
#include <set>

#include "nodes/core/errors.h"

namespace scanfill {
namespace {

constexpr double kSpacing = 0.02;

Eigen::Matrix3d rot(double angle, const Eigen::Vector3d& axis) {
  return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
}

// n samples in the unit cube around the origin with random frames and curvatures: |k1| in [2, 10] (curved: |k1|
// alpha >= 0.04 > flat_curvature), k2 / k1 in [-0.6, 0.6] (no umbilics: two rotations per pair), k1 of either sign.
PointSet random_features(Index n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-0.5, 0.5);
  std::normal_distribution<double> g;
  Eigen::Matrix3Xd p(3, n), nn(3, n), d(3, n);
  Eigen::Matrix2Xd k(2, n);
  for (Index i = 0; i < n; ++i) {
    p.col(i) = Eigen::Vector3d(u(rng), u(rng), u(rng));
    const Eigen::Vector3d normal = Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
    const Eigen::Vector3d any(g(rng), g(rng), g(rng));
    nn.col(i) = normal;
    d.col(i) = (any - any.dot(normal) * normal).normalized();
    const double k1 = (u(rng) > 0 ? 1 : -1) * (6 + 8 * u(rng));
    k.col(i) = Eigen::Vector2d(k1, 1.2 * u(rng) * k1);
  }
  PointSet out(p);
  out.set_normals(nn);
  out.set_directions(d);
  out.set_curvatures(k);
  return out;
}

// The samples moved by g: positions mapped, normals and directions rotated, curvatures divided by the scale.
PointSet moved(const PointSet& s, const Similarity& g) {
  Eigen::Matrix3Xd p(3, s.size()), n(3, s.size()), d(3, s.size());
  for (Index i = 0; i < s.size(); ++i) {
    p.col(i) = g.apply(s.positions().col(i));
    n.col(i) = g.apply_normal(s.normals().col(i));
    d.col(i) = g.apply_normal(s.directions().col(i));
  }
  PointSet out(p);
  out.set_normals(n);
  out.set_directions(d);
  out.set_curvatures(s.curvatures() / g.scale);
  return out;
}

PointSet concatenated(const PointSet& a, const PointSet& b) {
  Eigen::Matrix3Xd p(3, a.size() + b.size()), n(3, a.size() + b.size()), d(3, a.size() + b.size());
  Eigen::Matrix2Xd k(2, a.size() + b.size());
  p << a.positions(), b.positions();
  n << a.normals(), b.normals();
  d << a.directions(), b.directions();
  k << a.curvatures(), b.curvatures();
  PointSet out(p);
  out.set_normals(n);
  out.set_directions(d);
  out.set_curvatures(k);
  return out;
}

// Votes within `radius` of the embedding of q, and the distinct target samples that cast them.
struct Near {
  Index votes = 0;
  std::set<std::int32_t> voters;
};
Near near(const VoteResult& r, const Similarity& q, double radius) {
  const Eigen::Matrix<double, 13, 1> x = embed(q, r);
  Near out;
  for (Index v = 0; v < r.embedding.cols(); ++v)
    if ((r.embedding.col(v) - x).norm() < radius) {
      ++out.votes;
      out.voters.insert(r.voter[size_t(v)]);
    }
  return out;
}

std::set<std::int32_t> range(std::int32_t begin, std::int32_t end) {
  std::set<std::int32_t> s;
  for (std::int32_t i = begin; i < end; ++i) s.insert(i);
  return s;
}

const Similarity kG{rot(0.7, Eigen::Vector3d(1, 2, 3)), Eigen::Vector3d(0.3, -0.2, 0.5), 1.4};

TEST(Vote, EveryTargetSampleVotesOnceForTheKnownTransform) {
  const PointSet S = random_features(500, 1), T = moved(S, kG);
  const VoteOptions o;
  const VoteResult r = vote(S, T, kSpacing, o);
  // All 500 target samples vote (500 < target_samples), 12 matches each, 2 rotations per pair (no umbilics).
  EXPECT_EQ(std::set<std::int32_t>(r.voter.begin(), r.voter.end()), range(0, 500));
  EXPECT_EQ(r.pairs, r.embedding.cols());
  EXPECT_LE(r.pairs, 500 * 12 * 2);  // fewer: pairs of opposite bending or outside the scale range do not vote
  // Q = g^-1 exactly once per target sample (its own source sample, d1 unflipped), up to round-off.
  const Near exact = near(r, kG.inverse(), 1e-6);
  EXPECT_EQ(exact.votes, 500);
  EXPECT_EQ(exact.voters, range(0, 500));
}

TEST(Vote, TheKnownTransformIsTheDensestVoteCluster) {
  const PointSet S = random_features(400, 2), T = moved(S, kG);
  const VoteOptions o;
  const VoteResult r = vote(S, T, kSpacing, o);
  const double bandwidth = 0.25;  // the modes node's default kernel radius
  const Index at_truth = near(r, kG.inverse(), bandwidth).votes;
  EXPECT_EQ(at_truth, 400);  // random wrong votes do not fall near it either
  // No wrong vote has a tenth of that many votes around it.
  const auto truth = embed(kG.inverse(), r);
  Index densest_elsewhere = 0;
  for (Index v = 0; v < r.embedding.cols(); v += 3) {
    if ((r.embedding.col(v) - truth).norm() < 2 * bandwidth) continue;
    Index around = 0;
    for (Index w = 0; w < r.embedding.cols(); ++w)
      around += (r.embedding.col(w) - r.embedding.col(v)).norm() < bandwidth;
    densest_elsewhere = std::max(densest_elsewhere, around);
  }
  EXPECT_LT(densest_elsewhere, at_truth / 10);
}

TEST(Vote, TwoCopiesVoteForTheirOwnTransforms) {
  const PointSet S = random_features(300, 3);
  const Similarity g1{Eigen::Matrix3d::Identity(), Eigen::Vector3d(-1.5, 0, 0), 1.0};
  const Similarity g2{rot(M_PI / 2, Eigen::Vector3d::UnitZ()), Eigen::Vector3d(1.5, 0, 0), 0.8};
  const PointSet T = concatenated(moved(S, g1), moved(S, g2));
  const VoteOptions o;
  const VoteResult r = vote(S, T, kSpacing, o);
  const Near first = near(r, g1.inverse(), 1e-6), second = near(r, g2.inverse(), 1e-6);
  EXPECT_EQ(first.votes, 300);
  EXPECT_EQ(second.votes, 300);
  // Each copy's samples vote for their own copy's transform, and only they.
  EXPECT_EQ(first.voters, range(0, 300));
  EXPECT_EQ(second.voters, range(300, 600));
}

TEST(Vote, ScalesOutsideTheRangeAreNotVotedFor) {
  // T = 5 S: Q = g^-1 has scale 0.2, below the default min_scale 0.25. T's curvatures are a fifth of S's, so alpha is
  // taken large enough (0.06) that they still count as curved (|k1| alpha >= 0.024 > flat_curvature).
  const double alpha = 0.06;
  const PointSet S = random_features(200, 4);
  const Similarity g{Eigen::Matrix3d::Identity(), Eigen::Vector3d(0.1, 0, 0), 5.0};
  const PointSet T = moved(S, g);
  VoteOptions o;
  const VoteResult r = vote(S, T, alpha, o);
  EXPECT_EQ(near(r, g.inverse(), 1e-6).votes, 0);
  for (Index v = 0; v < r.embedding.cols(); ++v) {
    const double s = unembed(r.embedding.col(v), r).scale;
    EXPECT_GE(s, o.min_scale * (1 - 1e-12));
    EXPECT_LE(s, o.max_scale * (1 + 1e-12));
  }
  o.min_scale = 0.1;
  EXPECT_EQ(near(vote(S, T, alpha, o), g.inverse(), 1e-6).votes, 200);
}

// Votes whose rotation is R (the first nine embedding coordinates), whatever their translation and scale.
Index with_rotation(const VoteResult& r, const Eigen::Matrix3d& R) {
  const Eigen::Matrix<double, 13, 1> x = embed(Similarity{R, Eigen::Vector3d::Zero(), 1}, r);
  Index n = 0;
  for (Index v = 0; v < r.embedding.cols(); ++v) n += (r.embedding.col(v).head<9>() - x.head<9>()).norm() < 1e-6;
  return n;
}

TEST(Vote, RigidVotesHaveUnitScaleAndNeedAgreeingCurvatures) {
  const PointSet S = random_features(200, 5);
  VoteOptions o;
  o.allow_scale = false;
  Similarity g = kG;
  g.scale = 1.0;
  const VoteResult r = vote(S, moved(S, g), kSpacing, o);
  EXPECT_EQ(near(r, g.inverse(), 1e-6).votes, 200);
  for (Index v = 0; v < r.embedding.cols(); ++v) EXPECT_EQ(r.embedding(12, v), 0.0);  // log 1
  // A rigid vote needs curvatures within a ratio of 1.5: at scale 1.3 the true pairs still vote (with scale 1, so
  // only their rotation is right), at scale 2 they do not.
  g.scale = 1.3;
  EXPECT_EQ(with_rotation(vote(S, moved(S, g), kSpacing, o), g.rotation.transpose()), 200);
  g.scale = 2.0;
  EXPECT_EQ(with_rotation(vote(S, moved(S, g), kSpacing, o), g.rotation.transpose()), 0);
}

TEST(Vote, UmbilicsVoteWithFourRotations) {
  // k2 = k1 everywhere: one signature class, so with one match per target sample every target sample pairs with
  // source sample 0 (the first of the class); a quarter turn of d1 is as good as d1, so the pair votes four times.
  PointSet S = random_features(100, 6);
  Eigen::Matrix2Xd k = S.curvatures().cwiseAbs();  // all bending the same way: no pair is skipped
  k.row(1) = k.row(0);
  S.set_curvatures(k);
  const PointSet T = moved(S, kG);
  VoteOptions o;
  o.matches_per_point = 1;
  o.min_scale = 0.05;  // every curvature ratio (0.14 to 3.6) inside the range
  const VoteResult r = vote(S, T, kSpacing, o);
  EXPECT_EQ(r.pairs, 100 * 4);
  // Only target sample 0 met its own source sample: one vote for g^-1, its own.
  const Near exact = near(r, kG.inverse(), 1e-6);
  EXPECT_EQ(exact.votes, 1);
  EXPECT_EQ(exact.voters, range(0, 1));
}

TEST(Vote, FlatSamplesVoteOnlyWhenTooFewAreCurved) {
  // 1000 target samples of which `curved` are curved; the rest flat (k = 0).
  const auto make = [](Index curved) {
    PointSet p = random_features(1000, 7);
    Eigen::Matrix2Xd k = p.curvatures();
    for (Index i = curved; i < p.size(); ++i) k.col(i).setZero();
    p.set_curvatures(k);
    return p;
  };
  const VoteOptions o;  // min_curved_fraction 0.05
  const PointSet many = make(100), few = make(30);
  // 10% curved: only the curved ones vote.
  const VoteResult r1 = vote(many, many, kSpacing, o);
  EXPECT_EQ(std::set<std::int32_t>(r1.voter.begin(), r1.voter.end()), range(0, 100));
  // 3% curved: everyone votes; a flat sample pairs with 12 flat source samples under 4 rotations each.
  const VoteResult r2 = vote(few, few, kSpacing, o);
  EXPECT_EQ(std::set<std::int32_t>(r2.voter.begin(), r2.voter.end()), range(0, 1000));
  Index flat_votes = 0;
  for (const auto t : r2.voter) flat_votes += t >= 30;
  EXPECT_EQ(flat_votes, 970 * 12 * 4);
  // Flat pairs have scale 1.
  for (Index v = 0; v < r2.embedding.cols(); ++v) {
    if (r2.voter[size_t(v)] >= 30) {
      EXPECT_EQ(r2.embedding(12, v), 0.0);
    }
  }
}

TEST(Vote, TargetSamplesBoundsTheVotersAndTheSeedChoosesThem) {
  const PointSet S = random_features(500, 8);
  VoteOptions o;
  o.target_samples = 100;
  const VoteResult a = vote(S, S, kSpacing, o), b = vote(S, S, kSpacing, o);
  const std::set<std::int32_t> va(a.voter.begin(), a.voter.end());
  EXPECT_EQ(va.size(), 100u);
  EXPECT_TRUE(std::is_sorted(a.voter.begin(), a.voter.end()));
  EXPECT_EQ(a.embedding, b.embedding);  // deterministic
  EXPECT_EQ(a.voter, b.voter);
  o.seed = 2;
  const VoteResult c = vote(S, S, kSpacing, o);
  EXPECT_NE(std::set<std::int32_t>(c.voter.begin(), c.voter.end()), va);
  // S against itself: the identity gets exactly one vote per voter.
  EXPECT_EQ(near(a, Similarity{}, 1e-9).votes, 100);
}

TEST(Vote, TheEmbeddingFrameIsTheBoxOfBothShapes) {
  PointSet S(Eigen::Matrix3Xd::Zero(3, 1)), T(Eigen::Matrix3Xd::Constant(3, 1, 2.0));
  for (PointSet* p : {&S, &T}) {
    p->set_normals(Eigen::Vector3d::UnitZ());
    p->set_directions(Eigen::Vector3d::UnitX());
    p->set_curvatures(Eigen::Vector2d(5, 1));
  }
  const VoteResult r = vote(S, T, kSpacing, {});
  EXPECT_EQ(r.center, Eigen::Vector3d(1, 1, 1));
  EXPECT_DOUBLE_EQ(r.diagonal, 2 * std::sqrt(3.0));
  // One pair, two rotations (d1 and -d1); both translate T's point onto S's.
  ASSERT_EQ(r.pairs, 2);
  for (Index v = 0; v < 2; ++v) EXPECT_LT(unembed(r.embedding.col(v), r).apply(Eigen::Vector3d(2, 2, 2)).norm(), 1e-12);
}

// Shapes standing turned in the world's frame, with their own axes given, are embedded as unturned: the same box
// diagonal (the world's box of the turned shapes is 28% larger here), so the same translation scale, about the turned
// centre; the embedded votes of each pair are as far apart as unturned.
TEST(Vote, TheEmbeddingFrameIsTheBoxInTheShapesOwnAxes) {
  PointSet S = random_features(300, 5);
  Eigen::Matrix3Xd p = S.positions();
  p.row(0) *= 0.8;
  p.row(1) *= 0.5;
  p.row(2) *= 0.6;
  S = PointSet(p);
  S.set_normals(random_features(300, 5).normals());
  S.set_directions(random_features(300, 5).directions());
  S.set_curvatures(random_features(300, 5).curvatures());
  const PointSet T = moved(S, Similarity{Eigen::Matrix3d::Identity(), Eigen::Vector3d(0.1, 0, 0), 1.0});
  const Similarity turn{rot(20 * M_PI / 180, Eigen::Vector3d::UnitX()) * rot(30 * M_PI / 180, Eigen::Vector3d::UnitZ()),
                        Eigen::Vector3d::Zero(), 1.0};
  const VoteResult drawn = vote(S, T, kSpacing, {});
  VoteOptions own;
  own.axes = turn.rotation;
  const VoteResult turned = vote(moved(S, turn), moved(T, turn), kSpacing, own);
  EXPECT_NEAR(turned.diagonal, drawn.diagonal, 1e-9);
  EXPECT_LT((turned.center - turn.apply(drawn.center)).norm(), 1e-9);
  EXPECT_GT(vote(moved(S, turn), moved(T, turn), kSpacing, {}).diagonal, 1.2 * drawn.diagonal);
  ASSERT_EQ(turned.embedding.cols(), drawn.embedding.cols());
  for (Index v = 1; v < drawn.embedding.cols(); ++v)
    EXPECT_NEAR((turned.embedding.col(v) - turned.embedding.col(v - 1)).norm(),
                (drawn.embedding.col(v) - drawn.embedding.col(v - 1)).norm(), 1e-6);
}

TEST(Vote, EmbeddingDistancesAreChordalRotationScaledTranslationAndLogScale) {
  VoteResult frame;
  frame.center = Eigen::Vector3d(1, 2, 3);
  frame.diagonal = 4.0;
  const VoteOptions o;  // w_R 1, w_t 8, w_s 2
  const Similarity a{rot(0.3, Eigen::Vector3d(1, 0, 1)), Eigen::Vector3d(0.5, 0, -1), 1.5};
  // Rotation: the Frobenius (chordal) distance 2 sqrt(2) sin(theta / 2).
  Similarity b = a;
  b.rotation = rot(0.8, Eigen::Vector3d(0, 1, 0)) * a.rotation;
  EXPECT_NEAR((embed(a, frame) - embed(b, frame)).norm(), o.rotation_weight * 2 * std::sqrt(2.0) * std::sin(0.4),
              1e-12);
  // Translation: w_t |dt| / diagonal.
  Similarity c = a;
  c.translation += Eigen::Vector3d(0.3, 0.4, 0);
  EXPECT_NEAR((embed(a, frame) - embed(c, frame)).norm(), o.translation_weight * 0.5 / 4.0, 1e-12);
  // Scale: w_s |log(s_a / s_d)|.
  Similarity d = a;
  d.scale = 3.0;
  EXPECT_NEAR((embed(a, frame) - embed(d, frame)).norm(), o.scale_weight * std::log(2.0), 1e-12);
  // Round trip.
  const Similarity back = unembed(embed(a, frame), frame);
  EXPECT_LT((back.rotation - a.rotation).norm(), 1e-12);
  EXPECT_LT((back.translation - a.translation).norm(), 1e-12);
  EXPECT_NEAR(back.scale, a.scale, 1e-12);
}

TEST(Vote, MissingFeaturesOrEmptyShapesThrow) {
  const PointSet S = random_features(50, 9);
  const PointSet bare(S.positions());
  EXPECT_THROW(vote(S, bare, kSpacing, {}), InputError);
  EXPECT_THROW(vote(bare, S, kSpacing, {}), InputError);
  PointSet empty(Eigen::Matrix3Xd(3, 0));
  empty.set_normals(Eigen::Matrix3Xd(3, 0));
  empty.set_directions(Eigen::Matrix3Xd(3, 0));
  empty.set_curvatures(Eigen::Matrix2Xd(2, 0));
  EXPECT_THROW(vote(S, empty, kSpacing, {}), InputError);
}

// Curves in the z = 0 plane (mode curves): planar votes are motions of the plane, one per pair; without planar, the
// second frame of each pair (-d1) turns z over, a mirror image of the drawing.
TEST(Vote, PlanarVotesKeepToThePlane) {
  Polyline blob;
  blob.closed = true;
  blob.points.resize(2, 360);
  for (int i = 0; i < 360; ++i) {
    const double t = 2 * M_PI * i / 360, r = 1 + 0.3 * std::cos(t) + 0.1 * std::sin(2 * t);
    blob.points.col(i) = r * Eigen::Vector2d(std::cos(t), std::sin(t));
  }
  const CurveSamples s = sample_curves({blob}, 0.02, {});
  VoteOptions o;
  const auto flipped = [](const VoteResult& v) {
    Index n = 0;
    for (Index k = 0; k < v.embedding.cols(); ++k) n += unembed(v.embedding.col(k), v).rotation(2, 2) < 0;  // R z . z
    return n;
  };
  const VoteResult spatial = vote(s.samples, s.samples, s.spacing, o);
  EXPECT_GT(flipped(spatial), spatial.embedding.cols() / 3);
  o.planar = true;
  const VoteResult planar = vote(s.samples, s.samples, s.spacing, o);
  EXPECT_EQ(flipped(planar), 0);
  EXPECT_EQ(planar.pairs, planar.embedding.cols());
  for (Index k = 0; k < planar.embedding.cols(); ++k)
    EXPECT_NEAR(unembed(planar.embedding.col(k), planar).rotation(2, 2), 1.0, 1e-9);
}

}  // namespace
}  // namespace scanfill
