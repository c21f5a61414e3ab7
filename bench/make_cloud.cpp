// Writes the benchmark cloud, N points area-uniform on the procedural vase, as a file that PCL's own tools and
// scanfill read: bench_cloud N out.pcd | out.ply [normals]
//
// .pcd: binary PCD, x y z as float (bench/compare_pcl.sh); .ply: binary little-endian PLY, x y z as float, and with
// `normals` nx ny nz as float (the input of bench/configs/vase_100m.yaml). The points are made and written triangle by
// triangle in the mesh's order (ring by ring up the vase, so runs of the file are compact in space), each triangle
// getting its share of N by its area, never the whole cloud: memory does not grow with N (10^8 points: 1.2 GB of file,
// 2.4 GB with normals, a few MB of memory).
#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "nodes/procedural/shapes.h"

namespace {

using scanfill::Index;

// Cumulative triangle areas of the mesh (the last is the total).
std::vector<double> cumulative_areas(const scanfill::PointSet& mesh) {
  const auto& P = mesh.positions();
  const auto& F = mesh.faces();
  std::vector<double> cumulative(size_t(F.cols()));
  double total = 0;
  for (Index f = 0; f < F.cols(); ++f) {
    total += 0.5 * (P.col(F(1, f)) - P.col(F(0, f))).cross(P.col(F(2, f)) - P.col(F(0, f))).norm();
    cumulative[size_t(f)] = total;
  }
  return cumulative;
}

// Face f's share of n points: the rounded cumulative counts' difference, so that the shares add up to n exactly.
Index share(const std::vector<double>& cumulative, Index f, Index n) {
  const double total = cumulative.back();
  const auto upto = [&](Index g) {
    return g < 0 ? Index(0) : Index(std::llround(double(n) * cumulative[size_t(g)] / total));
  };
  return upto(f) - upto(f - 1);
}

void write_header(std::ofstream& out, const std::string& path, Index n, bool normals) {
  if (path.ends_with(".pcd")) {
    out << "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH " << n
        << "\nHEIGHT 1\nVIEWPOINT 3 0 0.5 1 0 0 0\nPOINTS " << n << "\nDATA binary\n";
    return;
  }
  out << "ply\nformat binary_little_endian 1.0\ncomment bench_cloud: " << n
      << " points on the procedural vase\nelement vertex " << n
      << "\nproperty float x\nproperty float y\nproperty float z\n"
      << (normals ? "property float nx\nproperty float ny\nproperty float nz\n" : "") << "end_header\n";
}

}  // namespace

int main(int argc, char** argv) {
  const bool normals = argc == 4 && std::string(argv[3]) == "normals";
  const std::string path = argc >= 3 ? argv[2] : "";
  if ((argc != 3 && !normals) || !(path.ends_with(".pcd") || path.ends_with(".ply")) ||
      (normals && !path.ends_with(".ply"))) {
    std::fprintf(stderr, "usage: bench_cloud N out.pcd | bench_cloud N out.ply [normals]\n");
    return 2;
  }
  const Index n = std::stoll(argv[1]);
  const scanfill::PointSet mesh = scanfill::make_vase();
  const auto& P = mesh.positions();
  const auto& F = mesh.faces();
  const std::vector<double> cumulative = cumulative_areas(mesh);
  std::ofstream out(path, std::ios::binary);
  write_header(out, path, n, normals);
  std::vector<float> record;
  for (Index f = 0; f < F.cols(); ++f) {
    const Index m = share(cumulative, f, n);
    std::mt19937_64 rng(0x9e3779b97f4a7c15ull ^ std::uint64_t(f));  // one generator per face: the same file any run
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    const Eigen::Vector3d a = P.col(F(0, f)), b = P.col(F(1, f)), c = P.col(F(2, f));
    const Eigen::Vector3d face_normal = (b - a).cross(c - a).normalized();
    record.clear();
    for (Index i = 0; i < m; ++i) {
      const double s = std::sqrt(u01(rng)), v = u01(rng);
      const Eigen::Vector3d p = (1 - s) * a + s * (1 - v) * b + s * v * c;
      record.insert(record.end(), {float(p.x()), float(p.y()), float(p.z())});
      if (normals)
        record.insert(record.end(), {float(face_normal.x()), float(face_normal.y()), float(face_normal.z())});
    }
    out.write(reinterpret_cast<const char*>(record.data()), std::streamsize(record.size() * sizeof(float)));
  }
  out.close();
  if (!out) {
    std::fprintf(stderr, "bench_cloud: %s: cannot write\n", path.c_str());
    return 1;
  }
  return 0;
}
