// The scanfill command line: the main run (--config), --print-defaults, the tools info, sample, eval and scan, and
// plan, apply and split, the run in tiles.
// Exit codes: 0 success, 1 a run or input error, 2 a usage or config error. Every error is one line on stderr
// (a config with several problems prints one line per problem).
#include <tbb/global_control.h>
#include <tbb/info.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "engine/config.h"
#include "engine/console.h"
#include "engine/fields.h"
#include "engine/pipeline.h"
#include "engine/staging.h"
#include "engine/tiles.h"
#include "nodes/core/errors.h"
#include "nodes/eval/evaluate.h"
#include "nodes/input/input.h"
#include "nodes/input/scan_alignment.h"
#include "nodes/io/write_ply.h"
#include "nodes/scan/crop.h"
#include "nodes/scan/virtual_scan.h"

namespace {

using namespace scanfill;

int fail(const std::string& what, int code = 1) {
  std::lock_guard<std::mutex> lock(Progress::instance().mutex());
  Progress::instance().clear_locked();
  std::cerr << "scanfill: error: " << what << std::endl;
  return code;
}

// A numeric option's check: a finite number in [lo, hi] (lo excluded when lo_open). Replaces CLI11's PositiveNumber
// and Range, which accept "nan" and print their bounds with all 309 digits of DBL_MAX.
CLI::Validator number_in(double lo, double hi, bool lo_open = false) {
  std::ostringstream range;
  range << (lo_open ? "a number > " : "a number >= ") << lo;
  if (hi < std::numeric_limits<double>::max()) range << " and <= " << hi;
  return CLI::Validator(
      [lo, hi, lo_open, what = range.str()](std::string& text) -> std::string {
        char* end = nullptr;
        const double v = std::strtod(text.c_str(), &end);
        const bool parsed = !text.empty() && end == text.c_str() + text.size();
        if (parsed && std::isfinite(v) && (lo_open ? v > lo : v >= lo) && v <= hi) return {};
        return "expected " + what + ", got '" + text + "'";
      },
      "", "");
}

std::unique_ptr<tbb::global_control> limit_threads(int threads) {
  const int n = threads > 0 ? threads : tbb::info::default_concurrency();
  return std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, size_t(n));
}

std::string join_list(const std::vector<std::string>& items) {
  std::string out;
  for (const auto& item : items) out += (out.empty() ? "" : ", ") + item;
  return out;
}

// `info` from the header alone (PLY, PCD): the counts and properties it declares, no bounding box.
int print_header_info(const std::string& file, const FileHeader& h, bool json) {
  const auto file_bytes = Index(std::filesystem::file_size(file));
  if (json) {
    nlohmann::json j = {{"read", "header"},           {"format", h.format},
                        {"encoding", h.encoding},     {"points", h.points},
                        {"faces", h.faces},           {"elements", h.elements},
                        {"properties", h.properties}, {"header_bytes", h.header_bytes},
                        {"file_bytes", file_bytes}};
    if (h.viewpoint) j["viewpoint"] = {h.viewpoint->x(), h.viewpoint->y(), h.viewpoint->z()};
    std::cout << j.dump(2) << std::endl;
    return 0;
  }
  std::cout << file << "\n"
            << "  read        header only (" << h.header_bytes << " of " << file_bytes
            << " bytes; --full reads the points for the bounding box)\n"
            << "  format      " << h.format << " (" << h.encoding << ")\n"
            << "  points      " << h.points << " declared\n"
            << "  faces       " << h.faces << (h.format == "ply" ? " face records" : "") << "\n"
            << "  " << (h.format == "ply" ? "elements    " : "size        ") << join_list(h.elements) << "\n"
            << "  properties  " << join_list(h.properties) << std::endl;
  return 0;
}

