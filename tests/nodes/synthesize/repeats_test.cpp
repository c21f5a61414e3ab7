#include "nodes/synthesize/repeats.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <functional>
#include <limits>
#include <optional>
#include <random>
#include <vector>

#include "nodes/core/kdtree.h"
#include "nodes/procedural/shapes.h"
#include "nodes/sample/sample.h"

namespace scanfill {

PointSet one_headed_body(bool head = true);  // synthesize_test.cpp

namespace {

struct Exemplar {
  Eigen::Matrix3Xd p, n;
  double alpha = 0;
};

// The half y < 0 of `mesh` (a one-sided scan), sampled with `count` points over the whole mesh, and its alpha.
Exemplar half_of(const PointSet& mesh, Index count) {
  const PointSet all = random_surface_points(mesh, count, 7);
  std::vector<Index> half;
  for (Index i = 0; i < all.size(); ++i)
    if (all.positions()(1, i) < 0) half.push_back(i);
  return {all.positions()(Eigen::all, half), all.normals()(Eigen::all, half),
          std::sqrt(0.64 * surface_area(mesh.positions(), mesh.faces()) / double(count))};
}

const TurningPart about_z{Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ()};

Similarity turn_about_z(double deg) {
  return {Eigen::AngleAxisd(deg * M_PI / 180, Eigen::Vector3d::UnitZ()).toRotationMatrix(), Eigen::Vector3d::Zero(), 1};
}

// The exemplar with Gaussian noise of `alphas` alpha along each normal (seeded), as a range scanner's.
Exemplar with_noise(Exemplar e, double alphas, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, alphas * e.alpha);
  for (Index i = 0; i < e.p.cols(); ++i) e.p.col(i) += noise(rng) * e.n.col(i);
  return e;
}

// The vase's ring of 16 beads (z 0.03-0.09) below 12 flutes (which fade out at z 0.12): two bands of two orders, cut
// between them.
void expect_beads_below_flutes(const Exemplar& e) {
  const auto r = axial_repeats(e.p, e.n, about_z, e.alpha, 3 * e.alpha);
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->order[0], 16);
  EXPECT_EQ(r->order[1], 12);
  EXPECT_GT(r->cut, 0.085);
  EXPECT_LT(r->cut, 0.16);
}

// Half a vase: beads and flutes as two bands.
TEST(AxialRepeats, FindsAVasesBeadsAndFlutesAsTwoBands) {
  expect_beads_below_flutes(half_of(make_vase(), 32000));
}

// The same half vase scanned with noise of half an alpha, about half its flutes' depth: every turn misfits by the
// noise, the flutes' repeats included, and the two bands are still found above it.
TEST(AxialRepeats, FindsAVasesBeadsAndFlutesUnderScannerNoise) {
  expect_beads_below_flutes(with_noise(half_of(make_vase(), 32000), 0.5, 11));
}

// About an axis 1.8 cm off a fluted column's (a region's turn axis on the sweep's column seen from the side), the
// turns' misfit dips near 21 degrees and grows past it, no later turn fitting: no repeat (not 18 flutes).
TEST(AxialRepeats, FindsNoRepeatAboutAnAxisOffTheColumns) {
  const Exemplar e = half_of(make_column(), 32000);
  ASSERT_TRUE(axial_repeats(e.p, e.n, about_z, e.alpha, 3 * e.alpha).has_value());
  const TurningPart off{Eigen::Vector3d(0.0074, 0.0167, 0), Eigen::Vector3d::UnitZ()};
  const auto r = axial_repeats(e.p, e.n, off, e.alpha, 3 * e.alpha);
  EXPECT_TRUE(!r || r->order[0] == 16) << r->order[0];
}

// About its axis pointing down, the same vase has the beads above the cut.
TEST(AxialRepeats, OrdersTheBandsAlongTheAxisDirection) {
  const Exemplar e = half_of(make_vase(), 32000);
  const auto r = axial_repeats(e.p, e.n, {Eigen::Vector3d(0, 0, 1), -Eigen::Vector3d::UnitZ()}, e.alpha, 3 * e.alpha);
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->order[0], 12);
  EXPECT_EQ(r->order[1], 16);
}

