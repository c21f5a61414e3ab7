#include "nodes/io/read_point_set.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstring>

#include "nodes/core/errors.h"
#include "test_util.h"

namespace scanfill {
namespace {

using test::TempDir;
using test::write_bytes;

// A test-name-safe identifier from a path or file name.
std::string identifier(std::string name) {
  for (char& c : name)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return name;
}

// Expected counts of every file in ../shared/data: vertices from the headers, triangles after splitting n-gons
// (sum of n - 2 over the OBJ faces), and for the organised PCD the finite points PCL's removeNaNFromPointCloud keeps.
struct Expected {
  const char* path;
  Index points;
  Index faces;
  Index dropped;
  bool normals;
};
const Expected kSharedFiles[] = {
    {"furniture/meshlab_furniture_3ds_converted.obj", 1156, 2184, 0, true},
    {"furniture/meshlab_office_chair.obj", 3476, 6893, 0, false},
    {"models/fandisk.obj", 6475, 12946, 0, false},
    {"models/rocker-arm.obj", 10044, 20088, 0, false},
    {"models/stanford-bunny.obj", 35947, 69451, 0, false},
    {"models/teapot.obj", 3644, 6320, 0, false},
    {"models/text2mesh_candle.obj", 16960, 33916, 0, true},
    {"models/text2mesh_lamp.obj", 20582, 41160, 0, true},
    {"models/text2mesh_vase.obj", 15401, 30798, 0, true},
    {"models/threedscans_Column03.obj", 6992, 13980, 0, true},
    {"models/vaselion.obj", 30610, 61216, 0, false},
    {"scans/cgal_hippo/hippo1.ply", 6104, 0, 0, true},
    {"scans/cgal_hippo/hippo2.ply", 4387, 0, 0, true},
    {"scans/pcl_kinect/bun0.pcd", 397, 0, 0, true},
    {"scans/pcl_kinect/bun4.pcd", 361, 0, 0, false},
    {"scans/pcl_kinect/milk.pcd", 13704, 0, 0, false},
    {"scans/pcl_kinect/milk_color.pcd", 13704, 0, 0, false},
    {"scans/pcl_kinect/table_scene_mug_stereo_textured.pcd", 209280, 0, 97920, false},
    {"scans/stanford_bunny/bun000.ply", 40256, 0, 0, false},
    {"scans/stanford_bunny/bun045.ply", 40097, 0, 0, false},
    {"scans/stanford_bunny/bun090.ply", 30379, 0, 0, false},
    {"scans/stanford_bunny/bun180.ply", 40251, 0, 0, false},
    {"scans/stanford_bunny/bun270.ply", 31701, 0, 0, false},
    {"scans/stanford_bunny/bun315.ply", 35336, 0, 0, false},
    {"scans/stanford_bunny/bun_zipper.ply", 35947, 69451, 0, false},
    {"scans/stanford_bunny/bun_zipper_res2.ply", 8171, 16301, 0, false},
    {"scans/stanford_bunny/chin.ply", 37738, 0, 0, false},
    {"scans/stanford_bunny/ear_back.ply", 32193, 0, 0, false},
    {"scans/stanford_bunny/top2.ply", 38298, 0, 0, false},
    {"scans/stanford_bunny/top3.ply", 36023, 0, 0, false},
};

class SharedData : public ::testing::TestWithParam<Expected> {};

TEST_P(SharedData, LoadsWithTheRightCounts) {
  SCANFILL_REQUIRE_SHARED_DATA();
  const Expected& e = GetParam();
  const LoadResult r = read_point_set(test::shared_data() / e.path);
  EXPECT_EQ(r.points.size(), e.points);
  EXPECT_EQ(r.points.faces().cols(), e.faces);
  EXPECT_EQ(r.dropped_nonfinite, e.dropped);
  EXPECT_EQ(r.file_points, e.points + e.dropped);
  EXPECT_EQ(r.points.has_normals(), e.normals);
  EXPECT_TRUE(r.points.positions().allFinite());
  // source_index maps each (Morton-ordered) point back to its place in the file.
  ASSERT_EQ(r.points.source_index().size(), e.points);
  EXPECT_GE(r.points.source_index().minCoeff(), 0);
  EXPECT_LT(r.points.source_index().maxCoeff(), e.points + e.dropped);
}

INSTANTIATE_TEST_SUITE_P(AllFiles, SharedData, ::testing::ValuesIn(kSharedFiles),
                         [](const auto& info) { return identifier(info.param.path); });

TEST(SharedDataDetail, StanfordScanKeepsCoordinatesOfFirstVertex) {
  SCANFILL_REQUIRE_SHARED_DATA();
  const LoadResult r = read_point_set(test::shared_data() / "scans/stanford_bunny/bun000.ply");
  // The first data line of bun000.ply is "-0.06325 0.0359793 0.0420873 \r\n".
  Index where = -1;
  for (Index i = 0; i < r.points.size(); ++i)
    if (r.points.source_index()(i) == 0) where = i;
  ASSERT_GE(where, 0);
  EXPECT_NEAR(r.points.positions()(0, where), -0.06325, 1e-7);
  EXPECT_NEAR(r.points.positions()(1, where), 0.0359793, 1e-7);
  EXPECT_NEAR(r.points.positions()(2, where), 0.0420873, 1e-7);
  EXPECT_EQ(r.encoding, "ascii");
}

TEST(SharedDataDetail, KinectPcdHasViewpointAndDropsNaNsWithWarning) {
  SCANFILL_REQUIRE_SHARED_DATA();
  const LoadResult r = read_point_set(test::shared_data() / "scans/pcl_kinect/table_scene_mug_stereo_textured.pcd");
  ASSERT_TRUE(r.points.viewpoint().has_value());
  EXPECT_EQ(r.encoding, "binary_compressed");
  ASSERT_FALSE(r.warnings.empty());
  EXPECT_NE(r.warnings[0].find("97920 of 307200"), std::string::npos) << r.warnings[0];
}

// --- Synthetic files: every format variant and every kind of broken file. ---

const char* kCube8 = "0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n";

TEST(Ply, AsciiWithCrlfQuadsAndExtraElements) {
  TempDir dir;
  std::string s =
      "ply\r\nformat ascii 1.0\r\ncomment made by hand\r\nobj_info whatever\r\nelement vertex 4\r\nproperty float x\r\n"
      "property float y\r\nproperty float z\r\nproperty float confidence\r\nelement range_grid 3\r\n"
      "property list uchar int vertex_indices\r\nelement face 1\r\nproperty list uchar int vertex_indices\r\n"
      "end_header\r\n0 0 0 1\r\n1 0 0 1\r\n1 1 0 1\r\n0 1 0 1\r\n1 0\r\n0\r\n2 2 3\r\n4 0 1 2 3\r\n";
  write_bytes(dir / "a.ply", s);
  const LoadResult r = read_point_set(dir / "a.ply", {.morton_sort = false});
  EXPECT_EQ(r.points.size(), 4);
  EXPECT_EQ(r.points.faces().cols(), 2);  // the quad, split
  EXPECT_EQ(r.points.positions()(0, 2), 1.0);
  EXPECT_EQ(r.points.positions()(1, 2), 1.0);
}

std::string binary_ply(bool big_endian, bool with_normals) {
  std::string s = std::string("ply\nformat ") + (big_endian ? "binary_big_endian" : "binary_little_endian") +
                  " 1.0\nelement vertex 3\nproperty double x\nproperty double y\nproperty double z\n";
  if (with_normals) s += "property float nx\nproperty float ny\nproperty float nz\n";
  s += "property uchar red\nelement face 1\nproperty list uchar uint vertex_indices\nend_header\n";
  auto put = [&](auto v) {
    char b[sizeof(v)];
    std::memcpy(b, &v, sizeof(v));
    if (big_endian) std::reverse(b, b + sizeof(v));
    s.append(b, sizeof(v));
  };
  const double pts[3][3] = {{0.5, 1.5, -2.0}, {3, 4, 5}, {-1, 0, 1e-3}};
  for (const auto& p : pts) {
    for (double c : p) put(c);
    if (with_normals) {
      put(0.0f);
      put(0.0f);
      put(2.0f);  // not unit: normalised on load
    }
    put(std::uint8_t(200));
  }
  put(std::uint8_t(3));
  for (std::uint32_t i : {0u, 1u, 2u}) put(i);
  return s;
}

TEST(Ply, BinaryBothEndiannesses) {
  TempDir dir;
  for (bool big : {false, true}) {
    write_bytes(dir / "b.ply", binary_ply(big, true));
    const LoadResult r = read_point_set(dir / "b.ply", {.morton_sort = false});
    EXPECT_EQ(r.encoding, big ? "binary_big_endian" : "binary_little_endian");
    ASSERT_EQ(r.points.size(), 3);
    EXPECT_EQ(r.points.positions()(0, 0), 0.5);
    EXPECT_EQ(r.points.positions()(2, 0), -2.0);
    EXPECT_EQ(r.points.positions()(2, 2), 1e-3);
    ASSERT_TRUE(r.points.has_normals());
    EXPECT_DOUBLE_EQ(r.points.normals()(2, 1), 1.0);
    EXPECT_EQ(r.points.faces().cols(), 1);
  }
}

TEST(Ply, NonFinitePointsAreDroppedWithTheirFaces) {
  TempDir dir;
  write_bytes(dir / "n.ply",
              "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
              "element face 2\nproperty list uchar int vertex_indices\nend_header\n"
              "0 0 0\nnan 0 0\n1 0 0\n0 1 0\n3 0 2 3\n3 0 1 2\n");
  const LoadResult r = read_point_set(dir / "n.ply", {.morton_sort = false});
  EXPECT_EQ(r.points.size(), 3);
  EXPECT_EQ(r.dropped_nonfinite, 1);
  EXPECT_EQ(r.points.faces().cols(), 1);
  ASSERT_EQ(r.warnings.size(), 2u);
  EXPECT_NE(r.warnings[0].find("1 of 4 points"), std::string::npos);
}

// Each bad file must throw an IoError naming the file and the problem.
struct BadFile {
  const char* name;
  std::string content;
  const char* message;
};

class BadFiles : public ::testing::TestWithParam<BadFile> {};

TEST_P(BadFiles, ThrowIoErrorNamingFileAndProblem) {
  TempDir dir;
  const BadFile& b = GetParam();
  const auto path = dir / b.name;
  write_bytes(path, b.content);
  try {
    read_point_set(path);
    FAIL() << "no error for " << b.name;
  } catch (const IoError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(path.string()), std::string::npos) << what;
    EXPECT_NE(what.find(b.message), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << "one line: " << what;
  }
}

const std::string kPlyHead =
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n";

INSTANTIATE_TEST_SUITE_P(
    All, BadFiles,
    ::testing::Values(
        BadFile{"empty.ply", "", "file is empty"}, BadFile{"empty.obj", "", "file is empty"},
        BadFile{"text.ply", "hello\n", "not a PLY file"}, BadFile{"noend.ply", kPlyHead, "no end_header"},
        BadFile{"short.ply", kPlyHead + "end_header\n0 0 0\n1 1 1\n", "truncated"},
        BadFile{"long.ply", kPlyHead + "end_header\n0 0 0\n1 1 1\n2 2 2\n3 3 3\n", "header counts do not match"},
        BadFile{"word.ply", kPlyHead + "end_header\n0 0 0\n1 x 1\n2 2 2\n", "'x' is not a number"},
        BadFile{"shortbin.ply",
                "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                "property float z\nend_header\n" +
                    std::string(20, '\0'),
                "truncated"},
        BadFile{"noxyz.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float a\nend_header\n1\n", "lacks x"},
        BadFile{"zero.ply",
                "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\n"
                "property float z\nend_header\n",
                "contains no points"},
        BadFile{"allnan.ply", kPlyHead + "end_header\nnan 0 0\n0 nan 0\ninf 0 0\n", "no point with finite"},
        BadFile{"face.ply",
                "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n",
                "outside [0, 3)"},
        BadFile{"face.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n", "names vertex 9"},
        BadFile{"bad.obj", "v 0 0 zz\n", "expected 3 numbers"},
        BadFile{"novert.obj", "# only a comment\n", "contains no points"},
        BadFile{"short.off", "OFF\n4 1 0\n0 0 0\n1 0 0\n", "truncated"},
        BadFile{"notoff.off", "PLY\n", "not an OFF file"},
        BadFile{"face.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", "outside [0, 3)"},
        BadFile{"short.stl", std::string(80, ' ') + std::string("\x05\0\0\0", 4) + std::string(60, '\0'), "truncated"},
        BadFile{"cols.xyz", "0 0 0\n1 1\n", "2 columns"},
        BadFile{"mixed.xyz", "0 0 0\n1 1 1 0 0 1\n", "where earlier lines have 3"},
        BadFile{"text.pcd", "not a pcd\n", "not a PCD file"},
        BadFile{"short.pcd",
                "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 10\nHEIGHT 1\nPOINTS 10\n"
                "DATA ascii\n0 0 0\n1 1 1\n",
                "truncated"},
        BadFile{"cloud.las", "LASF", "unknown format '.las'"}),
    [](const auto& info) { return identifier(info.param.name); });

TEST(Io, MissingFileIsReported) {
  try {
    read_point_set("/nonexistent/scan.ply");
    FAIL();
  } catch (const IoError& e) {
    EXPECT_STREQ(e.what(), "/nonexistent/scan.ply: no such file");
  }
}

TEST(Obj, AllIndexFormsNegativeIndicesAndNgons) {
  TempDir dir;
  write_bytes(dir / "m.obj",
              "# test\nmtllib x.mtl\no thing\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 0.5 1 0.2 0.3 0.4\n"
              "vt 0 0\nvn 0 0 2\ng part\ns off\nusemtl m\nf 1/1/1 2/1/1 3/1/1 4/1/1\nf  -5//1   -4//1 -1//1\n"
              "f 2/1 3/1 5/1\nf 3 4 5\nl 1 2\n");
  const LoadResult r = read_point_set(dir / "m.obj", {.morton_sort = false});
  EXPECT_EQ(r.points.size(), 5);
  EXPECT_EQ(r.points.faces().cols(), 5);  // quad -> 2, then 3 triangles
  // -5 -4 -1 are the first, second and last vertices (wound against the quad's shared edge, so load turns it).
  std::array<int, 3> third{r.points.faces()(0, 2), r.points.faces()(1, 2), r.points.faces()(2, 2)};
  std::sort(third.begin(), third.end());
  EXPECT_EQ(third, (std::array<int, 3>{0, 1, 4}));
  ASSERT_TRUE(r.points.has_normals());  // every vertex gets vn 1 through some corner; normalised
  EXPECT_DOUBLE_EQ(r.points.normals()(2, 4), 1.0);
}

TEST(Off, PlainNoffAndCommentsAndPolygons) {
  TempDir dir;
  write_bytes(dir / "a.off", "OFF\n# comment\n5 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n4 0 1 2 3 255 0 0\n3 0 1 4\n");
  LoadResult r = read_point_set(dir / "a.off");
  EXPECT_EQ(r.points.size(), 5);
  EXPECT_EQ(r.points.faces().cols(), 3);
  write_bytes(dir / "b.off", "NOFF 3 1 0\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2\n");
  r = read_point_set(dir / "b.off");
  EXPECT_TRUE(r.points.has_normals());
  EXPECT_EQ(r.points.faces().cols(), 1);
}

TEST(Stl, AsciiAndBinaryWeldSharedCorners) {
  TempDir dir;
  write_bytes(
      dir / "a.stl",
      "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 1 1 0\nendloop\nendfacet\n"
      "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 1 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n");
  LoadResult r = read_point_set(dir / "a.stl");
  EXPECT_EQ(r.encoding, "ascii");
  EXPECT_EQ(r.points.size(), 4);
  EXPECT_EQ(r.points.faces().cols(), 2);
  std::string bin(80, 's');  // a binary header may even start with "solid"
  const std::uint32_t n = 2;
  bin.append(reinterpret_cast<const char*>(&n), 4);
  const float tris[2][12] = {{0, 0, 1, 0, 0, 0, 1, 0, 0, 1, 1, 0}, {0, 0, 1, 0, 0, 0, 1, 1, 0, 0, 1, 0}};
  for (const auto& t : tris) {
    bin.append(reinterpret_cast<const char*>(t), 48);
    bin.append(2, '\0');
  }
  write_bytes(dir / "b.stl", bin);
  r = read_point_set(dir / "b.stl");
  EXPECT_EQ(r.encoding, "binary");
  EXPECT_EQ(r.points.size(), 4);
  EXPECT_EQ(r.points.faces().cols(), 2);
}

TEST(Xyz, PointsWithAndWithoutNormals) {
  TempDir dir;
  write_bytes(dir / "a.xyz", std::string("# x y z\n") + kCube8);
  LoadResult r = read_point_set(dir / "a.xyz");
  EXPECT_EQ(r.points.size(), 8);
  EXPECT_FALSE(r.points.has_normals());
  write_bytes(dir / "b.xyz", "0,0,0,0,0,1\r\n1,0,0,0,0,1\r\n");
  r = read_point_set(dir / "b.xyz");
  EXPECT_TRUE(r.points.has_normals());
  write_bytes(dir / "c.xyz", "0 0 0 255 0 0\n1 0 0 0 255 0\n");  // colours, not normals
  r = read_point_set(dir / "c.xyz");
  EXPECT_FALSE(r.points.has_normals());
  EXPECT_TRUE(r.points.has_colours());  // issue 14: kept as colours (tests/nodes/io/appearance_test.cpp)
  EXPECT_TRUE(r.warnings.empty());
}

TEST(Pcd, AsciiWithNaNsAndNormals) {
  TempDir dir;
  write_bytes(dir / "a.pcd",
              "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z normal_x normal_y normal_z\nSIZE 4 4 4 4 4 4\nTYPE F F F F F F\n"
              "COUNT 1 1 1 1 1 1\nWIDTH 2\nHEIGHT 2\nVIEWPOINT 1 2 3 1 0 0 0\nPOINTS 4\nDATA ascii\n"
              "0 0 0 0 0 1\nnan nan nan nan nan nan\n1 0 0 0 0 1\n0 1 0 0 0 1\n");
  const LoadResult r = read_point_set(dir / "a.pcd");
  EXPECT_EQ(r.points.size(), 3);
  EXPECT_EQ(r.dropped_nonfinite, 1);
  EXPECT_TRUE(r.points.has_normals());
  ASSERT_TRUE(r.points.viewpoint());
  EXPECT_EQ(*r.points.viewpoint(), Eigen::Vector3d(1, 2, 3));
}

TEST(Load, MortonOrderKeepsTheWayBackToFileOrder) {
  TempDir dir;
  write_bytes(dir / "a.xyz", kCube8);
  const LoadResult sorted = read_point_set(dir / "a.xyz");
  const LoadResult plain = read_point_set(dir / "a.xyz", {.morton_sort = false});
  for (Index i = 0; i < 8; ++i)
    EXPECT_EQ(sorted.points.positions().col(i), plain.points.positions().col(sorted.points.source_index()(i)));
}

}  // namespace
}  // namespace scanfill