// `info`: the header alone for PLY and PCD unless `full`; every point read otherwise (and for formats without one).
int run_info(const std::string& file, bool json, bool full) {
  const bool aligned = is_scan_alignment(file);  // a .conf: its range scans, posed
  if (!full && !aligned)
    if (const std::optional<FileHeader> header = read_header(file)) return print_header_info(file, *header, json);
  const LoadOptions unsorted{.morton_sort = false};
  const LoadResult r = aligned ? load_input(parse_input(file), unsorted) : read_point_set(file, unsorted);
  const PointSet& p = r.points;
  const BoundingBox box = bounding_box(p.positions());
  std::vector<std::string> attributes = p.attribute_names();
  if (json) {
    nlohmann::json j = {{"read", "full"},
                        {"format", r.format},
                        {"encoding", r.encoding},
                        {"points", p.size()},
                        {"faces", p.faces().cols()},
                        {"file_points", r.file_points},
                        {"dropped_nonfinite", r.dropped_nonfinite},
                        {"bbox", {{box.min.x(), box.min.y(), box.min.z()}, {box.max.x(), box.max.y(), box.max.z()}}},
                        {"attributes", attributes},
                        {"warnings", r.warnings}};
    std::cout << j.dump(2) << std::endl;
    return 0;
  }
  for (const auto& w : r.warnings) spdlog::warn("{}", w);
  std::cout << file << "\n"
            << "  read        all points" << (full ? "" : " (the format has no header)") << "\n"
            << "  format      " << r.format << " (" << r.encoding << ")\n"
            << "  points      " << p.size();
  if (r.dropped_nonfinite)
    std::cout << " (" << r.dropped_nonfinite << " non-finite of " << r.file_points << " dropped)";
  std::cout << "\n  faces       " << p.faces().cols() << "\n"
            << "  bbox min    " << box.min.transpose() << "\n"
            << "  bbox max    " << box.max.transpose() << "\n"
            << "  diagonal    " << box.diagonal() << "\n"
            << "  attributes  " << join_list(attributes) << std::endl;
  return 0;
}

// `input`: any form a config takes (a file, procedural:NAME, revolution:...).
int run_sample(const std::string& input, const std::string& output, double spacing, Index count, std::uint64_t seed,
               int k) {
  const InputSpec spec = parse_input(input);
  if (spec.procedural.empty() && !is_supported_extension(spec.path) && !is_scan_alignment(spec.path))
    return fail(input + ": unknown format (expected .ply, .pcd, .obj, .off, .stl, .xyz or .conf)", 2);
  if (std::filesystem::path(output).extension() != ".ply") return fail(output + ": the output must be a .ply file", 2);
  SampleOptions so;
  so.spacing = spacing;
  if (count > 0) so.count = count;
  so.seed = seed;
  FeaturesOptions fo;
  fo.k = k;
  const LoadResult loaded = load_input(spec);
  for (const auto& w : loaded.warnings) spdlog::warn("{}", w);
  Progress::instance().start("sample");
  const SampleResult s = sample(loaded.points, so, [](double f) { Progress::instance().update("sample", f); });
  Progress::instance().finish("sample");
  for (const auto& w : s.warnings) spdlog::warn("{}", w);
  Progress::instance().start("features");
  const FeaturesResult f =
      estimate_features(s.samples, fo, [](double x) { Progress::instance().update("features", x); });
  Progress::instance().finish("features");
  for (const auto& w : f.warnings) spdlog::warn("{}", w);
  write_ply(output, f.points);
  spdlog::info("{} samples (spacing {:.4g}) from {} with normals, k1 k2, d1 -> {}", f.points.size(), s.spacing, input,
               output);
  return 0;
}

// Any input form a config takes (a file, procedural:NAME, revolution:...).
PointSet load_shape(const std::string& text) {
  LoadResult r = load_input(parse_input(text));
  for (const auto& w : r.warnings) spdlog::warn("{}", w);
  return r.points;
}

