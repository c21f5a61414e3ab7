#include "engine/pipeline.h"

#include <sys/resource.h>
#include <tbb/flow_graph.h>

#include <array>
#include <chrono>
#include <cmath>
#include <mutex>
#include <nlohmann/json.hpp>

#include "engine/console.h"
#include "engine/fields.h"
#include "nodes/core/errors.h"
#include "nodes/io/write_ply.h"
#include "nodes/procedural/shapes.h"

namespace scanfill {
namespace {

namespace flow = tbb::flow;

// Messages between nodes: immutable, shared.
struct Loaded {
  InputSpec spec;
  LoadResult load;
};
struct Sampled {
  std::shared_ptr<const Loaded> loaded;
  SampleResult sample;
};
struct Featured {
  std::shared_ptr<const Sampled> sampled;
  FeaturesResult features;
};

// What the nodes share with the engine while the graph runs.
class RunState {
 public:
  void record(const std::string& name, double seconds) {
    std::lock_guard<std::mutex> lock(mutex_);
    timings_.push_back({name, seconds});
  }
  void warn(const std::string& node, const std::string& what) {
    node_logger(node)->warn("{}", what);
    std::lock_guard<std::mutex> lock(mutex_);
    warnings_.push_back(node + ": " + what);
  }
  void store(size_t slot, std::shared_ptr<const Featured> f) {
    std::lock_guard<std::mutex> lock(mutex_);
    results_[slot] = std::move(f);
  }
  explicit RunState(size_t inputs) : results_(inputs) {}
  std::vector<NodeTiming> timings_;
  std::vector<std::string> warnings_;
  std::vector<std::shared_ptr<const Featured>> results_;

