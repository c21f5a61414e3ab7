#include "nodes/correspond/correspondence_view.h"

#include <algorithm>
#include <cmath>

namespace scanfill {
namespace {

Rgb place_colour(const Eigen::Vector3d& p, const BoundingBox& box) {
  Rgb c{};
  for (int k = 0; k < 3; ++k) {
    const double extent = std::max(box.max(k) - box.min(k), 1e-12);
    c[size_t(k)] = std::uint8_t(std::lround(40 + 215 * std::clamp((p(k) - box.min(k)) / extent, 0.0, 1.0)));
  }
  return c;
}

}  // namespace

CorrespondenceView correspondence_view(const PointSet& source, const CorrespondResult& map) {
  const BoundingBox box = bounding_box(source.positions());
  const Index ns = source.size(), ne = map.registered.cols();
  const Eigen::Vector3d shift(1.2 * std::max(box.max.x() - box.min.x(), 1e-12) + 0.1 * box.diagonal(), 0, 0);
  Eigen::Matrix3Xd p(3, ns + ne);
  CorrespondenceView view;
  for (Index s = 0; s < ns; ++s) {
    p.col(s) = source.positions().col(s);
    view.colours.push_back(place_colour(source.positions().col(s), box));
    view.side.push_back(0);
  }
  for (Index e = 0; e < ne; ++e) {
    p.col(ns + e) = map.registered.col(e) + shift;
    const std::int32_t s = size_t(e) < map.exemplar_source.size() ? map.exemplar_source[size_t(e)] : -1;
    view.colours.push_back(s >= 0 ? place_colour(source.positions().col(s), box) : Rgb{150, 150, 150});
    view.side.push_back(1);
  }
  view.points = PointSet(std::move(p));
  return view;
}

}  // namespace scanfill
