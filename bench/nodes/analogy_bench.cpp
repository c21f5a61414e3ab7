// vote + modes + support + label (the analogy of paper section 5) on the L of two boxes, the target sampled to
// range(0) samples and the source at the same spacing, on range(1) threads. Items = target samples.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <map>

#include "bench_util.h"
#include "nodes/features/estimate_features.h"
#include "nodes/label/label.h"
#include "nodes/modes/modes.h"
#include "nodes/sample/sample.h"
#include "nodes/support/support.h"
#include "nodes/vote/vote.h"

namespace scanfill {
namespace {

struct Inputs {
  PointSet source, target;
  double spacing = 0;
};

const Inputs& inputs(Index target_samples) {
  static std::map<Index, Inputs> cache;
  auto it = cache.find(target_samples);
  if (it != cache.end()) return it->second;
  Inputs in;
  const SampleResult t = sample(make_shape("box_l"), {.count = target_samples});
  in.spacing = t.spacing;
  in.target = estimate_features(t.samples, {}).points;
  in.source = estimate_features(sample(make_shape("box"), {.spacing = in.spacing}).samples, {}).points;
  return cache.emplace(target_samples, std::move(in)).first->second;
}

void BM_Analogy(benchmark::State& state) {
  const Inputs& in = inputs(state.range(0));
  tbb::global_control threads(tbb::global_control::max_allowed_parallelism, size_t(state.range(1)));
  VoteOptions vo;
  vo.allow_scale = false;
  SupportOptions so;
  so.allow_scale = false;
  Index labels_used = 0, mode_count = 0, transform_count = 0;
  double stage_ms[4] = {0, 0, 0, 0};  // vote, modes, support, label: summed over iterations
  for (auto _ : state) {
    bench::Stopwatch clock;
    const VoteResult votes = vote(in.source, in.target, in.spacing, vo);
    stage_ms[0] += clock.lap_ms();
    const ModesResult modes = find_modes(votes, {});
    stage_ms[1] += clock.lap_ms();
    const SupportResult support =
        grow_supports(in.source, in.target, modes.modes, in.spacing, mode_accuracy(votes, {}), so);
    stage_ms[2] += clock.lap_ms();
    const LabelResult labels = label_target(in.source, in.target, support.transforms, in.spacing, {});
    stage_ms[3] += clock.lap_ms();
    mode_count = Index(modes.modes.size());
    transform_count = Index(support.transforms.size());
    std::vector<std::uint8_t> used(support.transforms.size() + 1, 0);
    for (int l : labels.labels) used[size_t(l)] = 1;
    labels_used = std::count(used.begin(), used.end(), 1);
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
  state.counters["labels_used"] = double(labels_used);
  state.counters["modes"] = double(mode_count);
  state.counters["transforms"] = double(transform_count);
  state.counters["source_samples"] = double(in.source.size());
  const char* names[4] = {"vote_ms", "modes_ms", "support_ms", "label_ms"};
  for (int i = 0; i < 4; ++i) state.counters[names[i]] = stage_ms[i] / double(state.iterations());
}
BENCHMARK(BM_Analogy)
    ->ArgsProduct({{10000, 50000, 200000}, {1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(1);

}  // namespace
}  // namespace scanfill
