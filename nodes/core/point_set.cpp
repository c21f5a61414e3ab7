#include "nodes/core/point_set.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <string>

#include "nodes/core/errors.h"

namespace scanfill {

PointSet::PointSet(Eigen::Matrix3Xd positions) {
  set_positions(std::move(positions));
}

void PointSet::set_positions(Eigen::Matrix3Xd m) {
  positions_ = std::make_shared<const Eigen::Matrix3Xd>(std::move(m));
}
void PointSet::set_normals(Eigen::Matrix3Xd m) {
  normals_ = std::make_shared<const Eigen::Matrix3Xd>(std::move(m));
}
void PointSet::set_curvatures(Eigen::Matrix2Xd m) {
  curvatures_ = std::make_shared<const Eigen::Matrix2Xd>(std::move(m));
}
void PointSet::set_directions(Eigen::Matrix3Xd m) {
  directions_ = std::make_shared<const Eigen::Matrix3Xd>(std::move(m));
}
void PointSet::set_faces(Matrix3Xi m) {
  faces_ = std::make_shared<const Matrix3Xi>(std::move(m));
}
void PointSet::set_face_provenance(VectorXi32 face, Eigen::Matrix3Xd barycentrics) {
  source_face_ = std::make_shared<const VectorXi32>(std::move(face));
  barycentrics_ = std::make_shared<const Eigen::Matrix3Xd>(std::move(barycentrics));
}
void PointSet::set_source_index(VectorXi64 index) {
  source_index_ = std::make_shared<const VectorXi64>(std::move(index));
}

void PointSet::set_colours(Matrix3Xu8 m) {
  colours_ = std::make_shared<const Matrix3Xu8>(std::move(m));
}
void PointSet::set_intensity(Eigen::VectorXf v) {
  intensity_ = std::make_shared<const Eigen::VectorXf>(std::move(v));
}

std::vector<std::string> PointSet::attribute_names() const {
  std::vector<std::string> names{"positions"};
  if (has_normals()) names.push_back("normals");
  if (has_curvatures()) names.push_back("curvatures");
  if (has_directions()) names.push_back("directions");
  if (has_faces()) names.push_back("faces");
  if (has_face_provenance()) names.push_back("face_provenance");
  if (has_source_index()) names.push_back("source_index");
  if (has_colours()) names.push_back("colours");
  if (has_intensity()) names.push_back("intensity");
  if (viewpoint_) names.push_back("viewpoint");
  return names;
}

void PointSet::check() const {
  const Index n = size();
  auto expect = [n](const char* name, Index cols) {
    if (cols != 0 && cols != n)
      throw InvariantError(std::string("point set attribute '") + name + "' has " + std::to_string(cols) +
                           " entries for " + std::to_string(n) + " points");
  };
  expect("normals", normals().cols());
  expect("curvatures", curvatures().cols());
  expect("directions", directions().cols());
  expect("source_face", source_face().size());
  expect("barycentrics", barycentrics().cols());
  expect("source_index", source_index().size());
  expect("colours", colours().cols());
  expect("intensity", intensity().size());
  if (source_face().size() != barycentrics().cols())
    throw InvariantError("point set face provenance: source_face and barycentrics differ in size");
  if (has_faces() && (faces().minCoeff() < 0 || faces().maxCoeff() >= n))
    throw InvariantError("point set face index out of range [0, " + std::to_string(n) + ")");
}

namespace {
template <class M>
M take_columns(const M& m, const std::vector<std::int32_t>& indices) {
  M out(m.rows(), Index(indices.size()));
  for (size_t i = 0; i < indices.size(); ++i) out.col(Index(i)) = m.col(indices[i]);
  return out;
}
template <class V>
V take_entries(const V& v, const std::vector<std::int32_t>& indices) {
  V out(Index(indices.size()));
  for (size_t i = 0; i < indices.size(); ++i) out(Index(i)) = v(indices[i]);
  return out;
}
}  // namespace

std::vector<std::int32_t> strided_indices(Index n, Index most) {
  const Index stride = std::max<Index>(1, (n + most - 1) / std::max<Index>(1, most));
  std::vector<std::int32_t> out;
  out.reserve(size_t((n + stride - 1) / stride));
  for (Index i = 0; i < n; i += stride) out.push_back(std::int32_t(i));
  return out;
}

PointSet subset(const PointSet& points, const std::vector<std::int32_t>& indices) {
  PointSet out(take_columns(points.positions(), indices));
  if (points.has_normals()) out.set_normals(take_columns(points.normals(), indices));
  if (points.has_curvatures()) out.set_curvatures(take_columns(points.curvatures(), indices));
  if (points.has_directions()) out.set_directions(take_columns(points.directions(), indices));
  if (points.has_face_provenance())
    out.set_face_provenance(take_entries(points.source_face(), indices), take_columns(points.barycentrics(), indices));
  if (points.has_source_index()) out.set_source_index(take_entries(points.source_index(), indices));
  if (points.has_colours()) out.set_colours(take_columns(points.colours(), indices));
  if (points.has_intensity()) out.set_intensity(take_entries(points.intensity(), indices));
  return out;
}

BoundingBox bounding_box(const Eigen::Matrix3Xd& positions) {
  if (positions.cols() == 0) throw InvariantError("bounding box of an empty point set");
  return {positions.rowwise().minCoeff(), positions.rowwise().maxCoeff()};
}

double surface_area(const Eigen::Matrix3Xd& positions, const Matrix3Xi& faces) {
  double area = 0.0;
  for (Eigen::Index f = 0; f < faces.cols(); ++f) {
    const Eigen::Vector3d a = positions.col(faces(0, f));
    area += 0.5 * (positions.col(faces(1, f)) - a).cross(positions.col(faces(2, f)) - a).norm();
  }
  return area;
}

}  // namespace scanfill
