// The plan file: a plan reads back bit for bit; another magic, another version, a truncated, overlong or corrupted
// file and an inconsistent plan are each refused with one line naming the file.
#include "nodes/io/plan_file.h"

#include <gtest/gtest.h>

#include <fstream>

#include "nodes/core/errors.h"
#include "test_util.h"

namespace scanfill {
namespace {

PlanFile small_plan() {
  PlanFile f;
  TransferPlan& p = f.plan;
  p.exemplar_samples = Eigen::Matrix3Xd::Random(3, 5);
  p.target_samples = Eigen::Matrix3Xd::Random(3, 4);
  p.exemplar_points = 123;
  p.exemplar_bounds = {Eigen::Vector3d(-1, -2, -3), Eigen::Vector3d(1, 2, 3)};
  p.mesh_output = true;
  p.colours = true;
  Similarity s;
  s.rotation = Eigen::Matrix3d::Random();
  s.translation = Eigen::Vector3d(0.1, 0.2, 0.3);
  s.scale = 1.7;
  p.patches = {
      {-1, Origin::kExemplar, false, Similarity{}}, {4, Origin::kSynthesized, false, s}, {7, Origin::kTarget, true, s}};
  p.patch = {0, 1, 1, 2};
  p.base = {4, 0, 3, 3};
  p.shift = {0.0, 0.25, -1e-3, 2.5};
  p.normal = Eigen::Matrix3Xd::Random(3, 4);
  f.self_label = 7;
  f.colour = PlanColour::kScan;
  return f;
}

// read_plan's error for the file, which must be one line naming it.
std::string refusal(const std::filesystem::path& p) {
  try {
    read_plan(p);
  } catch (const IoError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    EXPECT_EQ(what.rfind(p.string(), 0), 0u) << what;
    return what;
  }
  ADD_FAILURE() << p << " was read";
  return "";
}

TEST(PlanFile, ReadsBackBitForBit) {
  const test::TempDir dir;
  const PlanFile f = small_plan();
  write_plan(dir / "a.plan", f);
  const PlanFile g = read_plan(dir / "a.plan");
  EXPECT_EQ(g.self_label, 7);
  EXPECT_EQ(g.colour, PlanColour::kScan);
  const TransferPlan &p = f.plan, &q = g.plan;
  EXPECT_EQ(q.exemplar_samples, p.exemplar_samples);
  EXPECT_EQ(q.target_samples, p.target_samples);
  EXPECT_EQ(q.exemplar_points, 123);
  EXPECT_EQ(q.exemplar_bounds.max, p.exemplar_bounds.max);
  EXPECT_TRUE(q.mesh_output);
  EXPECT_TRUE(q.colours);
  EXPECT_FALSE(q.intensity);
  ASSERT_EQ(q.patches.size(), 3u);
  EXPECT_EQ(q.patches[1].whole.rotation, p.patches[1].whole.rotation);
  EXPECT_EQ(q.patches[1].whole.scale, 1.7);
  EXPECT_EQ(q.patches[2].origin, Origin::kTarget);
  EXPECT_TRUE(q.patches[2].from_target);
  EXPECT_EQ(q.patch, p.patch);
  EXPECT_EQ(q.base, p.base);
  EXPECT_EQ(q.shift, p.shift);
  EXPECT_EQ(q.normal, p.normal);
}

TEST(PlanFile, WrongTruncatedCorruptAndOtherVersionsAreRefused) {
  const test::TempDir dir;
  const auto good = dir / "good.plan", bad = dir / "bad.plan";
  write_plan(good, small_plan());
  const std::string b = test::read_bytes(good);
  const auto refused_as = [&](const std::string& bytes, const std::string& why) {
    test::write_bytes(bad, bytes);
    EXPECT_NE(refusal(bad).find(why), std::string::npos) << why;
  };
  EXPECT_NE(refusal(dir / "missing.plan").find("cannot be opened"), std::string::npos);
  refused_as("ply\nformat ascii 1.0\n", "not a scanfill plan");
  refused_as("", "not a scanfill plan");
  refused_as(b.substr(0, 20), "truncated");
  std::string other = b;
  other[8] = 9;  // the format version, a uint32 after the magic
  refused_as(other, "format version 9; this scanfill reads version 2");
  refused_as(b.substr(0, b.size() - 1), "truncated");
  refused_as(b + "x", "overlong");
  std::string flipped = b;
  flipped[b.size() / 2] ^= 0x10;
  refused_as(flipped, "corrupt");
}

TEST(PlanFile, AnInconsistentPlanIsRefusedWhenRead) {
  const test::TempDir dir;
  PlanFile f = small_plan();
  f.plan.base[0] = 99;  // no such exemplar sample
  write_plan(dir / "x.plan", f);
  EXPECT_NE(refusal(dir / "x.plan").find("base out of range"), std::string::npos);
  f = small_plan();
  f.plan.colours = false;  // the scan's own colours, but the scan had none
  write_plan(dir / "y.plan", f);
  EXPECT_NE(refusal(dir / "y.plan").find("asked for, but it has none"), std::string::npos);
}

}  // namespace
}  // namespace scanfill
