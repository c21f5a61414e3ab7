// icp_step with trusted pairs (stop 33): a point-to-plane step fits every pair but moves only along the motions the
// trusted pairs constrain.
#include "nodes/core/icp.h"

#include <gtest/gtest.h>

namespace scanfill {
namespace {

using Eigen::Index;

// A floor of trusted pairs (z = 0, normal +z), each 1 cm below its partner, and a wall of untrusted pairs (x = 1,
// normal +x), each 5 cm short of its partner: the floor asks for +1 cm in z and constrains z, the tilts about x and
// y; the wall alone asks for +5 cm in x.
IcpPairs floor_and_wall() {
  std::vector<Eigen::Vector3d> moved, to, normals;
  std::vector<char> trusted;
  for (int i = -5; i <= 5; ++i)
    for (int j = -5; j <= 5; ++j) {
      const Eigen::Vector3d p(0.1 * i, 0.1 * j, 0);
      moved.push_back(p);
      to.push_back(p + Eigen::Vector3d(0, 0, 0.01));
      normals.push_back(Eigen::Vector3d::UnitZ());
      trusted.push_back(1);
    }
  for (int j = -5; j <= 5; ++j)
    for (int k = 1; k <= 3; ++k) {
      const Eigen::Vector3d p(1, 0.1 * j, 0.1 * k);
      moved.push_back(p);
      to.push_back(p + Eigen::Vector3d(0.05, 0, 0));
      normals.push_back(Eigen::Vector3d::UnitX());
      trusted.push_back(0);
    }
  IcpPairs pairs;
  pairs.moved.resize(3, Index(moved.size()));
  pairs.to.resize(3, Index(moved.size()));
  pairs.normals.resize(3, Index(moved.size()));
  for (size_t i = 0; i < moved.size(); ++i) {
    pairs.moved.col(Index(i)) = moved[i];
    pairs.to.col(Index(i)) = to[i];
    pairs.normals.col(Index(i)) = normals[i];
  }
  pairs.trusted = trusted;
  return pairs;
}

TEST(Icp, AStepMovesOnlyAlongTheMotionsTheTrustedPairsConstrain) {
  const IcpPairs pairs = floor_and_wall();
  const Similarity step = icp_step(Similarity{}, pairs, true, false);
  EXPECT_NEAR(step.translation.z(), 0.01, 1e-6);  // the floor's own motion is kept
  EXPECT_NEAR(step.translation.x(), 0.0, 1e-6);   // the wall's is not: no trusted pair constrains x
  EXPECT_NEAR(step.translation.y(), 0.0, 1e-6);
  EXPECT_LT(rotation_angle(step.rotation), 1e-6);
}

TEST(Icp, WithoutTrustedFlagsTheStepFitsEveryPair) {
  IcpPairs pairs = floor_and_wall();
  pairs.trusted.clear();
  const Similarity step = icp_step(Similarity{}, pairs, true, false);
  EXPECT_NEAR(step.translation.x(), 0.05, 1e-6);
  EXPECT_NEAR(step.translation.z(), 0.01, 1e-6);
  EXPECT_LT(rotation_angle(step.rotation), 1e-6);
}

TEST(Icp, WhenEveryPairIsTrustedTheStepIsThePlainFit) {
  IcpPairs pairs = floor_and_wall();
  std::fill(pairs.trusted.begin(), pairs.trusted.end(), char(1));
  const Similarity all = icp_step(Similarity{}, pairs, true, false);
  pairs.trusted.clear();
  const Similarity plain = icp_step(Similarity{}, pairs, true, false);
  // The one motion no pair constrains (along y) is left out of the trusted span, and the plain fit does not make it
  // either, so the two steps agree.
  EXPECT_LT((all.translation - plain.translation).norm(), 1e-6);
  EXPECT_LT(rotation_angle(all.rotation.transpose() * plain.rotation), 1e-6);
}

}  // namespace
}  // namespace scanfill
