#include "nodes/io/write_ply.h"

#include <gtest/gtest.h>

#include "nodes/core/errors.h"
#include "nodes/io/read_point_set.h"
#include "nodes/procedural/shapes.h"
#include "test_util.h"

namespace scanfill {
namespace {

TEST(WritePly, RoundTripsPositionsNormalsFacesAndProperties) {
  test::TempDir dir;
  PointSet mesh = make_sphere(1.0, 16);
  Eigen::Matrix3Xd normals = mesh.positions().colwise().normalized();
  mesh.set_normals(normals);
  mesh.set_curvatures(Eigen::Matrix2Xd::Ones(2, mesh.size()));
  std::vector<double> labels(size_t(mesh.size()), 7.0);
  write_ply(dir / "out.ply", mesh, {{"label", PlyProperty::Type::kInt32, labels}});
  const std::string head = test::read_bytes(dir / "out.ply").substr(0, 400);
  EXPECT_NE(head.find("format binary_little_endian 1.0"), std::string::npos);
  EXPECT_NE(head.find("property float k1\nproperty float k2\n"), std::string::npos);
  EXPECT_NE(head.find("property int label\n"), std::string::npos);
  const LoadResult r = read_point_set(dir / "out.ply", {.morton_sort = false});
  ASSERT_EQ(r.points.size(), mesh.size());
  EXPECT_EQ(r.points.faces(), mesh.faces());
  EXPECT_LT((r.points.positions() - mesh.positions()).cwiseAbs().maxCoeff(), 1e-6);
  EXPECT_LT((r.points.normals() - mesh.normals()).cwiseAbs().maxCoeff(), 1e-6);
}

// A single-view scan keeps its sensor position through a PLY file: written as PCL writes it (a camera element after
// the faces), and read from PCL's own file, whose camera record has 21 properties.
TEST(WritePly, TheScannersPositionTravelsAsACameraElement) {
  test::TempDir dir;
  PointSet scan = make_plane(1.0, 3);
  scan.set_viewpoint(Eigen::Vector3d(0.5, -2.25, 3.0));
  write_ply(dir / "scan.ply", scan);
  const std::string head = test::read_bytes(dir / "scan.ply").substr(0, 300);
  EXPECT_NE(head.find("element camera 1\nproperty float view_px\n"), std::string::npos);
  const LoadResult r = read_point_set(dir / "scan.ply", {.morton_sort = false});
  ASSERT_TRUE(r.points.viewpoint().has_value());
  EXPECT_EQ(*r.points.viewpoint(), Eigen::Vector3d(0.5, -2.25, 3.0));
  EXPECT_EQ(r.points.size(), scan.size());

  std::string pcl =
      "ply\nformat ascii 1.0\ncomment PCL generated\nelement vertex 2\nproperty float x\nproperty float y\n"
      "property float z\nelement face 0\nelement camera 1\n";
  for (const char* name :
       {"view_px", "view_py", "view_pz", "x_axisx", "x_axisy", "x_axisz", "y_axisx", "y_axisy", "y_axisz", "z_axisx",
        "z_axisy", "z_axisz", "focal", "scalex", "scaley", "centerx", "centery"})
    pcl += std::string("property float ") + name + "\n";
  pcl += "property int viewportx\nproperty int viewporty\nproperty float k1\nproperty float k2\nend_header\n";
  test::write_bytes(dir / "pcl.ply", pcl + "1 2 3\n4 5 6\n0.5 1.5 2.5 1 0 0 0 1 0 0 0 1 0 0 0 0 0 2 1 0 0\n");
  const LoadResult p = read_point_set(dir / "pcl.ply", {.morton_sort = false});
  ASSERT_TRUE(p.points.viewpoint().has_value());
  EXPECT_EQ(*p.points.viewpoint(), Eigen::Vector3d(0.5, 1.5, 2.5));
  test::write_bytes(dir / "nan.ply", pcl + "1 2 3\n4 5 6\nnan 1.5 2.5 1 0 0 0 1 0 0 0 1 0 0 0 0 0 2 1 0 0\n");
  try {
    read_point_set(dir / "nan.ply", {});
    ADD_FAILURE() << "a camera at NaN was read";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("nan.ply"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("camera"), std::string::npos) << e.what();
  }
}

TEST(WritePly, FailureLeavesNoFile) {
  test::TempDir dir;
  const PointSet p = make_plane(1.0, 2);
  EXPECT_THROW(write_ply(dir / "missing_folder" / "out.ply", p), IoError);
  EXPECT_FALSE(std::filesystem::exists(dir / "missing_folder"));
  // A property of the wrong length is refused before anything is written.
  EXPECT_THROW(write_ply(dir / "bad.ply", p, {{"x2", PlyProperty::Type::kFloat32, {1.0}}}), InvariantError);
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

// PlyWriter in pieces writes write_ply's bytes; a writer that stops short of its declared counts leaves no file.
TEST(PlyWriter, PiecesGiveWritePlysBytesAndAShortFileIsRefused) {
  test::TempDir dir;
  PointSet mesh = make_sphere(1.0, 16);
  mesh.set_normals(mesh.positions().colwise().normalized());
  Matrix3Xu8 rgb = Matrix3Xu8::Constant(3, mesh.size(), 9);
  mesh.set_colours(rgb);
  std::vector<double> labels(size_t(mesh.size()));
  for (size_t i = 0; i < labels.size(); ++i) labels[i] = double(i % 11) - 3;
  const std::vector<PlyProperty> extra{{"label", PlyProperty::Type::kInt32, labels}};
  write_ply(dir / "whole.ply", mesh, extra);
  PlyWriter pieces(dir / "pieces.ply", ply_layout(mesh, extra));
  for (Index start = 0; start < mesh.size(); start += 13) {
    std::vector<std::int32_t> rows;
    for (Index i = start; i < std::min(mesh.size(), start + 13); ++i) rows.push_back(std::int32_t(i));
    const std::vector<double> part(labels.begin() + start, labels.begin() + start + Index(rows.size()));
    pieces.append(subset(mesh, rows), {{"label", PlyProperty::Type::kInt32, part}});
  }
  pieces.append_faces(mesh.faces().leftCols(5));
  pieces.append_faces(mesh.faces().rightCols(mesh.faces().cols() - 5));
  pieces.commit();
  EXPECT_EQ(test::read_bytes(dir / "pieces.ply"), test::read_bytes(dir / "whole.ply"));
  {
    PlyWriter short_file(dir / "short.ply", ply_layout(mesh, extra));
    short_file.append(subset(mesh, {0, 1, 2}), {{"label", PlyProperty::Type::kInt32, {1, 2, 3}}});
    EXPECT_THROW(short_file.commit(), InvariantError);
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "short.ply"));
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir.path()), {}), 2);  // no temporary left
}

TEST(WriteFileAtomic, ReplacesWholeFile) {
  test::TempDir dir;
  write_file_atomic(dir / "r.json", "first version, long");
  write_file_atomic(dir / "r.json", "second");
  EXPECT_EQ(test::read_bytes(dir / "r.json"), "second");
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir.path()), {}), 1);  // no temporaries left
}

}  // namespace
}  // namespace scanfill