int run_eval(const std::string& output, const std::string& reference, double threshold, const std::string& scan,
             const std::string& template_shape, Index samples, bool baselines) {
  if (baselines && scan.empty()) return fail("eval: --baselines needs --scan and --template", 2);
  if (scan.empty() != template_shape.empty()) return fail("eval: --scan and --template go together", 2);
  EvalOptions o;
  o.threshold = threshold;
  o.surface_samples = samples;
  const PointSet out = load_shape(output), ref = load_shape(reference);
  PointSet s, t;
  if (!scan.empty()) {
    s = load_shape(scan);
    t = load_shape(template_shape);
  }
  const EvalResult r = evaluate(out, ref, o, scan.empty() ? nullptr : &s, scan.empty() ? nullptr : &t);
  nlohmann::json j = {{"chamfer_l1", r.chamfer_l1},
                      {"chamfer_l2", r.chamfer_l2},
                      {"fscore", r.fscore},
                      {"precision", r.precision},
                      {"recall", r.recall},
                      {"hausdorff", r.hausdorff},
                      {"normal_consistency", r.normal_consistency},
                      {"threshold", threshold},
                      {"tau", r.tau},
                      {"chamfer_convention",
                       "chamfer_l1 = (mean d(o,R) + mean d(r,O)) / 2; chamfer_l2 the same with squared distances"}};
  if (r.unseen_detail_recall) {
    j["unseen_detail_recall"] = *r.unseen_detail_recall;
    j["unseen_detail_points"] = r.unseen_detail_points;
  }
  if (baselines) {
    // The scan alone, and the template filling what the scan lacks (gap: twice the F-score distance).
    const PointSet blend = template_blend(s, t, 2 * r.tau, o);
    for (const auto& [name, shape] :
         {std::pair<const char*, const PointSet*>{"scan_only", &s}, {"template_blend", &blend}}) {
      const EvalResult b = evaluate(*shape, ref, o, &s, &t);
      j["baselines"][name] = {{"fscore", b.fscore},
                              {"chamfer_l1", b.chamfer_l1},
                              {"precision", b.precision},
                              {"recall", b.recall},
                              {"unseen_detail_recall", b.unseen_detail_recall.value_or(0.0)}};
    }
  }
  std::cout << j.dump(2) << std::endl;
  return 0;
}

// "X,Y,Z" -> vector; false if malformed.
bool parse_vec3(const std::string& s, Eigen::Vector3d& v) {
  char extra;
  return std::sscanf(s.c_str(), "%lf,%lf,%lf%c", &v.x(), &v.y(), &v.z(), &extra) == 3 && v.allFinite();
}

int run_scan(const std::string& input, const std::string& output, const std::string& eye, const std::string& target,
             const std::string& resolution, double fov, double noise, std::uint64_t seed) {
  ScanOptions o;
  if (!parse_vec3(eye, o.eye)) return fail("scan: --eye expects X,Y,Z, got '" + eye + "'", 2);
  if (!target.empty() && !parse_vec3(target, o.target))
    return fail("scan: --target expects X,Y,Z, got '" + target + "'", 2);
  if (!resolution.empty()) {
    char extra;
    if (std::sscanf(resolution.c_str(), "%d,%d%c", &o.width, &o.height, &extra) != 2 || o.width < 1 || o.height < 1 ||
        o.width > 16384 || o.height > 16384)
      return fail("scan: --resolution expects W,H with 1 <= W, H <= 16384, got '" + resolution + "'", 2);
  }
  if ((o.eye - o.target).norm() == 0) return fail("scan: --eye and --target must differ", 2);
  if (std::filesystem::path(output).extension() != ".ply") return fail(output + ": the output must be a .ply file", 2);
  o.fov_deg = fov;
  o.noise = noise;
  o.seed = seed;
  const PointSet mesh = load_shape(input);
  const ScanResult r = virtual_scan(mesh, o);
  write_ply(output, r.points);
  spdlog::info("{} points seen from ({}) of {} -> {}", r.pixels_hit, eye, input, output);
  return 0;
}

// Flags every command takes.
struct CommonFlags {
  int threads = 0;
  bool verbose = false, quiet = false;
};

void add_common_flags(CLI::App* cmd, CommonFlags& c) {
  cmd->add_option("--threads", c.threads, "worker threads (default: all cores)")->check(number_in(1, 1 << 16));
  cmd->add_flag("-v,--verbose", c.verbose, "debug logging");
  cmd->add_flag("-q,--quiet", c.quiet, "warnings and errors only");
}

struct InfoArgs {
  std::string file;
  bool json = false;
  bool full = false;
};

