// Built by tests/install/install_test.cmake with nothing but `pkg-config --cflags --libs scanfill`: the .pc file's
// include path, Eigen and -lscanfill are enough to compile and link a call into the library.
#include <cstdio>

#include "nodes/procedural/shapes.h"

int main() {
  const scanfill::PointSet sphere = scanfill::make_sphere(1.0, 16);
  std::printf("pkg-config: sphere of %lld points\n", static_cast<long long>(sphere.size()));
  return sphere.size() > 0 ? 0 : 1;
}
