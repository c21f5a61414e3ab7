#include "nodes/core/similarity.h"

#include <Eigen/Geometry>

namespace scanfill {

Similarity fit_similarity(const Eigen::Matrix3Xd& from, const Eigen::Matrix3Xd& to, bool allow_scale) {
  Similarity q;
  if (from.cols() < 3 || from.cols() != to.cols()) return q;
  const Eigen::Matrix4d m = Eigen::umeyama(from, to, allow_scale);
  q.rotation = m.topLeftCorner<3, 3>();
  q.scale = allow_scale ? std::cbrt(q.rotation.determinant()) : 1.0;
  q.rotation /= q.scale;
  q.rotation = nearest_rotation(q.rotation);
  q.translation = m.topRightCorner<3, 1>();
  return q;
}

}  // namespace scanfill
