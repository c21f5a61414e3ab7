#include "nodes/core/analogy.h"

#include <cmath>

namespace scanfill {

Eigen::Matrix<double, 13, 1> embed(const Similarity& q, const VoteResult& f) {
  Eigen::Matrix<double, 13, 1> x;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) x(3 * r + c) = f.weights.rotation * q.rotation(r, c);
  x.segment<3>(9) = f.weights.translation * (q.translation - f.center) / f.diagonal;
  x(12) = f.weights.scale * std::log(q.scale);
  return x;
}

Similarity unembed(const Eigen::Matrix<double, 13, 1>& x, const VoteResult& f) {
  Similarity q;
  Eigen::Matrix3d M;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) M(r, c) = x(3 * r + c) / f.weights.rotation;
  q.rotation = nearest_rotation(M);
  q.translation = x.segment<3>(9) * f.diagonal / f.weights.translation + f.center;
  q.scale = std::exp(x(12) / f.weights.scale);
  return q;
}

}  // namespace scanfill
