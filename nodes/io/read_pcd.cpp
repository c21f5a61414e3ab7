// PCD reader: PCL's PCDReader (ascii, binary, binary_compressed), the one place PCL is included for I/O.
// Fields x y z (float or double) and, when present, normal_x normal_y normal_z. The VIEWPOINT origin becomes the
// point set's viewpoint (the sensor position of a single-view scan).
#include <pcl/PCLPointCloud2.h>
#include <pcl/console/print.h>
#include <pcl/io/pcd_io.h>

#include <cstring>
#include <fstream>
#include <mutex>

#include "nodes/io/raw_mesh.h"

namespace scanfill::io {
namespace {

const pcl::PCLPointField* find_field(const pcl::PCLPointCloud2& cloud, const char* name) {
  for (const auto& f : cloud.fields)
    if (f.name == name) return &f;
  return nullptr;
}

double field_value(const std::uint8_t* point, const pcl::PCLPointField& f) {
  const std::uint8_t* p = point + f.offset;
  switch (f.datatype) {
    case pcl::PCLPointField::FLOAT32: {
      float v;
      std::memcpy(&v, p, 4);
      return v;
    }
    case pcl::PCLPointField::FLOAT64: {
      double v;
      std::memcpy(&v, p, 8);
      return v;
    }
    case pcl::PCLPointField::INT32: {
      std::int32_t v;
      std::memcpy(&v, p, 4);
      return v;
    }
    case pcl::PCLPointField::UINT32: {
      std::uint32_t v;
      std::memcpy(&v, p, 4);
      return v;
    }
    case pcl::PCLPointField::INT16: {
      std::int16_t v;
      std::memcpy(&v, p, 2);
      return v;
    }
    case pcl::PCLPointField::UINT16: {
      std::uint16_t v;
      std::memcpy(&v, p, 2);
      return v;
    }
    case pcl::PCLPointField::INT8: {
      std::int8_t v;
      std::memcpy(&v, p, 1);
      return v;
    }
    case pcl::PCLPointField::UINT8: {
      std::uint8_t v;
      std::memcpy(&v, p, 1);
      return v;
    }
    default:
      return 0;
  }
}

}  // namespace

RawMesh read_pcd(const std::filesystem::path& path) {
  static std::once_flag quiet;
  std::call_once(quiet, [] { pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS); });
  (void)read_file(path);  // the same "no such file" / "file is empty" messages as the other formats

  std::string encoding = "ascii";
  {
    std::ifstream in(path);
    std::string line;
    bool magic = false;
    while (std::getline(in, line)) {
      if (line.rfind("DATA", 0) == 0) {
        encoding = line.substr(5);
        while (!encoding.empty() && (encoding.back() == '\r' || encoding.back() == ' ')) encoding.pop_back();
        break;
      }
      if (line.rfind("VERSION", 0) == 0 || line.rfind("FIELDS", 0) == 0) magic = true;
    }
    if (!magic) fail(path, "not a PCD file (no VERSION or FIELDS header line)");
  }

  pcl::PCDReader reader;
  pcl::PCLPointCloud2 cloud;
  Eigen::Vector4f origin;
  Eigen::Quaternionf orientation;
  int version = 0;
  int status;
  try {
    status = reader.read(path.string(), cloud, origin, orientation, version);
  } catch (const std::exception& e) {
    fail(path, std::string("PCD read error: ") + e.what());
  }
  if (status < 0) fail(path, "malformed or truncated PCD (" + encoding + " data)");
  const auto n = std::uint64_t(cloud.width) * cloud.height;
  if (cloud.data.size() < n * cloud.point_step)
    fail(path, "truncated: " + std::to_string(n) + " points declared, data holds " +
                   std::to_string(cloud.point_step ? cloud.data.size() / cloud.point_step : 0));
  const pcl::PCLPointField* fx = find_field(cloud, "x");
  const pcl::PCLPointField* fy = find_field(cloud, "y");
  const pcl::PCLPointField* fz = find_field(cloud, "z");
  if (!fx || !fy || !fz) fail(path, "PCD has no x, y, z fields");
  const pcl::PCLPointField* fn[3] = {find_field(cloud, "normal_x"), find_field(cloud, "normal_y"),
                                     find_field(cloud, "normal_z")};
  const bool normals = fn[0] && fn[1] && fn[2];

  RawMesh mesh;
  mesh.encoding = encoding;
  mesh.xyz.resize(3 * n);
  if (normals) mesh.normals.resize(3 * n);
  for (std::uint64_t i = 0; i < n; ++i) {
    const std::uint8_t* pt = cloud.data.data() + i * cloud.point_step;
    mesh.xyz[3 * i] = field_value(pt, *fx);
    mesh.xyz[3 * i + 1] = field_value(pt, *fy);
    mesh.xyz[3 * i + 2] = field_value(pt, *fz);
    if (normals)
      for (int k = 0; k < 3; ++k) mesh.normals[3 * i + k] = field_value(pt, *fn[k]);
  }
  mesh.viewpoint = origin.head<3>().cast<double>();
  return mesh;
}

}  // namespace scanfill::io
