#include "engine/stages.h"

#include <chrono>
#include <cmath>
#include <optional>
#include <tuple>
#include <utility>

#include "engine/console.h"
#include "engine/fields.h"
#include "engine/outputs.h"
#include "nodes/core/errors.h"
#include "nodes/correspond/free_space.h"
#include "nodes/input/scan_alignment.h"
#include "nodes/io/read_part_labels.h"
#include "nodes/io/read_ply_chunks.h"
#include "nodes/procedural/castle.h"
#include "nodes/scan/virtual_scan.h"
#include "nodes/symmetry/ground.h"
#include "nodes/symmetry/plain_faces.h"
#include "nodes/symmetry/profile.h"
#include "nodes/synthesize/repeats.h"

namespace scanfill {

void RunState::record(const std::string& name, double seconds) {
  std::lock_guard<std::mutex> lock(mutex_);
  timings_.push_back({name, seconds});
}

void RunState::warn(const std::string& node, const std::string& what) {
  node_logger(node)->warn("{}", what);
  std::lock_guard<std::mutex> lock(mutex_);
  warnings_.push_back(node + ": " + what);
}

void RunState::keep(FeaturedPtr f) {
  const Input& input = f->sampled->loaded->input;
  std::lock_guard<std::mutex> lock(mutex_);
  for (size_t slot = 0; slot < config.inputs.size(); ++slot)
    if (config.inputs[slot].role == input.role) inputs_[slot] = std::move(f);
}

void RunState::keep(LabelledPtr a) {
  std::lock_guard<std::mutex> lock(mutex_);
  analogy_ = std::move(a);
}

void RunState::keep(PlannedPtr p) {
  std::lock_guard<std::mutex> lock(mutex_);
  plan_ = std::move(p);
}

void RunState::keep(TransferredPtr t) {
  std::lock_guard<std::mutex> lock(mutex_);
  output_ = std::move(t);
}

void RunState::keep(DrawnPtr d) {
  std::lock_guard<std::mutex> lock(mutex_);
  drawing_ = std::move(d);
}

void RunState::keep(ExchangedPtr e) {
  std::lock_guard<std::mutex> lock(mutex_);
  exchanges_.push_back(std::move(e));
}

std::vector<ExchangedPtr> RunState::exchanges() const {
  std::vector<ExchangedPtr> out = exchanges_;
  std::sort(out.begin(), out.end(), [](const ExchangedPtr& a, const ExchangedPtr& b) { return a->pair < b->pair; });
  return out;
}

void RunState::keep(SurfacedPtr s) {
  std::lock_guard<std::mutex> lock(mutex_);
  surface_ = std::move(s);
}

namespace {

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

}  // namespace

std::string input_subject(const Input& input) {
  return input_name(input.spec) +
         (input.fragments.empty() ? "" : " and " + std::to_string(input.fragments.size()) + " more fragments");
}

LoadResult load_as_run(const RunConfig& config, const Input& input) {
  LoadResult load = load_fragments(all_specs(input), config.load);
  if (input.role == Role::kScan) load = virtual_scan_input(std::move(load), config.virtual_scan, input_subject(input));
  return load;
}

namespace {

// Input points per run of the streamed transfer (and of a streamed scan's reading): its buffers are about 100 bytes a
// point.
constexpr Index kTransferChunk = Index(1) << 20;
// A streamed scan's every-k-th points kept by its load: its area estimate, scale check and picture.
constexpr Index kStreamedSummaryPoints = Index(1) << 21;

// Whether the input is read in chunks (load.stream_above): a scan or exemplar that is one binary PLY of more points
// than that, not virtually scanned, in a mode that carries it by the transfer.
bool streams(const RunConfig& config, const Input& input) {
  if (config.load.stream_above <= 0 || !input.fragments.empty() || input.spec.path.empty() ||
      is_scan_alignment(input.spec.path))
    return false;
  if (config.mode != RunMode::kCompletion && config.mode != RunMode::kTransfer) return false;
  if (input.role != Role::kScan && input.role != Role::kExemplar) return false;
  if (input.role == Role::kScan && config.virtual_scan.eye) return false;
  const auto header = read_header(input.spec.path);
  return header && header->format == "ply" && header->encoding != "ascii" && header->points > config.load.stream_above;
}

// The load of a streamed input: one pass over its file for the count, the bounds and every k-th point.
LoadedPtr load_streamed(const Input& input) {
  auto streamed = std::make_shared<Streamed>();
  streamed->path = input.spec.path;
  PlyChunkReader reader(streamed->path);
  streamed->summary = summarize_chunks(reader, kTransferChunk, kStreamedSummaryPoints);
  if (streamed->summary.points == 0)
    throw IoError(streamed->path.string() + ": has no point with finite coordinates (" + std::to_string(reader.rows()) +
                  " points read)");
  LoadResult load;
  load.points = streamed->summary.every_kth;
  load.format = "ply";
  load.encoding = read_header(streamed->path)->encoding;
  load.file_points = reader.rows();
  load.dropped_nonfinite = reader.dropped_nonfinite();
  if (load.dropped_nonfinite > 0)
    load.warnings.push_back(std::to_string(load.dropped_nonfinite) + " of " + std::to_string(load.file_points) +
                            " points have non-finite coordinates and were dropped");
  const BoundingBox box = streamed->summary.bounds;
  return std::make_shared<const Loaded>(Loaded{input, std::move(load), box, nullptr, std::move(streamed)});
}

}  // namespace

LoadedPtr load_stage(RunState& state, const Input& input) {
  const std::string role = role_name(input.role), name = "load:" + role;
  const std::string subject = input_subject(input);
  return run_node(state, name, subject, [&](const ProgressFn&) {
    if (streams(state.config, input)) {
      if (state.config.output_colour == ColourChoice::kScan)
        throw InputError("output.colour is 'scan' but the " + role + " is read in chunks, without colours");
      LoadedPtr loaded = load_streamed(input);
      for (const auto& w : loaded->load.warnings) state.warn(name, w);
      node_logger("load")->info("{}: {} points read in chunks of {} ({} {}), not held; {} kept for its summary", role,
                                loaded->points(), kTransferChunk, loaded->load.format, loaded->load.encoding,
                                loaded->load.points.size());
      return loaded;
    }
    LoadResult load = load_as_run(state.config, input);
    // output.colour: scan asks for colours the output's points can only take from this input.
    if (state.config.output_colour == ColourChoice::kScan &&
        (input.role == Role::kScan || input.role == Role::kExemplar) && !load.points.has_colours())
      throw InputError("output.colour is 'scan' but the " + role +
                       " has no colours (PLY red green blue, PCD rgb or rgba, XYZ or OBJ r g b): use auto or origin");
    const BoundingBox box = input_bounds(load);
    auto loaded = std::make_shared<Loaded>(Loaded{input, std::move(load), box, nullptr, nullptr});
    for (const auto& w : loaded->load.warnings) state.warn(name, w);
    node_logger("load")->info("{}: {} points, {} faces ({} {}) from {}", role, loaded->load.points.size(),
                              loaded->load.points.faces().cols(), loaded->load.format, loaded->load.encoding, subject);
    return LoadedPtr(std::move(loaded));
  });
}

SampledPtr sample_stage(RunState& state, const LoadedPtr& in, const SampledPtr& reference) {
  const RunConfig& config = state.config;
  const std::string role = role_name(in->input.role), name = "sample:" + role;
  return run_node(state, name, input_name(in->input.spec), [&](const ProgressFn& progress) {
    SampleOptions options = config.sample;
    if (reference) {
      // All inputs share one spacing alpha (the paper's) and so must share a scale (paper section 3): checked before
      // sampling at a spacing that would mean nothing.
      const Loaded& ref = *reference->loaded;
      check_shared_scale("the " + role, in->load.points, "the " + role_name(ref.input.role), ref.load.points,
                         config.correspond.max_scale_ratio);
      if (config.sample.spacing <= 0) {
        options.spacing = reference->sample.spacing;
        options.all_points_when_sparse = true;  // a scan sparser than the template's alpha is used as it is
      }
    }
    std::optional<PlyChunkReader> reader;
    if (in->streamed) reader.emplace(in->streamed->path);
    auto out = std::make_shared<Sampled>(
        Sampled{in,
                in->streamed ? sample_chunks(*reader, in->streamed->summary, options, kTransferChunk, progress)
                             : sample(in->load.points, options, progress),
                nullptr});
    for (const auto& w : out->sample.warnings) state.warn(name, w);
    node_logger("sample")->info("{}: {} samples from {} candidates, spacing {:.4g}, {} rounds", role,
                                out->sample.samples.size(), out->sample.candidates, out->sample.spacing,
                                out->sample.rounds);
    return SampledPtr(std::move(out));
  });
}

FeaturedPtr features_stage(RunState& state, const SampledPtr& in) {
  const std::string role = role_name(in->loaded->input.role), name = "features:" + role;
  return run_node(state, name, input_name(in->loaded->input.spec), [&](const ProgressFn& progress) {
    auto out = std::make_shared<Featured>(
        Featured{in, estimate_features(in->sample.samples, state.config.features, progress)});
    for (const auto& w : out->features.warnings) state.warn(name, w);
    node_logger("features")
        ->info("{}: normals oriented by '{}', {} unreliable directions smoothed ({} CG iterations)", role,
               to_string(out->features.orientation_used), out->features.unreliable_directions,
               out->features.iterations);
    state.keep(out);
    return FeaturedPtr(std::move(out));
  });
}

LoadedPtr load_curves_stage(RunState& state, const Input& input) {
  const std::string role = role_name(input.role), name = "load:" + role;
  return run_node(state, name, input_name(input.spec), [&](const ProgressFn&) {
    auto curves = std::make_shared<const Curves>(read_curves(input.spec.path));
    LoadResult load;
    load.points = curve_vertices(*curves);
    load.format = input.spec.path.extension().string().substr(1);
    load.encoding = "ascii";
    load.file_points = load.points.size();
    const BoundingBox box = input_bounds(load);
    node_logger("load")->info("{}: {} curves, {} vertices from {}", role, curves->size(), load.points.size(),
                              input_name(input.spec));
    return LoadedPtr(std::make_shared<Loaded>(Loaded{input, std::move(load), box, std::move(curves), nullptr}));
  });
}

FeaturedPtr sample_curves_stage(RunState& state, const LoadedPtr& in, const FeaturedPtr& reference) {
  const RunConfig& config = state.config;
  const std::string role = role_name(in->input.role), name = "sample:" + role;
  return run_node(state, name, input_name(in->input.spec), [&](const ProgressFn&) {
    double spacing = curve_spacing(drawing_length(*in->curves), config.curves);
    if (reference) {  // one spacing alpha for all drawings, which must then share a scale (paper section 3)
      const Loaded& ref = *reference->sampled->loaded;
      check_shared_scale("the " + role, in->load.points, "the " + role_name(ref.input.role),
                         curve_vertices(*ref.curves), config.correspond.max_scale_ratio);
      spacing = reference->sampled->sample.spacing;
    }
    auto samples = std::make_shared<const CurveSamples>(sample_curves(*in->curves, spacing, config.curves));
    // The samples are the drawing's points from here on: transfer carries them, one output point each.
    LoadResult load{samples->samples, in->load.format, in->load.encoding, in->load.file_points, 0, {}};
    auto loaded = std::make_shared<const Loaded>(Loaded{in->input, std::move(load), in->box, in->curves, nullptr});
    SampleResult sample;
    sample.samples = samples->samples;
    sample.candidates = in->load.points.size();
    sample.spacing = spacing;
    auto sampled = std::make_shared<const Sampled>(Sampled{loaded, std::move(sample), samples});
    auto out = std::make_shared<Featured>(Featured{sampled, {}});
    out->features.points = samples->samples;
    out->features.orientation_used = NormalOrientation::kInput;
    node_logger("sample")->info("{}: {} samples along {} curves of length {:.4g}, spacing {:.4g}", role,
                                samples->samples.size(), in->curves->size(), samples->length, spacing);
    state.keep(out);
    return FeaturedPtr(std::move(out));
  });
}

namespace {

// What stands in for the template from the correspondence on (completion): the body of revolution a low-poly polygon
// template draws (CorrespondResult::polygon), or the template scaled to a scan it is drawn at another size than
// (template_scaled), or both. Its samples with their features estimated again, and the surface copies are made of
// (polygon_body_surface on a body), all in place.
FeaturedPtr stand_in_for(RunState& state, const Featured& templ, const CorrespondResult& map) {
  auto loaded = std::make_shared<Loaded>(*templ.sampled->loaded);
  PointSet& surface = loaded->load.points;
  if (map.polygon.sides > 0)
    surface =
        polygon_body_surface(surface, map.polygon, templ.sampled->sample.spacing, templ.sampled->sample.samples.size());
  if (map.template_scaled) surface = scaled_source(surface, map.template_scaling);
  loaded->box = input_bounds(loaded->load);
  auto sampled = std::make_shared<Sampled>(*templ.sampled);
  sampled->loaded = std::move(loaded);
  sampled->sample.samples = template_in_place(templ.sampled->sample.samples, map);
  FeaturesResult features = estimate_features(sampled->sample.samples, state.config.features);
  for (const auto& w : features.warnings) state.warn("features:template", w);
  return std::make_shared<const Featured>(Featured{std::move(sampled), std::move(features)});
}

}  // namespace

CorrespondencePtr correspond_stage(RunState& state, const FeaturedPtr& exemplar, const FeaturedPtr& source) {
  return run_node(state, "correspond", "", [&](const ProgressFn& progress) {
    auto c = std::make_shared<Correspondence>();
    c->exemplar = exemplar;
    c->source = source;
    const PointSet& E = exemplar->features.points;
    CorrespondOptions options = state.config.correspond;
    options.polygon_body = options.scaled_template = state.config.mode == RunMode::kCompletion;
    c->map = correspond(E, source->features.points, source->sampled->sample.spacing, options, progress);
    for (const auto& w : c->map.warnings) state.warn("correspond", w);
    if (c->map.polygon.sides > 0 || c->map.template_scaled) c->source = stand_in_for(state, *source, c->map);
    node_logger("correspond")
        ->info(
            "rigid registration: {:.3g} deg, shift {:.4g}, RMS {:.4g}{}{}; {} of {} exemplar samples matched, RMS "
            "{:.4g} after deformation",
            rotation_angle(c->map.rigid.rotation) * 180 / M_PI, c->map.rigid.translation.norm(), c->map.rigid_rms,
            c->map.polygon.sides > 0 ? fmt::format(" on the body of revolution through the corners of the template's "
                                                   "{} sides, which stands in for it from here on",
                                                   c->map.polygon.sides)
                                     : std::string(),
            c->map.template_scaled   ? " (ICP's, not taken: the template is drawn at another size than the scan, and "
                                       "scaled to it stands in for it from here on)"
            : c->map.another_size    ? " (ICP's, not taken: the template is drawn at another size than the scan)"
            : c->map.kept_input_pose ? " (ICP's, not taken: the scan's relief pulled it off the template)"
            : c->map.turned_in_place ? " (ICP's turn about the template's centroid: the scan's relief pulled its move)"
            : c->map.laid_on_axis    ? " (the scan's own axis of revolution laid on the template's)"
                                     : "",
            c->map.matched, E.size(), c->map.deformed_rms);
    for (size_t i = 0; i < c->map.deformation_solves.size(); ++i) {
      const SolverSummary& s = c->map.deformation_solves[i];
      node_logger("correspond")
          ->debug("deformation solve {}: {} after {} iterations, cost {:.6g} -> {:.6g}", i + 1, s.termination,
                  s.iterations, s.initial_cost, s.final_cost);
    }
    return CorrespondencePtr(std::move(c));
  });
}

CoveragePtr cover_stage(RunState& state, const CorrespondencePtr& correspondence) {
  return run_node(state, "cover", "", [&](const ProgressFn&) {
    const Featured& templ = *correspondence->source;
    auto c = std::make_shared<Coverage>();
    c->correspondence = correspondence;
    c->cover = cover_template(templ.features.points, correspondence->map, correspondence->exemplar->features.points,
                              templ.sampled->sample.spacing, state.config.cover);
    node_logger("cover")->info("the scan covers {} of {} template samples", c->cover.samples.size(),
                               templ.features.points.size());
    return CoveragePtr(std::move(c));
  });
}

namespace {

std::string describe(const SymmetryResult& s) {
  if (s.axes.empty()) return "no rotational symmetry";
  std::string out;
  for (const auto& a : s.axes)
    out += fmt::format("{}{} about ({:.3g}, {:.3g}, {:.3g})", out.empty() ? "" : ", ",
                       a.order == 0 ? std::string("continuous") : std::to_string(a.order) + "-fold", a.direction.x(),
                       a.direction.y(), a.direction.z());
  return out;
}

}  // namespace

SymmetriesPtr symmetry_stage(RunState& state, const PointSet& source, const FeaturedPtr& target,
                             const CorrespondencePtr& correspondence) {
  return run_node(state, "symmetry", "", [&](const ProgressFn&) {
    auto s = std::make_shared<Symmetries>();
    s->source = source;
    s->target = target;
    s->correspondence = correspondence;
    s->spacing = target->sampled->sample.spacing;
    SymmetryOptions options = state.config.symmetry;
    options.planar = state.config.mode == RunMode::kCurves;
    s->source_symmetry = find_symmetries(source, s->spacing, options);
    s->target_symmetry = find_symmetries(target->features.points, s->spacing, options);
    s->target_symmetry.parts = find_part_symmetries(target->features.points, s->spacing, s->target_symmetry, options,
                                                    &target->sampled->loaded->load.points);
    s->target_symmetry.faces = find_planar_faces(target->features.points, s->spacing, options);
    s->target_axes = object_axes(s->target_symmetry);
    node_logger("symmetry")
        ->info("source: {}; target: {} ({} rotations; {} parts about their own axis; {} flat faces)",
               describe(s->source_symmetry), describe(s->target_symmetry), s->target_symmetry.rotations.size(),
               s->target_symmetry.parts.size(), s->target_symmetry.faces.size());
    return SymmetriesPtr(std::move(s));
  });
}

namespace {

// vote's options with the scale range the mode allows: completion narrows it to [1 / completion_scale,
// completion_scale] (1.5 leaves a part repeated at 0.7, the scaled copy), since the transforms carry one
// object's seen parts onto its others. A flat face takes any shrunk copy of itself: a gear seen straight from below had
// its far face explained by its seen face flipped and scaled by 0.48, which left out the true flip as redundant.
VoteOptions vote_options(const RunConfig& config) {
  VoteOptions options = config.vote;
  if (config.mode == RunMode::kCompletion) {
    options.min_scale = std::max(options.min_scale, 1 / options.completion_scale);
    options.max_scale = std::min(options.max_scale, options.completion_scale);
  }
  return options;
}

}  // namespace

VotesPtr vote_stage(RunState& state, const SymmetriesPtr& in) {
  return run_node(state, "vote", "", [&](const ProgressFn&) {
    auto v = std::make_shared<Votes>();
    v->symmetries = in;
    VoteOptions options = vote_options(state.config);
    options.planar = state.config.mode == RunMode::kCurves;
    options.axes = in->target_axes;
    v->votes = vote(in->source, in->target->features.points, in->spacing, options);
    // A source symmetric about an axis votes for rings of equivalent motions: one mode per ring (DESIGN section 9).
    if (in->source_symmetry.continuous) quotient_votes(v->votes, *in->source_symmetry.continuous);
    node_logger("vote")->info("{} votes from {} target samples{}", v->votes.embedding.cols(),
                              std::min<Index>(state.config.vote.target_samples, in->target->features.points.size()),
                              in->source_symmetry.continuous ? ", modulo the source's continuous symmetry" : "");
    return VotesPtr(std::move(v));
  });
}

FoundModesPtr modes_stage(RunState& state, const VotesPtr& in) {
  return run_node(state, "modes", "", [&](const ProgressFn&) {
    auto m = std::make_shared<FoundModes>(FoundModes{in, find_modes(in->votes, state.config.modes)});
    node_logger("modes")->info("{} modes from {} seeds", m->modes.modes.size(), m->modes.seeds);
    if (m->modes.modes.empty()) state.warn("modes", "no transform found: every target sample is self-referenced");
    return FoundModesPtr(std::move(m));
  });
}

namespace {

// label.up, else the target's own axis, else (completion) the target's axis whose faces the scan shows plainest, else
// the one whose faces it does not show where it shows the other two (plain_faces.h), else the one it stands on the
// origin's plane along (ground.h), else +z, said when the config does not set it (a model drawn y-up without a telling
// symmetry, scan or ground needs the key). With where it came from, for the report.
std::pair<Eigen::Vector3d, const char*> up_direction(const LabelOptions& label, const Votes& v) {
  if (label.up) return {*label.up, "label.up"};
  const SymmetryResult& symmetry = v.symmetries->target_symmetry;
  const auto say = [](const Eigen::Vector3d& up, const char* from, const char* why) {
    node_logger("support")->info("up ({:.3g}, {:.3g}, {:.3g}): {}", up.x(), up.y(), up.z(), why);
    return std::pair{up, from};
  };
  if (const auto axis = upright_axis(symmetry)) return say(*axis, "symmetry", "the target's symmetry axis");
  const Correspondence* scan = v.symmetries->correspondence.get();
  if (scan && symmetry.axes.size() > 1) {
    const std::vector<FaceTally> tallies = plain_face_tallies(scan->exemplar->features.points, scan->map.rigid,
                                                              v.target()->features.points, symmetry.axes, v.spacing());
    if (const auto plain = plainest_face_axis(tallies, symmetry.axes))
      return say(*plain, "plainest_faces", "the target's axis whose faces the scan shows plainest (a lid and a floor)");
    if (const auto unseen = unseen_face_axis(tallies, symmetry.axes))
      return say(*unseen, "unseen_faces",
                 "the target's axis whose faces the scan does not show, where it shows two sides (seen from around)");
    if (const auto ground = grounded_axis(v.target()->features.points, symmetry.axes))
      return say(*ground, "ground", "the target's axis along which it stands on the origin's plane, as drawn");
  }
  node_logger("support")->info(
      "up +z: neither the target's symmetry, nor the scan, nor the plane it stands on singles out an axis (set "
      "label.up for a model drawn otherwise)");
  return {Eigen::Vector3d::UnitZ(), "default"};
}

// Whether the scan repeats about the target's axis of revolution (completion). Its quarter and half turns are the
// analogy's guess for a scan that does not (offered by support, preferred by label.quarter_unary); where it repeats,
// synthesize turns every image to its repeats, and the preference only moves regions between turns that are alike: the
// 24-gon column seen from
// (-0.61, -0.43, 0.67), 16 flutes, lost 0.987 -> 0.933 to it.
bool scan_repeats_about_axis(const Votes& v, double limit) {
  const auto& axis = v.symmetries->target_symmetry.continuous;
  const Correspondence* scan = v.symmetries->correspondence.get();
  return axis && scan &&
         repeats_about(scan->exemplar->features.points, scan->map.rigid, axis->centre, axis->direction, v.spacing(),
                       limit);
}

// Completion, a round target: the scan's own profile about its axis (symmetry/profile.h), which judges the candidates
// that move heights along it. A plain cylinder lies on itself end over end; a vase seen from below had its foot's
// beads carried to its neck.
std::optional<RadialProfile> scan_profile(const Votes& v) {
  const auto& axis = v.symmetries->target_symmetry.continuous;
  const Correspondence* scan = v.symmetries->correspondence.get();
  if (!axis || !scan) return std::nullopt;
  return radial_profile(scan->exemplar->features.points, scan->map.rigid, *axis, v.spacing());
}

// The candidates (modes or transforms) the profile refutes, dropped and said: flips end over end and slides along the
// axis that pair heights where the scan's radii differ. Returns how many.
template <typename Candidate>
Index drop_what_the_profile_refutes(std::vector<Candidate>& candidates, const std::optional<RadialProfile>& profile,
                                    double tolerance) {
  if (!profile) return 0;
  const auto refuted =
      std::erase_if(candidates, [&](const Candidate& c) { return profile_refutes(*profile, c.transform, tolerance); });
  if (refuted > 0)
    node_logger("support")->info(
        "{} candidates dropped: they pair heights along the target's axis where the scan's radii about it differ",
        refuted);
  return Index(refuted);
}

}  // namespace

SupportsPtr support_stage(RunState& state, const FoundModesPtr& in) {
  const RunConfig& config = state.config;
  return run_node(state, "support", "", [&](const ProgressFn&) {
    const Votes& v = *in->votes;
    auto s = std::make_shared<Supports>();
    s->modes = in;
    // Support refines the transforms vote proposed: vote.allow_scale decides their kind for both, and vote's scale
    // range (narrowed in completion) the scales support keeps.
    SupportOptions options = config.support;
    const VoteOptions voted_range = vote_options(config);
    options.allow_scale = voted_range.allow_scale;
    options.min_scale = voted_range.min_scale;
    options.max_scale = voted_range.max_scale;
    const PointSet& T = v.target()->features.points;
    SupportResult voted =
        grow_supports(v.source(), T, in->modes.modes, v.spacing(), mode_accuracy(v.votes, config.modes), options);
    const Correspondence* scan = v.symmetries->correspondence.get();
    const std::optional<RadialProfile> profile = scan_profile(v);
    const double refuting = config.support.distance * v.spacing();
    s->refuted += drop_what_the_profile_refutes(voted.transforms, profile, refuting);
    if (const auto& axis = v.symmetries->source_symmetry.continuous)
      snap_to_family_representatives(voted.transforms, *axis);
    // The candidates the paper expects: the motions found, composed with T's own symmetries (DESIGN section 9).
    const SymmetryResult& symmetry = v.symmetries->target_symmetry;
    std::tie(s->up, s->up_from) = up_direction(config.label, v);
    std::vector<Mode> composed =
        composed_candidates(voted.transforms, symmetry, T, v.spacing(), s->up, config.symmetry,
                            scan ? &scan->exemplar->features.points : nullptr, scan ? scan->map.rigid : Similarity{});
    s->refuted += drop_what_the_profile_refutes(composed, profile, refuting);
    // Where T's turns all explain the scan alike, voting finds turns at random angles: the quarter turns eq. 9
    // prefers are offered too, unless the scan's own repeats phase every image (synthesize).
    s->scan_repeats = scan && scan_repeats_about_axis(v, config.synthesize.refine_distance * v.spacing());
    const std::vector<Mode> quarters =
        scan && !s->scan_repeats ? axis_quarter_turns(voted.transforms, symmetry, T) : std::vector<Mode>{};
    // Completion: the upright turns beside any flip that explains the same face, for label.upright_unary to prefer.
    const std::vector<Mode> upright = scan && config.symmetry.enabled && config.label.upright_unary > 0
                                          ? upright_turns(voted.transforms, symmetry, T, s->up)
                                          : std::vector<Mode>{};
    std::vector<Mode> preferred = quarters;
    preferred.insert(preferred.end(), upright.begin(), upright.end());
    s->support = extend_supports(v.source(), T, voted, composed, v.spacing(), 0.0, options, preferred);
    if (!quarters.empty())
      node_logger("support")->info("the quarter and half turns about the target's axis offered as candidates");
    s->voted = Index(voted.transforms.size());
    s->composed = Index(composed.size());
    node_logger("support")->info(
        "{} transforms with support of at least {} samples ({} from votes; {} candidates composed with the target's "
        "symmetries)",
        s->support.transforms.size(), config.support.min_support, s->voted, s->composed);
    return SupportsPtr(std::move(s));
  });
}

LabelledPtr label_stage(RunState& state, const SupportsPtr& in) {
  return run_node(state, "label", "", [&](const ProgressFn&) {
    const Votes& v = *in->modes->votes;
    auto a = std::make_shared<Labelled>();
    a->supports = in;
    LabelOptions options = state.config.label;
    options.up = in->up;
    options.axes = v.symmetries->target_axes;
    // Completion: the scan's sides do not lend their style to a lid or a floor it did not see.
    options.caps_take_tips = state.config.mode != RunMode::kCompletion || options.upright_unary <= 0;
    if (options.quarter_unary > 0 && in->scan_repeats) {
      options.quarter_unary = 0;
      node_logger("label")->info("the scan repeats about the target's axis: no preference for quarter turns");
    }
    a->labels = label_target(v.source(), v.target()->features.points, in->support.transforms, v.spacing(), options);
    node_logger("label")->info("energy {:.6g} -> {:.6g} in {} sweeps; {} samples relabelled by the clean-up",
                               a->labels.energy_before, a->labels.energy_after, a->labels.cycles, a->labels.cleaned);
    state.keep(a);
    return LabelledPtr(std::move(a));
  });
}

// The template's axes of revolution, for synthesize's fill by turns: its own (unbounded) and each part's (a leg: the
// part's samples' reach from its axis and their heights, 3 alpha wider).
std::vector<TurningPart> turning_parts(const SymmetryResult& target, const PointSet& samples, double spacing) {
  std::vector<TurningPart> out;
  if (target.continuous) out.push_back({target.continuous->centre, target.continuous->direction.normalized()});
  for (const PartSymmetry& p : target.parts)
    out.push_back(part_holding(p.axis.centre, p.axis.direction, samples.positions(), p.samples, 3 * spacing));
  return out;
}

namespace {

// Completion: where the sensor stood, in the scan's frame: features.viewpoint when set, else the scan file's own (a
// PCD's VIEWPOINT, a PLY's camera element, the virtual scanner's eye).
std::optional<Eigen::Vector3d> scan_viewpoint(const RunConfig& config, const Featured& scan) {
  return config.features.viewpoint ? config.features.viewpoint : scan.sampled->loaded->load.points.viewpoint();
}

}  // namespace

SynthesizedPtr synthesize_stage(RunState& state, const CorrespondencePtr& correspondence, const LabelledPtr& analogy,
                                const CoveragePtr& coverage) {
  return run_node(state, "synthesize", "", [&](const ProgressFn&) {
    auto out = std::make_shared<Synthesized>();
    out->correspondence = correspondence;
    out->analogy = analogy;
    out->coverage = coverage;
    const Votes& v = analogy->votes();
    std::vector<Similarity> transforms;
    for (const auto& t : analogy->supports->support.transforms) transforms.push_back(t.transform);
    const std::vector<TurningPart> parts =
        turning_parts(v.symmetries->target_symmetry, v.target()->features.points, v.spacing());
    const auto principal = principal_axis(v.symmetries->target_symmetry);
    const std::optional<TurningPart> mirror_axis =
        principal ? std::optional<TurningPart>(TurningPart{principal->centre, principal->direction}) : std::nullopt;
    const CorrespondResult& map = correspondence->map;
    const std::optional<RadialProfile> profile = coverage ? scan_profile(v) : std::nullopt;
    const std::vector<std::uint8_t> off_profile =
        profile ? outside_the_profile(*profile, v.target()->features.points, v.spacing()) : std::vector<std::uint8_t>{};
    const std::optional<Eigen::Vector3d> eye = coverage && state.config.synthesize.seen_through
                                                   ? scan_viewpoint(state.config, *correspondence->exemplar)
                                                   : std::nullopt;
    const std::vector<std::uint8_t> seen = eye ? seen_through(correspondence->exemplar->features.points, map.rigid,
                                                              *eye, v.target()->features.points, v.spacing())
                                               : std::vector<std::uint8_t>{};
    const SynthesisInputs in{correspondence->exemplar->features.points,
                             map.rigid,
                             map.exemplar_source,
                             correspondence->source->features.points,
                             v.target()->features.points,
                             analogy->labels.labels,
                             analogy->labels.self_label,
                             transforms,
                             coverage ? &coverage->cover.covered : nullptr,
                             &parts,
                             mirror_axis ? &*mirror_axis : nullptr,
                             coverage && (!state.config.correspond.rigid || map.kept_input_pose || map.turned_in_place),
                             coverage ? std::optional<Eigen::Vector3d>(analogy->supports->up) : std::nullopt,
                             profile ? &off_profile : nullptr,
                             eye ? &seen : nullptr};
    out->synthesis = synthesize(in, v.spacing(), state.config.synthesize);
    Index by_origin[3] = {0, 0, 0};
    for (const auto o : out->synthesis.origin) ++by_origin[int(o)];
    node_logger("synthesize")
        ->info("{} patches: {} exemplar, {} synthesised, {} copied samples ({} where no patch reached)",
               out->synthesis.patches.size(), by_origin[0], by_origin[1], by_origin[2], out->synthesis.gap_copies);
    if (out->synthesis.off_profile > 0)
      node_logger("synthesize")
          ->info("{} template samples not copied: they stand outside the scan's own radii about the template's axis",
                 out->synthesis.off_profile);
    if (out->synthesis.seen_through > 0)
      node_logger("synthesize")
          ->info(
              "{} template samples not copied: the scanner, at ({:.6g}, {:.6g}, {:.6g}) in the scan's frame ({}), saw "
              "the scan through them",
              out->synthesis.seen_through, (*eye)(0), (*eye)(1), (*eye)(2),
              state.config.features.viewpoint ? "features.viewpoint"
                                              : "the scan's own; a scan not in its sensor's frame sets "
                                                "features.viewpoint or synthesize.seen_through: false");
    return SynthesizedPtr(std::move(out));
  });
}

AlignedPtr align_stage(RunState& state, const SynthesizedPtr& in) {
  return run_node(state, "align", "", [&](const ProgressFn&) {
    auto out = std::make_shared<Aligned>(
        Aligned{in, align(in->synthesis, in->analogy->votes().spacing(), state.config.align)});
    const AlignResult& al = out->alignment;
    node_logger("align")->info("{} seam pairs, RMS gap {:.4g} -> {:.4g}", al.seam_pairs, al.gap_before, al.gap_after);
    if (al.solver)
      node_logger("align")->debug("solve: {} after {} iterations, cost {:.6g} -> {:.6g}", al.solver->termination,
                                  al.solver->iterations, al.solver->initial_cost, al.solver->final_cost);
    return AlignedPtr(std::move(out));
  });
}

namespace {

// The working frame -> the output's: completion writes in the scan's own frame (the inverse of the registration).
Similarity output_frame(const Correspondence& c, bool to_scan_frame) {
  return to_scan_frame ? c.map.rigid.inverse() : Similarity{};
}

}  // namespace

PlannedPtr plan_stage(RunState& state, const AlignedPtr& in, bool to_scan_frame) {
  return run_node(state, "plan", "", [&](const ProgressFn&) {
    const Synthesized& syn = *in->synthesized;
    const Correspondence& c = *syn.correspondence;
    const Featured& target = *syn.analogy->votes().target();
    const TransferInputs inputs{c.exemplar->sampled->loaded->load.points,
                                c.exemplar->features.points,
                                target.sampled->loaded->load.points,
                                target.features.points,
                                c.map.rigid,
                                syn.synthesis,
                                in->alignment,
                                output_frame(c, to_scan_frame)};
    TransferPlan plan = plan_transfer(inputs);
    if (const auto& streamed = c.exemplar->sampled->loaded->streamed) {
      // load.points hold only its summary's points: the plan counts and bounds the whole file.
      plan.exemplar_points = streamed->summary.points;
      plan.exemplar_bounds = streamed->summary.bounds;
    }
    auto out = std::make_shared<Planned>(Planned{in, std::move(plan)});
    node_logger("plan")->info("{} patches, {} carried samples", out->plan.patches.size(), out->plan.patch.size());
    state.keep(out);
    return PlannedPtr(std::move(out));
  });
}

namespace {

// The output points the transfer's message keeps for the preview: all of them up to this many (and always in mode
// curves, whose drawing orders every point), else every stride-th point, about this many: a 360-pixel panel shows no
// more. (The surface is made from the synthesis' samples, not from these.)
constexpr Index kKeptPoints = Index(1) << 18;

Index kept_stride(const RunConfig& config, Index output_points) {
  if (config.mode == RunMode::kCurves) return 1;
  return std::max<Index>(1, (output_points + kKeptPoints - 1) / kKeptPoints);
}

}  // namespace

TransferredPtr transfer_stage(RunState& state, const PlannedPtr& in) {
  return run_node(state, "transfer", "", [&](const ProgressFn& progress) {
    const Synthesized& syn = *in->aligned->synthesized;
    const PointSet& exemplar = syn.correspondence->exemplar->sampled->loaded->load.points;
    const PointSet& target = syn.analogy->votes().target()->sampled->loaded->load.points;
    const TransferPlan& plan = in->plan;
    auto out = std::make_shared<Transferred>();
    out->aligned = in->aligned;
    out->written = state.write_dir / "output.ply";
    // Copies come from the target's surface at the exemplar's density; only the copied points are made and held.
    const PointSet copies = copied_points(plan, target);
    // Runs are encoded and written beside the computing of the next one (the last beside whatever still runs).
    out->writing = std::make_shared<SerialBackground>();
    std::shared_ptr<OutputPlyWriter> writer;
    std::optional<EveryKth> kept;
    const TransferSink sink{
        [&](const TransferCounts& c) {
          out->colour = resolved_colour(state.config.output_colour, plan.colours && c.points > 0);
          out->intensity = plan.intensity && c.points > 0;
          out->stride = kept_stride(state.config, c.points);
          writer = std::make_shared<OutputPlyWriter>(out->written, c, out->intensity, out->colour,
                                                     syn.analogy->labels.self_label);
          kept.emplace(out->stride);
        },
        [&](TransferResult run) {
          kept->add(run);
          auto held = std::make_shared<const TransferResult>(std::move(run));
          out->writing->submit([writer, held] { writer->append(*held); });
        },
        [&](const Matrix3Xi& faces) { out->writing->submit([writer, faces] { writer->append_faces(faces); }); }};
    if (const auto& streamed = syn.correspondence->exemplar->sampled->loaded->streamed) {
      PlyChunkReader reader(streamed->path);  // the scan a run at a time, as the sample node read it
      out->counts = stream_plan_chunks(plan, reader, streamed->summary.points, &copies, kTransferChunk, sink, progress);
    } else {
      out->counts = stream_plan(plan, &exemplar, &copies, kTransferChunk, sink, progress);
    }
    out->writing->submit([writer] { writer->commit(); });
    out->kept = kept->take();
    node_logger("transfer")
        ->info("{} output points, {} faces written to output.ply in runs of {} scan points; {} kept for the preview",
               out->counts.points, out->counts.faces, kTransferChunk, out->kept.points.size());
    state.keep(out);
    return TransferredPtr(std::move(out));
  });
}

SurfacedPtr surface_stage(RunState& state, const SynthesizedPtr& in, bool to_scan_frame) {
  return run_node(state, "surface", "", [&](const ProgressFn&) {
    // The synthesis as the output will have it (align's thinning of the overlaps, at zero offsets: align may still be
    // running), in the output's frame.
    const Synthesis& syn = in->synthesis;
    const std::vector<double> no_offsets(size_t(syn.points.size()), 0.0);
    const PointSet completed = kept_points(
        syn, thinned_overlaps(syn, no_offsets, in->analogy->votes().spacing(), state.config.align.thin_distance),
        output_frame(*in->correspondence, to_scan_frame));
    auto out = std::make_shared<Surfaced>(Surfaced{in, poisson_surface(completed, state.config.surface)});
    const SurfaceResult& s = out->surface;
    for (const auto& w : s.warnings) state.warn("surface", w);
    node_logger("surface")->info(
        "Poisson surface: {} vertices, {} triangles from {} points (spacing {:.4g}); {} of {} triangles trimmed as "
        "farther than {} spacings from the points",
        s.mesh.size(), s.mesh.faces().cols(), s.points_meshed, s.spacing, s.trimmed_faces, s.poisson_faces,
        state.config.surface.trim_distance);
    state.keep(out);
    return SurfacedPtr(std::move(out));
  });
}

namespace {

// The part property names to look for: the configured one, or the common ones when it is auto.
std::vector<std::string> part_property_names(const std::string& configured) {
  if (configured != "auto") return {configured};
  return common_part_properties();
}

// An input's boxes from its PLY's part property; InputError naming the file when it gives none or a flat one.
Parts parts_from_ply(const Input& input, const std::string& property) {
  const PartLabels labels = read_ply_part_labels(input.spec.path, part_property_names(property));
  Parts parts{input, {}, "PLY vertex property '" + labels.property + "'", {}};
  parts.boxes = boxes_of_parts(labels.positions, labels.labels, parts.part_labels);
  const std::string subject = input.spec.path.string() + ": vertex property '" + labels.property + "'";
  if (parts.boxes.empty()) throw InputError(subject + " gives no part (every label is negative)");
  for (size_t b = 0; b < parts.boxes.size(); ++b)
    if (!(parts.boxes[b].size().array() > 0).all())
      throw InputError(subject + ": part " + std::to_string(parts.part_labels[b]) +
                       " is flat (its bounding box has zero volume): every part needs a box with volume");
  return parts;
}

}  // namespace

PartsPtr parts_stage(RunState& state, const Input& input) {
  const std::string name = "parts:" + role_name(input.role) + ":" + input.name;
  return run_node(state, name, input.spec.text.empty() ? input.name : input_name(input.spec), [&](const ProgressFn&) {
    Parts parts;
    if (input.boxes)
      parts = Parts{input, *input.boxes, "config boxes", {}};
    else if (!input.spec.procedural.empty())
      parts = Parts{input, castle_part_boxes(input.spec.procedural).value(), "procedural layout", {}};
    else
      parts = parts_from_ply(input, state.config.exchange.part_property);
    node_logger("parts")->info("{} {}: {} part boxes from {}", role_name(input.role), input.name, parts.boxes.size(),
                               parts.from);
    return PartsPtr(std::make_shared<const Parts>(std::move(parts)));
  });
}

ExchangedPtr exchange_stage(RunState& state, const LoadedPtr& exemplar, const PartsPtr& exemplar_parts,
                            const PartsPtr& target_parts, size_t pair) {
  const std::string name = "exchange:" + exemplar_parts->input.name + ":" + target_parts->input.name;
  return run_node(state, name, "", [&](const ProgressFn&) {
    auto out = std::make_shared<Exchanged>(Exchanged{
        exemplar, exemplar_parts, target_parts, pair,
        exchange_style(exemplar->load.points, exemplar_parts->boxes, target_parts->boxes, state.config.exchange)});
    const BoxAnalogy& a = out->exchange.analogy;
    node_logger("exchange")
        ->info("{} -> {}: {} candidate maps, {} used on {} target boxes, energy {:.4g} -> {:.4g}, {} output points",
               exemplar_parts->input.name, target_parts->input.name, a.candidates, a.transforms.size(),
               a.box_label.size(), a.energy_before, a.energy_after, out->exchange.output.size());
    if (!a.converged) state.warn(name, "alpha-expansion stopped at exchange.max_cycles before converging");
    ExchangedPtr done(std::move(out));
    state.keep(done);
    return done;
  });
}

DrawnPtr draw_curves_stage(RunState& state, const TransferredPtr& in) {
  return run_node(state, "draw", "", [&](const ProgressFn&) {
    const Featured& target = *in->aligned->synthesized->analogy->votes().target();
    auto out = std::make_shared<Drawn>(
        Drawn{in, order_into_curves(in->kept.points.positions(), *target.sampled->curves, state.config.curves)});
    Index closed = 0;
    for (const Polyline& c : out->curves) closed += c.closed;
    node_logger("draw")->info("{} output points as {} polylines ({} closed)", in->kept.points.size(),
                              out->curves.size(), closed);
    state.keep(out);
    return DrawnPtr(std::move(out));
  });
}

}  // namespace scanfill
