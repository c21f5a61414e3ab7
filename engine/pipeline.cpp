#include "engine/pipeline.h"

#include <sys/resource.h>
#include <tbb/flow_graph.h>

#include <array>
#include <chrono>
#include <cmath>
#include <mutex>
#include <nlohmann/json.hpp>
#include <sstream>

#include "engine/console.h"
#include "engine/fields.h"
#include "nodes/core/errors.h"
#include "nodes/io/write_ply.h"
#include "nodes/procedural/shapes.h"
#include "nodes/scan/virtual_scan.h"
#include "nodes/synthesize/synthesize.h"
#include "nodes/transfer/transfer.h"

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
  if (spec.revolution) {
    InputSpec model = spec;
    model.revolution = false;
    LoadResult r = load_input(model, options);
    r.points = make_revolution(r.points);
    r.format += " (body of revolution)";
    r.file_points = r.points.size();
    return r;
  }
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
  PointSet source;  // S: the source samples (in completion, the template samples the scan covers)
  std::shared_ptr<const Featured> target;
  double spacing = 0;
  VoteResult votes;
  ModesResult modes;
  SupportResult support;
  LabelResult labels;
  SymmetryResult source_symmetry, target_symmetry;
  size_t composed_candidates = 0;
};

std::string describe(const SymmetryResult& s) {
  if (s.axes.empty()) return "no rotational symmetry";
  std::string out;
  for (const auto& a : s.axes) {
    std::ostringstream line;
    line << (out.empty() ? "" : ", ") << (a.order == 0 ? std::string("continuous") : std::to_string(a.order) + "-fold")
         << " about (" << a.direction.x() << ", " << a.direction.y() << ", " << a.direction.z() << ")";
    out += line.str();
  }
  return out;
}

// The correspondence node's result.
struct Correspondence {
  std::shared_ptr<const Featured> exemplar, source;
  CorrespondResult map;
  std::vector<std::uint8_t> covered;  // completion: per template sample, 1 when the registered scan covers it
  Index covered_count = 0;
};

