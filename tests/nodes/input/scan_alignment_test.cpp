#include "nodes/input/scan_alignment.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <vector>

#include "nodes/core/errors.h"
#include "nodes/core/kdtree.h"
#include "nodes/input/input.h"
#include "nodes/io/write_ply.h"
#include "test_util.h"

namespace scanfill {
namespace {

std::string message_of(const std::filesystem::path& conf) {
  try {
    read_scan_alignment(conf);
  } catch (const IoError& e) {
    return e.what();
  }
  return "";
}

TEST(ScanAlignment, ReadsPosesWithCrlfAndResolvesNamesBesideTheFile) {
  const test::TempDir dir;
  // A quarter turn about y (qj = sin 45, qr = cos 45), as the Stanford files write it, then a shift.
  test::write_bytes(dir / "two.conf",
                    "camera 0 0 -1 0 0 0 1\r\nbmesh a.ply 0 0 0 0 0 0 1\r\n\r\n"
                    "bmesh b.ply 1 2 3 0 0.70710678 0 0.70710678\r\n");
  const std::vector<ScanPose> scans = read_scan_alignment(dir / "two.conf");
  ASSERT_EQ(scans.size(), 2u);
  EXPECT_EQ(scans[0].file, dir / "a.ply");
  EXPECT_TRUE(scans[0].pose.rotation.isIdentity(1e-12));
  // The conjugate turns x to +z: a quarter turn about y the other way.
  const Eigen::Vector3d moved = scans[1].pose.apply(Eigen::Vector3d::UnitX());
  EXPECT_LT((moved - Eigen::Vector3d(1, 2, 4)).norm(), 1e-7) << moved.transpose();
}

TEST(ScanAlignment, SaysWhichLineIsWrong) {
  const test::TempDir dir;
  test::write_bytes(dir / "short.conf", "bmesh a.ply 0 0 0 0 0 1\n");
  EXPECT_NE(message_of(dir / "short.conf").find("short.conf:1: expected 7 numbers"), std::string::npos);
  test::write_bytes(dir / "other.conf", "bmesh a.ply 0 0 0 0 0 0 1\nmesh b.ply 0 0 0 0 0 0 1\n");
  EXPECT_NE(message_of(dir / "other.conf").find("other.conf:2: expected 'camera' or 'bmesh'"), std::string::npos);
  test::write_bytes(dir / "zero.conf", "bmesh a.ply 0 0 0 0 0 0 0\n");
  EXPECT_NE(message_of(dir / "zero.conf").find("quaternion"), std::string::npos);
  test::write_bytes(dir / "none.conf", "camera 0 0 0 0 0 0 1\n");
  EXPECT_NE(message_of(dir / "none.conf").find("lists no range scan"), std::string::npos);
  // A listed scan that is missing is named with its line, when checked and when loaded.
  test::write_bytes(dir / "missing.conf", "camera 0 0 0 0 0 0 1\nbmesh gone.ply 0 0 0 0 0 0 1\n");
  const auto problem = check_input(parse_input((dir / "missing.conf").string()));
  ASSERT_TRUE(problem.has_value());
  EXPECT_NE(problem->find("missing.conf:2: no such file: "), std::string::npos) << *problem;
  try {
    load_input(parse_input((dir / "missing.conf").string()));
    ADD_FAILURE() << "loaded a .conf whose scan is missing";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("missing.conf:2: "), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("gone.ply"), std::string::npos) << e.what();
  }
}

TEST(ScanAlignment, ACheckedInputMayBeAConf) {
  const test::TempDir dir;
  test::write_bytes(dir / "scans.conf", "bmesh a.ply 0 0 0 0 0 0 1\n");
  test::write_bytes(dir / "a.ply",
                    "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                    "property float z\nend_header\n0 0 0\n");
  EXPECT_FALSE(check_input(parse_input("scans.conf", dir.path())).has_value());
}

// The Stanford bunny's ten range scans, posed by bun.conf, lie on the reconstructed bunny (median 0.6 mm); unposed,
// bun045 alone lies centimetres off it.
TEST(ScanAlignment, TheStanfordScansPosedByBunConfLieOnTheBunny) {
  SCANFILL_REQUIRE_SHARED_DATA();
  const std::filesystem::path dir = test::shared_data() / "scans" / "stanford_bunny";
  const LoadResult scans = load_input(parse_input((dir / "bun.conf").string()));
  EXPECT_NE(scans.format.find("10 range scans posed by bun.conf"), std::string::npos) << scans.format;
  const LoadResult bunny = load_input(parse_input((dir / "bun_zipper.ply").string()));
  KdTree tree;
  tree.build(bunny.points.positions());
  const auto median_distance = [&](const Eigen::Matrix3Xd& p) {
    std::vector<std::int32_t> nearest;
    std::vector<double> d2;
    nearest_each(tree, p, nearest, d2);
    std::nth_element(d2.begin(), d2.begin() + long(d2.size() / 2), d2.end());
    return std::sqrt(d2[d2.size() / 2]);
  };
  EXPECT_LT(median_distance(scans.points.positions()), 0.001);
  const LoadResult raw = load_input(parse_input((dir / "bun045.ply").string()));
  EXPECT_GT(median_distance(raw.points.positions()), 0.005);
}

}  // namespace
}  // namespace scanfill
