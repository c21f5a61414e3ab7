// align node: known answers on flat patches whose heights differ by a known step (paper eq. 10). The seam closes; a
// fixed exemplar patch stays put and the other moves the whole step; two free patches meet half way; pairs too far
// apart or too differently oriented do not count; ring samples over another patch's region are thinned.
#include "nodes/align/align.h"

#include <gtest/gtest.h>

#include <numeric>

namespace scanfill {
namespace {

constexpr double kH = 0.01;  // grid step = alpha

// A grid of n x n points in a plane z = const with spacing h, offset by (x0, 0, z), normals +z.
PointSet grid(int n, double h, double x0, double z) {
  Eigen::Matrix3Xd p(3, n * n), nn(3, n * n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      p.col(i * n + j) = Eigen::Vector3d(x0 + i * h, j * h, z);
      nn.col(i * n + j) = Eigen::Vector3d::UnitZ();
    }
  PointSet out(p);
  out.set_normals(nn);
  return out;
}

// Patch 0 = a (origin `first`), patch 1 = b (synthesised); ring flags per point of a then b (default none).
Synthesis two_patches(const PointSet& a, const PointSet& b, Origin first = Origin::kSynthesized,
                      std::vector<std::uint8_t> ring = {}) {
  Synthesis s;
  Eigen::Matrix3Xd p(3, a.size() + b.size()), n(3, a.size() + b.size());
  p << a.positions(), b.positions();
  n << a.normals(), b.normals();
  s.points = PointSet(p);
  s.points.set_normals(n);
  if (ring.empty()) ring.assign(size_t(p.cols()), 0);
  for (Index i = 0; i < p.cols(); ++i) {
    const bool second = i >= a.size();
    s.origin.push_back(second ? Origin::kSynthesized : first);
    s.label.push_back(second ? 1 : (first == Origin::kExemplar ? -1 : 0));
    s.patch.push_back(second ? 1 : 0);
    s.base.push_back(std::int32_t(second ? i - a.size() : i));
    s.ring.push_back(ring[size_t(i)]);
  }
  s.patches = {{first == Origin::kExemplar ? -1 : 0, first, false, {}}, {1, Origin::kSynthesized, false, {}}};
  return s;
}

// Lowest and highest offset of a patch's points.
std::pair<double, double> offsets(const Synthesis& s, const AlignResult& r, int patch) {
  double lo = 1e9, hi = -1e9;
  for (size_t i = 0; i < r.offset.size(); ++i)
    if (s.patch[i] == patch) {
      lo = std::min(lo, r.offset[i]);
      hi = std::max(hi, r.offset[i]);
    }
  return {lo, hi};
}

// Two flat patches side by side whose heights differ: eq. 10 closes the step between them while each stays flat.
TEST(Align, ClosesTheSeamBetweenTwoPatchesAndKeepsEachFlat) {
  const Synthesis s = two_patches(grid(20, kH, 0.0, 0.0), grid(20, kH, 0.2, 0.004));
  const AlignResult r = align(s, kH, {});
  EXPECT_GT(r.seam_pairs, 0);
  EXPECT_GT(r.gap_before, 0.003);
  EXPECT_LT(r.gap_after, 0.1 * r.gap_before);
  // Each patch moves (nearly) as one piece: the spread of offsets inside a patch is small against the step.
  for (int patch = 0; patch < 2; ++patch) {
    const auto [lo, hi] = offsets(s, r, patch);
    EXPECT_LT(hi - lo, 0.002) << "patch " << patch;
  }
}

TEST(Align, TheRmsGapBeforeIsTheStep) {
  // Parallel normals: every seam pair's gap along the mean normal is the 0.004 step exactly.
  const Synthesis s = two_patches(grid(20, kH, 0.0, 0.0), grid(20, kH, 0.2, 0.004));
  const AlignResult r = align(s, kH, {});
  EXPECT_NEAR(r.gap_before, 0.004, 1e-12);
}

TEST(Align, AFixedExemplarStaysAndTheOtherPatchMovesTheWholeStep) {
  const Synthesis s = two_patches(grid(20, kH, 0.0, 0.0), grid(20, kH, 0.2, 0.004), Origin::kExemplar);
  const AlignResult r = align(s, kH, {});
  const auto [lo0, hi0] = offsets(s, r, 0);
  EXPECT_EQ(lo0, 0.0);
  EXPECT_EQ(hi0, 0.0);
  // The free patch comes down by the step, never past it and never up: at the seam by all but a few percent, further
  // away a little less (v = 0.01 pulls every sample towards its start, keep_weight 1 holds its neighbours; the far
  // side still follows by more than 70%).
  const auto [lo1, hi1] = offsets(s, r, 1);
  EXPECT_GT(lo1, -0.004);
  EXPECT_LT(hi1, -0.7 * 0.004);
  const auto column = [&](int c) {  // mean offset of the free patch's column c (c = 0 at the seam)
    double sum = 0;
    for (int j = 0; j < 20; ++j) sum += r.offset[size_t(400 + c * 20 + j)];
    return sum / 20;
  };
  EXPECT_LT(column(0), -0.95 * 0.004);
  for (int c = 1; c < 20; ++c) EXPECT_GE(column(c), column(c - 1)) << "column " << c;
  EXPECT_LT(r.gap_after, 0.05 * r.gap_before);
}

TEST(Align, TwoFreePatchesMeetHalfWay) {
  const Synthesis s = two_patches(grid(20, kH, 0.0, 0.0), grid(20, kH, 0.2, 0.004));
  const AlignResult r = align(s, kH, {});
  double mean[2] = {0, 0};
  for (size_t i = 0; i < r.offset.size(); ++i) mean[s.patch[i]] += r.offset[i] / 400;
  // Each goes (about) half the step towards the other: the lower one up, the upper one down, symmetrically.
  EXPECT_NEAR(mean[0], 0.002, 0.0004);
  EXPECT_NEAR(mean[1], -0.002, 0.0004);
  EXPECT_NEAR(mean[0] + mean[1], 0.0, 1e-4);
}

TEST(Align, NoSeamPairsNoMotion) {
  // Too far apart (6 alpha > pair_distance 2), or at right angles (normals more than 60 degrees apart).
  PointSet side = grid(20, kH, 0.2, 0.004);
  side.set_normals(Eigen::Matrix3Xd::Zero(3, side.size()).colwise() + Eigen::Vector3d::UnitX());
  for (const Synthesis& s :
       {two_patches(grid(20, kH, 0.0, 0.0), grid(20, kH, 0.25, 0.004)), two_patches(grid(20, kH, 0.0, 0.0), side)}) {
    const AlignResult r = align(s, kH, {});
    EXPECT_EQ(r.seam_pairs, 0);
    EXPECT_EQ(r.gap_before, 0.0);
    EXPECT_EQ(r.gap_after, 0.0);
    for (const double d : r.offset) EXPECT_EQ(d, 0.0);
  }
}

TEST(Align, ZeroGapWeightLeavesTheSeamOpen) {
  const Synthesis s = two_patches(grid(20, kH, 0.0, 0.0), grid(20, kH, 0.2, 0.004));
  AlignOptions o;
  o.gap_weight = 0;
  const AlignResult r = align(s, kH, o);
  EXPECT_GT(r.seam_pairs, 0);
  EXPECT_NEAR(r.gap_after, r.gap_before, 1e-9);
  for (const double d : r.offset) EXPECT_NEAR(d, 0.0, 1e-9);
}

TEST(Align, RingSamplesOverAnotherPatchsRegionAreThinned) {
  // Patch 1 overlaps patch 0 by its first 5 columns (x = 0.15 ... 0.19 coincide), which are its ring.
  const PointSet a = grid(20, kH, 0.0, 0.0), b = grid(20, kH, 0.15, 0.0);
  std::vector<std::uint8_t> ring(800, 0);
  for (Index i = 0; i < 5 * 20; ++i) ring[size_t(400 + i)] = 1;
  const Synthesis s = two_patches(a, b, Origin::kSynthesized, ring);
  const AlignResult r = align(s, kH, {});
  for (size_t i = 0; i < 800; ++i) EXPECT_EQ(r.keep[i], ring[i] ? 0 : 1) << "point " << i;
  // thin_distance 0 keeps them all.
  AlignOptions keep_all;
  keep_all.thin_distance = 0;
  const AlignResult k = align(s, kH, keep_all);
  EXPECT_EQ(std::accumulate(k.keep.begin(), k.keep.end(), 0), 800);
  // A ring sample over the other patch's ring (not its region) stays: mark patch 0's last 5 columns ring too.
  for (Index i = 15 * 20; i < 400; ++i) ring[size_t(i)] = 1;
  const AlignResult both = align(two_patches(a, b, Origin::kSynthesized, ring), kH, {});
  EXPECT_EQ(std::accumulate(both.keep.begin(), both.keep.end(), 0), 800);
}

TEST(Align, FewerThanTwoPointsIsANoOp) {
  const Synthesis s = two_patches(grid(1, kH, 0.0, 0.0), PointSet(Eigen::Matrix3Xd(3, 0)));
  const AlignResult r = align(s, kH, {});
  EXPECT_EQ(r.offset, std::vector<double>{0.0});
  EXPECT_EQ(r.keep, std::vector<std::uint8_t>{1});
  EXPECT_EQ(r.seam_pairs, 0);
}

}  // namespace
}  // namespace scanfill
