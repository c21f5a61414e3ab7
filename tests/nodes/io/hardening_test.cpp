// Issue 11: malformed files end in one IoError naming the file, never in a crash, a read past a buffer, or an
// allocation driven by a header count the file cannot hold. Also: every input a fuzz target ever crashed on
// (tests/nodes/io/regressions, minimised) loads or fails cleanly.
#include <gtest/gtest.h>
#include <sys/resource.h>

#include <chrono>
#include <cstring>

#include "nodes/core/errors.h"
#include "nodes/io/read_point_set.h"
#include "test_util.h"

namespace scanfill {
namespace {

using test::TempDir;
using test::write_bytes;

// Little-endian bytes of a value.
template <class T>
std::string le(T v) {
  std::string s(sizeof(T), '\0');
  std::memcpy(s.data(), &v, sizeof(T));
  return s;
}

struct Malformed {
  const char* name;
  std::string content;
  const char* message;
};

class MalformedFiles : public ::testing::TestWithParam<Malformed> {};

// One line naming the file and the problem, fast, and without the memory the header asks for.
TEST_P(MalformedFiles, FailInOneLineNamingTheFileWithoutAllocatingTheHeaderCounts) {
  TempDir dir;
  const Malformed& m = GetParam();
  const auto path = dir / m.name;
  write_bytes(path, m.content);
  const auto start = std::chrono::steady_clock::now();
  try {
    read_point_set(path);
    FAIL() << "no error for " << m.name;
  } catch (const IoError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind(path.string() + ": ", 0), 0u) << what;
    EXPECT_NE(what.find(m.message), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << "one line: " << what;
  }
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 5.0);
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  EXPECT_LT(usage.ru_maxrss, 300 * 1024) << "KiB";  // gtest_discover_tests runs each case in its own process
}

const std::string kPcdXyz = "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n";
const std::string kPlyBin =
    "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n";

INSTANTIATE_TEST_SUITE_P(
    Issue11, MalformedFiles,
    ::testing::Values(
        // PCD: these three crashed PCL's reader (SIGSEGV; "basic_string::substr" without a file name).
        Malformed{"version.pcd", "VERSION 0.7\n", "no FIELDS line"},
        Malformed{"fields.pcd", "FIELDS", "FIELDS lists no field"}, Malformed{"data.pcd", "DATA", "not a PCD file"},
        Malformed{"nodata.pcd", kPcdXyz + "WIDTH 1\nHEIGHT 1\nPOINTS 1\n", "no DATA line"},
        // SIZE smaller than TYPE: z used to be read as a 4-byte float from a 1-byte field, past the buffer.
        Malformed{"size1.pcd",
                  "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 1\nTYPE F F F\nWIDTH 1\nHEIGHT 1\nPOINTS 1\nDATA binary\n" +
                      std::string(9, '\0'),
                  "field 'z' has TYPE F with SIZE 1"},
        Malformed{"type.pcd",
                  "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F Q\nWIDTH 1\nPOINTS 1\nDATA ascii\n0 0 0\n",
                  "TYPE of field 'z' is 'Q'"},
        Malformed{"sizes.pcd",
                  "VERSION 0.7\nFIELDS x y z\nSIZE 4 4\nTYPE F F F\nWIDTH 1\nPOINTS 1\nDATA ascii\n0 0 0\n",
                  "SIZE has 2 entries for 3 fields"},
        Malformed{"wh.pcd", kPcdXyz + "WIDTH 3\nHEIGHT 2\nPOINTS 5\nDATA ascii\n0 0 0\n", "differs from POINTS"},
        Malformed{"kind.pcd", kPcdXyz + "WIDTH 1\nHEIGHT 1\nPOINTS 1\nDATA binary_lz4\n", "unknown DATA kind"},
        Malformed{"float.pcd", kPcdXyz + "WIDTH 1e300\nHEIGHT 1\nPOINTS 1\nDATA ascii\n0 0 0\n", "WIDTH expects one"},
        Malformed{"huge.pcd",
                  kPcdXyz + "WIDTH 4000000000000000000\nHEIGHT 1\nPOINTS 4000000000000000000\nDATA binary\n",
                  "truncated"},
        Malformed{"shortbin.pcd", kPcdXyz + "WIDTH 2\nHEIGHT 1\nPOINTS 2\nDATA binary\n" + std::string(20, '\0'),
                  "truncated: 2 points of 12 bytes"},
        Malformed{"lzf.pcd",
                  kPcdXyz + "WIDTH 1000000\nHEIGHT 1\nPOINTS 1000000\nDATA binary_compressed\n" + le<std::uint32_t>(4) +
                      le<std::uint32_t>(12000000) + std::string("\x01\x00\x00\x00", 4),
                  "cannot hold 12000000 bytes"},
        Malformed{"lzfbad.pcd",
                  kPcdXyz + "WIDTH 1\nHEIGHT 1\nPOINTS 1\nDATA binary_compressed\n" + le<std::uint32_t>(2) +
                      le<std::uint32_t>(12) + std::string("\xe0\x00", 2),
                  "corrupt binary_compressed"},
        Malformed{"cols.pcd", kPcdXyz + "WIDTH 2\nHEIGHT 1\nPOINTS 2\nDATA ascii\n0 0 0\n1 1\n", "line 11: 2 values"},
        // PLY: vertex counts the file cannot hold ("out of memory", "unexpected: vector::reserve" without a name).
        Malformed{"tera.ply",
                  "ply\nformat ascii 1.0\nelement vertex 1000000000000\nproperty float x\nproperty float y\n"
                  "property float z\nend_header\n0 0 0\n",
                  "element 'vertex' declares 1000000000000 records"},
        Malformed{"exa.ply",
                  "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000000000000\nproperty float x\n"
                  "property float y\nproperty float z\nend_header\n" +
                      std::string(12, '\0'),
                  "element 'vertex' declares 4000000000000000000 records"},
        Malformed{"floatcount.ply", "ply\nformat ascii 1.0\nelement vertex 1e300\nproperty float x\nend_header\n",
                  "invalid count '1e300'"},
        Malformed{"noprops.ply",
                  "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                  "property float z\nelement junk 4000000000000000000\nend_header\n0 0 0\n1 0 0\n0 1 0\n",
                  "element 'junk' declares 4000000000000000000 records without properties"},
        // A list count of 2x10^8 took 1.6 GB before "truncated".
        Malformed{"list.ply",
                  kPlyBin + "element face 1\nproperty list uint int vertex_indices\nend_header\n" +
                      std::string(36, '\0') + le<std::uint32_t>(200000000) + std::string(8, '\0'),
                  "declares a list of 200000000 items"},
        Malformed{"listf.ply",
                  kPlyBin + "element face 1\nproperty list float int vertex_indices\nend_header\n" +
                      std::string(36, '\0') + le<float>(1e30f) + std::string(8, '\0'),
                  "declares a list of"},
        Malformed{"listascii.ply",
                  "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                  "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                  "0 0 0\n1 0 0\n0 1 0\n1e300 0 1 2\n",
                  "'1e300' is not a list count"},
        Malformed{"index.ply",
                  "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                  "property float z\nelement face 1\nproperty list uchar float vertex_indices\nend_header\n"
                  "0 0 0\n1 0 0\n0 1 0\n3 0 1 1e300\n",
                  "not an integer"},
        // OFF: a 44-byte file whose face declares 2x10^8 vertices took 1.6 GB and 5 s.
        Malformed{"face.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n200000000 0 1 2\n",
                  "face 0 declares 200000000 vertices"},
        Malformed{"facef.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n1e300 0 1 2\n", "invalid face size '1e300'"},
        Malformed{"verts.off", "OFF\n1000000000000 0 0\n0 0 0\n", "declares 1000000000000 vertices"},
        Malformed{"faces.off", "OFF\n3 4000000000000000000 0\n0 0 0\n1 0 0\n0 1 0\n",
                  "declares 4000000000000000000 faces"},
        Malformed{"countf.off", "OFF\n1e300 1 0\n0 0 0\n", "expected vertex, face and edge counts"},
        Malformed{"index.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 1e300\n", "not an integer"},
        // STL: the triangle count against the file size.
        Malformed{"count.stl", std::string(80, ' ') + le<std::uint32_t>(4000000000u) + std::string(50, '\0'),
                  "declares 4000000000 triangles"},
        // OBJ and XYZ have no counts; numbers that are not are still named.
        Malformed{"corner.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 1e300\n", "bad face corner '1e300'"},
        Malformed{"nan.xyz", "0 0 0\n1 0 zz\n", "'zz' is not a number"}),
    [](const auto& info) {
      std::string s = info.param.name;
      for (char& c : s)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
      return s;
    });

// 64-bit integer fields are read, not silently 0 (TYPE I / U, SIZE 8), in binary and ascii.
TEST(PcdHardening, SixtyFourBitIntegerFieldsAreRead) {
  TempDir dir;
  const std::string head =
      "VERSION 0.7\nFIELDS x y z\nSIZE 8 8 8\nTYPE I U I\nCOUNT 1 1 1\nWIDTH 2\nHEIGHT 1\nPOINTS 2\n";
  write_bytes(dir / "b.pcd", head + "DATA binary\n" + le<std::int64_t>(-5) + le<std::uint64_t>(1ull << 40) +
                                 le<std::int64_t>(3) + le<std::int64_t>(7) + le<std::uint64_t>(9) +
                                 le<std::int64_t>(-(1ll << 50)));
  write_bytes(dir / "a.pcd", head + "DATA ascii\n-5 1099511627776 3\n7 9 -1125899906842624\n");
  for (const char* name : {"a.pcd", "b.pcd"}) {
    const LoadResult r = read_point_set(dir / name, {.morton_sort = false});
    ASSERT_EQ(r.points.size(), 2) << name;
    EXPECT_EQ(r.points.positions().col(0), Eigen::Vector3d(-5, double(1ull << 40), 3)) << name;
    EXPECT_EQ(r.points.positions().col(1), Eigen::Vector3d(7, 9, -double(1ll << 50))) << name;
  }
}

// Mixed field types and sizes, padding fields with COUNT > 1, and the three DATA kinds give the same points.
TEST(PcdHardening, AsciiBinaryAndCompressedAgree) {
  TempDir dir;
  const std::string head =
      "# .PCD v0.7\nVERSION 0.7\nFIELDS _ x y z rgb\nSIZE 1 4 8 2 4\nTYPE U F F I U\nCOUNT 3 1 1 1 1\nWIDTH 2\n"
      "HEIGHT 1\nVIEWPOINT 1 2 3 1 0 0 0\nPOINTS 2\n";
  write_bytes(dir / "a.pcd", head + "DATA ascii\n1 2 3 0.25 -1.5 7 99\n0 0 0 -2 0.125 -300 1\n");
  auto record = [](float x, double y, std::int16_t z) {
    return std::string(3, '\x01') + le(x) + le(y) + le(z) + le<std::uint32_t>(5);
  };
  write_bytes(dir / "b.pcd", head + "DATA binary\n" + record(0.25f, -1.5, 7) + record(-2, 0.125, -300));
  // binary_compressed: field by field, one LZF literal run (at most 32 bytes each).
  const std::string soa = std::string(6, '\x01') + le(0.25f) + le(-2.0f) + le(-1.5) + le(0.125) + le<std::int16_t>(7) +
                          le<std::int16_t>(-300) + le<std::uint32_t>(5) + le<std::uint32_t>(5);
  std::string lzf;
  for (size_t i = 0; i < soa.size(); i += 32) {
    const size_t n = std::min<size_t>(32, soa.size() - i);
    lzf += char(n - 1) + soa.substr(i, n);
  }
  write_bytes(dir / "c.pcd", head + "DATA binary_compressed\n" + le<std::uint32_t>(std::uint32_t(lzf.size())) +
                                 le<std::uint32_t>(std::uint32_t(soa.size())) + lzf);
  for (const char* name : {"a.pcd", "b.pcd", "c.pcd"}) {
    const LoadResult r = read_point_set(dir / name, {.morton_sort = false});
    ASSERT_EQ(r.points.size(), 2) << name;
    EXPECT_EQ(r.points.positions().col(0), Eigen::Vector3d(0.25, -1.5, 7)) << name;
    EXPECT_EQ(r.points.positions().col(1), Eigen::Vector3d(-2, 0.125, -300)) << name;
    ASSERT_TRUE(r.points.viewpoint()) << name;
    EXPECT_EQ(*r.points.viewpoint(), Eigen::Vector3d(1, 2, 3)) << name;
  }
}

// Every minimised input a fuzz target crashed on (tests/fuzz/README: how they get here) now loads or fails cleanly.
TEST(FuzzRegressions, EveryCrashInputLoadsOrFailsWithAnError) {
  const auto folder = test::source_dir() / "tests/nodes/io/regressions";
  int n = 0;
  for (const auto& entry : std::filesystem::directory_iterator(folder)) {
    if (entry.path().extension() == ".md") continue;
    ++n;
    try {
      const LoadResult r = read_point_set(entry.path());
      r.points.check();
    } catch (const Error& e) {
      EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << entry.path() << ": " << e.what();
    }
  }
  std::cout << n << " regression inputs\n";
}

}  // namespace
}  // namespace scanfill