CLI::App* add_info_command(CLI::App& app, InfoArgs& a, CommonFlags& common) {
  CLI::App* cmd = app.add_subcommand(
      "info",
      "print format, counts and properties of a file from its header (PLY, PCD); with --full, or for formats "
      "without a header, read every point for the bounding box and attributes");
  cmd->add_option("file", a.file, "point cloud or mesh (.ply .pcd .obj .off .stl .xyz)")->required();
  cmd->add_flag("--json", a.json, "print JSON ('read': 'header' or 'full')");
  cmd->add_flag("--full", a.full, "read every point: bounding box, attributes, non-finite points dropped");
  add_common_flags(cmd, common);
  return cmd;
}

struct SampleArgs {
  std::string input, output;
  double spacing = 0;
  Index count = 0;
  std::uint64_t seed = 1;
  int k = FeaturesOptions{}.k;
};

CLI::App* add_sample_command(CLI::App& app, SampleArgs& a, CommonFlags& common) {
  constexpr double kMax = std::numeric_limits<double>::max();
  CLI::App* cmd = app.add_subcommand("sample", "Poisson-disk sampling plus features of one file, written as PLY");
  cmd->add_option("--input", a.input, "point cloud or mesh (file, procedural:NAME or revolution:FILE)")->required();
  cmd->add_option("--output", a.output, "output .ply (x y z nx ny nz k1 k2 d1x d1y d1z)")->required();
  auto* spacing =
      cmd->add_option("--spacing", a.spacing, "mean sample spacing, model units")->check(number_in(0, kMax, true));
  auto* count = cmd->add_option("--count", a.count, "number of samples (default 20000)")->check(number_in(1, kMax));
  spacing->excludes(count);
  cmd->add_option("--seed", a.seed, "random seed (meshes)");
  cmd->add_option("--k", a.k, "neighbours for normals and curvature")->check(number_in(6, 128));
  add_common_flags(cmd, common);
  return cmd;
}

struct EvalArgs {
  std::string output, reference, scan, template_shape;
  double threshold = 0.01;
  Index samples = EvalOptions{}.surface_samples;
  bool baselines = false;
};

CLI::App* add_eval_command(CLI::App& app, EvalArgs& a, CommonFlags& common) {
  CLI::App* cmd = app.add_subcommand("eval", "accuracy of an output against a complete reference, as JSON");
  cmd->add_option("--output", a.output, "the completed or stylised model (file or procedural:NAME)")->required();
  cmd->add_option("--reference", a.reference, "the complete model to compare with")->required();
  cmd->add_option("--threshold", a.threshold, "F-score distance as a fraction of the reference's bounding-box diagonal")
      ->check(number_in(1e-9, 1.0));
  cmd->add_option("--scan", a.scan, "the partial scan (with --template: unseen-detail recall)");
  cmd->add_option("--template", a.template_shape, "the structural template (with --scan)");
  cmd->add_flag("--baselines", a.baselines,
                "with --scan and --template: also score the scan alone and the template-blending completion");
  cmd->add_option("--samples", a.samples, "random points drawn on each mesh")
      ->check(number_in(1, double(Index(1) << 30)));
  add_common_flags(cmd, common);
  return cmd;
}

struct ScanArgs {
  std::string input, output, eye, target, resolution;
  double fov = ScanOptions{}.fov_deg, noise = 0;
  std::uint64_t seed = 1;
};

CLI::App* add_scan_command(CLI::App& app, ScanArgs& a, CommonFlags& common) {
  CLI::App* cmd = app.add_subcommand("scan", "a single-view virtual range scan of a mesh, written as PLY");
  cmd->add_option("--input", a.input, "the mesh (file, procedural:NAME or revolution:FILE)")->required();
  cmd->add_option("--output", a.output, "output .ply (x y z nx ny nz; viewpoint = the eye)")->required();
  cmd->add_option("--eye", a.eye, "camera position X,Y,Z")->required();
  cmd->add_option("--target", a.target, "point looked at X,Y,Z (default 0,0,0)");
  cmd->add_option("--resolution", a.resolution, "image size W,H (default 640,480)");
  cmd->add_option("--fov", a.fov, "vertical field of view in degrees")->check(number_in(0.001, 179.0));
  cmd->add_option("--noise", a.noise, "Gaussian noise sigma along the ray, model units")
      ->check(number_in(0, std::numeric_limits<double>::max()));
  cmd->add_option("--seed", a.seed, "noise seed");
  add_common_flags(cmd, common);
  return cmd;
}

