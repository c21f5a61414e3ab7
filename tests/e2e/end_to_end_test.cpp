// End to end with ground truth (issue 4): procedural models scanned from one side by the virtual scanner, completed
// with their plain templates, scored against the complete models; a furniture transfer scored against the styled
// target; and inputs the pipeline must refuse with a clear message.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "engine/config.h"
#include "engine/console.h"
#include "engine/pipeline.h"
#include "input_util.h"
#include "nodes/core/errors.h"
#include "nodes/eval/evaluate.h"
#include "nodes/io/read_point_set.h"
#include "nodes/io/write_ply.h"
#include "nodes/procedural/shapes.h"
#include "nodes/scan/virtual_scan.h"
#include "sweep_camera.h"
#include "test_util.h"

namespace scanfill {
namespace {

struct Scores {
  double fscore = 0, unseen = 0;
};

RunConfig completion_config(const std::string& shape, const std::string& templ, const Eigen::Vector3d& eye,
                            const Eigen::Vector3d& target, const std::filesystem::path& out) {
  RunConfig c;
  c.mode = RunMode::kCompletion;
  c.inputs = {test::input(Role::kScan, parse_input("procedural:" + shape)),
              test::input(Role::kTemplate, parse_input("procedural:" + templ))};
  c.output_dir = out;
  c.virtual_scan.eye = eye;
  c.virtual_scan.target = target;
  c.virtual_scan.width = c.virtual_scan.height = 480;
  c.virtual_scan.fov_deg = 35;
  return c;
}

Scores score(const PointSet& output, const PointSet& reference, const PointSet& scan, const PointSet& templ) {
  const EvalResult r = evaluate(output, reference, {}, &scan, &templ);
  return {r.fscore, r.unseen_detail_recall.value_or(0)};
}

// The virtual scan of `reference` that run(c) completed: c.virtual_scan's eye, target, image and field of view.
PointSet scan_of_the_run(const RunConfig& c, const PointSet& reference) {
  ScanOptions so;
  so.eye = *c.virtual_scan.eye;
  so.target = *c.virtual_scan.target;
  so.width = c.virtual_scan.width;
  so.height = c.virtual_scan.height;
  so.fov_deg = c.virtual_scan.fov_deg;
  return virtual_scan(reference, so).points;
}

void complete_and_score(const std::string& shape, const std::string& templ, const Eigen::Vector3d& eye,
                        const Eigen::Vector3d& target) {
  setup_logging(false, true);
  test::TempDir dir;
  const RunConfig c = completion_config(shape, templ, eye, target, dir / "out");
  run(c);
  const PointSet reference = make_shape(shape), template_mesh = make_shape(templ);
  const PointSet scan = scan_of_the_run(c, reference);
  const PointSet output = read_point_set(dir / "out" / "output.ply").points;
  const Scores ours = score(output, reference, scan, template_mesh);
  const Scores scan_only = score(scan, reference, scan, template_mesh);
  const double tau = 0.01 * bounding_box(reference.positions()).diagonal();
  const Scores blend = score(template_blend(scan, template_mesh, 2 * tau, {}), reference, scan, template_mesh);
  std::printf("%s: F %.3f unseen %.3f | scan only F %.3f unseen %.3f | template blend F %.3f unseen %.3f\n",
              shape.c_str(), ours.fscore, ours.unseen, scan_only.fscore, scan_only.unseen, blend.fscore, blend.unseen);
  EXPECT_GE(ours.fscore, 0.90);
  EXPECT_GE(ours.unseen, 0.70);
  EXPECT_GT(ours.fscore, scan_only.fscore);
  EXPECT_GT(ours.fscore, blend.fscore);
  EXPECT_GT(ours.unseen, scan_only.unseen);
  EXPECT_GT(ours.unseen, blend.unseen);
}

TEST(EndToEnd, VaseFromOneSideWithItsBodyOfRevolution) {
  complete_and_score("vase", "vase_template", {0, -3, 0.6}, {0, 0, 0.5});
}

TEST(EndToEnd, GearWithADiskTemplate) {
  complete_and_score("gear", "gear_template", {0, -2.2, 1.2}, {0, 0, 0.075});
}

TEST(EndToEnd, FlutedColumnWithACylinderTemplate) {
  complete_and_score("column", "column_template", {0, -3.5, 2.0}, {0, 0, 0.6});
}

// A hexagon drawn for the vase, its vertices on the vase's cylinder as Blender and OpenSCAD draw one: its facets'
// centres lie 4.4 cm inside that circle, and the vase's bulge up to 11 cm outside them. Registered on the body of
// revolution through the hexagon's corners (stop 58) but labelled, carried and copied on the hexagon, the vase's images
// did not reach the facets' centres, and flat copies of them were left inside it: F 0.712, unseen-detail 0.535 here
// (3000 samples, 320 by 320 rays). The body stands in for the hexagon from the correspondence on: 0.913 / 0.945, and
// the template the analogy labels (analogy.ply) is round.
TEST(EndToEnd, AHexagonDrawnForTheVaseStandsInAsTheBodyThroughItsCorners) {
  setup_logging(false, true);
  test::TempDir dir;
  RunConfig c = completion_config("vase", "vase_cylinder6", {0, -3.5, 1.2}, {0, 0, 0.5}, dir / "out");
  c.virtual_scan.width = c.virtual_scan.height = 320;
  c.sample.count = 3000;
  c.output_surface = SurfaceChoice::kNone;
  run(c);
  const auto report = nlohmann::json::parse(test::read_bytes(dir / "out" / "report.json"));
  EXPECT_EQ(report["correspondence"]["polygon_sides"], 6);
  const PointSet reference = make_shape("vase"), hexagon = make_shape("vase_cylinder6");
  const Scores ours =
      score(read_point_set(dir / "out" / "output.ply").points, reference, scan_of_the_run(c, reference), hexagon);
  std::printf("vase in a hexagon: F %.3f unseen %.3f\n", ours.fscore, ours.unseen);
  EXPECT_GE(ours.fscore, 0.88);
  EXPECT_GE(ours.unseen, 0.85);
  const PointSet labelled = read_point_set(dir / "out" / "analogy.ply").points;
  for (Index i = 0; i < labelled.size(); ++i) {
    const double z = labelled.positions()(2, i), radius = labelled.positions().col(i).head<2>().norm();
    if (z > 0.05 && z < 0.95) {
      ASSERT_NEAR(radius, 0.33, 0.005) << "template sample " << i << " on the round body";
    }
  }
}

// The vase in its plain cylinder, seen from below (the sweep's eye): the cylinder lies on itself turned end over end,
// the vase does not. Its half turns about lines across the axis at mid-height carried the seen foot, beads and all,
// round the lip (105 synthesised points up there more than 0.33 from the axis, where the lip reaches 0.31, and 4988
// between the belly and the neck, where the vase narrows from 0.36 to 0.27). The scan saw its foot and its lip: their
// radii refute the turn (symmetry/profile.h), and no image is carried round the lip.
TEST(EndToEnd, AVaseInAPlainCylinderSeenFromBelowIsNotTurnedEndOverEnd) {
  setup_logging(false, true);
  test::TempDir dir;
  RunConfig c = completion_config("vase", "vase_cylinder", {1.26, -0.90, -3.11}, {0, 0, 0.5}, dir / "out");
  c.virtual_scan.fov_deg = 30;
  c.output_surface = SurfaceChoice::kNone;
  run(c);
  LoadOptions in_file_order;
  in_file_order.morton_sort = false;
  const PointSet output = read_point_set(dir / "out" / "output.ply", in_file_order).points;
  const std::vector<int> origin = test::ply_property(dir / "out" / "output.ply", "origin");
  ASSERT_EQ(Index(origin.size()), output.size());
  Index round_the_lip = 0, below_the_neck = 0;
  for (Index i = 0; i < output.size(); ++i) {
    const double z = output.positions()(2, i), radius = output.positions().col(i).head<2>().norm();
    if (origin[i] != 1 || radius <= 0.33) continue;
    round_the_lip += z > 0.86;
    below_the_neck += z > 0.66 && z <= 0.86;
  }
  std::printf("synthesised beyond 0.33 from the axis: %lld round the lip, %lld below the neck\n",
              static_cast<long long>(round_the_lip), static_cast<long long>(below_the_neck));
  EXPECT_EQ(round_the_lip, 0);
  EXPECT_LT(below_the_neck, 3500);
  const auto report = nlohmann::json::parse(test::read_bytes(dir / "out" / "report.json"));
  EXPECT_GT(report.at("symmetry").at("refuted_by_scan_profile").get<Index>(), 0);
}

// The beaded ring seen from below (a seeded random view of the sweep's, (0.16, -0.51, -0.85)) shows its beads' lower
// halves only, so the median radius of its outer wall at the heights under its equator stood out of the heights above:
// its flip end over end, the one transform that carries the seen underside to its top, was refuted (unseen-detail
// 0.995 -> 0.766 here, the sweep's eye). The lower quartile is the body under the beads, symmetric end over end.
TEST(EndToEnd, ABeadedRingSeenFromBelowKeepsItsFlipEndOverEnd) {
  setup_logging(false, true);
  test::TempDir dir;
  RunConfig c =
      completion_config("beaded_ring", "ring_template", {0.437, -1.4347, -2.3164}, {0, -0.0001, 0.06}, dir / "out");
  c.virtual_scan.fov_deg = 30;
  c.output_surface = SurfaceChoice::kNone;
  run(c);
  const PointSet reference = make_shape("beaded_ring"), torus = make_shape("ring_template");
  const Scores ours =
      score(read_point_set(dir / "out" / "output.ply").points, reference, scan_of_the_run(c, reference), torus);
  std::printf("beaded ring from below: F %.3f unseen %.3f\n", ours.fscore, ours.unseen);
  EXPECT_GE(ours.fscore, 0.99);
  EXPECT_GE(ours.unseen, 0.95);
}

// The gear seen straight from below (2 degrees off its axis, the sweep's --end-on view) shows its underside only, a
// flat face: any shrunk copy of that face, turned over, lies on the far face too. A flip scaled by 0.48 explained the
// top and left out the true flip end over end as redundant, so the top took a plain patch of the underside's middle
// (430 points of teeth on the top face). In completion a transform carries one part of an object onto another at
// nearly its size (vote.completion_scale): the flip carries the underside's teeth to the top.
TEST(EndToEnd, AGearSeenStraightFromBelowIsTurnedOverNotShrunk) {
  setup_logging(false, true);
  test::TempDir dir;
  RunConfig c = completion_config("gear", "gear_template", {0.11, 0.075, -3.7}, {0, 0, 0.075}, dir / "out");
  c.virtual_scan.fov_deg = 30;
  c.output_surface = SurfaceChoice::kNone;
  run(c);
  const auto report = nlohmann::json::parse(test::read_bytes(dir / "out" / "report.json"));
  bool flipped = false;
  for (const auto& t : report.at("transforms")) {
    if (t.at("kind") != "similarity" || t.at("labelled").get<Index>() == 0) continue;
    EXPECT_NEAR(t.at("scale").get<double>(), 1.0, 0.2) << "transform " << t.at("label");
    flipped =
        flipped || (t.at("rotation_deg").get<double>() > 170 &&
                    std::abs(t.at("rotation_axis")[2].get<double>()) < 0.1 && t.at("labelled").get<Index>() > 5000);
  }
  EXPECT_TRUE(flipped) << "no flip end over end labels the top face";
  const PointSet output = read_point_set(dir / "out" / "output.ply").points;
  Index teeth_on_top = 0;
  for (Index i = 0; i < output.size(); ++i)
    teeth_on_top += output.positions()(2, i) > 0.14 && output.positions().col(i).head<2>().norm() > 0.49;
  std::printf("gear from below: %lld points of teeth on the top face\n", static_cast<long long>(teeth_on_top));
  EXPECT_GE(teeth_on_top, 1000);
}

// A hexagonal prism seen straight from below: its scan is the hexagonal floor, which lies inside the disk of the body
// of revolution through the hexagon's corners as well as on the hexagon (shares of the scan 0.929 and 0.919). The body
// stood in for the template, and its round walls were copied round the prism (F 0.518 here). The template is taken as
// drawn unless the body lays clearly more of the scan on itself.
TEST(EndToEnd, AHexagonalPrismSeenStraightFromBelowKeepsItsHexagon) {
  setup_logging(false, true);
  test::TempDir dir;
  RunConfig c =
      completion_config("medallion_prism6", "prism_template6", {0.11, 0.07, -3.16}, {0, 0, 0.45}, dir / "out");
  c.virtual_scan.fov_deg = 30;
  c.virtual_scan.width = c.virtual_scan.height = 320;
  c.sample.count = 6000;
  c.output_surface = SurfaceChoice::kNone;
  run(c);
  const auto report = nlohmann::json::parse(test::read_bytes(dir / "out" / "report.json"));
  EXPECT_EQ(report.at("correspondence").at("polygon_sides"), 0);
  const PointSet reference = make_shape("medallion_prism6"), hexagon = make_shape("prism_template6");
  const Scores ours =
      score(read_point_set(dir / "out" / "output.ply").points, reference, scan_of_the_run(c, reference), hexagon);
  std::printf("hexagonal prism from below: F %.3f unseen %.3f\n", ours.fscore, ours.unseen);
  EXPECT_GE(ours.fscore, 0.88);
}

TEST(EndToEnd, FurnitureTransferGetsTheExemplarsLegsOnANewStructure) {
  setup_logging(false, true);
  test::TempDir dir;
  RunConfig c;
  c.mode = RunMode::kTransfer;
  c.inputs = {test::input(Role::kSource, parse_input("procedural:table_template")),
              test::input(Role::kTarget, parse_input("procedural:bench_template")),
              test::input(Role::kExemplar, parse_input("procedural:table"))};
  c.output_dir = dir / "out";
  run(c);
  const PointSet output = read_point_set(dir / "out" / "output.ply").points;
  EXPECT_GT(output.faces().cols(), 0);  // a mesh exemplar gives a mesh
  const PointSet styled = make_bench();
  const double ours = evaluate(output, styled, {}).fscore;
  const double plain = evaluate(make_bench_template(), styled, {}).fscore;
  std::printf("transfer: F %.3f against the styled target; the plain target scores %.3f\n", ours, plain);
  EXPECT_GE(ours, 0.85);
  EXPECT_GT(ours, plain);
  // The seams of this run are aligned by a Ceres solve, summarised in the report (issue 9).
  const auto report = nlohmann::json::parse(test::read_bytes(dir / "out" / "report.json"));
  ASSERT_GT(report.at("synthesis").at("seam_pairs").get<Index>(), 0);
  const auto& solver = report.at("align").at("solver");
  ASSERT_TRUE(solver.is_object());
  EXPECT_EQ(solver.at("termination"), "CONVERGENCE");  // eq. 10 is linear: a few steps converge
  EXPECT_GE(solver.at("iterations").get<int>(), 2);
  EXPECT_LT(solver.at("final_cost").get<double>(), solver.at("initial_cost").get<double>());
  EXPECT_EQ(report.at("correspondence").at("deformation_solves").size(), size_t(CorrespondOptions{}.outer_iterations));
}

TEST(EndToEnd, TheSameInputGivesTheSameOutput) {
  setup_logging(false, true);
  test::TempDir dir;
  RunConfig c = completion_config("gear", "gear_template", {0, -2.2, 1.2}, {0, 0, 0.075}, dir / "a");
  c.sample.count = 6000;
  run(c);
  c.output_dir = dir / "b";
  run(c);
  EXPECT_EQ(test::read_bytes(dir / "a" / "output.ply"), test::read_bytes(dir / "b" / "output.ply"));
}

// Real data (../shared/data): no threshold from the issue, but regression floors a little under the scores measured
// when these configs were made (README), and both baselines must stay below.
struct RealScores {
  Scores ours, scan_only, blend;
};

RealScores run_real(const std::string& config_name, const PointSet& reference, const PointSet& scan,
                    const PointSet& templ) {
  setup_logging(false, true);
  test::TempDir dir;
  RunConfig c = load_config(test::source_dir() / "configs" / config_name);
  c.output_dir = dir / "out";
  run(c);
  const PointSet output = read_point_set(dir / "out" / "output.ply").points;
  const double tau = 0.01 * bounding_box(reference.positions()).diagonal();
  RealScores r{score(output, reference, scan, templ), score(scan, reference, scan, templ),
               score(template_blend(scan, templ, 2 * tau, {}), reference, scan, templ)};
  std::printf("%s: F %.3f unseen %.3f | scan only F %.3f | template blend F %.3f unseen %.3f\n", config_name.c_str(),
              r.ours.fscore, r.ours.unseen, r.scan_only.fscore, r.blend.fscore, r.blend.unseen);
  return r;
}

TEST(EndToEndRealData, VaseLionFromItsFront) {
  SCANFILL_REQUIRE_SHARED_DATA();
  const PointSet model = read_point_set(test::shared_data() / "models" / "vaselion.obj").points;
  ScanOptions so;
  so.eye = {0, -3, 0.4};
  so.target = {0, 0, 0};
  so.width = so.height = 480;
  so.fov_deg = 30;
  const RealScores r = run_real("vaselion.yaml", model, virtual_scan(model, so).points, make_revolution(model));
  // Measured 0.572 / 0.310 (stop 48, quarter and half turns preferred; 0.576 / 0.322 before, 0.578 / 0.361 when this
  // test was written). Before the symmetry work 0.682 / 0.263: region membership now follows the labelled
  // transform, so 14x more of the unseen side is synthesised (53 k points, was 3.8 k) and unseen detail rises, but this
  // vase is not round (0.73 x 0.60), so the rotated relief lands off its surface and precision drops (0.53, was 0.82).
  EXPECT_GE(r.ours.fscore, 0.55);
  EXPECT_GE(r.ours.unseen, 0.30);
  EXPECT_GT(r.ours.fscore, r.scan_only.fscore);
  EXPECT_GT(r.ours.fscore, r.blend.fscore);
}

// The text2mesh vase (drawn y-up; a knob in front and behind, a handle on each side) seen from the robustness sweep's
// front view, completed with its own body of revolution. The back takes the front's half turn, which puts the front's
// knob on the back's. Before stop 48 the turns about the template's axis were composed about a centre a tenth of an
// alpha off it (the half turn fitted the template to 0.15 alpha, a turn of 30 degrees to 0.04), and turns of 60, 120
// and 150 degrees took the back, the knob 30 degrees beside its place: F 0.859 and unseen-detail 0.20, under template
// blending's 0.912. Measured 0.972 / 0.62 at stop 48, 0.965 / 0.545 at stop 65.
TEST(EndToEndRealData, Text2meshVaseFromTheFrontTheBackTakesTheFrontsHalfTurn) {
  SCANFILL_REQUIRE_SHARED_DATA();
  setup_logging(false, true);
  test::TempDir dir;
  const auto model_path = test::shared_data() / "models" / "text2mesh_vase.obj";
  const PointSet model = read_point_set(model_path).points;
  const PointSet scan =
      virtual_scan(model, test::sweep_camera(model, Eigen::Vector3d(0, 0.2, 1))).points;  // the sweep's front, y-up
  write_ply(dir / "scan.ply", scan);
  RunConfig c;
  c.mode = RunMode::kCompletion;
  c.inputs = {test::input(Role::kScan, parse_input((dir / "scan.ply").string())),
              test::input(Role::kTemplate, parse_input("revolution:" + model_path.string()))};
  c.output_dir = dir / "out";
  c.sample.count = 20000;
  run(c);
  const PointSet output = read_point_set(dir / "out" / "output.ply").points;
  const PointSet templ = make_revolution(model);
  const double tau = 0.01 * bounding_box(model.positions()).diagonal();
  const Scores ours = score(output, model, scan, templ);
  const Scores blend = score(template_blend(scan, templ, 2 * tau, {}), model, scan, templ);
  std::printf("text2mesh vase, front: F %.3f unseen %.3f | template blend F %.3f\n", ours.fscore, ours.unseen,
              blend.fscore);
  EXPECT_GE(ours.fscore, 0.95);
  EXPECT_GE(ours.unseen, 0.5);
  EXPECT_GT(ours.fscore, blend.fscore);
}

TEST(EndToEndRealData, StanfordBunnyScanWithTheCoarseBunny) {
  SCANFILL_REQUIRE_SHARED_DATA();
  const auto dir = test::shared_data() / "scans" / "stanford_bunny";
  const RealScores r =
      run_real("bunny_scan.yaml", read_point_set(dir / "bun_zipper.ply").points,
               read_point_set(dir / "bun000.ply").points, read_point_set(dir / "bun_zipper_res2.ply").points);
  EXPECT_GE(r.ours.fscore, 0.98);  // measured 0.995
  EXPECT_GT(r.ours.fscore, r.scan_only.fscore);
}

// Inputs at this level that must end with a clear message and no output.
std::string refusal(const PointSet& scan, const PointSet& templ) {
  setup_logging(false, true);
  test::TempDir dir;
  write_ply(dir / "scan.ply", scan);
  write_ply(dir / "template.ply", templ);
  RunConfig c;
  c.mode = RunMode::kCompletion;
  c.inputs = {test::input(Role::kScan, parse_input("scan.ply", dir.path())),
              test::input(Role::kTemplate, parse_input("template.ply", dir.path()))};
  c.output_dir = dir / "out";
  c.sample.count = 4000;
  try {
    run(c);
  } catch (const Error& e) {
    EXPECT_FALSE(std::filesystem::exists(dir / "out"));
    return e.what();
  }
  return "no error";
}

TEST(EndToEnd, RefusesATemplateThatDoesNotOverlapTheScan) {
  ScanOptions so;
  so.eye = {0, -3, 0.6};
  so.target = {0, 0, 0.5};
  const PointSet scan = virtual_scan(make_vase(), so).points;
  const PointSet far = transformed(make_vase_template(), {Eigen::Matrix3d::Identity(), {4, 0, 0}, 1});
  const std::string what = refusal(scan, far);
  EXPECT_NE(what.find("node 'correspond' failed"), std::string::npos) << what;
  EXPECT_NE(what.find("do not overlap"), std::string::npos) << what;
}

TEST(EndToEnd, RefusesInputsOfVeryDifferentScale) {
  ScanOptions so;
  so.eye = {0, -3, 0.6};
  so.target = {0, 0, 0.5};
  const PointSet scan = virtual_scan(make_vase(), so).points;
  const PointSet mm = transformed(make_vase_template(), {Eigen::Matrix3d::Identity(), {0, 0, 0}, 1000});
  const std::string what = refusal(scan, mm);
  EXPECT_NE(what.find("share a scale"), std::string::npos) << what;
}

TEST(EndToEnd, RefusesAScanOfTenPoints) {
  Eigen::Matrix3Xd p(3, 10);
  for (int i = 0; i < 10; ++i) p.col(i) = Eigen::Vector3d(0.3 * std::cos(i), 0.3 * std::sin(i), 0.1 * i);
  const std::string what = refusal(PointSet(p), make_vase_template());
  EXPECT_NE(what.find("scan"), std::string::npos) << what;
  EXPECT_NE(what.find("10"), std::string::npos) << what;
}

}  // namespace
}  // namespace scanfill
