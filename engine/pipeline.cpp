#include "engine/pipeline.h"

#include <sys/resource.h>
#include <tbb/flow_graph.h>

#include <chrono>
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

RunOutcome run_pipeline(const RunConfig& config) {
  const auto& specs = config.inputs;
  RunState state(specs.size());
  flow::graph g;
  flow::broadcast_node<flow::continue_msg> start(g);
  using LoadedPtr = std::shared_ptr<const Loaded>;
  using SampledPtr = std::shared_ptr<const Sampled>;
  std::vector<std::unique_ptr<flow::graph_node>> nodes;

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
        g, flow::serial, [&, spec, subject](const LoadedPtr& in) {
          const std::string name = "sample:" + spec.role;
          return run_node(state, name, subject, [&](const ProgressFn& progress) {
            auto out = std::make_shared<Sampled>(Sampled{in, sample(in->load.points, config.sample, progress)});
            for (const auto& w : out->sample.warnings) state.warn(name, w);
            node_logger("sample")->info("{}: {} samples from {} candidates, spacing {:.4g}, {} rounds", spec.role,
                                        out->sample.samples.size(), out->sample.candidates, out->sample.spacing,
                                        out->sample.rounds);
            return SampledPtr(std::move(out));
          });
        });
    auto features_node = std::make_unique<flow::function_node<SampledPtr, flow::continue_msg>>(
        g, flow::serial, [&, spec, subject, slot](const SampledPtr& in) {
          const std::string name = "features:" + spec.role;
          run_node(state, name, subject, [&](const ProgressFn& progress) {
            auto out = std::make_shared<Featured>(
                Featured{in, estimate_features(in->sample.samples, config.features, progress)});
            for (const auto& w : out->features.warnings) state.warn(name, w);
            node_logger("features")
                ->info("{}: normals oriented by '{}', {} unreliable directions smoothed ({} CG iterations)", spec.role,
                       to_string(out->features.orientation_used), out->features.unreliable_directions,
                       out->features.iterations);
            state.store(slot, std::move(out));
            return 0;
          });
          return flow::continue_msg();
        });
    flow::make_edge(start, *load_node);
    flow::make_edge(*load_node, *sample_node);
    flow::make_edge(*sample_node, *features_node);
    nodes.push_back(std::move(load_node));
    nodes.push_back(std::move(sample_node));
    nodes.push_back(std::move(features_node));
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
  state.record("write", std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());

  nlohmann::json node_list = nlohmann::json::array();
  for (const auto& t : state.timings_) node_list.push_back({{"name", t.name}, {"wall_s", t.wall_s}});
  nlohmann::json report = {
      {"mode", config.mode},
      {"inputs", inputs},
      {"transforms", nlohmann::json::array()},
      {"energy", nullptr},
      {"nodes", node_list},
      {"peak_rss_mb", peak_rss_mb()},
      {"warnings", state.warnings_},
      {"stages_run", {"load", "sample", "features"}},
      {"stages_pending", {"correspond", "vote", "modes", "support", "label", "synthesize", "align", "transfer"}},
      {"note",
       "this build runs the stages load, sample and features; the analogy and synthesis stages are not "
       "implemented yet, so no output.ply or analogy.ply is written"},
  };
  const std::filesystem::path report_path = config.output_dir / "report.json";
  write_file_atomic(report_path, report.dump(2) + "\n");
  outcome.outputs.push_back(report_path);
  outcome.nodes = state.timings_;
  outcome.warnings = state.warnings_;
  return outcome;
}

}  // namespace scanfill