struct CropArgs {
  std::string input, output, box;
  bool drop_plane = false, largest_part = false;
  double plane_distance = 0, gap = 0;
  std::uint64_t seed = 1;
};

CLI::App* add_crop_command(CLI::App& app, CropArgs& a, CommonFlags& common) {
  constexpr double kMax = std::numeric_limits<double>::max();
  CLI::App* cmd = app.add_subcommand(
      "crop", "one object cut out of a scanned scene: a box, the table it stands on dropped, its largest part kept");
  cmd->add_option("--input", a.input, "the scene (any point file, or a .conf of range scans)")->required();
  cmd->add_option("--output", a.output, "output .ply: the kept points with every attribute")->required();
  cmd->add_option("--box", a.box, "keep the points inside XMIN,YMIN,ZMIN,XMAX,YMAX,ZMAX (the scene's coordinates)");
  cmd->add_flag("--drop-plane", a.drop_plane, "drop the largest plane (the table the object stands on)");
  cmd->add_flag("--largest-part", a.largest_part, "keep the largest connected part");
  cmd->add_option("--plane-distance", a.plane_distance, "the plane's inliers lie closer (default: 2 x median spacing)")
      ->check(number_in(0, kMax, true));
  cmd->add_option("--gap", a.gap, "parts are joined across shorter gaps (default: 4 x median spacing)")
      ->check(number_in(0, kMax, true));
  cmd->add_option("--seed", a.seed, "RANSAC's seed");
  add_common_flags(cmd, common);
  return cmd;
}

// The scene's points in the box, off its largest plane, in its largest part (nodes/scan/crop.h).
int run_crop(const CropArgs& a) {
  CropOptions o;
  if (!a.box.empty()) {
    BoundingBox b;
    char extra;
    if (std::sscanf(a.box.c_str(), "%lf,%lf,%lf,%lf,%lf,%lf%c", &b.min.x(), &b.min.y(), &b.min.z(), &b.max.x(),
                    &b.max.y(), &b.max.z(), &extra) != 6 ||
        !b.min.allFinite() || !b.max.allFinite())
      return fail("crop: --box expects XMIN,YMIN,ZMIN,XMAX,YMAX,ZMAX, got '" + a.box + "'", 2);
    if (!(b.min.array() <= b.max.array()).all())
      return fail("crop: --box's minimum exceeds its maximum on an axis: '" + a.box + "'", 2);
    o.box = b;
  }
  if (!o.box && !a.drop_plane && !a.largest_part)
    return fail("crop: nothing to do: give --box, --drop-plane or --largest-part", 2);
  if (std::filesystem::path(a.output).extension() != ".ply")
    return fail(a.output + ": the output must be a .ply file", 2);
  o.drop_plane = a.drop_plane;
  o.largest_part = a.largest_part;
  o.plane_distance = a.plane_distance;
  o.gap = a.gap;
  o.seed = a.seed;
  const PointSet scene = load_shape(a.input);
  CropResult r;
  try {
    r = crop(scene, o);
  } catch (const InputError& e) {
    return fail(a.input + ": " + e.what(), 1);
  }
  write_ply(a.output, r.points);
  spdlog::info("{} of {} points of {} -> {}", r.points.size(), scene.size(), a.input, a.output);
  if (o.box) spdlog::info("  {} inside the box", r.in_box);
  if (o.drop_plane)
    spdlog::info("  {} on the largest plane ({:.4f} {:.4f} {:.4f}) . x + {:.4f} = 0 dropped (median spacing {:.4g})",
                 r.plane_points, r.plane_normal.x(), r.plane_normal.y(), r.plane_normal.z(), r.plane_offset, r.spacing);
  if (o.largest_part) spdlog::info("  the largest of {} connected parts kept", r.parts);
  return 0;
}

// plan, apply and split (DESIGN section 10): the run in tiles, for Dask, a Slurm job array or any batch system.
struct TileArgs {
  std::string config, plan, plan_points, input, tile, output, output_dir;
  std::vector<std::string> overrides;
  Index tiles = 0;
};

void add_config_flags(CLI::App* cmd, TileArgs& a) {
  cmd->add_option("--config", a.config, "the run's YAML config")->check(CLI::ExistingFile);
  cmd->add_option("--set", a.overrides, "KEY=VALUE: override a config key (repeatable)")
      ->expected(1)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
}

