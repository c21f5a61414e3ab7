#include "engine/outputs.h"

#include "engine/staging.h"

#include <array>
#include <chrono>
#include <cmath>
#include <nlohmann/json.hpp>
#include <sstream>

#include "nodes/core/errors.h"
#include "nodes/correspond/correspondence_view.h"
#include "nodes/curves/curves.h"
#include "nodes/io/write_ply.h"
#include "nodes/io/write_png.h"
#include "nodes/render/render.h"

namespace scanfill {
namespace {

nlohmann::json json_vec(const Eigen::Vector3d& v) {
  return nlohmann::json::array({v.x(), v.y(), v.z()});
}

nlohmann::json rotation_json(const Eigen::Matrix3d& R) {
  nlohmann::json rotation = nlohmann::json::array();
  for (int r = 0; r < 3; ++r) rotation.push_back({R(r, 0), R(r, 1), R(r, 2)});
  return rotation;
}

// `axes`: the target's own (Symmetries::target_axes), in which `axis_rotation` is measured; unset: the world's.
nlohmann::json transform_json(int label, const char* kind, const Similarity& q, Index support, Index labelled,
                              const std::optional<Eigen::Matrix3d>& axes) {
  return {{"label", label},
          {"kind", kind},
          {"rotation", rotation_json(q.rotation)},
          {"rotation_deg", rotation_angle(q.rotation) * 180 / M_PI},
          {"rotation_axis", json_vec(rotation_axis(q.rotation))},
          {"axis_rotation", is_axis_rotation(in_frame(q.rotation, axes), M_PI / 180)},
          {"translation", json_vec(q.translation)},
          {"scale", q.scale},
          {"support", support},
          {"labelled", labelled}};
}

// A node's Ceres solve (nodes/core/solver_summary.h).
nlohmann::json solver_json(const SolverSummary& s) {
  return {{"termination", s.termination},
          {"iterations", s.iterations},
          {"initial_cost", s.initial_cost},
          {"final_cost", s.final_cost}};
}

// The exemplar's repeats about the axes the regions turn about (nodes/synthesize/repeats.h).
nlohmann::json repeats_json(const std::vector<AxialRepeats>& repeats) {
  nlohmann::json out = nlohmann::json::array();
  for (const AxialRepeats& r : repeats)
    out.push_back({{"point", json_vec(r.part.point)},
                   {"direction", json_vec(r.part.direction)},
                   {"part_radius", std::isfinite(r.part.radius) ? nlohmann::json(r.part.radius) : nlohmann::json()},
                   {"revolution", r.continuous},
                   {"cut_height", r.cut},
                   {"order_below_cut", r.order[0]},
                   {"order_above_cut", r.order[1]}});
  return out;
}

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

// output.ply's colour of a point: by origin (scan or exemplar grey, synthesised orange, copied blue), or by label
// (as analogy.ply; the scan's own points grey).
std::array<double, 3> output_colour(Origin origin, int label, int self_label, bool by_label) {
  if (origin == Origin::kExemplar) return {190, 190, 190};
  if (by_label) return label_colour(label, self_label);
  if (origin == Origin::kSynthesized) return {235, 130, 35};
  return {60, 120, 225};
}

// output.ply's points with their RGB as `choice` (resolved) says: the scan's own colours (already on the points), or
// by origin or label.
PointSet coloured_output(const TransferResult& o, ColourChoice choice, int self_label) {
  if (choice == ColourChoice::kScan) return o.points;  // a scan without colours was refused at load
  Matrix3Xu8 rgb(3, o.points.size());
  for (size_t i = 0; i < o.origin.size(); ++i) {
    const auto c = output_colour(o.origin[i], o.label[i], self_label, choice == ColourChoice::kLabel);
    for (int k = 0; k < 3; ++k) rgb(k, Index(i)) = std::uint8_t(c[size_t(k)]);
  }
  PointSet points = o.points;
  points.set_colours(std::move(rgb));
  return points;
}

// What the summary says output.ply's RGB is.
std::string colour_words(ColourChoice choice, bool completion) {
  switch (choice) {
    case ColourChoice::kLabel:
      return "label";
    case ColourChoice::kScan:
      return std::string("the ") + (completion ? "scan" : "exemplar") + "'s own colours (copied points grey)";
    default:
      return "origin (" + std::string(completion ? "scan" : "exemplar") + " grey, synthesised orange, copied blue)";
  }
}

// samples_ROLE.ply per input; the report's inputs.
nlohmann::json write_samples(const RunState& state, RunOutcome& outcome) {
  const RunConfig& config = state.config;
  nlohmann::json inputs = nlohmann::json::object();
  for (size_t slot = 0; slot < config.inputs.size(); ++slot) {
    const Featured& f = *state.inputs()[slot];
    const Loaded& loaded = *f.sampled->loaded;
    const LoadResult& load = loaded.load;
    const std::string role = role_name(config.inputs[slot].role);
    const std::filesystem::path out = state.write_dir / ("samples_" + role + ".ply");
    write_ply(out, f.features.points);
    outcome.outputs.push_back(out);
    inputs[role] = {{"path", input_name(config.inputs[slot].spec)},
                    {"format", load.format},
                    {"points", loaded.points()},
                    {"faces", load.points.faces().cols()},
                    {"dropped_nonfinite", load.dropped_nonfinite},
                    {"bbox", {json_vec(loaded.box.min), json_vec(loaded.box.max)}},
                    {"samples", f.features.points.size()},
                    {"spacing", f.sampled->sample.spacing},
                    {"unreliable_directions", f.features.unreliable_directions}};
    for (const InputSpec& fragment : config.inputs[slot].fragments)
      inputs[role]["fragments"].push_back(input_name(fragment));
  }
  return inputs;
}

// correspondence.ply: the exemplar <-> source map, matched samples in the same colour (paper Figures 6 and 13c).
void write_correspondence(const RunState& state, const Correspondence& c, RunOutcome& outcome) {
  const CorrespondenceView view = correspondence_view(c.source->features.points, c.map);
  std::vector<double> side(view.side.begin(), view.side.end()), rgb[3];
  for (const Rgb& colour : view.colours)
    for (int k = 0; k < 3; ++k) rgb[k].push_back(colour[size_t(k)]);
  const std::filesystem::path out = state.write_dir / "correspondence.ply";
  write_ply(out, view.points,
            {{"side", PlyProperty::Type::kUint8, side},
             {"red", PlyProperty::Type::kUint8, rgb[0]},
             {"green", PlyProperty::Type::kUint8, rgb[1]},
             {"blue", PlyProperty::Type::kUint8, rgb[2]}});
  outcome.outputs.push_back(out);
}

// output.ply; the report's output, synthesis, correspondence and align.
void write_output(const Transferred& t, nlohmann::json& report, RunOutcome& outcome) {
  const TransferCounts& c = t.counts;
  const ColourChoice colour = t.colour;
  outcome.outputs.push_back(t.written);  // streamed by the transfer node
  report["output"] = {{"points", c.points},
                      {"faces", c.faces},
                      {"exemplar_points", c.by_origin[0]},
                      {"synthesized_points", c.by_origin[1]},
                      {"copied_points", c.by_origin[2]},
                      {"colour", colour == ColourChoice::kScan    ? "scan"
                                 : colour == ColourChoice::kLabel ? "label"
                                                                  : "origin"},
                      {"intensity", t.intensity}};
  const Synthesized& s = *t.aligned->synthesized;
  const Synthesis& syn = s.synthesis;
  const AlignResult& al = t.aligned->alignment;
  report["synthesis"] = {{"samples", syn.points.size()},
                         {"patches", syn.patches.size()},
                         {"gap_copies", syn.gap_copies},
                         {"off_profile_uncopied", syn.off_profile},
                         {"seen_through_uncopied", syn.seen_through},
                         {"filled_patches", syn.filled_patches},
                         {"seam_pairs", al.seam_pairs},
                         {"seam_gap_before", al.gap_before},
                         {"seam_gap_after", al.gap_after},
                         {"refinement_deg", syn.refinement_deg},
                         {"pinned_by_template", syn.pinned_by_template},
                         {"refinement_shift", syn.refinement_shift},
                         {"registration_offset", json_vec(syn.registration_offset)},
                         {"second_phase_deg", syn.second_phase_deg},
                         {"repeats", repeats_json(syn.repeats)},
                         {"repeat_fill", syn.repeat_fill},
                         {"mirror", syn.mirror ? nlohmann::json{{"point", json_vec(syn.mirror->point)},
                                                                {"normal", json_vec(syn.mirror->normal)},
                                                                {"misfit", syn.mirror->misfit},
                                                                {"pairs", syn.mirror->pairs}}
                                               : nlohmann::json(nullptr)},
                         {"mirror_fill", syn.mirror_fill},
                         {"mirror_replaced", syn.mirror_replaced}};
  const CorrespondResult& m = s.correspondence->map;
  report["correspondence"] = {
      {"rigid", {{"rotation", rotation_json(m.rigid.rotation)}, {"translation", json_vec(m.rigid.translation)}}},
      {"rigid_rms", m.rigid_rms},
      {"kept_input_pose", m.kept_input_pose},
      {"turned_in_place", m.turned_in_place},
      {"laid_on_axis", m.laid_on_axis},
      {"polygon_sides", m.polygon.sides},
      {"another_size", m.another_size},
      {"template_scale", json_vec(m.template_scaling.scale)},
      {"template_shift", json_vec(m.template_scaling.shift)},
      {"template_scaled", m.template_scaled},
      {"matched", m.matched},
      {"exemplar_samples", m.exemplar_match.size()},
      {"deformed_rms", m.deformed_rms}};
  if (s.coverage) report["correspondence"]["covered_template_samples"] = Index(s.coverage->cover.samples.size());
  nlohmann::json solves = nlohmann::json::array();
  for (const SolverSummary& solve : m.deformation_solves) solves.push_back(solver_json(solve));
  report["correspondence"]["deformation_solves"] = solves;
  report["align"] = {{"solver", al.solver ? solver_json(*al.solver) : nlohmann::json(nullptr)}};
}

// output_mesh.ply; the report's surface, with the node's time (its cost, for the README).
void write_surface(const RunState& state, const Surfaced& s, nlohmann::json& report, RunOutcome& outcome) {
  const std::filesystem::path out = state.write_dir / "output_mesh.ply";
  write_ply(out, s.surface.mesh);
  outcome.outputs.push_back(out);
  double seconds = 0;
  for (const NodeTiming& t : state.timings())
    if (t.name == "surface") seconds = t.wall_s;
  const SurfaceOptions& o = state.config.surface;
  report["surface"] = {{"method", "poisson"},
                       {"vertices", s.surface.mesh.size()},
                       {"faces", s.surface.mesh.faces().cols()},
                       {"trimmed", s.surface.trimmed_faces},
                       {"poisson_faces", s.surface.poisson_faces},
                       {"poisson_diagnostics", s.surface.diagnostics},
                       {"points_meshed", s.surface.points_meshed},
                       {"spacing", s.surface.spacing},
                       {"depth", o.depth},
                       {"trim_distance", o.trim_distance},
                       {"seconds", seconds}};
}

// analogy.ply, the target samples coloured by transform; the report's transforms.
nlohmann::json write_analogy(const RunState& state, const Labelled& a, RunOutcome& outcome) {
  const LabelResult& L = a.labels;
  const auto& transforms = a.supports->support.transforms;
  std::vector<Index> count(size_t(L.self_label) + 1, 0);
  for (int l : L.labels) ++count[size_t(l)];
  nlohmann::json list = nlohmann::json::array();
  for (int l = 0; l < L.self_label; ++l)
    list.push_back(transform_json(l, "similarity", transforms[size_t(l)].transform,
                                  Index(transforms[size_t(l)].support.size()), count[size_t(l)],
                                  a.votes().symmetries->target_axes));
  list.push_back(transform_json(L.self_label, "self", Similarity{}, count[size_t(L.self_label)],
                                count[size_t(L.self_label)], a.votes().symmetries->target_axes));
  std::vector<double> label(L.labels.begin(), L.labels.end());
  PointSet points = a.votes().target()->features.points;  // the target's own colours, if any, give way to labels'
  Matrix3Xu8 rgb(3, points.size());
  for (size_t i = 0; i < L.labels.size(); ++i) {
    const auto c = label_colour(L.labels[i], L.self_label);
    for (int k = 0; k < 3; ++k) rgb(k, Index(i)) = std::uint8_t(c[size_t(k)]);
  }
  points.set_colours(std::move(rgb));
  const std::filesystem::path out = state.write_dir / "analogy.ply";
  write_ply(out, points, {{"label", PlyProperty::Type::kInt32, label}});
  outcome.outputs.push_back(out);
  return list;
}

Rgb rgb_of(const std::array<double, 3>& c) {
  return {std::uint8_t(c[0]), std::uint8_t(c[1]), std::uint8_t(c[2])};
}

// The inputs' side of the preview: the scan (or exemplar, or source) in grey and the target samples coloured by
// transform as in analogy.ply.
std::vector<PreviewPanel> input_panels(const RunState& state) {
  const RunConfig& config = state.config;
  const Role first = config.mode == RunMode::kCompletion ? Role::kScan
                     : config.mode == RunMode::kTransfer ? Role::kExemplar
                                                         : Role::kSource;
  std::vector<PreviewPanel> panels;
  for (size_t slot = 0; slot < config.inputs.size(); ++slot)
    if (config.inputs[slot].role == first) {
      const Featured& f = *state.inputs()[slot];
      PreviewPanel panel{&f.features.points, {Rgb{190, 190, 190}}, f.sampled->sample.spacing};
      // The scan in its own colours when output.ply shows them.
      const TransferredPtr& t = state.output();
      if (t && t->colour == ColourChoice::kScan && f.features.points.has_colours()) {
        const Matrix3Xu8& c = f.features.points.colours();
        panel.colours.clear();
        for (Index i = 0; i < c.cols(); ++i) panel.colours.push_back({c(0, i), c(1, i), c(2, i)});
      }
      panels.push_back(std::move(panel));
    }
  if (const LabelledPtr& a = state.analogy()) {
    const Featured& target = *a->votes().target();
    PreviewPanel labelled{&target.features.points, {}, target.sampled->sample.spacing};
    for (const int l : a->labels.labels) labelled.colours.push_back(rgb_of(label_colour(l, a->labels.self_label)));
    panels.push_back(std::move(labelled));
  }
  return panels;
}

// preview.png: the inputs, the analogy and the output side by side, seen from the scan's side (the virtual scanner's
// eye, or the scan's own viewpoint) and from the opposite one.
void write_preview(const RunState& state, RunOutcome& outcome) {
  const RunConfig& config = state.config;
  std::vector<PreviewPanel> panels = input_panels(state);
  if (panels.empty()) return;
  if (const TransferredPtr& t = state.output()) {
    const TransferResult& o = t->kept;  // output.ply's points, or an even subsample of them
    // The output's spacing from the samples': as many points on the same surface.
    const double spacing = panels.back().spacing * std::sqrt(double(panels.back().points->size()) /
                                                             double(std::max<Index>(o.points.size(), 1)));
    PreviewPanel out{&o.points, {}, spacing};
    const PointSet coloured =  // as output.ply
        coloured_output(o, t->colour, t->aligned->synthesized->analogy->labels.self_label);
    const Matrix3Xu8& c = coloured.colours();
    for (Index i = 0; i < c.cols(); ++i) out.colours.push_back({c(0, i), c(1, i), c(2, i)});
    panels.push_back(std::move(out));
  }
  std::optional<Eigen::Vector3d> eye = config.virtual_scan.eye;
  if (!eye && config.mode == RunMode::kCompletion) eye = state.inputs()[0]->sampled->loaded->load.points.viewpoint();
  const std::filesystem::path path = state.write_dir / "preview.png";
  write_png(path, preview_image(panels, panels.size() - 1, eye));
  outcome.outputs.push_back(path);
}

std::string css_colour(const std::array<double, 3>& c) {
  char buf[8];
  std::snprintf(buf, sizeof buf, "#%02x%02x%02x", int(c[0]), int(c[1]), int(c[2]));
  return buf;
}

const Featured& input_of(const RunState& state, Role role) {
  for (size_t slot = 0; slot < state.config.inputs.size(); ++slot)
    if (state.config.inputs[slot].role == role) return *state.inputs()[slot];
  throw InvariantError("no input '" + role_name(role) + "'");
}

// Mode curves: output.svg and output.txt (the output's polylines), analogy.svg (the target's samples coloured by
// transform over its curves) and preview.png (source, target by transform, exemplar, output by transform, in the
// plane); the report's drawing.
void write_curves(const RunState& state, const Drawn& d, nlohmann::json& report, RunOutcome& outcome) {
  const Labelled& a = *d.transferred->aligned->synthesized->analogy;
  const double spacing = a.votes().spacing(), stroke = 0.25 * spacing;
  std::vector<SvgStroke> strokes;
  for (const Polyline& c : d.curves) strokes.push_back({c, "#000000", stroke});
  const auto& dir = state.write_dir;
  write_svg(dir / "output.svg", strokes, {}, 0);
  write_polylines(dir / "output.txt", d.curves);
  const Featured& target = *a.votes().target();
  std::vector<SvgStroke> grey;
  for (const Polyline& c : *target.sampled->loaded->curves) grey.push_back({c, "#d0d0d0", stroke});
  std::vector<SvgDot> dots;
  for (size_t i = 0; i < a.labels.labels.size(); ++i)
    dots.push_back({target.features.points.positions().col(Index(i)).head<2>(),
                    css_colour(label_colour(a.labels.labels[i], a.labels.self_label))});
  write_svg(dir / "analogy.svg", grey, dots, 0.4 * spacing);
  const Featured &source = input_of(state, Role::kSource), &exemplar = input_of(state, Role::kExemplar);
  PreviewPanel labelled{&target.features.points, {}, spacing}, output{&d.transferred->kept.points, {}, spacing};
  for (const int l : a.labels.labels) labelled.colours.push_back(rgb_of(label_colour(l, a.labels.self_label)));
  for (const int l : d.transferred->kept.label) output.colours.push_back(rgb_of(label_colour(l, a.labels.self_label)));
  const std::vector<PreviewPanel> panels{{&source.features.points, {Rgb{40, 40, 40}}, spacing},
                                         std::move(labelled),
                                         {&exemplar.features.points, {Rgb{40, 40, 40}}, spacing},
                                         std::move(output)};
  write_png(dir / "preview.png", plane_image(panels));
  for (const char* name : {"output.svg", "output.txt", "analogy.svg", "preview.png"})
    outcome.outputs.push_back(dir / name);
  Index points = 0, closed = 0;
  for (const Polyline& c : d.curves) points += c.points.cols(), closed += c.closed;
  report["drawing"] = {{"polylines", d.curves.size()}, {"closed", closed}, {"points", points}};
}

// The symmetries found and the candidates they gave (DESIGN section 9).
nlohmann::json symmetry_json(const Labelled& a) {
  const auto axes = [](const SymmetryResult& sym) {
    nlohmann::json list = nlohmann::json::array();
    for (const auto& ax : sym.axes)
      list.push_back({{"order", ax.order}, {"direction", json_vec(ax.direction)}, {"centre", json_vec(ax.centre)}});
    return list;
  };
  const auto parts = [](const SymmetryResult& sym) {
    nlohmann::json list = nlohmann::json::array();
    for (const auto& p : sym.parts)
      list.push_back({{"samples", p.samples.size()},
                      {"direction", json_vec(p.axis.direction)},
                      {"centre", json_vec(p.axis.centre)}});
    return list;
  };
  const Symmetries& s = *a.votes().symmetries;
  return {{"source_axes", axes(s.source_symmetry)},
          {"target_axes", axes(s.target_symmetry)},
          {"target_rotations", s.target_symmetry.rotations.size()},
          {"target_parts", parts(s.target_symmetry)},
          {"votes_quotiented", bool(s.source_symmetry.continuous)},
          {"voted_transforms", a.supports->voted},
          {"composed_candidates", a.supports->composed},
          {"refuted_by_scan_profile", a.supports->refuted},
          {"up", json_vec(a.supports->up)},
          {"up_from", a.supports->up_from}};
}

// Mode exchange: a part box as the report writes it.
nlohmann::json box_json(const PartBox& b) {
  return nlohmann::json::array({json_vec(b.min), json_vec(b.max)});
}

nlohmann::json parts_json(const Parts& p) {
  nlohmann::json boxes = nlohmann::json::array();
  for (const PartBox& b : p.boxes) boxes.push_back(box_json(b));
  nlohmann::json out = {{"name", p.input.name},
                        {"path", p.input.spec.text.empty() ? "" : input_name(p.input.spec)},
                        {"parts_from", p.from},
                        {"boxes", boxes}};
  if (!p.part_labels.empty()) out["part_labels"] = p.part_labels;
  return out;
}

nlohmann::json box_transform_json(int label, const BoxTransform& t) {
  return {{"label", label},
          {"source_box", t.source_box},
          {"rotation", rotation_json(t.rotation_matrix)},
          {"rotation_deg", t.angle() * 180 / M_PI},
          {"scales", json_vec(t.scales)},
          {"translation", json_vec(t.translation)}};
}

// Points coloured by label, with `label` (and `origin` 1 = synthesised, for output points) as PLY properties.
void write_labelled_ply(const std::filesystem::path& path, const PointSet& points, const std::vector<int>& labels,
                        bool with_origin) {
  Matrix3Xu8 rgb(3, points.size());
  for (Index i = 0; i < points.size(); ++i) {
    const auto c = label_colour(labels[size_t(i)], -1);
    for (int k = 0; k < 3; ++k) rgb(k, i) = std::uint8_t(c[size_t(k)]);
  }
  PointSet coloured = points;
  coloured.set_colours(std::move(rgb));
  std::vector<PlyProperty> extra;
  if (with_origin) extra.push_back({"origin", PlyProperty::Type::kUint8, std::vector<double>(labels.size(), 1.0)});
  extra.push_back({"label", PlyProperty::Type::kInt32, std::vector<double>(labels.begin(), labels.end())});
  write_ply(path, coloured, extra);
}

// One pair: output_E__T.ply, analogy_E__T.ply and its report entry.
nlohmann::json write_exchange_pair(const RunState& state, const Exchanged& x, RunOutcome& outcome) {
  const std::string stem = x.exemplar_parts->input.name + "__" + x.target_parts->input.name;
  const BoxAnalogy& a = x.exchange.analogy;
  const std::filesystem::path output = state.write_dir / ("output_" + stem + ".ply"),
                              analogy = state.write_dir / ("analogy_" + stem + ".ply");
  write_labelled_ply(output, x.exchange.output, x.exchange.output_label, true);
  write_labelled_ply(analogy, a.samples.points, a.sample_label, false);
  outcome.outputs.push_back(output);
  outcome.outputs.push_back(analogy);
  nlohmann::json transforms = nlohmann::json::array(), boxes = nlohmann::json::array();
  for (size_t l = 0; l < a.transforms.size(); ++l) transforms.push_back(box_transform_json(int(l), a.transforms[l]));
  for (size_t j = 0; j < a.box_label.size(); ++j)
    boxes.push_back({{"target_box", j},
                     {"box", box_json(x.target_parts->boxes[j])},
                     {"label", a.box_label[j]},
                     {"source_box", a.box_source[j]},
                     {"rotation_deg", a.transforms[size_t(a.box_label[j])].angle() * 180 / M_PI},
                     {"scales", json_vec(a.transforms[size_t(a.box_label[j])].scales)}});
  return {{"exemplar", x.exemplar_parts->input.name},
          {"target", x.target_parts->input.name},
          {"output", output.filename().string()},
          {"analogy", analogy.filename().string()},
          {"exemplar_points", x.exemplar->load.points.size()},
          {"exemplar_faces", x.exemplar->load.points.faces().cols()},
          {"output_points", x.exchange.output.size()},
          {"output_faces", x.exchange.output.faces().cols()},
          {"target_samples", a.samples.points.size()},
          {"candidates", a.candidates},
          {"transforms", transforms},
          {"target_boxes", boxes},
          {"energy", {{"before", a.energy_before}, {"after", a.energy_after}}}};
}

// What every report ends with (each node's wall time, peak memory, the warnings); then report.json is written and,
// every file being written, all of them are flushed and moved into the output folder together.
void write_report_and_commit(RunState& state, Staging& staging, nlohmann::json& report, RunOutcome& outcome) {
  nlohmann::json node_list = nlohmann::json::array();
  for (const auto& t : state.timings()) node_list.push_back({{"name", t.name}, {"wall_s", t.wall_s}});
  report["nodes"] = node_list;
  report["peak_rss_mb"] = peak_rss_mb();
  report["warnings"] = state.warnings();
  const std::filesystem::path report_path = state.write_dir / "report.json";
  write_file_atomic(report_path, report.dump(2) + "\n");
  outcome.outputs.push_back(report_path);
  std::vector<std::string> names;
  for (const auto& out : outcome.outputs) names.push_back(out.filename().string());
  outcome.outputs = staging.commit(names);
}

// Mode exchange: every pair's files, then report.json: inputs with their boxes, pairs with their box-wise analogy.
RunOutcome write_exchange_outputs(RunState& state, Staging& staging) {
  RunOutcome outcome;
  const auto t0 = std::chrono::steady_clock::now();
  nlohmann::json exemplars = nlohmann::json::array(), targets = nlohmann::json::array(),
                 pairs = nlohmann::json::array();
  const std::vector<ExchangedPtr> exchanges = state.exchanges();
  const size_t n_targets = inputs_for(state.config, Role::kTarget).size();
  for (const ExchangedPtr& x : exchanges) {
    pairs.push_back(write_exchange_pair(state, *x, outcome));
    if (x->pair % n_targets == 0) exemplars.push_back(parts_json(*x->exemplar_parts));
    if (x->pair < n_targets) targets.push_back(parts_json(*x->target_parts));
  }
  state.record("write", std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  nlohmann::json report = {
      {"mode", "exchange"}, {"inputs", {{"exemplars", exemplars}, {"targets", targets}}}, {"pairs", pairs}};
  write_report_and_commit(state, staging, report, outcome);
  std::ostringstream s;
  s << "scanfill: style exchange of " << exemplars.size() << " exemplars and " << targets.size()
    << " targets: " << pairs.size() << " outputs in " << state.config.output_dir.string() << "\n"
    << "  output_EXEMPLAR__TARGET.ply: the exemplar carried onto the target's boxes, triangles and all ('label' = the "
       "transform, see report.json)\n"
    << "  analogy_EXEMPLAR__TARGET.ply: the target's box samples coloured by transform\n";
  for (const auto& p : pairs) {
    s << "  " << p["exemplar"].get<std::string>() << " -> " << p["target"].get<std::string>() << ":";
    for (const auto& b : p["target_boxes"])
      s << " " << b["target_box"].get<int>() << "<-" << b["source_box"].get<int>();
    s << " (target box <- exemplar box)\n";
  }
  outcome.summary = s.str();
  outcome.nodes = state.timings();
  outcome.warnings = state.warnings();
  return outcome;
}

// The summary's line for output_mesh.ply, empty without one.
std::string surface_line(const nlohmann::json& report) {
  if (!report.contains("surface")) return "";
  const auto& s = report["surface"];
  return "  output_mesh.ply: a Poisson surface of the completed shape, " + std::to_string(s["vertices"].get<Index>()) +
         " vertices, " + std::to_string(s["faces"].get<Index>()) + " triangles\n";
}

std::string summary(const RunConfig& config, const nlohmann::json& report, bool has_output) {
  std::ostringstream s;
  const bool completion = config.mode == RunMode::kCompletion;
  if (has_output) {
    const auto& o = report["output"];
    const auto& transforms = report["transforms"];
    const Index used = std::count_if(transforms.begin(), transforms.end(), [](const nlohmann::json& t) {
      return t["kind"] == "similarity" && t["labelled"].get<Index>() > 0;
    });
    if (config.mode == RunMode::kCurves)
      s << "scanfill: stylised drawing: " << report["drawing"]["polylines"].get<Index>() << " polylines of "
        << report["drawing"]["points"].get<Index>() << " points\n"
        << "  output.svg, output.txt: the stylised curves (SVG paths; 'x y' lines, a blank line between curves)\n"
        << "  analogy.svg: the target coloured by transform (grey = self-reference)\n"
        << "  preview.png: source, target by transform, exemplar and output, side by side\n";
    s << "scanfill: " << (completion ? "completed scan" : "stylised model") << ": " << o["points"].get<Index>()
      << " points";
    if (o["faces"].get<Index>() > 0) s << ", " << o["faces"].get<Index>() << " triangles";
    s << " (" << o["exemplar_points"].get<Index>() << " from the " << (completion ? "scan" : "exemplar") << ", "
      << o["synthesized_points"].get<Index>() << " synthesised by " << used << " transforms, "
      << o["copied_points"].get<Index>() << " copied from the " << (completion ? "template" : "target") << ")\n"
      << "  output.ply: vertex 'origin' 0 = " << (completion ? "scan" : "exemplar")
      << ", 1 = synthesised, 2 = copied; 'label' = the transform (see report.json); RGB: "
      << (o["colour"] == "scan"    ? colour_words(ColourChoice::kScan, completion)
          : o["colour"] == "label" ? colour_words(ColourChoice::kLabel, completion)
                                   : colour_words(ColourChoice::kOrigin, completion))
      << (o["intensity"].get<bool>() ? "; 'intensity' carried from the " + std::string(completion ? "scan" : "exemplar")
                                     : std::string())
      << "\n"
      << surface_line(report) << "  analogy.ply: the " << (completion ? "template" : "target")
      << " samples coloured by transform (grey = self-reference)\n"
      << "  preview.png: the inputs, the analogy and the output, from the scan's side (top) and the other (bottom)\n"
      << "  correspondence.ply: the " << (completion ? "template" : "source") << " samples and, beside them, the "
      << (completion ? "scan" : "exemplar") << "'s, matched samples in the same colour\n"
      << "  score it: scanfill eval --output " << (config.output_dir / "output.ply").string() << " --reference "
      << (completion && config.virtual_scan.eye ? input_name(input_for(config, Role::kScan).spec) : "COMPLETE_MODEL")
      << "\n";
  } else {
    s << "scanfill: analogy of " << config.inputs.size()
      << " inputs: analogy.ply holds the target samples coloured by transform (grey = self-reference)\n"
      << "  preview.png: the source and the labelled target, from the front (top) and the back (bottom)\n";
  }
  return s.str();
}

}  // namespace

ColourChoice resolved_colour(ColourChoice configured, bool carried_colours) {
  if (configured != ColourChoice::kAuto) return configured;
  return carried_colours ? ColourChoice::kScan : ColourChoice::kOrigin;
}

namespace {

// output.ply's layout: what write_ply gave a coloured output with origin and label.
PlyLayout output_layout(const TransferCounts& counts, bool intensity) {
  PlyLayout layout;
  layout.vertices = counts.points;
  layout.faces = counts.faces;
  const bool any = counts.points > 0;
  layout.normals = any;
  layout.colours = any;
  layout.intensity = any && intensity;
  layout.extra = {{"origin", PlyProperty::Type::kUint8}, {"label", PlyProperty::Type::kInt32}};
  return layout;
}

}  // namespace

OutputPlyWriter::OutputPlyWriter(const std::filesystem::path& path, const TransferCounts& counts, bool intensity,
                                 ColourChoice colour, int self_label)
    : ply_(path, output_layout(counts, intensity)), colour_(colour), self_label_(self_label) {}

void OutputPlyWriter::append(const TransferResult& run) {
  std::vector<double> origin(run.origin.size()), label(run.label.begin(), run.label.end());
  for (size_t i = 0; i < run.origin.size(); ++i) origin[i] = double(int(run.origin[i]));
  ply_.append(coloured_output(run, colour_, self_label_),
              {{"origin", PlyProperty::Type::kUint8, origin}, {"label", PlyProperty::Type::kInt32, label}});
}

void write_output_ply(const std::filesystem::path& path, const TransferResult& o, ColourChoice colour, int self_label) {
  TransferCounts counts;
  counts.points = o.points.size();
  counts.faces = o.points.faces().cols();
  OutputPlyWriter writer(path, counts, o.points.has_intensity(), colour, self_label);
  writer.append(o);
  writer.append_faces(o.points.faces());
  writer.commit();
}

RunOutcome write_outputs(RunState& state, Staging& staging) {
  const RunConfig& config = state.config;
  if (config.mode == RunMode::kExchange) return write_exchange_outputs(state, staging);
  RunOutcome outcome;
  const auto t0 = std::chrono::steady_clock::now();
  if (state.output()) state.output()->writing->wait();  // output.ply's last run, written beside the graph's last nodes
  nlohmann::json report = {{"mode", mode_name(config.mode)}, {"inputs", write_samples(state, outcome)}};
  if (state.output()) {
    write_output(*state.output(), report, outcome);
    write_correspondence(state, *state.output()->aligned->synthesized->correspondence, outcome);
  }
  if (state.surface()) write_surface(state, *state.surface(), report, outcome);
  nlohmann::json transforms = nlohmann::json::array();
  nlohmann::json energy = nullptr;
  if (state.analogy()) {
    transforms = write_analogy(state, *state.analogy(), outcome);
    energy = {{"before", state.analogy()->labels.energy_before}, {"after", state.analogy()->labels.energy_after}};
    report["symmetry"] = symmetry_json(*state.analogy());
  }
  if (state.drawing())
    write_curves(state, *state.drawing(), report, outcome);
  else
    write_preview(state, outcome);
  state.record("write", std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());

  report["transforms"] = transforms;
  report["energy"] = energy;
  write_report_and_commit(state, staging, report, outcome);
  outcome.summary = summary(config, report, bool(state.output()));
  outcome.nodes = state.timings();
  outcome.warnings = state.warnings();
  return outcome;
}

}  // namespace scanfill
