// Writes the benchmark cloud (N points on the procedural vase) as a binary PCD, so that PCL's own tools can be timed
// on exactly the input the benchmarks use: bench_cloud N out.pcd
#include <cstdio>
#include <fstream>
#include <string>

#include "bench_util.h"

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: bench_cloud N out.pcd\n");
    return 2;
  }
  const scanfill::Index n = std::stoll(argv[1]);
  const scanfill::PointSet cloud = scanfill::bench::vase_cloud(n);
  std::ofstream out(argv[2], std::ios::binary);
  out << "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH " << n
      << "\nHEIGHT 1\nVIEWPOINT 3 0 0.5 1 0 0 0\nPOINTS " << n << "\nDATA binary\n";
  for (scanfill::Index i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) {
      const float v = float(cloud.positions()(k, i));
      out.write(reinterpret_cast<const char*>(&v), 4);
    }
  return out ? 0 : 1;
}