CLI::App* add_plan_command(CLI::App& app, TileArgs& a, CommonFlags& common) {
  CLI::App* cmd = app.add_subcommand("plan", "the run up to the labelled, aligned samples, written as a plan file");
  add_config_flags(cmd, a);
  cmd->get_option("--config")->required();
  cmd->add_option("--output", a.plan, "the plan file (default: <output.dir>/scanfill.plan)");
  cmd->add_option("--plan-points", a.plan_points,
                  "the plan-level points, the target's copies (.ply; default: plan_points.ply beside the plan)");
  add_common_flags(cmd, common);
  return cmd;
}

CLI::App* add_apply_command(CLI::App& app, TileArgs& a, CommonFlags& common) {
  CLI::App* cmd = app.add_subcommand("apply", "carries one tile of the exemplar through a plan file");
  cmd->add_option("--plan", a.plan, "the plan file of scanfill plan")->required();
  cmd->add_option("--input", a.tile, "the tile: a point file of the exemplar's points")->required();
  cmd->add_option("--output", a.output, "the tile's output .ply (output.ply's properties)")->required();
  add_common_flags(cmd, common);
  return cmd;
}

CLI::App* add_split_command(CLI::App& app, TileArgs& a, CommonFlags& common) {
  CLI::App* cmd = app.add_subcommand("split", "splits the exemplar (or any point file) into tiles for scanfill apply");
  add_config_flags(cmd, a);
  auto* input = cmd->add_option("--input", a.input, "a point file (or procedural:NAME) instead of a config's exemplar");
  input->excludes(cmd->get_option("--config"));
  cmd->add_option("--tiles", a.tiles, "number of tiles")->required()->check(number_in(1, 1 << 20));
  cmd->add_option("--output-dir", a.output_dir, "folder for tile_0000.ply ...")->required();
  add_common_flags(cmd, common);
  return cmd;
}

RunConfig config_of(const TileArgs& a, int threads) {
  RunConfig config = load_config(a.config, a.overrides);
  if (threads > 0) config.threads = threads;
  return config;
}

int run_plan(const TileArgs& a, int threads) {
  const RunConfig config = config_of(a, threads);
  const auto limit = limit_threads(config.threads);
  const PlanPaths paths = plan_paths(config, a.plan, a.plan_points);
  const PlanOutcome o = make_plan(config, paths);
  std::cout << "scanfill: plan of " << a.config << ": " << o.patches << " patches, " << o.carried_samples
            << " carried samples\n  wrote " << paths.plan.string() << " (" << o.plan_bytes << " bytes)\n  wrote "
            << paths.points.string() << " (" << o.plan_points << " plan-level points: the copies of the "
            << (config.mode == RunMode::kCompletion ? "template" : "target") << ")" << std::endl;
  return 0;
}

int run_apply(const TileArgs& a) {
  const ApplyOutcome o = apply_tile(a.plan, a.tile, a.output);
  spdlog::info("{} points of {} -> {} output points in {}", o.tile_points, a.tile, o.output_points, a.output);
  return 0;
}

int run_split(const TileArgs& a, int threads) {
  if (a.config.empty() && a.input.empty()) return fail("split: give --config FILE or --input FILE", 2);
  PointSet points;
  if (!a.config.empty()) {
    points = exemplar_of(config_of(a, threads));
  } else {
    const LoadResult loaded = load_input(parse_input(a.input));
    for (const auto& w : loaded.warnings) spdlog::warn("{}", w);
    points = loaded.points;
  }
  const auto tiles = split_into_tiles(points, a.tiles, a.output_dir);
  spdlog::info("{} points in {} tiles -> {}", points.size(), tiles.size(), a.output_dir);
  return 0;
}

