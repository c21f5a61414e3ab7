// A part's axis-aligned box: the proxy of style exchange (paper section 7, "Style Exchange"; Figure 14).
#pragma once

#include <Eigen/Core>
#include <vector>

namespace scanfill {

struct PartBox {
  Eigen::Vector3d min = Eigen::Vector3d::Zero();
  Eigen::Vector3d max = Eigen::Vector3d::Zero();
  Eigen::Vector3d size() const { return max - min; }
  Eigen::Vector3d centre() const { return (min + max) / 2; }
  double volume() const { return size().prod(); }
};

using PartBoxes = std::vector<PartBox>;

}  // namespace scanfill
