#include "nodes/io/read_ply_chunks.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <limits>

#include "nodes/core/errors.h"
#include "nodes/io/read_point_set.h"
#include "test_util.h"

namespace scanfill {
namespace {

using test::TempDir;
using test::write_bytes;

template <typename T>
void put(std::string& s, T v, bool big) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  if (big != (std::endian::native == std::endian::big)) std::reverse(b, b + sizeof(T));
  s.append(b, sizeof(T));
}

// A binary PLY of n vertices: x y z as double, a float property read past, normals as float (one of them not unit),
// every 11th point with a NaN coordinate.
std::string vertex_ply(int n, bool big) {
  std::string s = std::string("ply\nformat ") + (big ? "binary_big_endian" : "binary_little_endian") +
                  " 1.0\nelement vertex " + std::to_string(n) +
                  "\nproperty double x\nproperty double y\nproperty double z\nproperty float quality\n"
                  "property float nx\nproperty float ny\nproperty float nz\nend_header\n";
  for (int i = 0; i < n; ++i) {
    const double x = i % 11 == 5 ? std::numeric_limits<double>::quiet_NaN() : std::sin(0.37 * i);
    put(s, x, big);
    put(s, std::cos(0.11 * i), big);
    put(s, 0.001 * i * i, big);
    put(s, float(i), big);
    put(s, float(i % 3 == 0 ? 2.0 : 0.6), big);
    put(s, 0.8f, big);
    put(s, 0.0f, big);
  }
  return s;
}

// Every run of the reader appended: what a chunked pass over the file gives.
PointSet read_in_chunks(PlyChunkReader& reader, Index chunk) {
  Eigen::Matrix3Xd P(3, 0), N(3, 0);
  VectorXi64 source(0);
  PointSet run;
  while (reader.next(chunk, run)) {
    const Index at = P.cols(), n = run.size();
    P.conservativeResize(3, at + n);
    N.conservativeResize(3, at + n);
    source.conservativeResize(at + n);
    P.middleCols(at, n) = run.positions();
    N.middleCols(at, n) = run.normals();
    source.segment(at, n) = run.source_index();
  }
  PointSet all(std::move(P));
  all.set_normals(std::move(N));
  all.set_source_index(std::move(source));
  return all;
}

TEST(PlyChunks, ChunkedReadIsTheWholeReadBitForBit) {
  TempDir dir;
  constexpr int kPoints = 100;
  for (bool big : {false, true}) {
    write_bytes(dir / "v.ply", vertex_ply(kPoints, big));
    const LoadResult whole = read_point_set(dir / "v.ply", {.morton_sort = false});
    ASSERT_EQ(whole.points.size(), kPoints - 9);  // rows 5, 16, ..., 93 are not finite
    PlyChunkReader reader(dir / "v.ply");
    EXPECT_EQ(reader.rows(), kPoints);
    EXPECT_TRUE(reader.has_normals());
    for (const Index chunk : {Index(1), Index(7), Index(kPoints)}) {
      reader.rewind();
      const PointSet chunked = read_in_chunks(reader, chunk);
      EXPECT_EQ(reader.dropped_nonfinite(), 9);
      ASSERT_EQ(chunked.size(), whole.points.size()) << "chunk " << chunk;
      EXPECT_EQ(0, std::memcmp(chunked.positions().data(), whole.points.positions().data(),
                               sizeof(double) * size_t(3 * chunked.size())))
          << "chunk " << chunk;
      EXPECT_EQ(0, std::memcmp(chunked.normals().data(), whole.points.normals().data(),
                               sizeof(double) * size_t(3 * chunked.size())))
          << "chunk " << chunk;
      EXPECT_EQ(chunked.source_index(), whole.points.source_index()) << "chunk " << chunk;
    }
  }
}

TEST(PlyChunks, RefusesWhatItCannotReadInChunksNamingTheFile) {
  TempDir dir;
  write_bytes(dir / "a.ply",
              "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
              "property float z\nend_header\n0 0 0\n");
  try {
    PlyChunkReader reader(dir / "a.ply");
    FAIL() << "an ascii PLY was accepted";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("a.ply"), std::string::npos) << e.what();
  }
  std::string cut = vertex_ply(10, false);
  write_bytes(dir / "cut.ply", cut.substr(0, cut.size() - 5));
  EXPECT_THROW(PlyChunkReader(dir / "cut.ply"), IoError);  // the header's counts against the file's size
}

}  // namespace
}  // namespace scanfill