// The main run: the pipeline a config file describes.
int run_config(const std::string& config_path, const std::vector<std::string>& overrides, int threads) {
  RunConfig config;
  try {
    config = load_config(config_path, overrides);
  } catch (const ConfigError& e) {
    return fail(e.what(), 2);
  }
  if (threads > 0) config.threads = threads;
  const auto limit = limit_threads(config.threads);
  spdlog::info("{} run of {} on {} threads", mode_name(config.mode), config_path,
               tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
  const RunOutcome outcome = run(config);
  std::cout << outcome.summary;
  for (const auto& out : outcome.outputs) std::cout << "  wrote " << out.string() << "\n";
  std::cout << "  peak memory " << int(peak_rss_mb()) << " MiB" << std::endl;
  return 0;
}

// Runs f with at most `threads` worker threads (0: all cores).
template <typename F>
int with_threads(int threads, F&& f) {
  const auto limit = limit_threads(threads);
  return f();
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"scanfill: complete partial 3D scans and transfer geometric style by shape analogies"};
  app.set_version_flag("--version", std::string("scanfill ") + SCANFILL_VERSION);
  std::string config_path;
  bool print_defaults = false;
  CommonFlags common;
  app.add_option("--config", config_path, "run the pipeline configured by this YAML file")->check(CLI::ExistingFile);
  app.add_flag("--print-defaults", print_defaults, "print a complete config with every option and its default");
  std::vector<std::string> overrides;
  app.add_option("--set", overrides,
                 "KEY=VALUE: override a config key, e.g. --set sample.count=40000 --set preset=paper (repeatable)")
      ->expected(1)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  add_common_flags(&app, common);
  InfoArgs info;
  SampleArgs samp;
  EvalArgs ev;
  ScanArgs sc;
  CLI::App* info_cmd = add_info_command(app, info, common);
  CLI::App* sample_cmd = add_sample_command(app, samp, common);
  CLI::App* eval_cmd = add_eval_command(app, ev, common);
  CLI::App* scan_cmd = add_scan_command(app, sc, common);
  CropArgs cr;
  CLI::App* crop_cmd = add_crop_command(app, cr, common);
  TileArgs tile;
  CLI::App* plan_cmd = add_plan_command(app, tile, common);
  CLI::App* apply_cmd = add_apply_command(app, tile, common);
  CLI::App* split_cmd = add_split_command(app, tile, common);
  app.require_subcommand(0, 1);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version print and exit 0; every other parse error is a usage error: exit 2, one line.
    if (e.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) return app.exit(e);
    std::string what = e.what();
    std::replace(what.begin(), what.end(), '\n', ' ');
    return fail(what + " (see scanfill --help)", 2);
  }
  setup_logging(common.verbose, common.quiet);
  remove_staging_on_signals();
  try {
    if (print_defaults) {
      std::cout << default_config_yaml();
      return 0;
    }
    if (info_cmd->parsed())
      return with_threads(common.threads, [&] { return run_info(info.file, info.json, info.full); });
    if (scan_cmd->parsed())
      return with_threads(common.threads, [&] {
        return run_scan(sc.input, sc.output, sc.eye, sc.target, sc.resolution, sc.fov, sc.noise, sc.seed);
      });
    if (eval_cmd->parsed())
      return with_threads(common.threads, [&] {
        return run_eval(ev.output, ev.reference, ev.threshold, ev.scan, ev.template_shape, ev.samples, ev.baselines);
      });
    if (sample_cmd->parsed())
      return with_threads(common.threads, [&] {
        return run_sample(samp.input, samp.output, samp.spacing, samp.count, samp.seed, samp.k);
      });
    if (crop_cmd->parsed()) return with_threads(common.threads, [&] { return run_crop(cr); });
    if (plan_cmd->parsed()) return run_plan(tile, common.threads);
    if (apply_cmd->parsed()) return with_threads(common.threads, [&] { return run_apply(tile); });
    if (split_cmd->parsed()) return with_threads(common.threads, [&] { return run_split(tile, common.threads); });
    if (config_path.empty() && !overrides.empty()) return fail("--set needs --config FILE", 2);
    if (config_path.empty()) {
      std::cerr << app.help() << std::endl;
      return fail("nothing to do: give --config FILE, --print-defaults or a subcommand", 2);
    }
    return run_config(config_path, overrides, common.threads);
  } catch (const ConfigError& e) {
    return fail(e.what(), 2);
  } catch (const Error& e) {
    return fail(e.what());
  } catch (const std::bad_alloc&) {
    return fail("out of memory");
  } catch (const std::exception& e) {
    return fail(std::string("unexpected: ") + e.what());
  }
}
