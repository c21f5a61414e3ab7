// Issue 14, item 3: the scan's colours and intensity are carried through a completion to the output points. A single
// view of the vase is written with a colour and an intensity that both name the point (its index in the file, as the
// three bytes of its colour and as a float): every output point taken from the scan, kept (origin 0) or moved by a
// transform (origin 1), must carry one scan point's colour and that same point's intensity, and a kept point must sit
// where that scan point is; copied points get the neutral grey and 0. The run is the same bytes on 1 and 2 threads,
// output.colour: auto shows the scan's colours and origin shows origins, and scan refuses a scan without colours.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "nodes/io/read_point_set.h"
#include "nodes/io/write_ply.h"
#include "nodes/procedural/shapes.h"
#include "nodes/scan/virtual_scan.h"
#include "nodes/transfer/transfer.h"
#include "test_util.h"

namespace scanfill {
namespace {

std::string q(const std::filesystem::path& p) {
  return test::quoted(p);
}

Eigen::Matrix<std::uint8_t, 3, 1> colour_of_index(Index i) {
  return {std::uint8_t(i & 255), std::uint8_t(i >> 8 & 255), std::uint8_t(i >> 16 & 255)};
}
Index index_of_colour(const Eigen::Matrix<std::uint8_t, 3, 1>& c) {
  return Index(c(0)) | Index(c(1)) << 8 | Index(c(2)) << 16;
}

// The vase seen from the front, each point coloured and weighted by its index.
PointSet coloured_scan(const std::filesystem::path& file) {
  ScanOptions o;
  o.eye = Eigen::Vector3d(0, -3, 0.6);
  o.target = Eigen::Vector3d(0, 0, 0.5);
  o.width = o.height = 300;
  o.fov_deg = 30;
  PointSet scan = virtual_scan(make_shape("vase"), o).points;
  Matrix3Xu8 colours(3, scan.size());
  Eigen::VectorXf intensity(scan.size());
  for (Index i = 0; i < scan.size(); ++i) {
    colours.col(i) = colour_of_index(i);
    intensity(i) = float(i);
  }
  scan.set_colours(std::move(colours));
  scan.set_intensity(std::move(intensity));
  write_ply(file, scan);
  return read_point_set(file, LoadOptions{.morton_sort = false}).points;  // as float32, in file order
}

std::string config(const std::filesystem::path& scan, const std::filesystem::path& out, const char* colour) {
  return "mode: completion\ninputs:\n  scan: " + scan.string() +
         "\n  template: procedural:vase_template\noutput:\n  dir: " + out.string() + "\n  surface: none\n" +
         (colour ? std::string("  colour: ") + colour + "\n" : "") + "sample:\n  count: 8000\n";
}

TEST(Appearance, TheScansColoursAndIntensityReachTheOutputPointsTheyBecame) {
  test::TempDir dir;
  const PointSet scan = coloured_scan(dir / "scan.ply");
  ASSERT_GT(scan.size(), 5000);
  test::write_bytes(dir / "a.yaml", config(dir / "scan.ply", dir / "out1", nullptr));
  const auto one = test::run_scanfill("--config " + q(dir / "a.yaml") + " --quiet --threads 1");
  ASSERT_EQ(one.exit_code, 0) << one.out;
  const std::string header = test::read_bytes(dir / "out1" / "output.ply").substr(0, 600);
  EXPECT_NE(header.find("property uchar red\nproperty uchar green\nproperty uchar blue\nproperty float intensity\n"),
            std::string::npos)
      << header;
  const LoadResult loaded = read_point_set(dir / "out1" / "output.ply", LoadOptions{.morton_sort = false});
  const PointSet& out = loaded.points;
  ASSERT_TRUE(out.has_colours());
  ASSERT_TRUE(out.has_intensity());
  const std::vector<int> origin = test::ply_property(dir / "out1" / "output.ply", "origin");
  ASSERT_EQ(Index(origin.size()), out.size());
  Index from_scan[2] = {0, 0}, copied = 0;
  for (Index i = 0; i < out.size(); ++i) {
    const int o = origin[size_t(i)];
    if (o == 2) {
      ++copied;
      ASSERT_EQ(out.colours().col(i), kCopiedColour) << i;
      ASSERT_EQ(out.intensity()(i), kCopiedIntensity) << i;
      continue;
    }
    ++from_scan[o];
    const Index source = index_of_colour(out.colours().col(i));
    ASSERT_LT(source, scan.size()) << i;
    ASSERT_EQ(out.intensity()(i), scan.intensity()(source)) << i << ": colour and intensity name different points";
    // A kept point is where its scan point is (in the scan's frame, to float32's rounding of the frame changes).
    if (o == 0) {
      ASSERT_LT((out.positions().col(i) - scan.positions().col(source)).norm(), 1e-5) << i;
    }
  }
  std::printf("output: %ld kept and %ld synthesised points with the scan's colours, %ld copied\n", long(from_scan[0]),
              long(from_scan[1]), long(copied));
  EXPECT_GT(from_scan[0], scan.size() / 2);
  EXPECT_GT(from_scan[1], 1000);
  std::ifstream report_file(dir / "out1" / "report.json");
  const auto report = nlohmann::json::parse(report_file);
  EXPECT_EQ(report["output"]["colour"], "scan");
  EXPECT_EQ(report["output"]["intensity"], true);
  EXPECT_NE(one.out.find("RGB: the scan's own colours"), std::string::npos) << one.out;

  // The same bytes on 2 threads.
  test::write_bytes(dir / "b.yaml", config(dir / "scan.ply", dir / "out2", nullptr));
  const auto two = test::run_scanfill("--config " + q(dir / "b.yaml") + " --quiet --threads 2");
  ASSERT_EQ(two.exit_code, 0) << two.out;
  EXPECT_EQ(test::read_bytes(dir / "out2" / "output.ply"), test::read_bytes(dir / "out1" / "output.ply"));

  // output.colour: origin colours by origin while the intensity still rides along.
  test::write_bytes(dir / "c.yaml", config(dir / "scan.ply", dir / "out3", "origin"));
  ASSERT_EQ(test::run_scanfill("--config " + q(dir / "c.yaml") + " --quiet").exit_code, 0);
  const PointSet by_origin = read_point_set(dir / "out3" / "output.ply", LoadOptions{.morton_sort = false}).points;
  ASSERT_EQ(by_origin.size(), out.size());
  const Index first_kept = std::find(origin.begin(), origin.end(), 0) - origin.begin();
  const Index first_synthesised = std::find(origin.begin(), origin.end(), 1) - origin.begin();
  ASSERT_LT(std::max(first_kept, first_synthesised), by_origin.size());
  EXPECT_EQ(by_origin.colours().col(first_kept), (Eigen::Matrix<std::uint8_t, 3, 1>(190, 190, 190)));
  EXPECT_EQ(by_origin.colours().col(first_synthesised), (Eigen::Matrix<std::uint8_t, 3, 1>(235, 130, 35)));
  EXPECT_EQ(by_origin.intensity(), out.intensity());
}

TEST(Appearance, OutputColourScanRefusesAScanWithoutColours) {
  test::TempDir dir;
  write_ply(dir / "plain.ply", make_shape("vase"));
  test::write_bytes(dir / "s.yaml", config(dir / "plain.ply", dir / "out", "scan"));
  const auto r = test::run_scanfill("--config " + q(dir / "s.yaml") + " --quiet");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.out.find("output.colour is 'scan' but the scan has no colours"), std::string::npos) << r.out;
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
  EXPECT_FALSE(std::filesystem::exists(dir / "out"));
}

}  // namespace
}  // namespace scanfill
