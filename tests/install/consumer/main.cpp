// A program that uses scanfill as a library (tests/install/install_test.cmake builds it against an installed tree):
// it loads a config, runs it (the TBB flow graph of the engine), reads output.ply back and scores it against the
// complete shape, printing one line "consumer: POINTS points, fscore F".
//   consumer CONFIG.yaml REFERENCE_SHAPE
#include <cstdio>
#include <exception>

#include "engine/config.h"
#include "engine/pipeline.h"
#include "nodes/eval/evaluate.h"
#include "nodes/io/read_point_set.h"
#include "nodes/procedural/shapes.h"

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: consumer CONFIG.yaml REFERENCE_SHAPE\n");
    return 2;
  }
  try {
    const scanfill::RunConfig config = scanfill::load_config(argv[1]);
    scanfill::run(config);
    const scanfill::PointSet output = scanfill::read_point_set(config.output_dir / "output.ply").points;
    scanfill::EvalOptions options;
    options.surface_samples = 50000;
    const scanfill::EvalResult score = scanfill::evaluate(output, scanfill::make_shape(argv[2]), options);
    std::printf("consumer: %lld points, fscore %.4f\n", static_cast<long long>(output.size()), score.fscore);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "consumer: %s\n", e.what());
    return 1;
  }
}
