// orient_faces: a mesh's parts wound consistently, closed parts facing out, as a file gives them.
#include "nodes/io/orient_faces.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <sstream>

#include "nodes/io/read_point_set.h"
#include "test_util.h"

namespace scanfill {
namespace {

// A unit cube about `centre` drawn face by face, as a script draws a box: each face its own four corners and two
// triangles, the faces in `inward` wound to face into the cube.
struct FaceByFaceCube {
  Eigen::Matrix3Xd positions{3, 0};
  std::vector<std::int32_t> triangles;

  FaceByFaceCube(const Eigen::Vector3d& centre, const std::vector<int>& inward) {
    for (int face = 0; face < 6; ++face) {
      const int axis = face / 2;
      const double side = face % 2 ? 0.5 : -0.5;
      Eigen::Vector3d u = Eigen::Vector3d::Unit((axis + 1) % 3), v = Eigen::Vector3d::Unit((axis + 2) % 3);
      if (side < 0) std::swap(u, v);  // u x v along the outward normal
      const auto first = std::int32_t(positions.cols());
      positions.conservativeResize(3, first + 4);
      const Eigen::Vector3d c = centre + side * Eigen::Vector3d::Unit(axis);
      positions.col(first) = c - 0.5 * u - 0.5 * v;
      positions.col(first + 1) = c + 0.5 * u - 0.5 * v;
      positions.col(first + 2) = c + 0.5 * u + 0.5 * v;
      positions.col(first + 3) = c - 0.5 * u + 0.5 * v;
      const bool in = std::find(inward.begin(), inward.end(), face) != inward.end();
      for (const auto& t : {std::array<int, 3>{0, 1, 2}, std::array<int, 3>{0, 2, 3}})
        triangles.insert(triangles.end(), {first + t[0], first + (in ? t[2] : t[1]), first + (in ? t[1] : t[2])});
    }
  }
};

// Per triangle, whether its normal points away from `centre`.
std::vector<bool> facing_out(const Eigen::Matrix3Xd& p, const std::vector<std::int32_t>& tri,
                             const Eigen::Vector3d& centre) {
  std::vector<bool> out;
  for (size_t f = 0; f * 3 < tri.size(); ++f) {
    const Eigen::Vector3d a = p.col(tri[3 * f]), b = p.col(tri[3 * f + 1]), c = p.col(tri[3 * f + 2]);
    out.push_back((b - a).cross(c - a).dot((a + b + c) / 3 - centre) > 0);
  }
  return out;
}

TEST(OrientFaces, AFaceByFaceBoxWithFacesDrawnInwardFacesOut) {
  FaceByFaceCube cube(Eigen::Vector3d(2, -1, 0.5), {0, 3, 4});  // bottom-x, top-y and bottom-z drawn inward
  EXPECT_EQ(orient_faces(cube.positions, cube.triangles), 6);
  for (const bool out : facing_out(cube.positions, cube.triangles, Eigen::Vector3d(2, -1, 0.5))) EXPECT_TRUE(out);
}

TEST(OrientFaces, AClosedPartWoundInwardThroughoutIsTurnedWhole) {
  FaceByFaceCube cube(Eigen::Vector3d::Zero(), {0, 1, 2, 3, 4, 5});
  EXPECT_EQ(orient_faces(cube.positions, cube.triangles), 12);
  for (const bool out : facing_out(cube.positions, cube.triangles, Eigen::Vector3d::Zero())) EXPECT_TRUE(out);
}

TEST(OrientFaces, AnOpenPartKeepsItsFirstFacesWindingAndAConsistentMeshIsUntouched) {
  FaceByFaceCube cube(Eigen::Vector3d::Zero(), {});
  const std::vector<std::int32_t> as_drawn = cube.triangles;
  EXPECT_EQ(orient_faces(cube.positions, cube.triangles), 0);
  EXPECT_EQ(cube.triangles, as_drawn);
  // A square of two triangles, the second drawn the other way: open, so the first decides (here: facing -z).
  Eigen::Matrix3Xd square(3, 4);
  square << 0, 0, 1, 1, 0, 1, 1, 0, 0, 0, 0, 0;
  std::vector<std::int32_t> tri{0, 1, 2, 0, 3, 2};
  EXPECT_EQ(orient_faces(square, tri), 1);
  for (size_t f = 0; f < 2; ++f) {
    const Eigen::Vector3d n = (square.col(tri[3 * f + 1]) - square.col(tri[3 * f]))
                                  .cross(square.col(tri[3 * f + 2]) - square.col(tri[3 * f]));
    EXPECT_LT(n.z(), 0) << "triangle " << f;
  }
}

TEST(OrientFaces, AnObjTemplateWithInwardFacesLoadsFacingOutWithAWarning) {
  const FaceByFaceCube cube(Eigen::Vector3d(0, 0, 0.5), {1, 5});
  std::ostringstream obj;
  for (Eigen::Index i = 0; i < cube.positions.cols(); ++i)
    obj << "v " << cube.positions(0, i) << ' ' << cube.positions(1, i) << ' ' << cube.positions(2, i) << '\n';
  for (size_t f = 0; f * 3 < cube.triangles.size(); ++f)
    obj << "f " << cube.triangles[3 * f] + 1 << ' ' << cube.triangles[3 * f + 1] + 1 << ' '
        << cube.triangles[3 * f + 2] + 1 << '\n';
  const test::TempDir dir;
  test::write_bytes(dir / "box.obj", obj.str());
  const LoadResult r = read_point_set(dir / "box.obj");
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_NE(r.warnings[0].find("4 of 12 faces"), std::string::npos) << r.warnings[0];
  const auto& F = r.points.faces();
  const std::vector<std::int32_t> tri(F.data(), F.data() + F.size());
  for (const bool out : facing_out(r.points.positions(), tri, Eigen::Vector3d(0, 0, 0.5))) EXPECT_TRUE(out);
}

}  // namespace
}  // namespace scanfill