 private:
  std::mutex mutex_;
};

// Runs `body` as node `name`: progress, timing, and the node's name on any error.
template <class F>
auto run_node(RunState& state, const std::string& name, const std::string& subject, F&& body) {
  Progress::instance().start(name);
  const auto t0 = std::chrono::steady_clock::now();
  const ProgressFn progress = [name](double f) { Progress::instance().update(name, f); };
  try {
    auto out = body(progress);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    state.record(name, s);
    Progress::instance().finish(name);
    return out;
  } catch (const std::exception& e) {
    Progress::instance().finish(name);
    throw Error("node '" + name + "' failed" + (subject.empty() ? "" : " on " + subject) + ": " + e.what());
  }
}

std::string subject_of(const InputSpec& spec) {
  return spec.procedural.empty() ? spec.path.string() : spec.text;
}

nlohmann::json json_vec(const Eigen::Vector3d& v) {
  return nlohmann::json::array({v.x(), v.y(), v.z()});
}

}  // namespace

double peak_rss_mb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return double(usage.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB on Linux
}

LoadResult load_input(const InputSpec& spec, const LoadOptions& options) {
  if (spec.procedural.empty()) return read_point_set(spec.path, options);
  LoadResult r;
  r.points = make_shape(spec.procedural);
  r.format = "procedural";
  r.encoding = spec.procedural;
  r.file_points = r.points.size();
  return r;
}

namespace {

// The analogy nodes' results: immutable messages like the others.
struct Analogy {
  std::shared_ptr<const Featured> source, target;
  double spacing = 0;
  VoteResult votes;
  ModesResult modes;
  SupportResult support;
  LabelResult labels;
};

// A colour per label (golden-ratio hues), grey for the self-reference.
std::array<double, 3> label_colour(int label, int self_label) {
  if (label == self_label) return {128, 128, 128};
  const double h = std::fmod(0.61803398875 * label + 0.1, 1.0) * 6.0;
  const double x = 1 - std::abs(std::fmod(h, 2.0) - 1);
  std::array<double, 3> rgb{};
  const int sector = int(h);
  const double table[6][3] = {{1, x, 0}, {x, 1, 0}, {0, 1, x}, {0, x, 1}, {x, 0, 1}, {1, 0, x}};
  for (int k = 0; k < 3; ++k) rgb[size_t(k)] = std::round(40 + 215 * table[sector % 6][k]);
  return rgb;
}

nlohmann::json transform_json(int label, const char* kind, const Similarity& q, Index support, Index labelled) {
  nlohmann::json rotation = nlohmann::json::array();
  for (int r = 0; r < 3; ++r) rotation.push_back({q.rotation(r, 0), q.rotation(r, 1), q.rotation(r, 2)});
  return {{"label", label},   {"kind", kind},       {"rotation", rotation}, {"translation", json_vec(q.translation)},
          {"scale", q.scale}, {"support", support}, {"labelled", labelled}};
}

}  // namespace

RunOutcome run_pipeline(const RunConfig& config) {
  const auto& specs = config.inputs;
  RunState state(specs.size());
  flow::graph g;
  flow::broadcast_node<flow::continue_msg> start(g);
  using LoadedPtr = std::shared_ptr<const Loaded>;
  using SampledPtr = std::shared_ptr<const Sampled>;
  using FeaturedPtr = std::shared_ptr<const Featured>;
  using AnalogyPtr = std::shared_ptr<const Analogy>;
  std::vector<std::unique_ptr<flow::graph_node>> nodes;
  const bool analogy = config.mode == "analogy";

  // Per input: load -> sample -> features. In analogy mode the source is sampled at the target's spacing (the
  // paper's alpha, the same on all inputs), so its sample node waits for the target's.
  std::vector<flow::function_node<LoadedPtr, SampledPtr>*> sample_nodes(specs.size());
  std::vector<flow::function_node<SampledPtr, FeaturedPtr>*> feature_nodes(specs.size());
  std::vector<flow::function_node<flow::continue_msg, LoadedPtr>*> load_nodes(specs.size());
  auto sample_body = [&](const InputSpec& spec, const LoadedPtr& in, double spacing) {
    const std::string name = "sample:" + spec.role;
    return run_node(state, name, subject_of(spec), [&](const ProgressFn& progress) {
      SampleOptions options = config.sample;
      if (spacing > 0) options.spacing = spacing;
      auto out = std::make_shared<Sampled>(Sampled{in, sample(in->load.points, options, progress)});
      for (const auto& w : out->sample.warnings) state.warn(name, w);
      node_logger("sample")->info("{}: {} samples from {} candidates, spacing {:.4g}, {} rounds", spec.role,
                                  out->sample.samples.size(), out->sample.candidates, out->sample.spacing,
                                  out->sample.rounds);
      return SampledPtr(std::move(out));
    });
  };
  for (size_t slot = 0; slot < specs.size(); ++slot) {
    const InputSpec spec = specs[slot];
    const std::string subject = subject_of(spec);
    auto load_node = std::make_unique<flow::function_node<flow::continue_msg, LoadedPtr>>(
        g, flow::serial, [&, spec, subject](flow::continue_msg) {
          const std::string name = "load:" + spec.role;
          return run_node(state, name, subject, [&](const ProgressFn&) {
            auto loaded = std::make_shared<Loaded>(Loaded{spec, load_input(spec, config.load)});
            for (const auto& w : loaded->load.warnings) state.warn(name, w);
            node_logger("load")->info("{}: {} points, {} faces ({} {}) from {}", spec.role, loaded->load.points.size(),
                                      loaded->load.points.faces().cols(), loaded->load.format, loaded->load.encoding,
                                      subject);
            return LoadedPtr(std::move(loaded));
          });
        });
    auto sample_node = std::make_unique<flow::function_node<LoadedPtr, SampledPtr>>(
        g, flow::serial, [&, spec](const LoadedPtr& in) { return sample_body(spec, in, 0.0); });
    auto features_node = std::make_unique<flow::function_node<SampledPtr, FeaturedPtr>>(
        g, flow::serial, [&, spec, subject, slot](const SampledPtr& in) {
          const std::string name = "features:" + spec.role;
          return run_node(state, name, subject, [&](const ProgressFn& progress) {
            auto out = std::make_shared<Featured>(
                Featured{in, estimate_features(in->sample.samples, config.features, progress)});
            for (const auto& w : out->features.warnings) state.warn(name, w);
            node_logger("features")
                ->info("{}: normals oriented by '{}', {} unreliable directions smoothed ({} CG iterations)", spec.role,
                       to_string(out->features.orientation_used), out->features.unreliable_directions,
                       out->features.iterations);
            state.store(slot, out);
            return FeaturedPtr(std::move(out));
          });
        });
    flow::make_edge(start, *load_node);
    flow::make_edge(*sample_node, *features_node);
    load_nodes[slot] = load_node.get();
    sample_nodes[slot] = sample_node.get();
    feature_nodes[slot] = features_node.get();
    nodes.push_back(std::move(load_node));
    nodes.push_back(std::move(sample_node));
    nodes.push_back(std::move(features_node));
  }

  std::shared_ptr<const Analogy> analogy_result;
  if (!analogy) {
    for (size_t slot = 0; slot < specs.size(); ++slot) flow::make_edge(*load_nodes[slot], *sample_nodes[slot]);
  } else {
    // specs are in role order: 0 = source, 1 = target.
    const InputSpec source_spec = specs[0];
    flow::make_edge(*load_nodes[1], *sample_nodes[1]);
    using SourceJoin = flow::join_node<std::tuple<LoadedPtr, SampledPtr>, flow::queueing>;
    auto source_join = std::make_unique<SourceJoin>(g);
    auto source_sample = std::make_unique<flow::function_node<std::tuple<LoadedPtr, SampledPtr>, SampledPtr>>(
        g, flow::serial, [&, source_spec](const std::tuple<LoadedPtr, SampledPtr>& in) {
          const double spacing = config.sample.spacing > 0 ? 0.0 : std::get<1>(in)->sample.spacing;
          return sample_body(source_spec, std::get<0>(in), spacing);
        });
    flow::make_edge(*load_nodes[0], flow::input_port<0>(*source_join));
    flow::make_edge(*sample_nodes[1], flow::input_port<1>(*source_join));
    flow::make_edge(*source_join, *source_sample);
    flow::make_edge(*source_sample, *feature_nodes[0]);

    using Pair = std::tuple<FeaturedPtr, FeaturedPtr>;
    auto pair_join = std::make_unique<flow::join_node<Pair, flow::queueing>>(g);
    auto analogy_node = std::make_unique<flow::function_node<Pair, AnalogyPtr>>(g, flow::serial, [&](const Pair& in) {
      auto a = std::make_shared<Analogy>();
      a->source = std::get<0>(in);
      a->target = std::get<1>(in);
      a->spacing = a->target->sampled->sample.spacing;
      const PointSet& S = a->source->features.points;
      const PointSet& T = a->target->features.points;
      run_node(state, "vote", "", [&](const ProgressFn&) {
        a->votes = vote(S, T, a->spacing, config.vote);
        node_logger("vote")->info("{} votes from {} target samples", a->votes.embedding.cols(),
                                  std::min<Index>(config.vote.target_samples, T.size()));
        return 0;
      });
      run_node(state, "modes", "", [&](const ProgressFn&) {
        a->modes = find_modes(a->votes, config.vote, config.modes);
        node_logger("modes")->info("{} modes from {} seeds", a->modes.modes.size(), a->modes.seeds);
        if (a->modes.modes.empty()) state.warn("modes", "no transform found: every target sample is self-referenced");
        return 0;
      });
      run_node(state, "support", "", [&](const ProgressFn&) {
        a->support = grow_supports(S, T, a->modes.modes, a->spacing, mode_accuracy(a->votes, config.vote, config.modes),
                                   config.support);
        node_logger("support")->info("{} transforms with support of at least {} samples", a->support.transforms.size(),
                                     config.support.min_support);
        return 0;
      });
      run_node(state, "label", "", [&](const ProgressFn&) {
        a->labels = label_target(S, T, a->support.transforms, a->spacing, config.label);
        node_logger("label")->info("energy {:.6g} -> {:.6g} in {} sweeps; {} samples relabelled by the clean-up",
                                   a->labels.energy_before, a->labels.energy_after, a->labels.cycles,
                                   a->labels.cleaned);
        return 0;
      });
      return AnalogyPtr(std::move(a));
    });
    auto analogy_sink = std::make_unique<flow::function_node<AnalogyPtr, flow::continue_msg>>(
        g, flow::serial, [&](const AnalogyPtr& a) {
          analogy_result = a;
          return flow::continue_msg();
        });
    flow::make_edge(*feature_nodes[0], flow::input_port<0>(*pair_join));
    flow::make_edge(*feature_nodes[1], flow::input_port<1>(*pair_join));
    flow::make_edge(*pair_join, *analogy_node);
    flow::make_edge(*analogy_node, *analogy_sink);
    nodes.push_back(std::move(source_join));
    nodes.push_back(std::move(source_sample));
    nodes.push_back(std::move(pair_join));
    nodes.push_back(std::move(analogy_node));
    nodes.push_back(std::move(analogy_sink));
  }
  start.try_put(flow::continue_msg());
  g.wait_for_all();  // rethrows the first node error; the graph is cancelled

  // Every node succeeded: write the outputs.
  RunOutcome outcome;
  const auto t0 = std::chrono::steady_clock::now();
  std::error_code ec;
  std::filesystem::create_directories(config.output_dir, ec);
  if (ec) throw IoError(config.output_dir.string() + ": cannot create the output folder (" + ec.message() + ")");
  nlohmann::json inputs = nlohmann::json::object();
  for (size_t slot = 0; slot < specs.size(); ++slot) {
    const Featured& f = *state.results_[slot];
    const LoadResult& load = f.sampled->loaded->load;
    const std::filesystem::path out = config.output_dir / ("samples_" + specs[slot].role + ".ply");
    write_ply(out, f.features.points);
    outcome.outputs.push_back(out);
    const BoundingBox box = bounding_box(load.points.positions());
    inputs[specs[slot].role] = {{"path", subject_of(specs[slot])},
                                {"format", load.format},
                                {"points", load.points.size()},
                                {"faces", load.points.faces().cols()},
                                {"dropped_nonfinite", load.dropped_nonfinite},
                                {"bbox", {json_vec(box.min), json_vec(box.max)}},
                                {"samples", f.features.points.size()},
                                {"spacing", f.sampled->sample.spacing},
                                {"unreliable_directions", f.features.unreliable_directions}};
  }
  nlohmann::json transforms = nlohmann::json::array();
  nlohmann::json energy = nullptr;
  if (analogy_result) {
    const Analogy& a = *analogy_result;
    const LabelResult& L = a.labels;
    std::vector<Index> count(size_t(L.self_label) + 1, 0);
    for (int l : L.labels) ++count[size_t(l)];
    for (int l = 0; l < L.self_label; ++l)
      transforms.push_back(transform_json(l, "similarity", a.support.transforms[size_t(l)].transform,
                                          Index(a.support.transforms[size_t(l)].support.size()), count[size_t(l)]));
    transforms.push_back(
        transform_json(L.self_label, "self", Similarity{}, count[size_t(L.self_label)], count[size_t(L.self_label)]));
    energy = {{"before", L.energy_before}, {"after", L.energy_after}};
    std::vector<double> label(L.labels.begin(), L.labels.end());
    std::vector<double> rgb[3];
    for (int l : L.labels) {
      const auto c = label_colour(l, L.self_label);
      for (int k = 0; k < 3; ++k) rgb[k].push_back(c[size_t(k)]);
    }
    const std::filesystem::path out = config.output_dir / "analogy.ply";
    write_ply(out, a.target->features.points,
              {{"label", PlyProperty::Type::kInt32, label},
               {"red", PlyProperty::Type::kUint8, rgb[0]},
               {"green", PlyProperty::Type::kUint8, rgb[1]},
               {"blue", PlyProperty::Type::kUint8, rgb[2]}});
    outcome.outputs.push_back(out);
  }
  state.record("write", std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());

  nlohmann::json node_list = nlohmann::json::array();
  for (const auto& t : state.timings_) node_list.push_back({{"name", t.name}, {"wall_s", t.wall_s}});
  std::vector<std::string> run{"load", "sample", "features"};
  std::vector<std::string> pending{"correspond", "vote",       "modes", "support",
                                   "label",      "synthesize", "align", "transfer"};
  if (analogy) {
    run.insert(run.end(), {"vote", "modes", "support", "label"});
    pending = {};
  } else {
    pending.erase(std::remove_if(pending.begin(), pending.end(),
                                 [](const std::string& s) {
                                   return s == "vote" || s == "modes" || s == "support" || s == "label";
                                 }),
                  pending.end());
    pending.insert(pending.begin() + 1, {"vote", "modes", "support", "label"});
  }
  nlohmann::json report = {
      {"mode", config.mode},         {"inputs", inputs},
      {"transforms", transforms},    {"energy", energy},
      {"nodes", node_list},          {"peak_rss_mb", peak_rss_mb()},
      {"warnings", state.warnings_}, {"stages_run", run},
      {"stages_pending", pending},
  };
  if (!analogy)
    report["note"] =
        "mode '" + config.mode +
        "' runs load, sample and features for now; correspondence, synthesis and "
        "alignment are not implemented yet, so no output.ply is written (mode 'analogy' runs the labelling)";
  const std::filesystem::path report_path = config.output_dir / "report.json";
  write_file_atomic(report_path, report.dump(2) + "\n");
  outcome.outputs.push_back(report_path);
  outcome.nodes = state.timings_;
  outcome.warnings = state.warnings_;
  return outcome;
}

}  // namespace scanfill
