// MeshLab's picked-points files (.pp, "Edit > PickPoints > Save"): an XML list of named points,
//   <PickedPoints> ... <point x="0.1" y="0.2" z="0.3" active="1" name="nose"/> ... </PickedPoints>
// Attributes in any order; points marked active="0" are left out, as MeshLab leaves them unused.
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

namespace scanfill {

struct NamedPoint {
  std::string name;
  Eigen::Vector3d position;
};

// Throws IoError naming the file when it cannot be read, is not a picked-points file, or a point lacks a finite x, y
// or z or a name.
std::vector<NamedPoint> read_picked_points(const std::filesystem::path& path);

}  // namespace scanfill
