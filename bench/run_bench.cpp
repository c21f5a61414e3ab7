// Whole runs: every config in bench/configs through run(), on 1 and 2 threads. Peak RSS is the process's so
// far (it accumulates); run one config per process (--benchmark_filter) for a run's own peak.
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include "engine/config.h"
#include "engine/console.h"
#include "engine/pipeline.h"

namespace scanfill {
namespace {

void BM_Run(benchmark::State& state, const std::string& config_name) {
  setup_logging(false, true);
  RunConfig config = load_config(std::filesystem::path(SCANFILL_SOURCE_DIR) / "bench" / "configs" / config_name);
  config.output_dir = std::filesystem::temp_directory_path() / ("scanfill_bench_" + config_name);
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, size_t(state.range(0)));
  for (auto _ : state) run(config);
  std::filesystem::remove_all(config.output_dir);
  state.counters["peak_rss_mb"] = peak_rss_mb();
}
// Each config at 1 and 2 threads. vase_1m and vase_10m are the large scans of DESIGN section 7 (10^6 points under
// 30 s and 4 GB, 10^7 under 5 minutes): a virtual range scan of the vase at 1830^2 and 5800^2 rays, about 10^6 and
// 10^7 points; the 10^7 run writes a ~700 MB output.ply.
const bool registered = [] {
  const struct {
    const char* name;
    const char* config;
    int iterations;
  } runs[] = {{"vase", "vase.yaml", 2},
              {"vase_40k", "vase_40k.yaml", 1},
              {"furniture_transfer", "furniture_transfer.yaml", 2},
              {"curves_iq", "curves_iq.yaml", 5},
              {"vase_1m", "vase_1m.yaml", 1},
              {"vase_10m", "vase_10m.yaml", 1}};
  for (const auto& r : runs)
    benchmark::RegisterBenchmark((std::string("BM_Run/") + r.name).c_str(),
                                 [config = std::string(r.config)](benchmark::State& s) { BM_Run(s, config); })
        ->Arg(1)
        ->Arg(2)
        ->Iterations(r.iterations)
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
  return true;
}();

}  // namespace
}  // namespace scanfill