// synthesize -> align -> transfer.
struct Completed {
  Synthesis synthesis;
  AlignResult alignment;
  TransferResult output;
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

nlohmann::json rotation_json(const Eigen::Matrix3d& R) {
  nlohmann::json rotation = nlohmann::json::array();
  for (int r = 0; r < 3; ++r) rotation.push_back({R(r, 0), R(r, 1), R(r, 2)});
  return rotation;
}

nlohmann::json transform_json(int label, const char* kind, const Similarity& q, Index support, Index labelled) {
  return {{"label", label},
          {"kind", kind},
          {"rotation_deg", rotation_angle(q.rotation) * 180 / M_PI},
          {"rotation_axis", json_vec(rotation_axis(q.rotation))},
          {"axis_rotation", is_axis_rotation(q.rotation, M_PI / 180)},
          {"rotation", rotation_json(q.rotation)},
          {"translation", json_vec(q.translation)},
          {"scale", q.scale},
          {"support", support},
          {"labelled", labelled}};
}

// vote -> modes -> support -> label on S and T.
std::shared_ptr<const Analogy> compute_analogy(RunState& state, const RunConfig& config, PointSet source,
                                               std::shared_ptr<const Featured> target) {
  auto a = std::make_shared<Analogy>();
  a->source = std::move(source);
  a->target = std::move(target);
  a->spacing = a->target->sampled->sample.spacing;
  const PointSet& S = a->source;
  const PointSet& T = a->target->features.points;
  run_node(state, "symmetry", "", [&](const ProgressFn&) {
    a->source_symmetry = find_symmetries(S, a->spacing, config.symmetry);
    a->target_symmetry = find_symmetries(T, a->spacing, config.symmetry);
    node_logger("symmetry")
        ->info("source: {}; target: {} ({} rotations)", describe(a->source_symmetry), describe(a->target_symmetry),
               a->target_symmetry.rotations.size());
    return 0;
  });
  run_node(state, "vote", "", [&](const ProgressFn&) {
    a->votes = vote(S, T, a->spacing, config.vote);
    if (a->source_symmetry.continuous) quotient_votes(a->votes, *a->source_symmetry.continuous, config.vote);
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
    const std::vector<Mode> composed = composed_candidates(a->support, a->target_symmetry, T, config.symmetry);
    const size_t voted = a->support.transforms.size();
    a->support = extend_supports(S, T, a->support, composed, a->spacing, 0.0, config.support);
    a->composed_candidates = composed.size();
    node_logger("support")->info(
        "{} transforms with support of at least {} samples ({} from votes; {} candidates composed with the target's "
        "symmetries)",
        a->support.transforms.size(), config.support.min_support, voted, composed.size());
    return 0;
  });
  run_node(state, "label", "", [&](const ProgressFn&) {
    a->labels = label_target(S, T, a->support.transforms, a->spacing, config.label);
    node_logger("label")->info("energy {:.6g} -> {:.6g} in {} sweeps; {} samples relabelled by the clean-up",
                               a->labels.energy_before, a->labels.energy_after, a->labels.cycles, a->labels.cleaned);
    return 0;
  });
  return a;
}

std::shared_ptr<const Correspondence> compute_correspondence(RunState& state, const RunConfig& config,
                                                             std::shared_ptr<const Featured> exemplar,
                                                             std::shared_ptr<const Featured> source, bool completion) {
  auto c = std::make_shared<Correspondence>();
  c->exemplar = std::move(exemplar);
  c->source = std::move(source);
  const double spacing = c->source->sampled->sample.spacing;
  const PointSet& E = c->exemplar->features.points;
  const PointSet& S = c->source->features.points;
  run_node(state, "correspond", "", [&](const ProgressFn& progress) {
    c->map = correspond(E, S, spacing, config.correspond, progress);
    for (const auto& w : c->map.warnings) state.warn("correspond", w);
    const double angle = rotation_angle(c->map.rigid.rotation) * 180 / M_PI;
    node_logger("correspond")
        ->info(
            "rigid registration: {:.3g} deg, shift {:.4g}, RMS {:.4g}; {} of {} exemplar samples matched, RMS {:.4g} "
            "after deformation",
            angle, c->map.rigid.translation.norm(), c->map.rigid_rms, c->map.matched, E.size(), c->map.deformed_rms);
    if (completion) {
      c->covered.assign(size_t(S.size()), 0);
      for (const auto s : covered_samples(S, c->map.deformed, config.cover_distance * spacing)) {
        c->covered[size_t(s)] = 1;
        ++c->covered_count;
      }
      node_logger("correspond")->info("the scan covers {} of {} template samples", c->covered_count, S.size());
      if (c->covered_count < config.support.min_support)
        throw InputError("the registered scan covers only " + std::to_string(c->covered_count) +
                         " template samples: too little of the template to learn from");
    }
    return 0;
  });
  return c;
}

std::shared_ptr<const Completed> compute_output(RunState& state, const RunConfig& config,
                                                const std::shared_ptr<const Correspondence>& c,
                                                const std::shared_ptr<const Analogy>& a, const PointSet& source,
                                                const Similarity& working_to_output) {
  auto out = std::make_shared<Completed>();
  const double spacing = a->spacing;
  std::vector<Similarity> transforms;
  for (const auto& t : a->support.transforms) transforms.push_back(t.transform);
  run_node(state, "synthesize", "", [&](const ProgressFn&) {
    const SynthesisInputs in{c->exemplar->features.points,
                             c->map.rigid,
                             c->map.exemplar_source,
                             source,
                             a->target->features.points,
                             a->labels.labels,
                             a->labels.self_label,
                             transforms,
                             c->covered.empty() ? nullptr : &c->covered};
    out->synthesis = synthesize(in, spacing, config.synthesize);
    Index by_origin[3] = {0, 0, 0};
    for (const auto o : out->synthesis.origin) ++by_origin[int(o)];
    node_logger("synthesize")
        ->info("{} patches: {} exemplar, {} synthesised, {} copied samples ({} where no patch reached)",
               out->synthesis.patches.size(), by_origin[0], by_origin[1], by_origin[2], out->synthesis.gap_copies);
    return 0;
  });
  run_node(state, "align", "", [&](const ProgressFn&) {
    out->alignment = align(out->synthesis, spacing, config.align);
    node_logger("align")->info("{} seam pairs, RMS gap {:.4g} -> {:.4g}", out->alignment.seam_pairs,
                               out->alignment.gap_before, out->alignment.gap_after);
    return 0;
  });
  run_node(state, "transfer", "", [&](const ProgressFn& progress) {
    const TransferInputs in{c->exemplar->sampled->loaded->load.points,
                            c->exemplar->features.points,
                            a->target->sampled->loaded->load.points,
                            a->target->features.points,
                            c->map.rigid,
                            out->synthesis,
                            out->alignment,
                            working_to_output};
    out->output = transfer(in, progress);
    node_logger("transfer")
        ->info("{} output points, {} faces", out->output.points.size(), out->output.points.faces().cols());
    return 0;
  });
  return out;
}

// The completion input replaced by its virtual scan, when the config asks for one.
LoadResult maybe_virtual_scan(LoadResult load, const VirtualScanConfig& v, const std::string& subject) {
  if (!v.eye) return load;
  if (!load.points.has_faces())
    throw InputError(subject + ": virtual_scan needs a mesh (triangles), got a point cloud of " +
                     std::to_string(load.points.size()) + " points");
  ScanOptions o;
  o.eye = *v.eye;
  const BoundingBox box = bounding_box(load.points.positions());
  o.target = v.target ? *v.target : Eigen::Vector3d((box.min + box.max) / 2);
  if (v.up) {
    o.up = *v.up;
  } else if (std::abs((o.target - o.eye).normalized().z()) > 0.99) {
    o.up = Eigen::Vector3d::UnitY();
  }
  o.width = v.width;
  o.height = v.height;
  o.fov_deg = v.fov_deg;
  o.noise = v.noise;
  o.seed = v.seed;
  ScanResult scan = virtual_scan(load.points, o);
  load.points = std::move(scan.points);
  load.format += " (virtual scan)";
  load.file_points = load.points.size();
  return load;
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
  using CorrespondencePtr = std::shared_ptr<const Correspondence>;
  using CompletedPtr = std::shared_ptr<const Completed>;
  std::vector<std::unique_ptr<flow::graph_node>> nodes;
  const std::string& mode = config.mode;
  const bool completion = mode == "completion", transfer_mode = mode == "transfer";
  const auto slot_of = [&](const std::string& role) {
    for (size_t i = 0; i < specs.size(); ++i)
      if (specs[i].role == role) return i;
    throw InvariantError("no input '" + role + "' in mode " + mode);
  };
  // All inputs are sampled at one spacing alpha (the paper's): the reference input's, measured after its sampling.
  const size_t reference = slot_of(completion ? "template" : "target");

  std::vector<flow::function_node<LoadedPtr, SampledPtr>*> sample_nodes(specs.size());
  std::vector<flow::function_node<SampledPtr, FeaturedPtr>*> feature_nodes(specs.size());
  std::vector<flow::function_node<flow::continue_msg, LoadedPtr>*> load_nodes(specs.size());
  // `ref_load`: the reference input, whose spacing this one takes; both must share a scale (paper section 3), checked
  // before sampling at a spacing that would mean nothing.
  auto sample_body = [&](const InputSpec& spec, const LoadedPtr& in, double spacing, const LoadResult* ref_load) {
    const std::string name = "sample:" + spec.role;
    return run_node(state, name, subject_of(spec), [&](const ProgressFn& progress) {
      if (ref_load)
        check_shared_scale("the " + spec.role, bounding_box(in->load.points.positions()).diagonal(),
                           "the " + specs[reference].role, bounding_box(ref_load->points.positions()).diagonal(),
                           config.correspond.max_scale_ratio);
      SampleOptions options = config.sample;
      if (spacing > 0) {
        options.spacing = spacing;
        options.all_points_when_sparse = true;  // a scan sparser than the template's alpha is used as it is
      }
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
    const bool scanned = completion && spec.role == "scan";
    auto load_node = std::make_unique<flow::function_node<flow::continue_msg, LoadedPtr>>(
        g, flow::serial, [&, spec, subject, scanned](flow::continue_msg) {
          const std::string name = "load:" + spec.role;
          return run_node(state, name, subject, [&](const ProgressFn&) {
            LoadResult load = load_input(spec, config.load);
            if (scanned) load = maybe_virtual_scan(std::move(load), config.virtual_scan, subject);
            auto loaded = std::make_shared<Loaded>(Loaded{spec, std::move(load)});
            for (const auto& w : loaded->load.warnings) state.warn(name, w);
            node_logger("load")->info("{}: {} points, {} faces ({} {}) from {}", spec.role, loaded->load.points.size(),
                                      loaded->load.points.faces().cols(), loaded->load.format, loaded->load.encoding,
                                      subject);
            return LoadedPtr(std::move(loaded));
          });
        });
    auto sample_node = std::make_unique<flow::function_node<LoadedPtr, SampledPtr>>(
        g, flow::serial, [&, spec](const LoadedPtr& in) { return sample_body(spec, in, 0.0, nullptr); });
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
    load_nodes[slot] = load_node.get();
    sample_nodes[slot] = sample_node.get();
    feature_nodes[slot] = features_node.get();
    nodes.push_back(std::move(load_node));
    nodes.push_back(std::move(sample_node));
    nodes.push_back(std::move(features_node));
  }
  // The reference input samples as configured; every other one waits for its spacing (a join), unless the config
  // fixes the spacing.
  for (size_t slot = 0; slot < specs.size(); ++slot) {
    if (slot == reference) {
      flow::make_edge(*load_nodes[slot], *sample_nodes[slot]);
      flow::make_edge(*sample_nodes[slot], *feature_nodes[slot]);
      continue;
    }
    const InputSpec spec = specs[slot];
    using SpacingJoin = flow::join_node<std::tuple<LoadedPtr, SampledPtr>, flow::queueing>;
    auto join = std::make_unique<SpacingJoin>(g);
    auto at_spacing = std::make_unique<flow::function_node<std::tuple<LoadedPtr, SampledPtr>, SampledPtr>>(
        g, flow::serial, [&, spec](const std::tuple<LoadedPtr, SampledPtr>& in) {
          const double spacing = config.sample.spacing > 0 ? 0.0 : std::get<1>(in)->sample.spacing;
          return sample_body(spec, std::get<0>(in), spacing, &std::get<1>(in)->loaded->load);
        });
    flow::make_edge(*load_nodes[slot], flow::input_port<0>(*join));
    flow::make_edge(*sample_nodes[reference], flow::input_port<1>(*join));
    flow::make_edge(*join, *at_spacing);
    flow::make_edge(*at_spacing, *feature_nodes[slot]);
    nodes.push_back(std::move(join));
    nodes.push_back(std::move(at_spacing));
  }

  using Pair = std::tuple<FeaturedPtr, FeaturedPtr>;
  AnalogyPtr analogy_result;
  CorrespondencePtr correspondence_result;
  CompletedPtr completed_result;
  Similarity working_to_output;  // completion: back to the scan's frame
  const auto pair_join = [&](size_t first, size_t second) {
    auto join = std::make_unique<flow::join_node<Pair, flow::queueing>>(g);
    flow::make_edge(*feature_nodes[first], flow::input_port<0>(*join));
    flow::make_edge(*feature_nodes[second], flow::input_port<1>(*join));
    auto* raw = join.get();
    nodes.push_back(std::move(join));
    return raw;
  };
  if (mode == "analogy") {
    auto* join = pair_join(slot_of("source"), slot_of("target"));
    auto node = std::make_unique<flow::function_node<Pair, flow::continue_msg>>(g, flow::serial, [&](const Pair& in) {
      analogy_result = compute_analogy(state, config, std::get<0>(in)->features.points, std::get<1>(in));
      return flow::continue_msg();
    });
    flow::make_edge(*join, *node);
    nodes.push_back(std::move(node));
  } else if (completion) {
    // correspond(scan, template) -> source = covered template samples -> analogy(S, template) -> output.
    auto* join = pair_join(slot_of("scan"), slot_of("template"));
    auto node = std::make_unique<flow::function_node<Pair, flow::continue_msg>>(g, flow::serial, [&](const Pair& in) {
      const FeaturedPtr& scan = std::get<0>(in);
      const FeaturedPtr& templ = std::get<1>(in);
      correspondence_result = compute_correspondence(state, config, scan, templ, true);
      std::vector<std::int32_t> covered;
      for (size_t s = 0; s < correspondence_result->covered.size(); ++s)
        if (correspondence_result->covered[s]) covered.push_back(std::int32_t(s));
      analogy_result = compute_analogy(state, config, subset(templ->features.points, covered), templ);
      working_to_output = correspondence_result->map.rigid.inverse();
      completed_result = compute_output(state, config, correspondence_result, analogy_result, templ->features.points,
                                        working_to_output);
      return flow::continue_msg();
    });
    flow::make_edge(*join, *node);
    nodes.push_back(std::move(node));
  } else if (transfer_mode) {
    // correspond(S, E) and analogy(S, T) have no dependency on each other: two nodes, run in parallel.
    auto* corr_join = pair_join(slot_of("exemplar"), slot_of("source"));
    auto* analogy_join = pair_join(slot_of("source"), slot_of("target"));
    auto corr_node = std::make_unique<flow::function_node<Pair, CorrespondencePtr>>(
        g, flow::serial,
        [&](const Pair& in) { return compute_correspondence(state, config, std::get<0>(in), std::get<1>(in), false); });
    auto analogy_node = std::make_unique<flow::function_node<Pair, AnalogyPtr>>(g, flow::serial, [&](const Pair& in) {
      return compute_analogy(state, config, std::get<0>(in)->features.points, std::get<1>(in));
    });
    using Both = std::tuple<CorrespondencePtr, AnalogyPtr>;
    auto both = std::make_unique<flow::join_node<Both, flow::queueing>>(g);
    auto output_node =
        std::make_unique<flow::function_node<Both, flow::continue_msg>>(g, flow::serial, [&](const Both& in) {
          correspondence_result = std::get<0>(in);
          analogy_result = std::get<1>(in);
          completed_result = compute_output(state, config, correspondence_result, analogy_result,
                                            correspondence_result->source->features.points, working_to_output);
          return flow::continue_msg();
        });
    flow::make_edge(*corr_join, *corr_node);
    flow::make_edge(*analogy_join, *analogy_node);
    flow::make_edge(*corr_node, flow::input_port<0>(*both));
    flow::make_edge(*analogy_node, flow::input_port<1>(*both));
    flow::make_edge(*both, *output_node);
    nodes.push_back(std::move(corr_node));
    nodes.push_back(std::move(analogy_node));
    nodes.push_back(std::move(both));
    nodes.push_back(std::move(output_node));
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
  nlohmann::json report = {{"mode", mode}, {"inputs", inputs}};
  if (completed_result) {
    const TransferResult& o = completed_result->output;
    std::vector<double> origin(o.origin.size()), label(o.label.begin(), o.label.end());
    Index by_origin[3] = {0, 0, 0};
    for (size_t i = 0; i < o.origin.size(); ++i) {
      origin[i] = double(int(o.origin[i]));
      ++by_origin[int(o.origin[i])];
    }
    const std::filesystem::path out = config.output_dir / "output.ply";
    write_ply(out, o.points,
              {{"origin", PlyProperty::Type::kUint8, origin}, {"label", PlyProperty::Type::kInt32, label}});
    outcome.outputs.push_back(out);
    report["output"] = {{"points", o.points.size()},
                        {"faces", o.points.faces().cols()},
                        {"exemplar_points", by_origin[0]},
                        {"synthesized_points", by_origin[1]},
                        {"copied_points", by_origin[2]}};
    const Synthesis& syn = completed_result->synthesis;
    const AlignResult& al = completed_result->alignment;
    report["synthesis"] = {{"samples", syn.points.size()},         {"patches", syn.patches.size()},
                           {"gap_copies", syn.gap_copies},         {"seam_pairs", al.seam_pairs},
                           {"seam_gap_before", al.gap_before},     {"seam_gap_after", al.gap_after},
                           {"refinement_deg", syn.refinement_deg}, {"refinement_shift", syn.refinement_shift}};
  }
  if (correspondence_result) {
    const CorrespondResult& m = correspondence_result->map;
    report["correspondence"] = {
        {"rigid", {{"rotation", rotation_json(m.rigid.rotation)}, {"translation", json_vec(m.rigid.translation)}}},
        {"rigid_rms", m.rigid_rms},
        {"matched", m.matched},
        {"exemplar_samples", m.exemplar_match.size()},
        {"deformed_rms", m.deformed_rms}};
    if (completion) report["correspondence"]["covered_template_samples"] = correspondence_result->covered_count;
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
    const auto axes_json = [](const SymmetryResult& sym) {
      nlohmann::json axes = nlohmann::json::array();
      for (const auto& ax : sym.axes)
        axes.push_back({{"order", ax.order}, {"direction", json_vec(ax.direction)}, {"centre", json_vec(ax.centre)}});
      return axes;
    };
    report["symmetry"] = {{"source_axes", axes_json(a.source_symmetry)},
                          {"target_axes", axes_json(a.target_symmetry)},
                          {"target_rotations", a.target_symmetry.rotations.size()},
                          {"votes_quotiented", bool(a.source_symmetry.continuous)},
                          {"composed_candidates", a.composed_candidates}};
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
  report["transforms"] = transforms;
  report["energy"] = energy;
  report["nodes"] = node_list;
  report["peak_rss_mb"] = peak_rss_mb();
  report["warnings"] = state.warnings_;
  const std::filesystem::path report_path = config.output_dir / "report.json";
  write_file_atomic(report_path, report.dump(2) + "\n");
  outcome.outputs.push_back(report_path);
  std::ostringstream summary;
  if (completed_result) {
    const auto& o = report["output"];
    const Index used = std::count_if(transforms.begin(), transforms.end(), [](const nlohmann::json& t) {
      return t["kind"] == "similarity" && t["labelled"].get<Index>() > 0;
    });
    summary << "scanfill: " << (completion ? "completed scan" : "stylised model") << ": " << o["points"].get<Index>()
            << " points";
    if (o["faces"].get<Index>() > 0) summary << ", " << o["faces"].get<Index>() << " triangles";
    summary << " (" << o["exemplar_points"].get<Index>() << " from the " << (completion ? "scan" : "exemplar") << ", "
            << o["synthesized_points"].get<Index>() << " synthesised by " << used << " transforms, "
            << o["copied_points"].get<Index>() << " copied from the " << (completion ? "template" : "target") << ")\n"
            << "  output.ply: vertex 'origin' 0 = " << (completion ? "scan" : "exemplar")
            << ", 1 = synthesised, 2 = copied; 'label' = the transform (see report.json)\n"
            << "  analogy.ply: the " << (completion ? "template" : "target")
            << " samples coloured by transform (grey = self-reference)\n"
            << "  score it: scanfill eval --output " << (config.output_dir / "output.ply").string() << " --reference "
            << (completion && config.virtual_scan.eye ? subject_of(specs[slot_of("scan")]) : "COMPLETE_MODEL") << "\n";
  } else if (analogy_result) {
    summary << "scanfill: analogy of " << specs.size()
            << " inputs: analogy.ply holds the target samples coloured by transform (grey = self-reference)\n";
  }
  outcome.summary = summary.str();
  outcome.nodes = state.timings_;
  outcome.warnings = state.warnings_;
  return outcome;
}

}  // namespace scanfill
