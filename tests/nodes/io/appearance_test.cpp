// Colours and intensity as each reader finds them (issue 14: the scan's appearance is carried to the output): PLY
// red/green/blue in 8-bit, 16-bit and float, diffuse_red..., intensity and scalar_intensity; PCD packed rgb (float
// bits) and rgba (integer) in ascii, binary and binary_compressed, intensity; XYZ and OBJ r g b. Every file is made
// here with known values, and the Morton reordering keeps them with their points.
#include <gtest/gtest.h>

#include <cstring>

#include "nodes/core/errors.h"
#include "nodes/io/read_point_set.h"
#include "nodes/io/write_ply.h"
#include "test_util.h"

namespace scanfill {
namespace {

constexpr LoadOptions kFileOrder{.morton_sort = false};

template <class T>
std::string bytes_of(T v) {
  std::string b(sizeof v, '\0');
  std::memcpy(b.data(), &v, sizeof v);
  return b;
}

// LZF as literal runs only (each at most 32 bytes, preceded by its length - 1): a valid stream for our reader.
std::string lzf_literal(const std::string& raw) {
  std::string out;
  for (size_t at = 0; at < raw.size(); at += 32) {
    const size_t n = std::min<size_t>(32, raw.size() - at);
    out += char(n - 1);
    out += raw.substr(at, n);
  }
  return out;
}

std::array<int, 3> rgb(const PointSet& p, Index i) {
  return {p.colours()(0, i), p.colours()(1, i), p.colours()(2, i)};
}

TEST(Appearance, PlyUcharColoursAndFloatIntensityInAsciiAndBinary) {
  test::TempDir dir;
  const std::string head =
      "property float x\nproperty float y\nproperty float z\nproperty uchar red\n"
      "property uchar green\nproperty uchar blue\nproperty float intensity\nend_header\n";
  test::write_bytes(dir / "a.ply", "ply\nformat ascii 1.0\nelement vertex 3\n" + head +
                                       "0 0 0 255 0 7 0.25\n1 0 0 1 2 3 100\n0 1 0 200 100 50 -3.5\n");
  std::string binary = "ply\nformat binary_little_endian 1.0\nelement vertex 3\n" + head;
  const float xyz[3][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const std::uint8_t colours[3][3] = {{255, 0, 7}, {1, 2, 3}, {200, 100, 50}};
  const float intensity[3] = {0.25f, 100.0f, -3.5f};
  for (int i = 0; i < 3; ++i) {
    for (const float v : xyz[i]) binary += bytes_of(v);
    for (const std::uint8_t c : colours[i]) binary += char(c);
    binary += bytes_of(intensity[i]);
  }
  test::write_bytes(dir / "b.ply", binary);
  for (const char* name : {"a.ply", "b.ply"}) {
    const PointSet p = read_point_set(dir / name, kFileOrder).points;
    ASSERT_TRUE(p.has_colours()) << name;
    ASSERT_TRUE(p.has_intensity()) << name;
    for (int i = 0; i < 3; ++i) {
      EXPECT_EQ(rgb(p, i), (std::array<int, 3>{colours[i][0], colours[i][1], colours[i][2]})) << name << " " << i;
      EXPECT_EQ(p.intensity()(i), intensity[i]) << name << " " << i;
    }
  }
}

TEST(Appearance, PlyFloatSixteenBitAndDiffuseColoursAreScaledToBytes) {
  test::TempDir dir;
  const std::string xyz = "property float x\nproperty float y\nproperty float z\n";
  // Floats in [0, 1] are scaled by 255.
  test::write_bytes(dir / "f.ply", "ply\nformat ascii 1.0\nelement vertex 2\n" + xyz +
                                       "property float red\nproperty float green\nproperty float blue\nend_header\n"
                                       "0 0 0 1 0.5 0\n1 0 0 0.2 0.004 0.998\n");
  const PointSet f = read_point_set(dir / "f.ply", kFileOrder).points;
  ASSERT_TRUE(f.has_colours());
  EXPECT_EQ(rgb(f, 0), (std::array<int, 3>{255, 128, 0}));  // 127.5 rounds up
  EXPECT_EQ(rgb(f, 1), (std::array<int, 3>{51, 1, 254}));
  // A float above 1: the file holds [0, 255] floats, with a warning.
  test::write_bytes(dir / "g.ply", "ply\nformat ascii 1.0\nelement vertex 2\n" + xyz +
                                       "property float red\nproperty float green\nproperty float blue\nend_header\n"
                                       "0 0 0 255 0.5 10\n1 0 0 1 2 3\n");
  const LoadResult g = read_point_set(dir / "g.ply", kFileOrder);
  EXPECT_EQ(rgb(g.points, 0), (std::array<int, 3>{255, 1, 10}));
  ASSERT_EQ(g.warnings.size(), 1u);
  EXPECT_NE(g.warnings[0].find("read as [0, 255]"), std::string::npos) << g.warnings[0];
  // 16-bit colours scaled by 1/257; MeshLab's diffuse_ names; CloudCompare's scalar_intensity.
  test::write_bytes(dir / "u.ply", "ply\nformat ascii 1.0\nelement vertex 1\n" + xyz +
                                       "property ushort diffuse_red\nproperty ushort diffuse_green\n"
                                       "property ushort diffuse_blue\nproperty ushort scalar_intensity\nend_header\n"
                                       "0 0 0 65535 257 0 4000\n");
  const PointSet u = read_point_set(dir / "u.ply", kFileOrder).points;
  EXPECT_EQ(rgb(u, 0), (std::array<int, 3>{255, 1, 0}));
  EXPECT_EQ(u.intensity()(0), 4000.0f);
  // Two of three channels are no colour.
  test::write_bytes(dir / "two.ply", "ply\nformat ascii 1.0\nelement vertex 1\n" + xyz +
                                         "property uchar red\nproperty uchar green\nend_header\n0 0 0 1 2\n");
  EXPECT_FALSE(read_point_set(dir / "two.ply").points.has_colours());
}

TEST(Appearance, PcdPackedRgbAndRgbaAndIntensityInEveryEncoding) {
  test::TempDir dir;
  const std::uint32_t packed[3] = {0xFF102030u, 0x00FF8001u, 0x7F000000u};  // alpha, red, green, blue
  const float intensity[3] = {1.5f, 0.0f, 65535.0f};
  const auto head = [](const char* fields, const char* types, const char* data) {
    return std::string("VERSION 0.7\nFIELDS x y z ") + fields + "\nSIZE 4 4 4 4 4\nTYPE F F F " + types +
           "\nCOUNT 1 1 1 1 1\nWIDTH 3\nHEIGHT 1\nPOINTS 3\nDATA " + data + "\n";
  };
  // ascii: rgba as PCL writes it (an integer), rgb as a float whose bits are the packed value (PCL's reading of F).
  std::string ascii_u = head("rgba intensity", "U F", "ascii"), ascii_f = head("rgb intensity", "F F", "ascii");
  std::string binary = head("rgb intensity", "F F", "binary");
  std::string columns[5];  // binary_compressed: field by field
  for (int i = 0; i < 3; ++i) {
    float bits;
    std::memcpy(&bits, &packed[i], 4);
    char f[64];
    std::snprintf(f, sizeof f, "%.9g", double(bits));
    ascii_u += std::to_string(i) + " 0 0 " + std::to_string(packed[i]) + " " + std::to_string(intensity[i]) + "\n";
    ascii_f += std::to_string(i) + " 0 0 " + f + " " + std::to_string(intensity[i]) + "\n";
    const float x[3] = {float(i), 0, 0};
    for (int k = 0; k < 3; ++k) {
      binary += bytes_of(x[k]);
      columns[k] += bytes_of(x[k]);
    }
    binary += bytes_of(packed[i]) + bytes_of(intensity[i]);
    columns[3] += bytes_of(packed[i]);
    columns[4] += bytes_of(intensity[i]);
  }
  std::string raw;
  for (const auto& c : columns) raw += c;
  const std::string lzf = lzf_literal(raw);
  const std::string compressed = head("rgba intensity", "U F", "binary_compressed") +
                                 bytes_of(std::uint32_t(lzf.size())) + bytes_of(std::uint32_t(raw.size())) + lzf;
  const std::pair<const char*, std::string> files[] = {
      {"ascii_u.pcd", ascii_u}, {"ascii_f.pcd", ascii_f}, {"binary.pcd", binary}, {"compressed.pcd", compressed}};
  for (const auto& [name, bytes] : files) {
    test::write_bytes(dir / name, bytes);
    const PointSet p = read_point_set(dir / name, kFileOrder).points;
    ASSERT_TRUE(p.has_colours()) << name;
    ASSERT_TRUE(p.has_intensity()) << name;
    for (int i = 0; i < 3; ++i) {
      const std::array<int, 3> expected{int(packed[i] >> 16 & 255), int(packed[i] >> 8 & 255), int(packed[i] & 255)};
      EXPECT_EQ(rgb(p, i), expected) << name << " " << i;
      EXPECT_EQ(p.intensity()(i), intensity[i]) << name << " " << i;
    }
  }
  test::write_bytes(dir / "wide.pcd",
                    "VERSION 0.7\nFIELDS x y z rgb\nSIZE 4 4 4 8\nTYPE F F F F\nCOUNT 1 1 1 1\n"
                    "WIDTH 1\nHEIGHT 1\nPOINTS 1\nDATA ascii\n0 0 0 1\n");
  try {
    read_point_set(dir / "wide.pcd");
    ADD_FAILURE() << "an 8-byte rgb field was accepted";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("wide.pcd: field 'rgb' has SIZE 8 (a packed colour has 4 bytes)"),
              std::string::npos)
        << e.what();
  }
}

TEST(Appearance, XyzAndObjColourColumns) {
  test::TempDir dir;
  // Columns 4-6 that are not unit vectors but lie in [0, 255] are colours; in [0, 1], scaled by 255.
  test::write_bytes(dir / "c.xyz", "0 0 0 255 10 0\n1 0 0 3 2 1\n0 1 0 0 0 0\n");
  const PointSet c = read_point_set(dir / "c.xyz", kFileOrder).points;
  ASSERT_TRUE(c.has_colours());
  EXPECT_FALSE(c.has_normals());
  EXPECT_EQ(rgb(c, 0), (std::array<int, 3>{255, 10, 0}));
  EXPECT_EQ(rgb(c, 1), (std::array<int, 3>{3, 2, 1}));
  test::write_bytes(dir / "f.xyz", "0 0 0 0.2 0.4 0\n1 0 0 1 0.5 0\n0 1 0 0 0 0\n");
  EXPECT_EQ(rgb(read_point_set(dir / "f.xyz", kFileOrder).points, 0), (std::array<int, 3>{51, 102, 0}));
  // Unit vectors stay normals; values outside [0, 255] are neither, with a warning.
  test::write_bytes(dir / "n.xyz", "0 0 0 0 0 1\n1 0 0 1 0 0\n0 1 0 0 1 0\n");
  EXPECT_FALSE(read_point_set(dir / "n.xyz").points.has_colours());
  test::write_bytes(dir / "bad.xyz", "0 0 0 -4 0 300\n1 0 0 1 1 1\n0 1 0 0 0 0\n");
  const LoadResult bad = read_point_set(dir / "bad.xyz");
  EXPECT_FALSE(bad.points.has_colours());
  ASSERT_EQ(bad.warnings.size(), 1u);
  EXPECT_NE(bad.warnings[0].find("neither unit normals nor colours"), std::string::npos) << bad.warnings[0];
  // OBJ "v x y z r g b" in [0, 1]; kept only when every vertex has one.
  test::write_bytes(dir / "c.obj", "v 0 0 0 1 0 0.5\nv 1 0 0 0 1 0\nv 0 1 0 0.2 0.2 0.2\nf 1 2 3\n");
  const PointSet obj = read_point_set(dir / "c.obj", kFileOrder).points;
  ASSERT_TRUE(obj.has_colours());
  EXPECT_EQ(rgb(obj, 0), (std::array<int, 3>{255, 0, 128}));
  EXPECT_EQ(rgb(obj, 2), (std::array<int, 3>{51, 51, 51}));
  test::write_bytes(dir / "some.obj", "v 0 0 0 1 0 0.5\nv 1 0 0\nv 0 1 0 0.2 0.2 0.2\nf 1 2 3\n");
  EXPECT_FALSE(read_point_set(dir / "some.obj").points.has_colours());
  test::write_bytes(dir / "w.obj", "v 0 0 0 1\nv 1 0 0 1\nv 0 1 0 1\nf 1 2 3\n");  // homogeneous w, no colour
  EXPECT_FALSE(read_point_set(dir / "w.obj").points.has_colours());
}

// The Morton reordering and write_ply keep colours and intensity with their points, through a write and a read back.
TEST(Appearance, ReorderingAndWritingKeepAppearanceWithItsPoints) {
  test::TempDir dir;
  const Index n = 500;
  Eigen::Matrix3Xd p = Eigen::Matrix3Xd::Random(3, n);
  Matrix3Xu8 c(3, n);
  Eigen::VectorXf v(n);
  for (Index i = 0; i < n; ++i) {
    c.col(i) << std::uint8_t(i & 255), std::uint8_t(i >> 8), std::uint8_t(7 * i & 255);
    v(i) = float(i) + 0.5f;
  }
  PointSet points(p);
  points.set_colours(c);
  points.set_intensity(v);
  write_ply(dir / "p.ply", points);
  const PointSet sorted = read_point_set(dir / "p.ply").points;  // Morton order
  ASSERT_TRUE(sorted.has_colours());
  ASSERT_TRUE(sorted.has_intensity());
  bool reordered = false;
  for (Index j = 0; j < n; ++j) {
    const Index i = sorted.source_index()(j);
    reordered = reordered || i != j;
    ASSERT_EQ(sorted.colours().col(j), c.col(i)) << j;
    ASSERT_EQ(sorted.intensity()(j), v(i)) << j;
    ASSERT_EQ(sorted.positions().col(j).cast<float>(), p.col(i).cast<float>()) << j;
  }
  EXPECT_TRUE(reordered);
  // A point set's colours size is checked like any attribute.
  PointSet wrong(p);
  wrong.set_colours(Matrix3Xu8(3, n - 1));
  EXPECT_THROW(wrong.check(), InvariantError);
  // An extra property cannot repeat the point set's own colours.
  EXPECT_THROW(write_ply(dir / "q.ply", points, {{"red", PlyProperty::Type::kUint8, std::vector<double>(size_t(n))}}),
               InvariantError);
}

}  // namespace
}  // namespace scanfill
