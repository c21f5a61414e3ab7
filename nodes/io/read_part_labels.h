// A part label per vertex of a PLY (mode exchange): the segmentation a user gives with the exemplar or target.
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

namespace scanfill {

struct PartLabels {
  std::string property;                    // the vertex property read
  std::vector<Eigen::Vector3d> positions;  // the vertices with finite coordinates
  std::vector<int> labels;                 // their parts, as the file gives them
};

// Reads x y z and the first of `names` present among the PLY's vertex properties. Throws IoError naming the file
// when none is present (listing the properties it has), the property is a list, a value is not an integer, or the file
// is not a readable PLY.
PartLabels read_ply_part_labels(const std::filesystem::path& path, const std::vector<std::string>& names);

}  // namespace scanfill
