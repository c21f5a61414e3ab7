// render and write_png: the preview's rasteriser and its PNG file, against known answers.
#include "nodes/render/render.h"

#include <gtest/gtest.h>
#include <zlib.h>

#include "nodes/io/write_png.h"
#include "test_util.h"

namespace scanfill {
namespace {

std::uint32_t be32(const std::string& s, size_t at) {
  std::uint32_t v = 0;
  for (size_t k = 0; k < 4; ++k) v = v << 8 | std::uint8_t(s[at + k]);
  return v;
}

const std::uint8_t* pixel(const Image& image, int x, int y) {
  return &image.rgb[3 * (size_t(y) * image.width + x)];
}

TEST(Render, APointAtTheTargetLandsInTheImageCentreAndTheNearestWins) {
  Eigen::Matrix3Xd p(3, 2);
  p.col(0) = Eigen::Vector3d(0, 1, 0);  // behind the first, seen from -y
  p.col(1) = Eigen::Vector3d(0, 0, 0);
  const PointSet points(p);
  Camera camera;  // eye (0, -3, 0), looking at the origin, z up
  Image image = blank_image(101, 101);
  render_points(points, {Rgb{255, 0, 0}, Rgb{0, 0, 255}}, camera, 2.0, image);
  const std::uint8_t* c = pixel(image, 50, 50);
  EXPECT_EQ(c[0], 0);
  EXPECT_EQ(c[2], 255);                   // the nearer (blue) point, whatever the order
  EXPECT_EQ(pixel(image, 0, 0)[0], 255);  // background stays white
  EXPECT_EQ(pixel(image, 0, 0)[1], 255);
  // +x appears on the right, +z at the top.
  Eigen::Matrix3Xd q(3, 2);
  q.col(0) = Eigen::Vector3d(0.5, 0, 0);
  q.col(1) = Eigen::Vector3d(0, 0, 0.5);
  Image moved = blank_image(101, 101);
  render_points(PointSet(q), {Rgb{0, 0, 0}}, camera, 1.0, moved);
  const double f = 0.5 * 101 / std::tan(15 * M_PI / 180);
  EXPECT_EQ(pixel(moved, int(std::lround(50.5 + f * 0.5 / 3)), 50)[0], 0);
  EXPECT_EQ(pixel(moved, 50, int(std::lround(50.5 - f * 0.5 / 3)))[0], 0);
}

TEST(Render, PreviewCamerasFrameTheBoxFromBothSides) {
  const BoundingBox box{Eigen::Vector3d(-1, -1, 0), Eigen::Vector3d(1, 1, 2)};
  const auto cams = preview_cameras(box, Eigen::Vector3d(0, -5, 1));
  EXPECT_TRUE(cams[0].target.isApprox(Eigen::Vector3d(0, 0, 1)));
  EXPECT_LT(cams[0].eye.y(), -1);  // the scan's side
  EXPECT_GT(cams[1].eye.y(), 1);   // the opposite one, at the same height
  EXPECT_NEAR(cams[0].eye.z(), cams[1].eye.z(), 1e-12);
  EXPECT_NEAR((cams[0].eye - cams[0].target).norm(), (cams[1].eye - cams[1].target).norm(), 1e-12);
}

TEST(WritePng, TheFileIsAValidPngHoldingThePixels) {
  test::TempDir dir;
  Image image = blank_image(7, 3);
  for (size_t i = 0; i < image.rgb.size(); ++i) image.rgb[i] = std::uint8_t(i * 37);
  write_png(dir / "a.png", image);
  const std::string png = test::read_bytes(dir / "a.png");
  ASSERT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  ASSERT_EQ(png.substr(12, 4), "IHDR");
  EXPECT_EQ(be32(png, 16), 7u);
  EXPECT_EQ(be32(png, 20), 3u);
  EXPECT_EQ(be32(png, 29), std::uint32_t(crc32(0, reinterpret_cast<const Bytef*>(png.data() + 12), 17)));
  const size_t idat = 8 + 25;
  ASSERT_EQ(png.substr(idat + 4, 4), "IDAT");
  const std::uint32_t length = be32(png, idat);
  std::string raw(3 * (1 + 7 * 3), '\0');
  uLongf raw_size = raw.size();
  ASSERT_EQ(uncompress(reinterpret_cast<Bytef*>(raw.data()), &raw_size,
                       reinterpret_cast<const Bytef*>(png.data() + idat + 8), length),
            Z_OK);
  for (int y = 0; y < 3; ++y) {
    EXPECT_EQ(raw[size_t(y) * 22], '\0');  // filter: none
    EXPECT_EQ(raw.substr(size_t(y) * 22 + 1, 21),
              std::string(reinterpret_cast<const char*>(image.rgb.data()) + y * 21, 21));
  }
  EXPECT_EQ(png.substr(png.size() - 8, 4), "IEND");
}

}  // namespace
}  // namespace scanfill
