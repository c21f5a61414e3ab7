#include "engine/pipeline.h"

#include <sys/resource.h>
#include <tbb/flow_graph.h>

#include "engine/outputs.h"
#include "engine/stages.h"
#include "engine/staging.h"
#include "nodes/core/errors.h"

namespace scanfill {
namespace {

namespace flow = tbb::flow;

// One run's graph and the nodes it owns; every node is serial and runs once.
class Wiring {
 public:
  Wiring(flow::graph& g, RunState& state) : state(state), g_(g), start(g) {}
  RunState& state;

  template <class In, class Out, class F>
  flow::function_node<In, Out>& node(F&& body) {
    return own(std::make_unique<flow::function_node<In, Out>>(g_, flow::serial, std::forward<F>(body)));
  }
  // Waits for one message on each input: the node after it gets them together.
  template <class A, class B>
  flow::join_node<std::tuple<A, B>, flow::queueing>& join(flow::sender<A>& a, flow::sender<B>& b) {
    auto& j = own(std::make_unique<flow::join_node<std::tuple<A, B>, flow::queueing>>(g_));
    flow::make_edge(a, flow::input_port<0>(j));
    flow::make_edge(b, flow::input_port<1>(j));
    return j;
  }
  void run() {
    start.try_put(flow::continue_msg());
    g_.wait_for_all();  // rethrows the first node error; the graph is cancelled
  }

 private:
  template <class N>
  N& own(std::unique_ptr<N> n) {
    N& ref = *n;
    nodes_.push_back(std::move(n));
    return ref;
  }
  flow::graph& g_;
  std::vector<std::unique_ptr<flow::graph_node>> nodes_;

