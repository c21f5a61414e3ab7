// modes node: mean shift on synthetic votes drawn (seeded) around known transforms, with known counts and voters, over
// a sparse uniform background: the modes are those transforms, ranked by votes, and max_modes, min_votes and the
// merging of near modes hold.
#include "nodes/modes/modes.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

namespace scanfill {
namespace {

Eigen::Matrix3d rot(double angle, const Eigen::Vector3d& axis) {
  return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
}

struct Cluster {
  Similarity centre;
  Index votes;
  std::int32_t first_voter;  // its votes come from voters first_voter ... first_voter + votes / 2 - 1, twice each
};

// Votes around each cluster's embedding (per-coordinate Gaussian noise of `sigma`, far inside the 0.25 bandwidth),
// then `background` votes uniform in [-3, 3]^13 from voters 100000 and up.
VoteResult synthetic_votes(const std::vector<Cluster>& clusters, double sigma, Index background, std::uint64_t seed) {
  VoteResult r;
  r.center = Eigen::Vector3d(0.5, 0.5, 0.5);
  r.diagonal = 2.0;
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0, sigma);
  std::uniform_real_distribution<double> u(-3, 3);
  Index total = background;
  for (const auto& c : clusters) total += c.votes;
  r.embedding.resize(13, total);
  Index v = 0;
  for (const auto& c : clusters) {
    const Eigen::Matrix<double, 13, 1> x = embed(c.centre, r);
    for (Index k = 0; k < c.votes; ++k, ++v) {
      for (int d = 0; d < 13; ++d) r.embedding(d, v) = x(d) + noise(rng);
      r.voter.push_back(c.first_voter + std::int32_t(k / 2));
    }
  }
  for (Index k = 0; k < background; ++k, ++v) {
    for (int d = 0; d < 13; ++d) r.embedding(d, v) = u(rng);
    r.voter.push_back(100000 + std::int32_t(k));
  }
  r.pairs = total;
  return r;
}

// Three well-separated transforms; listed weakest first, so that the ranking is the node's doing.
const std::vector<Cluster> kClusters = {
    {Similarity{rot(0.5, Eigen::Vector3d::UnitX()), Eigen::Vector3d(0.2, 0.1, 0.9), 1.3}, 100, 1000},
    {Similarity{rot(M_PI / 2, Eigen::Vector3d::UnitZ()), Eigen::Vector3d(-0.4, 0.3, 0.0), 1.0}, 300, 0},
    {Similarity{Eigen::Matrix3d::Identity(), Eigen::Vector3d(0.6, 0.5, 0.4), 0.8}, 200, 500},
};

void expect_near(const Similarity& got, const Similarity& want, const std::string& what) {
  EXPECT_LT(rotation_angle(got.rotation.transpose() * want.rotation), 0.01) << what;
  EXPECT_LT((got.translation - want.translation).norm(), 0.005) << what;
  EXPECT_NEAR(got.scale, want.scale, 0.01 * want.scale) << what;
}

TEST(Modes, FindsTheKnownCentresRankedByVotes) {
  const VoteResult votes = synthetic_votes(kClusters, 0.02, 300, 1);
  const ModesResult r = find_modes(votes, {});
  ASSERT_EQ(r.modes.size(), 3u);  // background seeds gather far fewer than min_votes
  EXPECT_GT(r.seeds, 3);
  // By decreasing votes: the 300, 200 and 100 clusters; every vote of a cluster lies within the bandwidth of its mode.
  const int order[3] = {1, 2, 0};
  for (int m = 0; m < 3; ++m) {
    const Cluster& c = kClusters[size_t(order[m])];
    const Mode& mode = r.modes[size_t(m)];
    EXPECT_EQ(mode.votes, c.votes) << "mode " << m;
    expect_near(mode.transform, c.centre, "mode " + std::to_string(m));
    // Its voters: the cluster's, each once, ascending.
    std::vector<std::int32_t> want;
    for (std::int32_t k = 0; k < std::int32_t(c.votes / 2); ++k) want.push_back(c.first_voter + k);
    EXPECT_EQ(mode.voters, want) << "mode " << m;
  }
}

TEST(Modes, TheRotationOfAModeIsARotation) {
  const ModesResult r = find_modes(synthetic_votes(kClusters, 0.05, 0, 2), {});
  ASSERT_EQ(r.modes.size(), 3u);
  for (const Mode& m : r.modes) {
    EXPECT_NEAR(m.transform.rotation.determinant(), 1.0, 1e-9);
    EXPECT_LT((m.transform.rotation.transpose() * m.transform.rotation - Eigen::Matrix3d::Identity()).norm(), 1e-9);
  }
}

TEST(Modes, MaxModesKeepsTheStrongest) {
  const VoteResult votes = synthetic_votes(kClusters, 0.02, 300, 3);
  ModesOptions o;
  o.max_modes = 2;
  const ModesResult r = find_modes(votes, o);
  ASSERT_EQ(r.modes.size(), 2u);
  EXPECT_EQ(r.modes[0].votes, 300);
  EXPECT_EQ(r.modes[1].votes, 200);
  o.max_modes = 1;
  const ModesResult one = find_modes(votes, o);
  ASSERT_EQ(one.modes.size(), 1u);
  expect_near(one.modes[0].transform, kClusters[1].centre, "strongest");
}

TEST(Modes, MinVotesDropsWeakModes) {
  const VoteResult votes = synthetic_votes(kClusters, 0.02, 300, 4);
  ModesOptions o;
  o.min_votes = 150;
  const ModesResult r = find_modes(votes, o);
  ASSERT_EQ(r.modes.size(), 2u);
  EXPECT_EQ(r.modes[0].votes, 300);
  EXPECT_EQ(r.modes[1].votes, 200);
  // min_votes 1: every background vote alone is a mode of its own too (they are far apart in 13-D).
  o.min_votes = 1;
  o.max_modes = 1000;
  EXPECT_EQ(find_modes(votes, o).modes.size(), 3u + 300u);
}

TEST(Modes, CentresCloserThanTheBandwidthBecomeOneMode) {
  // Two clusters 0.1 apart in the embedding (a translation difference of 0.1 diag / w_t): one mode at their mean.
  Similarity a{rot(0.3, Eigen::Vector3d::UnitY()), Eigen::Vector3d(0.1, 0.2, 0.3), 1.0};
  Similarity b = a;
  b.translation.x() += 0.1 * 2.0 / 8.0;
  const VoteResult votes = synthetic_votes({{a, 100, 0}, {b, 100, 1000}}, 0.01, 0, 5);
  const ModesResult r = find_modes(votes, {});
  ASSERT_EQ(r.modes.size(), 1u);
  EXPECT_EQ(r.modes[0].votes, 200);
  Similarity mid = a;
  mid.translation.x() += 0.05 * 2.0 / 8.0;
  expect_near(r.modes[0].transform, mid, "merged");
  // Far apart (0.6 > bandwidth) they stay two.
  b.translation.x() = a.translation.x() + 0.6 * 2.0 / 8.0;
  EXPECT_EQ(find_modes(synthetic_votes({{a, 100, 0}, {b, 100, 1000}}, 0.01, 0, 6), {}).modes.size(), 2u);
}

TEST(Modes, MaxSeedsBoundsTheSeeds) {
  const VoteResult votes = synthetic_votes(kClusters, 0.02, 300, 7);
  ModesOptions o;
  o.max_seeds = 5;
  EXPECT_EQ(find_modes(votes, o).seeds, 5);
  o.max_seeds = 100000;
  // Every background vote sits in a bin of its own: at least 300 bins, plus the clusters' few.
  const Index all = find_modes(votes, o).seeds;
  EXPECT_GE(all, 303);
  EXPECT_LE(all, 300 + 600);
}

TEST(Modes, NoVotesNoModes) {
  VoteResult none;
  const ModesResult r = find_modes(none, {});
  EXPECT_TRUE(r.modes.empty());
  EXPECT_EQ(r.seeds, 0);
}

TEST(Modes, AccuracyIsTheBandwidthInModelUnits) {
  VoteResult votes;
  votes.diagonal = 2.0;
  votes.weights.translation = 8.0;
  ModesOptions o;
  o.bandwidth = 0.25;
  EXPECT_DOUBLE_EQ(mode_accuracy(votes, o), 0.0625);  // 0.25 of the embedding = 0.25 / 8 diagonals
}

}  // namespace
}  // namespace scanfill