// A gear's 20 teeth: one band.
TEST(AxialRepeats, FindsAGearsTeethAsOneBand) {
  const Exemplar e = half_of(make_gear(), 24000);
  const auto r = axial_repeats(e.p, e.n, about_z, e.alpha, 3 * e.alpha);
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->order[0], 20);
  EXPECT_EQ(r->order[1], 20);
}

// A plain body of revolution, as a part (bounded), fits itself under every turn: no order, a body of revolution.
// Unbounded (the whole shape's axis, where the labels' turns carry the exemplar), it is no repeat; nor is the vase
// about an axis it is not turned about.
TEST(AxialRepeats, FindsABodyOfRevolutionAsAPartAndNothingAboutAnotherAxis) {
  const Exemplar plain = half_of(make_vase_template(), 32000);
  const TurningPart bounded{Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), 0.5, -0.01, 1.01};
  const auto r = axial_repeats(plain.p, plain.n, bounded, plain.alpha, 3 * plain.alpha);
  ASSERT_TRUE(r.has_value());
  EXPECT_TRUE(r->continuous);
  EXPECT_EQ(r->order[0] + r->order[1], 0);
  EXPECT_FALSE(axial_repeats(plain.p, plain.n, about_z, plain.alpha, 3 * plain.alpha).has_value());
  const Exemplar vase = half_of(make_vase(), 32000);
  EXPECT_FALSE(
      axial_repeats(vase.p, vase.n, {Eigen::Vector3d(0, 0, 0.5), Eigen::Vector3d::UnitX()}, vase.alpha, 3 * vase.alpha)
          .has_value());
  EXPECT_FALSE(axial_repeats(vase.p, vase.n, about_z, vase.alpha, 3 * vase.alpha)->continuous);
}

// A table's turned leg (bulb, rings) is a body of revolution about its own axis, within its part, found from an axis
// 4 mm off (as the template's was on the sweep's table); about that axis the whole table is not (the top turns off
// itself), and a part that holds no samples finds nothing.
TEST(AxialRepeats, FindsATableLegABodyOfRevolutionWithinItsPart) {
  const Exemplar table = half_of(make_table(), 40000);
  TurningPart leg{Eigen::Vector3d(0.424, -0.223, 0), Eigen::Vector3d::UnitZ(), 0.1, -0.01, 0.71};
  const auto r = axial_repeats(table.p, table.n, leg, table.alpha, 3 * table.alpha);
  ASSERT_TRUE(r.has_value());
  EXPECT_TRUE(r->continuous);
  EXPECT_LT((r->part.point.head<2>() - Eigen::Vector2d(0.42, -0.22)).norm(), 0.5 * table.alpha);
  leg.radius = std::numeric_limits<double>::infinity();
  leg.high = std::numeric_limits<double>::infinity();
  const auto whole = axial_repeats(table.p, table.n, leg, table.alpha, 3 * table.alpha);
  EXPECT_TRUE(!whole || !whole->continuous);
  const TurningPart empty{Eigen::Vector3d(5, 5, 0), Eigen::Vector3d::UnitZ(), 0.1, -0.01, 0.71};
  EXPECT_FALSE(axial_repeats(table.p, table.n, empty, table.alpha, 3 * table.alpha).has_value());
}