 public:
  flow::broadcast_node<flow::continue_msg> start;
};

// One input's branch: load -> sample -> features.
struct Branch {
  flow::sender<SampledPtr>* sampled;
  flow::sender<FeaturedPtr>* features;
};

// Every input but the reference is sampled at the reference's spacing alpha (the paper's): its sample node waits for
// the reference's samples.
Branch add_input_branch(Wiring& w, Role role, const Branch* reference = nullptr) {
  const Input& input = input_for(w.state.config, role);
  auto& load =
      w.node<flow::continue_msg, LoadedPtr>([&w, input](flow::continue_msg) { return load_stage(w.state, input); });
  flow::make_edge(w.start, load);
  flow::sender<SampledPtr>* sampled = nullptr;
  if (!reference) {
    auto& sample = w.node<LoadedPtr, SampledPtr>([&w](const LoadedPtr& in) { return sample_stage(w.state, in, {}); });
    flow::make_edge(load, sample);
    sampled = &sample;
  } else {
    auto& sample = w.node<std::tuple<LoadedPtr, SampledPtr>, SampledPtr>(
        [&w](const auto& in) { return sample_stage(w.state, std::get<0>(in), std::get<1>(in)); });
    flow::make_edge(w.join(load, *reference->sampled), sample);
    sampled = &sample;
  }
  auto& features = w.node<SampledPtr, FeaturedPtr>([&w](const SampledPtr& in) { return features_stage(w.state, in); });
  flow::make_edge(*sampled, features);
  return {sampled, &features};
}

// Mode curves, one drawing's branch: load -> sample (arc-length samples with their frames, the plane's features). Every
// drawing but the target is sampled at the target's spacing: its sample node waits for the target's samples.
Branch add_curve_branch(Wiring& w, Role role, const Branch* reference = nullptr) {
  const Input& input = input_for(w.state.config, role);
  auto& load = w.node<flow::continue_msg, LoadedPtr>(
      [&w, input](flow::continue_msg) { return load_curves_stage(w.state, input); });
  flow::make_edge(w.start, load);
  if (!reference) {
    auto& sample =
        w.node<LoadedPtr, FeaturedPtr>([&w](const LoadedPtr& in) { return sample_curves_stage(w.state, in, {}); });
    flow::make_edge(load, sample);
    return {nullptr, &sample};
  }
  auto& sample = w.node<std::tuple<LoadedPtr, FeaturedPtr>, FeaturedPtr>(
      [&w](const auto& in) { return sample_curves_stage(w.state, std::get<0>(in), std::get<1>(in)); });
  flow::make_edge(w.join(load, *reference->features), sample);
  return {nullptr, &sample};
}

// M: correspond(exemplar, source).
flow::sender<CorrespondencePtr>& add_correspond(Wiring& w, const Branch& exemplar, const Branch& source) {
  auto& correspond = w.node<std::tuple<FeaturedPtr, FeaturedPtr>, CorrespondencePtr>(
      [&w](const auto& in) { return correspond_stage(w.state, std::get<0>(in), std::get<1>(in)); });
  flow::make_edge(w.join(*exemplar.features, *source.features), correspond);
  return correspond;
}

// A: vote -> modes -> support -> label, from the symmetry node.
flow::sender<LabelledPtr>& add_analogy_chain(Wiring& w, flow::sender<SymmetriesPtr>& symmetry) {
  auto& vote = w.node<SymmetriesPtr, VotesPtr>([&w](const SymmetriesPtr& in) { return vote_stage(w.state, in); });
  flow::make_edge(symmetry, vote);
  auto& modes = w.node<VotesPtr, FoundModesPtr>([&w](const VotesPtr& in) { return modes_stage(w.state, in); });
  auto& support =
      w.node<FoundModesPtr, SupportsPtr>([&w](const FoundModesPtr& in) { return support_stage(w.state, in); });
  auto& label = w.node<SupportsPtr, LabelledPtr>([&w](const SupportsPtr& in) { return label_stage(w.state, in); });
  flow::make_edge(vote, modes);
  flow::make_edge(modes, support);
  flow::make_edge(support, label);
  return label;
}

// A: S -> T with S the source input's samples.
flow::sender<LabelledPtr>& add_analogy(Wiring& w, const Branch& source, const Branch& target) {
  auto& symmetry = w.node<std::tuple<FeaturedPtr, FeaturedPtr>, SymmetriesPtr>(
      [&w](const auto& in) { return symmetry_stage(w.state, std::get<0>(in)->features.points, std::get<1>(in)); });
  flow::make_edge(w.join(*source.features, *target.features), symmetry);
  return add_analogy_chain(w, symmetry);
}

// synthesized -> align -> plan -> transfer, and synthesized -> surface beside them when output.surface asks for one;
// returns transfer, or nullptr for a plan run, which stops at the plan.
flow::sender<TransferredPtr>* add_align_transfer(Wiring& w, flow::sender<SynthesizedPtr>& synthesize,
                                                 bool to_scan_frame) {
  auto& align = w.node<SynthesizedPtr, AlignedPtr>([&w](const SynthesizedPtr& in) { return align_stage(w.state, in); });
  auto& plan = w.node<AlignedPtr, PlannedPtr>(
      [&w, to_scan_frame](const AlignedPtr& in) { return plan_stage(w.state, in, to_scan_frame); });
  flow::make_edge(synthesize, align);
  flow::make_edge(align, plan);
  if (w.state.plan_only) return nullptr;
  auto& transfer =
      w.node<PlannedPtr, TransferredPtr>([&w](const PlannedPtr& in) { return transfer_stage(w.state, in); });
  flow::make_edge(plan, transfer);
  if (!makes_surface(w.state.config)) return &transfer;
  auto& surface = w.node<SynthesizedPtr, SurfacedPtr>(
      [&w, to_scan_frame](const SynthesizedPtr& in) { return surface_stage(w.state, in, to_scan_frame); });
  flow::make_edge(synthesize, surface);  // beside align, plan and transfer: the surface needs only the synthesis
  return &transfer;
}

// correspond(scan, template) -> cover: S = the template samples the scan covers -> symmetry(S, template) -> vote ->
// modes -> support -> label; synthesize(M, A) -> align -> transfer, back in the scan's frame, and the surface beside
// them.
void build_completion(Wiring& w) {
  const Branch templ = add_input_branch(w, Role::kTemplate);
  const Branch scan = add_input_branch(w, Role::kScan, &templ);
  auto& cover =
      w.node<CorrespondencePtr, CoveragePtr>([&w](const CorrespondencePtr& in) { return cover_stage(w.state, in); });
  flow::make_edge(add_correspond(w, scan, templ), cover);
  auto& symmetry = w.node<CoveragePtr, SymmetriesPtr>([&w](const CoveragePtr& in) {
    return symmetry_stage(w.state, in->cover.source, in->correspondence->source, in->correspondence);
  });
  flow::make_edge(cover, symmetry);
  auto& synthesize = w.node<std::tuple<CoveragePtr, LabelledPtr>, SynthesizedPtr>([&w](const auto& in) {
    const CoveragePtr& coverage = std::get<0>(in);
    return synthesize_stage(w.state, coverage->correspondence, std::get<1>(in), coverage);
  });
  flow::make_edge(w.join(cover, add_analogy_chain(w, symmetry)), synthesize);
  add_align_transfer(w, synthesize, true);
}

// correspond(exemplar, source) and vote(source, target) -> ... -> label have no dependency on each other and run in
// parallel; synthesize joins them.
flow::sender<TransferredPtr>* add_style_transfer(Wiring& w, const Branch& target, const Branch& source,
                                                 const Branch& exemplar) {
  auto& synthesize = w.node<std::tuple<CorrespondencePtr, LabelledPtr>, SynthesizedPtr>(
      [&w](const auto& in) { return synthesize_stage(w.state, std::get<0>(in), std::get<1>(in), nullptr); });
  flow::make_edge(w.join(add_correspond(w, exemplar, source), add_analogy(w, source, target)), synthesize);
  return add_align_transfer(w, synthesize, false);
}

void build_transfer(Wiring& w) {
  const Branch target = add_input_branch(w, Role::kTarget);
  const Branch source = add_input_branch(w, Role::kSource, &target);
  add_style_transfer(w, target, source, add_input_branch(w, Role::kExemplar, &target));
}

// The same graph on 2D drawings, in the z = 0 plane (vote and symmetry keep to motions of the plane: their `planar`
// options, set by the stages in this mode); then draw: the output points as polylines along the target's curves.
void build_curves(Wiring& w) {
  const Branch target = add_curve_branch(w, Role::kTarget);
  const Branch source = add_curve_branch(w, Role::kSource, &target);
  auto* transfer = add_style_transfer(w, target, source, add_curve_branch(w, Role::kExemplar, &target));
  if (!transfer) return;  // a plan run
  auto& draw =
      w.node<TransferredPtr, DrawnPtr>([&w](const TransferredPtr& in) { return draw_curves_stage(w.state, in); });
  flow::make_edge(*transfer, draw);
}

// vote(source, target) -> modes -> support -> label: the labelled target is the output.
void build_analogy(Wiring& w) {
  const Branch target = add_input_branch(w, Role::kTarget);
  const Branch source = add_input_branch(w, Role::kSource, &target);
  add_analogy(w, source, target);
}

// Mode exchange, one input's parts: its boxes, from the config, a castle's layout or its PLY.
flow::sender<PartsPtr>& add_parts(Wiring& w, const Input& input) {
  auto& parts =
      w.node<flow::continue_msg, PartsPtr>([&w, &input](flow::continue_msg) { return parts_stage(w.state, input); });
  flow::make_edge(w.start, parts);
  return parts;
}

// Mode exchange (paper section 7, Figure 14): per exemplar load, and its parts (S); per target its parts (T); per
// exemplar/target pair, exchange: the box-wise analogy S -> T applied to the whole exemplar (no sampling: the maps are
// found on the boxes alone and carry every point or triangle).
void build_exchange(Wiring& w) {
  using Exemplar = std::tuple<LoadedPtr, PartsPtr>;
  std::vector<flow::sender<Exemplar>*> exemplars;
  for (const Input* e : inputs_for(w.state.config, Role::kExemplar)) {
    auto& load = w.node<flow::continue_msg, LoadedPtr>([&w, e](flow::continue_msg) { return load_stage(w.state, *e); });
    flow::make_edge(w.start, load);
    exemplars.push_back(&w.join(load, add_parts(w, *e)));
  }
  const std::vector<const Input*> targets = inputs_for(w.state.config, Role::kTarget);
  for (size_t t = 0; t < targets.size(); ++t) {
    flow::sender<PartsPtr>& target = add_parts(w, *targets[t]);
    for (size_t e = 0; e < exemplars.size(); ++e) {
      auto& exchange =
          w.node<std::tuple<Exemplar, PartsPtr>, ExchangedPtr>([&w, pair = e * targets.size() + t](const auto& in) {
            const Exemplar& ex = std::get<0>(in);
            return exchange_stage(w.state, std::get<0>(ex), std::get<1>(ex), std::get<1>(in), pair);
          });
      flow::make_edge(w.join(*exemplars[e], target), exchange);
    }
  }
}

}  // namespace

double peak_rss_mb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return double(usage.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB on Linux
}

void run_graph(RunState& state) {
  const RunConfig& config = state.config;
  flow::graph g;
  Wiring w(g, state);
  switch (config.mode) {
    case RunMode::kCompletion:
      build_completion(w);
      break;
    case RunMode::kTransfer:
      build_transfer(w);
      break;
    case RunMode::kAnalogy:
      build_analogy(w);
      break;
    case RunMode::kCurves:
      build_curves(w);
      break;
    case RunMode::kExchange:
      build_exchange(w);
      break;
  }
  w.run();
}

RunOutcome run(const RunConfig& config) {
  // Refused before any work: an output that would overwrite an input, an output folder that cannot be written.
  check_outputs_spare_inputs(config);
  Staging staging(config.output_dir);
  RunState state(config);
  state.write_dir = staging.folder();
  run_graph(state);
  return write_outputs(state, staging);
}

}  // namespace scanfill
