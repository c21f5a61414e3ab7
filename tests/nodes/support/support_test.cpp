// support node: known answers on T = S ∪ g(part of S), S random samples of a blob (no symmetry). The identity explains
// exactly T's copy of S and g^-1 exactly the moved part (Q maps target to source); a wrong transform explains nearly
// nothing; ICP pulls a perturbed mode back onto the truth; duplicates and small supports are dropped; the distance and
// normal rules hold; extend_supports keeps only extras that explain something new.
#include "nodes/support/support.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "nodes/procedural/shapes.h"
#include "nodes/sample/sample.h"

namespace scanfill {
namespace {

constexpr Index kS = 3000, kMoved = 1800;  // S, and the first kMoved of S (a Morton-ordered chunk) moved by g

Eigen::Matrix3d rot(double angle, const Eigen::Vector3d& axis) {
  return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
}

const Similarity kG{rot(0.8, Eigen::Vector3d(1, 1, 0)), Eigen::Vector3d(3, 0, 0), 1.3};

struct Fixture {
  PointSet source, target;
  double alpha = 0;
};

PointSet with_normals(Eigen::Matrix3Xd p, Eigen::Matrix3Xd n) {
  PointSet out(std::move(p));
  out.set_normals(std::move(n));
  return out;
}

const Fixture& fixture() {
  static const Fixture f = [] {
    Fixture x;
    const PointSet blob = make_blob();
    const PointSet s = random_surface_points(blob, kS, 11);
    x.source = with_normals(s.positions(), s.normals());
    x.alpha = std::sqrt(0.64 * surface_area(blob.positions(), blob.faces()) / double(kS));
    Eigen::Matrix3Xd p(3, kS + kMoved), n(3, kS + kMoved);
    p.leftCols(kS) = s.positions();
    n.leftCols(kS) = s.normals();
    for (Index i = 0; i < kMoved; ++i) {
      p.col(kS + i) = kG.apply(s.positions().col(i));
      n.col(kS + i) = kG.apply_normal(s.normals().col(i));
    }
    x.target = with_normals(p, n);
    return x;
  }();
  return f;
}

// A mode with every `step`-th target sample of [begin, end) as its voters.
Mode mode(const Similarity& q, Index begin, Index end, Index step = 100) {
  Mode m;
  m.transform = q;
  for (Index t = begin; t < end; t += step) m.voters.push_back(std::int32_t(t));
  m.votes = Index(m.voters.size());
  return m;
}

Index inside(const std::vector<std::int32_t>& support, Index begin, Index end) {
  return std::count_if(support.begin(), support.end(), [&](std::int32_t t) { return t >= begin && t < end; });
}

bool near(const Similarity& a, const Similarity& b, double angle, double distance) {
  return rotation_angle(a.rotation.transpose() * b.rotation) < angle &&
         (a.translation - b.translation).norm() < distance && std::abs(a.scale / b.scale - 1) < 1e-3;
}

TEST(Support, IdentityAndTheKnownTransformExplainTheirPartsAndAWrongOneNothing) {
  const Fixture& f = fixture();
  const Similarity wrong{Eigen::Matrix3d::Identity(), Eigen::Vector3d(0.9, 0, 0), 1};
  // Given weakest first: the ranking is the node's.
  const std::vector<Mode> modes{mode(kG.inverse(), kS, kS + kMoved), mode(wrong, 0, kS), mode(Similarity{}, 0, kS)};
  const SupportResult r = grow_supports(f.source, f.target, modes, f.alpha, 3 * f.alpha, {});
  ASSERT_EQ(r.transforms.size(), 2u);
  const SupportedTransform& id = r.transforms[0];
  const SupportedTransform& back = r.transforms[1];
  EXPECT_TRUE(near(id.transform, Similarity{}, 1e-6, 1e-6 * f.alpha));
  EXPECT_TRUE(near(back.transform, kG.inverse(), 1e-6, 1e-6 * f.alpha));
  // Each explains its own part, all of it but what the kNN graph cannot reach from the voters, and nothing else.
  EXPECT_EQ(inside(id.support, 0, kS), Index(id.support.size()));
  EXPECT_GE(Index(id.support.size()), kS * 99 / 100);
  EXPECT_EQ(inside(back.support, kS, kS + kMoved), Index(back.support.size()));
  EXPECT_GE(Index(back.support.size()), kMoved * 99 / 100);
  EXPECT_TRUE(std::is_sorted(id.support.begin(), id.support.end()));
  EXPECT_LT(id.rms, 1e-9);
  EXPECT_LT(back.rms, 1e-9);
}

// The blob is nearly a sphere of radius 0.5: any rotation about its centre explains much of it, and so does a small
// shift, in the band where the shifted sphere crosses the original with normals about 30 degrees apart. A shift by
// nearly the diameter is wrong everywhere: where the distances agree, the normals are over 120 degrees apart, beyond
// the 90 degrees (delta_n) the default accepts.
TEST(Support, AWrongTransformGrowsAlmostNoSupport) {
  const Fixture& f = fixture();
  SupportOptions o;
  o.icp_iterations = 0;
  o.min_support = 1;
  const Similarity wrong{Eigen::Matrix3d::Identity(), Eigen::Vector3d(0.9, 0, 0), 1};
  const SupportResult r = grow_supports(f.source, f.target, {mode(wrong, 0, kS, 1)}, f.alpha, f.alpha, o);
  const Index n = r.transforms.empty() ? 0 : Index(r.transforms[0].support.size());
  EXPECT_LT(n, kS / 25) << "of " << kS;  // the blob is not quite a sphere: a few percent where it bulges
  // The same seeds under the right transform: everything.
  const SupportResult right = grow_supports(f.source, f.target, {mode(Similarity{}, 0, kS, 1)}, f.alpha, f.alpha, o);
  ASSERT_EQ(right.transforms.size(), 1u);
  EXPECT_EQ(Index(right.transforms[0].support.size()), kS);
}

TEST(Support, IcpPullsAPerturbedModeOntoTheTruth) {
  const Fixture& f = fixture();
  // g^-1 off by 1.5 degrees and 1.5 alpha: about what mean shift leaves.
  Similarity off = kG.inverse();
  off.rotation = rot(1.5 * M_PI / 180, Eigen::Vector3d(0, 0, 1)) * off.rotation;
  off.translation += Eigen::Vector3d(1.5 * f.alpha, 0, 0);
  const SupportResult r =
      grow_supports(f.source, f.target, {mode(off, kS, kS + kMoved)}, f.alpha, 4 * f.alpha, SupportOptions{});
  ASSERT_EQ(r.transforms.size(), 1u);
  const Similarity& q = r.transforms[0].transform;
  // Compared on the moved part, where it matters: every sample lands within a tenth of alpha of its source.
  double worst = 0;
  for (Index i = 0; i < kMoved; ++i)
    worst = std::max(worst, (q.apply(f.target.positions().col(kS + i)) - f.source.positions().col(i)).norm());
  EXPECT_LT(worst, 0.1 * f.alpha);
  EXPECT_GE(Index(r.transforms[0].support.size()), kMoved * 99 / 100);
  EXPECT_LT(r.transforms[0].rms, 0.1 * f.alpha);
}

TEST(Support, DuplicatesAndSmallSupportsAreDropped) {
  const Fixture& f = fixture();
  Similarity nudged;
  nudged.translation = Eigen::Vector3d(0, 0.2 * f.alpha, 0);
  // The identity twice (the second nudged): one transform.
  EXPECT_EQ(grow_supports(f.source, f.target, {mode(Similarity{}, 0, kS), mode(nudged, 0, kS)}, f.alpha, f.alpha, {})
                .transforms.size(),
            1u);
  // min_support between the two parts' sizes: only the identity's 3000 stay.
  SupportOptions o;
  o.min_support = 2000;
  const SupportResult r = grow_supports(
      f.source, f.target, {mode(Similarity{}, 0, kS), mode(kG.inverse(), kS, kS + kMoved)}, f.alpha, f.alpha, o);
  ASSERT_EQ(r.transforms.size(), 1u);
  EXPECT_TRUE(near(r.transforms[0].transform, Similarity{}, 1e-6, 1e-6));
}

// ICP can shrink a transform onto a few source samples; every target sample then lands near them, and any whose normal
// is within delta_n is "explained". Such a transform would outrank the real ones, so it is dropped by its scale.
TEST(Support, ATransformShrunkOutOfTheScaleRangeIsDropped) {
  const Fixture& f = fixture();
  const double tiny = 0.003;
  const Eigen::Vector3d centre = f.target.positions().rowwise().mean();
  const Similarity collapsed{Eigen::Matrix3d::Identity(), f.source.positions().col(0) - tiny * centre, tiny};
  const std::vector<Mode> modes{mode(collapsed, 0, kS + kMoved, 10), mode(Similarity{}, 0, kS)};
  SupportOptions o;
  o.icp_iterations = 0;
  const SupportResult r = grow_supports(f.source, f.target, modes, f.alpha, f.alpha, o);
  ASSERT_EQ(r.transforms.size(), 1u);
  EXPECT_TRUE(near(r.transforms[0].transform, Similarity{}, 1e-6, 1e-6));
  o.min_scale = tiny / 2;  // allowed: it then "explains" about half of the whole target
  const SupportResult all = grow_supports(f.source, f.target, modes, f.alpha, f.alpha, o);
  ASSERT_EQ(all.transforms.size(), 2u);
  EXPECT_EQ(all.transforms[1].transform.scale, tiny);
  EXPECT_GT(Index(all.transforms[1].support.size()), (kS + kMoved) / 3);
}

TEST(Support, ASampleIsExplainedOnlyWithinTheDistanceAndTheNormalAngle) {
  const Fixture& f = fixture();
  const Index n = kS;
  const Eigen::Matrix3Xd& p = f.source.positions();
  const Eigen::Matrix3Xd& nn = f.source.normals();
  SupportOptions o;
  o.icp_iterations = 0;
  o.min_support = 1;
  const std::vector<Mode> identity{mode(Similarity{}, 0, n, 1)};
  // S offset by 1.5 alpha along its normals: explained within 2 alpha, not within 1 alpha.
  const PointSet offset = with_normals(p + 1.5 * f.alpha * nn, nn);
  const SupportResult within = grow_supports(f.source, offset, identity, f.alpha, f.alpha, o);
  ASSERT_EQ(within.transforms.size(), 1u);
  EXPECT_EQ(Index(within.transforms[0].support.size()), n);
  o.distance = 1.0;
  const SupportResult beyond = grow_supports(f.source, offset, identity, f.alpha, f.alpha, o);
  EXPECT_LT(beyond.transforms.empty() ? 0 : Index(beyond.transforms[0].support.size()), n / 100);
  // S in place with every normal tilted by 20 degrees: explained within 30 degrees, not within 15.
  o.distance = 2.0;
  Eigen::Matrix3Xd tilted(3, n);
  for (Index i = 0; i < n; ++i) {
    const Eigen::Vector3d axis = nn.col(i).cross(Eigen::Vector3d(1, 2, 3).normalized()).normalized();
    tilted.col(i) = rot(20 * M_PI / 180, axis) * nn.col(i);
  }
  const PointSet turned = with_normals(p, tilted);
  const SupportResult agree = grow_supports(f.source, turned, identity, f.alpha, f.alpha, o);
  ASSERT_EQ(agree.transforms.size(), 1u);
  EXPECT_EQ(Index(agree.transforms[0].support.size()), n);
  o.normal_angle_deg = 15;
  EXPECT_TRUE(grow_supports(f.source, turned, identity, f.alpha, f.alpha, o).transforms.empty());
}

TEST(Support, ExtendKeepsOnlyExtrasThatExplainSomethingNew) {
  const Fixture& f = fixture();
  const SupportResult found = grow_supports(f.source, f.target, {mode(Similarity{}, 0, kS)}, f.alpha, f.alpha, {});
  ASSERT_EQ(found.transforms.size(), 1u);
  // No extras: unchanged.
  EXPECT_EQ(extend_supports(f.source, f.target, found, {}, f.alpha, f.alpha, {}).transforms.size(), 1u);
  // The identity again explains nothing new.
  EXPECT_EQ(
      extend_supports(f.source, f.target, found, {mode(Similarity{}, 0, kS)}, f.alpha, f.alpha, {}).transforms.size(),
      1u);
  // g^-1 explains the moved part: kept, as it is (extras are not refined).
  const SupportResult more =
      extend_supports(f.source, f.target, found, {mode(kG.inverse(), kS, kS + kMoved)}, f.alpha, f.alpha, {});
  ASSERT_EQ(more.transforms.size(), 2u);
  EXPECT_EQ(more.transforms[0].support, found.transforms[0].support);
  EXPECT_TRUE(near(more.transforms[1].transform, kG.inverse(), 1e-6, 1e-9));
  EXPECT_GE(Index(more.transforms[1].support.size()), kMoved * 99 / 100);
  EXPECT_EQ(inside(more.transforms[1].support, kS, kS + kMoved), Index(more.transforms[1].support.size()));
}

// A preferred mode is kept though it explains nothing new, and a near duplicate among the found transforms gives way
// to it: the identity found a degree off (within duplicate_angle_deg) yields to the exact identity preferred.
TEST(Support, ExtendKeepsPreferredModesBeforeTheirNearDuplicates) {
  const Fixture& f = fixture();
  const Similarity off{rot(1.0 * M_PI / 180, Eigen::Vector3d::UnitZ()), Eigen::Vector3d::Zero(), 1};
  SupportOptions o;
  o.icp_iterations = 0;  // keep the found transform a degree off
  const SupportResult found = grow_supports(f.source, f.target, {mode(off, 0, kS)}, f.alpha, f.alpha, o);
  ASSERT_EQ(found.transforms.size(), 1u);
  const SupportResult kept =
      extend_supports(f.source, f.target, found, {}, f.alpha, f.alpha, o, {mode(Similarity{}, 0, kS)});
  ASSERT_EQ(kept.transforms.size(), 1u);
  EXPECT_TRUE(near(kept.transforms[0].transform, Similarity{}, 1e-9, 1e-9));
  EXPECT_GE(Index(kept.transforms[0].support.size()), kS * 99 / 100);
  // Beside the moved part's transform, still strongest first.
  const SupportResult both = extend_supports(f.source, f.target, found, {mode(kG.inverse(), kS, kS + kMoved)}, f.alpha,
                                             f.alpha, o, {mode(Similarity{}, 0, kS)});
  ASSERT_EQ(both.transforms.size(), 2u);
  EXPECT_TRUE(near(both.transforms[0].transform, Similarity{}, 1e-9, 1e-9));
  EXPECT_TRUE(near(both.transforms[1].transform, kG.inverse(), 1e-6, 1e-9));
}

}  // namespace
}  // namespace scanfill