// An image turned 119.6 degrees goes to 120 for a 12-fold band and to 112.5 for a 16-fold one; turns about another
// axis, lifts along the axis, and turns past `most` are left alone.
TEST(TurnToRepeat, TurnsToTheNearestMultipleOfTheOrder) {
  AxialRepeats r;
  r.radius = 0.3;  // about z through the origin
  const Similarity q = turn_about_z(119.6);
  const auto to12 = turn_to_repeat(r, 12, q, 1.0, 0.01), to16 = turn_to_repeat(r, 16, q, 1.0, 0.01);
  ASSERT_TRUE(to12 && to16);
  EXPECT_NEAR(rotation_angle(to12->compose(q).rotation) * 180 / M_PI, 120.0, 1e-9);
  EXPECT_NEAR(rotation_angle(to16->compose(q).rotation) * 180 / M_PI, 112.5, 1e-9);
  EXPECT_LT(to16->compose(q).translation.norm(), 1e-12);  // about the axis through the origin
  EXPECT_FALSE(turn_to_repeat(r, 0, q, 1.0, 0.01));
  const Similarity about_x{Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitX()).toRotationMatrix(), Eigen::Vector3d::Zero(),
                           1};
  EXPECT_FALSE(turn_to_repeat(r, 12, about_x, 1.0, 0.01));
  Similarity lifted = q;
  lifted.translation.z() = 0.02;
  EXPECT_FALSE(turn_to_repeat(r, 12, lifted, 1.0, 0.01));
  EXPECT_FALSE(turn_to_repeat(r, 16, q, 0.3 * 7 * M_PI / 180, 0.01));  // 7.1 degrees at radius 0.3 is too far
}

// The share of the samples `which` picks that repeating_samples marks, at the exemplar's alpha (pairs within 3 alpha).
double repeating_share(const Exemplar& e, const AxialRepeats& r,
                       const std::function<bool(const Eigen::Vector3d&)>& which) {
  KdTree tree;
  tree.build(e.p);
  const std::vector<std::uint8_t> repeating = repeating_samples(tree, e.p, e.n, r, e.alpha, 3 * e.alpha);
  double picked = 0, marked = 0;
  for (Index i = 0; i < e.p.cols(); ++i)
    if (which(e.p.col(i))) ++picked, marked += repeating[size_t(i)];
  return picked > 0 ? marked / picked : std::numeric_limits<double>::quiet_NaN();
}

// Of half a gear with its 20 teeth, every part repeats: at an edge of what was seen, the turn the other way lands on
// it.
TEST(RepeatingSamples, MarksAllOfAGearsTeeth) {
  const Exemplar e = half_of(make_gear(), 24000);
  AxialRepeats r;
  r.part = about_z;
  r.order = {20, 20};
  EXPECT_GT(repeating_share(e, r, [](const Eigen::Vector3d&) { return true; }), 0.97);
}

// A round body with one head on it (a bump 0.08 high, 20 degrees wide, at -y), said to repeat 23 times, as the facets
// of a teapot's body say it does: its wall repeats, its head (the teapot's spout) does not, so it is not turned round
// the body. Said to repeat 4 times, or to be a body of revolution, it is not checked: all of it is marked.
TEST(RepeatingSamples, LeavesOutDetailSeenOnce) {
  const PointSet body = make_prism(
      [](double phi) { return 0.3 + 0.08 * std::exp(-std::pow(std::remainder(phi + M_PI / 2, 2 * M_PI) / 0.35, 2)); },
      0.0, 0.8, 256);
  const auto from_head = [](const Eigen::Vector3d& x) {  // the angle about z from the head's direction, -y
    return std::abs(std::remainder(std::atan2(x.y(), x.x()) + M_PI / 2, 2 * M_PI));
  };
  const auto on_wall = [](const Eigen::Vector3d& x) { return x.z() > 0.01 && x.z() < 0.79; };
  const auto on_head = [&](const Eigen::Vector3d& x) { return on_wall(x) && x.head<2>().norm() > 0.33; };
  AxialRepeats facets;
  facets.part = about_z;
  facets.order = {23, 23};
  const Exemplar half = half_of(body, 30000);
  EXPECT_GT(
      repeating_share(half, facets,
                      [&](const Eigen::Vector3d& x) { return on_wall(x) && from_head(x) > 1.0 && from_head(x) < 1.3; }),
      0.97);
  EXPECT_LT(repeating_share(half, facets, on_head), 0.03);
  AxialRepeats fourfold = facets, round = facets;
  fourfold.order = {4, 4};
  round.order = {0, 0};
  round.continuous = true;
  for (const AxialRepeats& r : {fourfold, round})
    EXPECT_EQ(repeating_share(half, r, [](const Eigen::Vector3d&) { return true; }), 1.0);
}

