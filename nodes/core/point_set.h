// The data model passed between nodes: a struct-of-arrays point set (DESIGN section 3).
//
// Every per-point attribute is either empty or has exactly size() columns; check() enforces it. Attribute buffers are
// shared and immutable: copying a PointSet is cheap and a node that adds an attribute returns a copy with one buffer
// replaced, leaving the input untouched. PCL types never appear here.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace scanfill {

using Index = std::int64_t;
using Matrix3Xi = Eigen::Matrix<std::int32_t, 3, Eigen::Dynamic>;
using VectorXi64 = Eigen::Matrix<std::int64_t, Eigen::Dynamic, 1>;
using VectorXi32 = Eigen::Matrix<std::int32_t, Eigen::Dynamic, 1>;
using Matrix3Xu8 = Eigen::Matrix<std::uint8_t, 3, Eigen::Dynamic>;

class PointSet {
 public:
  PointSet() = default;
  explicit PointSet(Eigen::Matrix3Xd positions);

  Index size() const { return positions_ ? positions_->cols() : 0; }
  bool empty() const { return size() == 0; }

  // positions  3 by N
  const Eigen::Matrix3Xd& positions() const { return *positions_; }
  // normals  3 by N unit vectors, or 3 by 0
  const Eigen::Matrix3Xd& normals() const { return get(normals_); }
  // curvatures  2 by N signed principal curvatures (k1, k2), |k1| >= |k2|, or 2 by 0
  const Eigen::Matrix2Xd& curvatures() const { return get(curvatures_); }
  // directions  3 by N unit direction of k1 in the tangent plane, or 3 by 0
  const Eigen::Matrix3Xd& directions() const { return get(directions_); }
  // faces  3 by F vertex indices (triangles), or 3 by 0 for a point cloud
  const Matrix3Xi& faces() const { return get(faces_); }
  // source_face  N: the face of the mesh a sample was drawn from, or empty
  const VectorXi32& source_face() const { return get(source_face_); }
  // barycentrics  3 by N: the sample's barycentric coordinates in source_face, or 3 by 0
  const Eigen::Matrix3Xd& barycentrics() const { return get(barycentrics_); }
  // source_index  N: the index of the original input point a sample (or a reordered point) came from, or empty
  const VectorXi64& source_index() const { return get(source_index_); }
  // colours  3 by N red, green, blue in [0, 255] as the input file gave them (scaled from [0, 1] where it used floats),
  // or 3 by 0
  const Matrix3Xu8& colours() const { return get(colours_); }
  // intensity  N: a scanner's return strength as the input file gave it (no unit, no fixed range), or empty
  const Eigen::VectorXf& intensity() const { return get(intensity_); }

  bool has_normals() const { return normals().cols() > 0; }
  bool has_curvatures() const { return curvatures().cols() > 0; }
  bool has_directions() const { return directions().cols() > 0; }
  bool has_faces() const { return faces().cols() > 0; }
  bool has_face_provenance() const { return source_face().size() > 0; }
  bool has_source_index() const { return source_index().size() > 0; }
  bool has_colours() const { return colours().cols() > 0; }
  bool has_intensity() const { return intensity().size() > 0; }

  // The sensor position of a single-view scan, when the file says (PCD VIEWPOINT) or the user does.
  const std::optional<Eigen::Vector3d>& viewpoint() const { return viewpoint_; }

  void set_positions(Eigen::Matrix3Xd m);
  void set_normals(Eigen::Matrix3Xd m);
  void set_curvatures(Eigen::Matrix2Xd m);
  void set_directions(Eigen::Matrix3Xd m);
  void set_faces(Matrix3Xi m);
  void set_face_provenance(VectorXi32 face, Eigen::Matrix3Xd barycentrics);
  void set_source_index(VectorXi64 index);
  void set_colours(Matrix3Xu8 m);
  void set_intensity(Eigen::VectorXf v);
  void set_viewpoint(std::optional<Eigen::Vector3d> v) { viewpoint_ = v; }

  // Names of the attributes present, in a fixed order (for `info` and reports).
  std::vector<std::string> attribute_names() const;

  // Throws InvariantError naming the attribute whose size differs from size(), or a face index out of range.
  void check() const;

 private:
  template <class M>
  static const M& get(const std::shared_ptr<const M>& p) {
    static const M kEmpty;
    return p ? *p : kEmpty;
  }

  std::shared_ptr<const Eigen::Matrix3Xd> positions_ = std::make_shared<const Eigen::Matrix3Xd>();
  std::shared_ptr<const Eigen::Matrix3Xd> normals_;
  std::shared_ptr<const Eigen::Matrix2Xd> curvatures_;
  std::shared_ptr<const Eigen::Matrix3Xd> directions_;
  std::shared_ptr<const Matrix3Xi> faces_;
  std::shared_ptr<const VectorXi32> source_face_;
  std::shared_ptr<const Eigen::Matrix3Xd> barycentrics_;
  std::shared_ptr<const VectorXi64> source_index_;
  std::shared_ptr<const Matrix3Xu8> colours_;
  std::shared_ptr<const Eigen::VectorXf> intensity_;
  std::optional<Eigen::Vector3d> viewpoint_;
};

// Axis-aligned bounding box of the positions (min, max). Requires a non-empty set.
struct BoundingBox {
  Eigen::Vector3d min;
  Eigen::Vector3d max;
  double diagonal() const { return (max - min).norm(); }
};
BoundingBox bounding_box(const Eigen::Matrix3Xd& positions);

// The points `indices` of `points` with every per-point attribute (faces and viewpoint are dropped: a subset of a
// mesh's vertices is a cloud).
PointSet subset(const PointSet& points, const std::vector<std::int32_t>& indices);

// Every stride-th of the indices [0, n), the stride the smallest that keeps at most `most` of them (all when n <=
// most).
std::vector<std::int32_t> strided_indices(Index n, Index most);

// Total area of a triangle mesh.
double surface_area(const Eigen::Matrix3Xd& positions, const Matrix3Xi& faces);

}  // namespace scanfill