// The exemplar's mirror plane through the axis, at its alpha (pairs within 3 alpha).
std::optional<MirrorPlane> mirror_of(const Exemplar& e, const TurningPart& axis) {
  KdTree tree;
  tree.build(e.p);
  return mirror_plane(tree, e.p, e.n, axis, e.alpha, 3 * e.alpha);
}

// Seen from -y (its half y < 0), the body's plane through the axis and the head: x = 0, within a degree, and
// within an alpha of it though the axis given is 0.3 alpha off; its reflection maps the head onto itself.
TEST(MirrorPlane, FindsThePlaneThroughTheAxisAndAHead) {
  const Exemplar e = half_of(one_headed_body(), 30000);
  const auto m = mirror_of(e, {Eigen::Vector3d(0.002, 0, 0), Eigen::Vector3d::UnitZ()});
  ASSERT_TRUE(m.has_value());
  EXPECT_GT(std::abs(m->normal.x()), std::cos(1.0 * M_PI / 180));
  EXPECT_LT(std::abs(m->point.x()), 0.5 * e.alpha);
  EXPECT_LT(m->misfit, 0.35 * e.alpha);
  const Similarity r = reflection_across(*m);
  EXPECT_LT(r.rotation.determinant(), 0);
  EXPECT_LT((r.apply(Eigen::Vector3d(0.2, -0.3, 0.4)) - Eigen::Vector3d(-0.2, -0.3, 0.4)).norm(), 2 * e.alpha);
}

// The template's axis is the scan's only to a degree or two. Given one tilted 2 degrees towards the head and an alpha
// off, the plane is still x = 0, within half a degree and half an alpha, tilted off square to the axis given: over the
// body's 0.8 height a plane square to that axis is up to two alphas off the head's.
TEST(MirrorPlane, FindsThePlaneWhenTheAxisGivenIsTilted) {
  const Exemplar e = half_of(one_headed_body(), 30000);
  const double tilt = 2 * M_PI / 180;
  const TurningPart axis{Eigen::Vector3d(e.alpha, 0, 0), Eigen::Vector3d(std::sin(tilt), 0, std::cos(tilt))};
  const auto m = mirror_of(e, axis);
  ASSERT_TRUE(m.has_value());
  EXPECT_GT(std::abs(m->normal.x()), std::cos(0.5 * M_PI / 180));
  EXPECT_LT(std::abs(m->normal.dot(m->point)), 0.5 * e.alpha);
  EXPECT_LT(m->misfit, 0.25 * e.alpha);
}

// Scanned with noise of 0.4 alpha along the normal, the head's mirrored samples misfit by the noise of two samples (a
// median near 0.4 alpha, over the 0.25 alpha a noiseless plane must fit to); measured above the noise, the plane is
// still found, and a noisy blob still has none.
TEST(MirrorPlane, FindsThePlaneUnderScannerNoise) {
  const Exemplar e = with_noise(half_of(one_headed_body(), 30000), 0.4, 5);
  const auto m = mirror_of(e, {Eigen::Vector3d(0.002, 0, 0), Eigen::Vector3d::UnitZ()});
  ASSERT_TRUE(m.has_value());
  EXPECT_GT(std::abs(m->normal.x()), std::cos(1.0 * M_PI / 180));
  EXPECT_LT(std::abs(m->point.x()), 0.5 * e.alpha);
  EXPECT_FALSE(mirror_of(with_noise(half_of(make_blob(), 30000), 0.4, 5), about_z).has_value());
}

// A blob has no mirror plane through any axis.
TEST(MirrorPlane, FindsNoneOnAShapeWithout) {
  const Exemplar e = half_of(make_blob(), 30000);
  EXPECT_FALSE(mirror_of(e, about_z).has_value());
}

}  // namespace
}  // namespace scanfill
