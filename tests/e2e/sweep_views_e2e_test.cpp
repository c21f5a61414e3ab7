// Issue 10, end to end: procedural shapes completed from the robustness sweep's views (bench/robustness.py), each
// scored against its complete model.
//
// The four-legged table seen from the side, completed with its plain-legs template. The legs' unseen sides need a
// turn about each leg's own axis (a symmetry of a part of the template, not of the whole), which the symmetry node
// offers as part candidates (symmetry.parts): measured here, unseen-detail 0.40 -> 0.58 and F 0.929 -> 0.949 with
// them.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "engine/config.h"
#include "engine/console.h"
#include "engine/pipeline.h"
#include "input_util.h"
#include "nodes/core/similarity.h"
#include "nodes/eval/evaluate.h"
#include "nodes/input/input.h"
#include "nodes/io/read_point_set.h"
#include "nodes/io/write_ply.h"
#include "nodes/procedural/shapes.h"
#include "nodes/scan/virtual_scan.h"
#include "sweep_camera.h"
#include "test_util.h"

namespace scanfill {
namespace {

struct SweepRun {
  EvalResult result;
  nlohmann::json report;
  PointSet output;
};

// The turn of a model drawn z-up to y-up.
const Similarity kToYUp{Eigen::AngleAxisd(-M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix(),
                        Eigen::Vector3d::Zero(), 1.0};

// How a sweep run is set up beyond its view.
struct RunChoice {
  bool parts = true;          // symmetry.parts
  bool own_pose = false;      // correspond.rigid false: the scan is kept where it stands, exactly on the template
  bool scan_file = false;     // the scan read from a PLY file (float coordinates), as bench/robustness.py passes it
  double noise = 0;           // range noise (sigma along the ray) as a share of the model's diagonal (--noise)
  bool face_turns = true;     // symmetry.face_turns
  bool box_template = false;  // the template is `box:` of the model's mesh (its bounding box), not `templ`
  bool revolution = false;    // the template is `revolution:` of the model (its body of revolution), not `templ`
  std::optional<Similarity> turned = std::nullopt;  // model and scan turned so (with box_template and scan_file):
                                                    // kToYUp as many meshes are drawn, or a scan standing turned in its
                                                    // sensor's frame; scored at the drawn model's tau
  std::optional<Similarity> box_drawn = std::nullopt;  // the template is the model's bounding box moved so, written as
                                                       // a mesh file: a user's box not quite square to the scan
  int resolution = 480;  // the virtual scanner's image, resolution by resolution rays (--resolution)
  std::optional<PointSet> drawn_template = std::nullopt;  // the template, a mesh written to a file as a user draws it
};

// Procedural `shape` completed with procedural `templ`, seen as in a robustness sweep's view: 2.6 diagonals away
// along `view`, 480 x 480 (choice.resolution) at 30 degrees.
SweepRun complete_seen(const std::string& shape, const std::string& templ, const Eigen::Vector3d& eye,
                       const Eigen::Vector3d& centre, RunChoice choice = {}) {
  setup_logging(false, true);
  test::TempDir dir;
  const PointSet drawn = make_shape(shape);
  const Similarity turn = choice.turned.value_or(Similarity{});
  const PointSet model = transformed(drawn, turn);
  const BoundingBox drawn_bounds = bounding_box(drawn.positions());
  const std::string template_spec = choice.box_drawn || choice.drawn_template ? (dir / "box.ply").string()
                                    : choice.box_template                     ? "box:" + (dir / "model.ply").string()
                                    : choice.revolution                       ? "revolution:procedural:" + shape
                                                                              : "procedural:" + templ;
  const PointSet box = make_lowpoly_box(drawn_bounds.max - drawn_bounds.min, (drawn_bounds.min + drawn_bounds.max) / 2);
  const PointSet plain = choice.drawn_template ? *choice.drawn_template
                         : choice.box_drawn    ? transformed(box, *choice.box_drawn)
                         : choice.box_template ? transformed(box, turn)
                                               : load_input(parse_input(template_spec)).points;
  if (choice.box_template) write_ply(dir / "model.ply", model);
  if (choice.box_drawn || choice.drawn_template) write_ply(dir / "box.ply", plain);
  ScanOptions camera = test::sweep_camera(drawn, eye, centre);
  camera.width = camera.height = choice.resolution;
  camera.noise = choice.noise * drawn_bounds.diagonal();
  const PointSet seen = virtual_scan(drawn, camera).points;
  const PointSet scan = moved_by(seen, turn);
  RunConfig c;
  c.mode = RunMode::kCompletion;
  if (choice.scan_file) write_ply(dir / "scan.ply", scan);
  c.inputs = {
      test::input(Role::kScan, parse_input(choice.scan_file ? (dir / "scan.ply").string() : "procedural:" + shape)),
      test::input(Role::kTemplate, parse_input(template_spec))};
  c.output_dir = dir / "out";
  if (!choice.scan_file) {
    c.virtual_scan.eye = eye;
    c.virtual_scan.target = centre;
    c.virtual_scan.width = c.virtual_scan.height = choice.resolution;
    c.virtual_scan.fov_deg = 30;
    c.virtual_scan.noise = camera.noise;
  }
  c.symmetry.parts = choice.parts;
  c.symmetry.face_turns = choice.face_turns;
  c.correspond.rigid = !choice.own_pose;
  run(c);
  const PointSet output = read_point_set(dir / "out" / "output.ply").points;
  std::ifstream in(dir / "out" / "report.json");
  const EvalOptions at_drawn_tau{.threshold =
                                     0.01 * drawn_bounds.diagonal() / bounding_box(model.positions()).diagonal()};
  return {evaluate(output, model, at_drawn_tau, &scan, &plain), nlohmann::json::parse(in), output};
}

SweepRun complete_from(const std::string& shape, const std::string& templ, const Eigen::Vector3d& view,
                       RunChoice choice = {}) {
  const BoundingBox box = bounding_box(make_shape(shape).positions());
  return complete_seen(shape, templ, test::sweep_eye(box, view), (box.min + box.max) / 2, choice);
}

// The table's centre as bench/robustness.py puts it (its bounding box from 2000 samples; the exact box's centre is
// 0.2 mm lower, and some fits differ from there).
const Eigen::Vector3d kSweepTableCentre(0, 0, 0.3802285185083747);

// Prints the run's scores under `what` and expects at least `f` and `unseen` (F-score, unseen-detail recall).
void expect_scores(const SweepRun& run, const char* what, double f, double unseen) {
  std::printf("%s: F %.3f unseen-detail %.3f\n", what, run.result.fscore, run.result.unseen_detail_recall.value_or(0));
  EXPECT_GE(run.result.fscore, f);
  EXPECT_GE(run.result.unseen_detail_recall.value_or(0), unseen);
}

TEST(TableLegs, TheLegsUnseenSidesGainTheTurnedDetailFromTurnsAboutEachLegsOwnAxis) {
  const Eigen::Vector3d side(1, 0, 0.25);
  const SweepRun with = complete_from("table", "table_template", side);
  EXPECT_EQ(with.report["symmetry"]["target_parts"].size(), 4u);  // the four legs
  const SweepRun without = complete_from("table", "table_template", side, {.parts = false});
  std::printf("table from the side: F %.3f unseen-detail %.3f | without part turns: F %.3f unseen-detail %.3f\n",
              with.result.fscore, with.result.unseen_detail_recall.value_or(0), without.result.fscore,
              without.result.unseen_detail_recall.value_or(0));
  EXPECT_GE(with.result.unseen_detail_recall.value_or(0), without.result.unseen_detail_recall.value_or(0) + 0.02);
  EXPECT_GE(with.result.fscore, without.result.fscore + 0.01);
}

// The front view: the scan sees the legs' bulbs from the front, and their backs are carried by the table's half turn
// about z. synthesize's refinement used to slide that turn 2.8 cm sideways on the table top (a free rigid fit on an
// overlap that fixes little), so the bulbs landed off the legs: unseen-detail 0.30, F 0.794. It now moves only along
// the region's slippable motions unless a free fit lowers the misfit clearly.
TEST(TableLegs, TheLegsBacksSeenFromTheFrontKeepTheirBulbs) {
  const SweepRun front = complete_from("table", "table_template", Eigen::Vector3d(0, -1, 0.2));
  std::printf("table from the front: F %.3f unseen-detail %.3f\n", front.result.fscore,
              front.result.unseen_detail_recall.value_or(0));
  EXPECT_GE(front.result.fscore, 0.9);
  EXPECT_GE(front.result.unseen_detail_recall.value_or(0), 0.6);
}

// Seen from behind and above, the flips that carry the top's underside used to slide off it: one flip's free fit
// moved 9 cm for a 20% lower misfit on 15% less overlap, and the next flip fitted onto that image (F 0.854 in the
// robustness sweep, template blending 0.959). A fit that loses more than 10% of the phase's overlap is not taken.
TEST(TableLegs, SeenFromBehindTheTopsFlipsStayOnTheTop) {
  const SweepRun behind = complete_from("table", "table_template", Eigen::Vector3d(-0.7, 0.7, 0.5));
  std::printf("table from behind: F %.3f unseen-detail %.3f\n", behind.result.fscore,
              behind.result.unseen_detail_recall.value_or(0));
  EXPECT_GE(behind.result.fscore, 0.95);
}

// Seen from (-0.2, -0.6, 0.9), a view the sweep does not use: two labels carry a row of legs onto the other, their
// regions two legs and a strip of the top. Their overlap with the placed images is mostly the flat top, and the free
// fit slid them along it, 19 alpha, for a 30% lower mean misfit: the legs stood beside the legs, F 0.943 (template
// blending 0.953). A free fit that carries its image off the template is not taken where the exemplar sits on it.
// The eye is the one bench/robustness.py puts there; from the exact box the fits do not slide.
TEST(TableLegs, SeenFromAboveTheFrontTheRowsOfLegsStayOnTheLegs) {
  const SweepRun high =
      complete_seen("table", "table_template",
                    Eigen::Vector3d(-0.6579075587011587, -1.9737226761034758, 3.340812532663589), kSweepTableCentre);
  std::printf("table from (-0.2, -0.6, 0.9): F %.3f unseen-detail %.3f\n", high.result.fscore,
              high.result.unseen_detail_recall.value_or(0));
  const auto& shifts = high.report["synthesis"]["refinement_shift"];
  for (size_t l = 0; l < shifts.size(); ++l) EXPECT_LT(shifts[l].get<double>(), 0.03) << "label " << l;
  EXPECT_GE(high.result.fscore, 0.95);
  EXPECT_GE(high.result.unseen_detail_recall.value_or(0), 0.85);
}

// The crate (relief on its four sides, plain top and bottom) with a plain 8-vertex box, seen from above (the sweep's
// view). The unseen floor is the lid's flip. Another flip labels only strips of two walls, which slide up and down,
// and the phase search slid it 2.7 cm down them, taking its image of the floor off the box; the floor's own flip was
// then fitted onto that image: F 0.727. A label's image now slides only where the template slides under all of it.
TEST(Crate, SeenFromAboveTheFlippedLidStaysOnTheFloor) {
  const SweepRun above = complete_from("crate", "crate_template", Eigen::Vector3d(0.25, -0.35, 1.0));
  std::printf("crate from above: F %.3f unseen-detail %.3f\n", above.result.fscore,
              above.result.unseen_detail_recall.value_or(0));
  EXPECT_GE(above.result.fscore, 0.95);
  EXPECT_GE(above.result.unseen_detail_recall.value_or(0), 0.85);
}

// A gear seen obliquely from the front registered 3 cm towards its seen teeth, off the plain annulus's axis: its tooth
// roots paired with the annulus's faces and pulled it there. One registration offset, shared by every label and
// fitted to all their images together, then turned each image about the scan's own axis. The point-to-plane steps now
// move only along the motions the pairs with agreeing normals constrain (icp.h): the scan registers on the axis, and
// what offset is left is a few millimetres.
TEST(Gear, SeenObliquelyTheScanRegistersOnTheAnnulussAxis) {
  const SweepRun oblique = complete_from("gear", "gear_template", Eigen::Vector3d(0.6, -0.8, 0.4));
  const auto& t = oblique.report["correspondence"]["rigid"]["translation"];
  const auto& offset = oblique.report["synthesis"]["registration_offset"];
  const double moved = std::hypot(t[0].get<double>(), t[1].get<double>());
  const double shift = std::hypot(offset[0].get<double>(), offset[1].get<double>());
  std::printf("registered %.4f off the axis, offset %.4f\n", moved, shift);
  EXPECT_LT(moved, 0.005);
  EXPECT_LT(shift, 0.005);
  expect_scores(oblique, "gear from the front, obliquely", 0.98, 0.95);
}

// Seen from the front, with the scan now on the axis, the gear's unseen back came from a half turn about a line across
// the axis (its top face to its bottom), whose image meets the scan almost nowhere (94 samples): the refinement left
// its phase as voted, teeth in the gaps, F 0.913. Its phase now comes from the scan's own repeats (flip_phase), and a
// turn about the axis that the refinement moved off it goes back to the repeats' nearest phase.
TEST(Gear, SeenFromTheFrontTheHalfTurnsTeethMeetTheTeeth) {
  expect_scores(complete_from("gear", "gear_template", Eigen::Vector3d(0.0, -1.0, 0.2)), "gear from the front", 0.98,
                0.95);
}

// The fluted column (16 flutes) seen obliquely from behind: its repeats fitted 17 flutes below a cut and 16 above as
// well as 16 all the way up (0.3% apart), and the lower band's labels turned by 21.2 degrees, not 22.5. A split of
// the bands must now fit clearly better. Its registration offset (4.2 mm, 0.42 alpha) is applied too: F 0.959 -> 1.
TEST(FlutedColumn, SeenObliquelyFromBehindTheFlutesRepeatSixteenTimesAllTheWayUp) {
  const SweepRun behind = complete_from("column", "column_template", Eigen::Vector3d(-0.7, 0.7, 0.5));
  ASSERT_FALSE(behind.report["synthesis"]["repeats"].empty());
  for (const auto& r : behind.report["synthesis"]["repeats"]) {
    EXPECT_EQ(r["order_below_cut"].get<int>(), 16);
    EXPECT_EQ(r["order_above_cut"].get<int>(), 16);
  }
  expect_scores(behind, "fluted column from behind, obliquely", 0.98, 0.95);
}

// The gear seen edge-on shows the scanner only its band of teeth. The rigid ICP paired the tooth roots near the faces
// with the template annulus's faces (normals 90 degrees apart) and, with nothing else holding the band along the axis,
// tilted it 6.6 degrees and slid it 2.2 cm: the plain faces came out tilted, F 0.499. Its point-to-plane steps now
// move only along the motions the pairs with agreeing normals constrain (icp.h).
TEST(Gear, SeenEdgeOnTheRegistrationDoesNotTiltTheBand) {
  const SweepRun edge_on = complete_from("gear", "gear_template", Eigen::Vector3d(-0.95, -0.3, 0.0));
  const auto& rigid = edge_on.report["correspondence"]["rigid"];
  Eigen::Matrix3d r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r(i, j) = rigid["rotation"][i][j].get<double>();
  const Eigen::Vector3d t(rigid["translation"][0].get<double>(), rigid["translation"][1].get<double>(),
                          rigid["translation"][2].get<double>());
  const double degrees = rotation_angle(r) * 180 / M_PI;
  std::printf("gear edge-on: F %.3f unseen-detail %.3f, rigid registration %.2f degrees, %.4f along the axis\n",
              edge_on.result.fscore, edge_on.result.unseen_detail_recall.value_or(0), degrees, t.z());
  EXPECT_LT(degrees, 3.0);
  EXPECT_LT(std::abs(t.z()), 0.005);
  EXPECT_GE(edge_on.result.fscore, 0.93);
  EXPECT_GE(edge_on.result.unseen_detail_recall.value_or(0), 0.9);
}

// Seen edge-on a little from above (`--random-views 6 --view-seed 6565`'s (-0.99, 0.11, 0.06), the sweep's exact eye
// and scan file), 28% of the scan lies on the plain disk, its teeth standing in and out of it by 8.5 spacings: ICP
// moved it 2.4 spacings and turned it 0.94 degrees towards their middle, 19% on, and every image landed off the teeth
// (F 0.879, unseen-detail 0.60; 0.988 / 0.999 in its own pose). On a round template, such a pull of the relief leaves
// the scan's own pose.
TEST(Gear, SeenEdgeOnFromALittleAboveItsTeethDoNotPullItOffItsPose) {
  const SweepRun run =
      complete_seen("gear", "gear_template", test::kGearEdgeOnEye, test::kSweepGearCentre, {.scan_file = true});
  EXPECT_TRUE(run.report["correspondence"]["kept_input_pose"].get<bool>());
  expect_scores(run, "gear edge-on from a little above", 0.97, 0.95);
}

TEST(Crate, SeenFromBelowTheFlipsStayOnTheBox) {
  const SweepRun below = complete_from("crate", "crate_template", Eigen::Vector3d(0.35, -0.25, -1.0));
  std::printf("crate from below: F %.3f unseen-detail %.3f\n", below.result.fscore,
              below.result.unseen_detail_recall.value_or(0));
  EXPECT_GE(below.result.fscore, 0.95);
  EXPECT_GE(below.result.unseen_detail_recall.value_or(0), 0.85);
}

// The scan exactly on the box, from below: the flip that carries the floor onto the lid also carries the seen walls'
// relief onto themselves upside down, and its free fit slid it 1.8 cm (2 alpha) up, the lid off the box, for a lower
// mean misfit of the walls (F 0.742). Where no registration moved the scan, a free fit that moves a pinned region more
// than an alpha and lands a tenth less of it on the template is not taken.
TEST(Crate, SeenFromBelowInItsOwnPoseTheLidStaysOnTheBox) {
  const SweepRun below =
      complete_from("crate", "crate_template", Eigen::Vector3d(0.35, -0.25, -1.0), {.own_pose = true});
  expect_scores(below, "crate from below, in its own pose", 0.95, 0.85);
}

// The same from nearly straight below (a view drawn by `--random-views 6 --view-seed 777`): the scan keeps its own
// pose, and the flip's free fit slid the lid 1.6 cm (1.8 alpha) up off the box, where it still landed within the
// regions' reach of 2 alpha (F 0.705, under template blending's 0.839). A scan in its own pose lands within an alpha.
TEST(Crate, SeenFromNearlyStraightBelowTheLidStaysOnTheBox) {
  const SweepRun below = complete_seen("crate", "crate_template",
                                       Eigen::Vector3d(0.7750342850847133, 0.5416533916053448, -2.595016745525883),
                                       Eigen::Vector3d(0, 0, 0.4), {.scan_file = true});
  EXPECT_TRUE(below.report["correspondence"]["kept_input_pose"].get<bool>());
  expect_scores(below, "crate from nearly straight below", 0.95, 0.85);
}

// Square on a face at nearly no elevation (a random direction of `bench/robustness.py --random-views`): ICP slid the
// one face it sees 1.1 cm off the box, between its 2 cm raised frame and diamond and the ground they stand on, and the
// half turn laid the back face 2.1 cm inside the box (F 0.798, unseen-detail 0.55). That slide puts less of the scan
// on the template than its own pose: the scan keeps its own pose.
TEST(Crate, SeenSquareOnItsFrontTheScanKeepsItsOwnPose) {
  const SweepRun front = complete_from("crate", "crate_template", Eigen::Vector3d(-1.0, 0.01, 0.03));
  EXPECT_TRUE(front.report["correspondence"]["kept_input_pose"].get<bool>());
  expect_scores(front, "crate square on its front", 0.95, 0.85);
}

// Seen from a low side (its +x face and a strip of +y), the crate registers 1.5 cm off its box, and the labelling takes
// only the identity and the half turn about z, whose image meets the scan nowhere: with two turned labels required,
// no offset was fitted, and the half turn's image landed 1.9 cm off the unseen walls (F 0.661, unseen-detail 0.02,
// below template blending's 0.846). The quarter turns no region took carry one seen face onto the other: the offset
// is fitted with them too.
TEST(Crate, SeenFromALowSideTheHalfTurnTurnsAboutTheScansAxis) {
  const SweepRun low = complete_from("crate", "crate_template", Eigen::Vector3d(0.9, 0.5, 0.1));
  std::printf("crate from a low side: F %.3f unseen-detail %.3f\n", low.result.fscore,
              low.result.unseen_detail_recall.value_or(0));
  EXPECT_GE(low.result.fscore, 0.95);
  EXPECT_GE(low.result.unseen_detail_recall.value_or(0), 0.85);
}

// Seen from the side, the vase's unseen half is carried by turns whose phase the overlap cannot settle for both of its
// kinds of detail: one phase suited the 12 flutes and put the 16 beads between the beads (unseen-detail 0.71). The
// scan's own repeats (every 30 degrees above z = 0.1, every 22.5 below) turn each band to its kind, and its turns
// fill the beads' hidden halves: F 0.997, unseen-detail 0.96 measured (0.98 on the sweep's scan).
TEST(Vase, SeenFromTheSideTheBeadsTurnToTheScansOwnRepeats) {
  const SweepRun side = complete_from("vase", "vase_template", Eigen::Vector3d(1.0, 0.0, 0.25));
  std::printf("vase from the side: F %.3f unseen-detail %.3f\n", side.result.fscore,
              side.result.unseen_detail_recall.value_or(0));
  const auto& repeats = side.report["synthesis"]["repeats"];
  ASSERT_EQ(repeats.size(), 1u);
  EXPECT_EQ(repeats[0]["order_below_cut"].get<int>() * repeats[0]["order_above_cut"].get<int>(), 12 * 16);
  EXPECT_GE(side.result.fscore, 0.98);
  EXPECT_GE(side.result.unseen_detail_recall.value_or(0), 0.9);
}

// Scanned with range noise of 0.3% of its diagonal (a third of the F-score's threshold, about half the flutes' depth),
// from the front obliquely: every turn of the scan misfits by the noise, and the misfit grows with the turn, so the
// repeats' dips were not deep against zero and none was found (on the sweep's scan unseen-detail 0.59, beads between
// the beads). Measured above the noise, the two bands are found: 0.98 on the sweep's scan.
TEST(Vase, ScannedWithRangeNoiseTheBeadsAndFlutesStillRepeat) {
  const SweepRun noisy = complete_from("vase", "vase_template", Eigen::Vector3d(0.6, -0.8, 0.4), {.noise = 0.003});
  const auto& repeats = noisy.report["synthesis"]["repeats"];
  ASSERT_EQ(repeats.size(), 1u);
  EXPECT_EQ(repeats[0]["order_below_cut"].get<int>(), 16);
  EXPECT_EQ(repeats[0]["order_above_cut"].get<int>(), 12);
  expect_scores(noisy, "noisy vase from the front obliquely", 0.98, 0.9);
}

// The vase from nearly straight below (a view drawn by `--random-views 6 --view-seed 777`, its exact eye) in its mesh
// template: three flips turned the scan end over end about a height of 0.375 and carried the foot's ring of 16 beads
// onto the shoulder, where the vase has none (F 0.961, under template blending's 0.965). The scan's repeats split it
// into the foot's band (order 16) and the body's (order 12), and an image now carries a band's relief only into that
// band (banded_relief in synthesize.cpp).
TEST(Vase, SeenFromNearlyStraightBelowTheFootsBeadsStayAtTheFoot) {
  const SweepRun run = complete_seen(
      "vase", "vase_template", Eigen::Vector3d(0.962968588283511, 0.6730982289777777, -3.2195233745525553),
      Eigen::Vector3d(0.000452578067779541, 0.00041823089122772217, 0.49999152904274524), {.scan_file = true});
  expect_scores(run, "vase from (0.25, 0.17, -0.95)", 0.98, 0.7);
}

// From below the scan sees each bead's lower half; the upper halves are unseen everywhere but where the ring turns
// towards the scanner. The turns of the scan by its repeats fill them (on the sweep's scan, unseen-detail 0.68 ->
// 0.81; 0.73 measured on this one).
TEST(Vase, SeenFromBelowTheBeadsHiddenHalvesAreFilledByTheScansTurns) {
  const SweepRun below = complete_from("vase", "vase_template", Eigen::Vector3d(0.35, -0.25, -1.0));
  std::printf("vase from below: F %.3f unseen-detail %.3f, %d samples filled by turns\n", below.result.fscore,
              below.result.unseen_detail_recall.value_or(0), below.report["synthesis"]["repeat_fill"].get<int>());
  EXPECT_GT(below.report["synthesis"]["repeat_fill"].get<int>(), 0);
  EXPECT_GE(below.result.fscore, 0.98);
  EXPECT_GE(below.result.unseen_detail_recall.value_or(0), 0.7);
}

// From above the gear's back wall is seen in a strip: 41-56% of it was missed (unseen-detail 0.47). Its 20 teeth
// repeat every 18 degrees, and the scan's turns fill the wall (on the sweep's scan F 0.972, unseen-detail 0.90; here
// 0.978 and 0.998).
TEST(Gear, SeenFromAboveTheBackWallIsFilledByTheScansTurns) {
  expect_scores(complete_from("gear", "gear_template", Eigen::Vector3d(0.25, -0.35, 1.0)), "gear from above", 0.95,
                0.85);
}

// Seen from behind and above, the table's legs show their front halves; their backs were labelled for template copies
// or a vertical flip, and their bulbs were missed (unseen-detail 0.65 on the sweep). Each leg is a body of revolution
// about its own axis (a part symmetry of the template), and the scan's samples in it fit themselves under its turns:
// the turns fill the backs (0.90 on the sweep; F 0.998, unseen-detail 0.986 and 3 legs on this scan).
TEST(TableLegs, SeenFromBehindTheLegsBacksFillWithTheirOwnTurns) {
  const SweepRun behind = complete_from("table", "table_template", Eigen::Vector3d(-0.7, 0.7, 0.5));
  int legs = 0;
  for (const auto& r : behind.report["synthesis"]["repeats"]) legs += r["revolution"].get<bool>();
  std::printf("table from behind: F %.3f unseen-detail %.3f, %d legs filled by their turns\n", behind.result.fscore,
              behind.result.unseen_detail_recall.value_or(0), legs);
  EXPECT_GE(legs, 2);
  EXPECT_GE(behind.result.fscore, 0.95);
  EXPECT_GE(behind.result.unseen_detail_recall.value_or(0), 0.8);
}

// The table from the side, exactly on its template (the scan read from a file, as the sweep does; the exact box's eye
// does not show it): the registration offset fitted to the legs' turned images was 1.55 cm across the seen legs,
// which laid the turned images of the legs' far halves onto their near halves (F 0.793, unseen-detail 0.16). The
// offset undoes the relief's pull on a registration; where no registration moved the scan, none is fitted.
TEST(TableLegs, SeenFromTheSideInItsOwnPoseNoRegistrationOffsetIsFitted) {
  const SweepRun side =
      complete_seen("table", "table_template", Eigen::Vector3d(3.510452461245696, 0, 1.2578416338197989),
                    kSweepTableCentre, {.own_pose = true, .scan_file = true});
  const auto& offset = side.report["synthesis"]["registration_offset"];
  for (int i = 0; i < 3; ++i) EXPECT_EQ(offset[i].get<double>(), 0.0);
  expect_scores(side, "table from the side, in its own pose", 0.95, 0.85);
}

// A box that is not square (0.8 x 0.5 x 0.6) with ribs on its four sides. Its 8-vertex template has half turns only,
// so seen from the front its short sides were copied plain (F 0.851 under template blending's 0.869, unseen-detail
// 0.52, measured on the same box built outside the repository); the turns between its faces (symmetry.face_turns)
// carry the long side's ribs onto them, centred. Seen from the side, the short side's ribs reach the long sides'
// middle.
TEST(RibbedBox, SeenFromTheFrontItsShortSidesTakeTheLongSidesRibs) {
  const Eigen::Vector3d front(0.0, -1.0, 0.2);
  const SweepRun with = complete_from("ribbed_box", "ribbed_box_template", front);
  const SweepRun without = complete_from("ribbed_box", "ribbed_box_template", front, {.face_turns = false});
  std::printf("ribbed box from the front: F %.3f unseen-detail %.3f | without face turns: F %.3f unseen-detail %.3f\n",
              with.result.fscore, with.result.unseen_detail_recall.value_or(0), without.result.fscore,
              without.result.unseen_detail_recall.value_or(0));
  EXPECT_GE(with.result.fscore, 0.95);
  EXPECT_GE(with.result.unseen_detail_recall.value_or(0), 0.9);
  EXPECT_LT(without.result.unseen_detail_recall.value_or(0), 0.7);
  expect_scores(complete_from("ribbed_box", "ribbed_box_template", Eigen::Vector3d(1.0, 0.0, 0.25)),
                "ribbed box from the side", 0.95, 0.8);
}

// Seen obliquely from the front, the ribbed box's floor takes its plain lid, flipped end over end. That image has no
// detail of its own to fit; only its ring (the sides' top strips, turned upside down onto the plinth) overlapped
// detail, and fitting that slid the flipped lid 1.5 cm along the floor and tilted it 0.75 degrees (F 0.877, template
// blending 0.905). A plain image keeps the analogy's transform.
TEST(RibbedBox, SeenObliquelyItsFlippedLidStaysOnItsFloor) {
  const SweepRun run =
      complete_from("ribbed_box", "ribbed_box_template", Eigen::Vector3d(0.6, -0.8, 0.4), {.scan_file = true});
  expect_scores(run, "ribbed box from the front obliquely", 0.95, 0.9);
}

// The ribbed box seen from the side, completed with its bounding box (`box:` of its mesh, which stands the ribs' height
// off its plain sides). The short side's ribs, turned centre onto centre, reach only the middle of the long sides;
// their ends were copied plain from the box, at the ribs' height (here F 0.769, unseen-detail 0.525 without the
// shifts). The turn shifted along the short side by the scan's own repeat (two ribs, 0.2) carries them, in phase with
// the middle (0.968 / 0.987).
TEST(RibbedBox, SeenFromTheSideWithItsBoundingBoxTheLongSidesEndsTakeRibsInPhase) {
  const SweepRun run = complete_from("ribbed_box", "", Eigen::Vector3d(1.0, 0.0, 0.25), {.box_template = true});
  expect_scores(run, "ribbed box from the side, box: template", 0.95, 0.95);
  EXPECT_EQ(run.report["output"]["copied_points"].get<Index>(), 0);
}

// The ribbed box seen square on its long side from a little below (a held-out view): its ribs and plinth turned ICP's
// pose 0.8 degrees off its own, more than the relief's turn allowed, and every turned image landed off the unseen
// walls (F 0.661, unseen-detail 0.58, under template blending's 0.908). Within the relief's thickness, it keeps its
// pose (0.956 / 0.956 here). And with `box:` of its mesh from above, where ICP slid it 1.7 cm (the held-out scan
// F 0.742 / 0.11; here 0.943 / 0.728).
TEST(RibbedBox, SeenSquareOnItsLongSideFromALittleBelowTheScanKeepsItsOwnPose) {
  const SweepRun run = complete_from("ribbed_box", "ribbed_box_template", Eigen::Vector3d(-0.19, -0.97, -0.16));
  EXPECT_TRUE(run.report["correspondence"]["kept_input_pose"].get<bool>());
  expect_scores(run, "ribbed box square on its long side from a little below", 0.95, 0.9);
  const SweepRun above = complete_from("ribbed_box", "", Eigen::Vector3d(0.25, -0.35, 1.0), {.box_template = true});
  EXPECT_TRUE(above.report["correspondence"]["kept_input_pose"].get<bool>());
  expect_scores(above, "ribbed box from above, box: template", 0.92, 0.7);
}

// The ribbed box drawn y-up, as many meshes are, with `box:` of its mesh, seen from the side. A box with three
// different sides has three half-turn axes alike; up was taken to be +z, here its front-back axis, and the cap rule,
// the upright turns and the quarter preference then favoured turns that tip it over (F 0.745, unseen-detail 0.28, on
// the sweep's scan turned y-up; 0.969 / 0.99 z-up). Up is now the axis whose faces the scan shows plainest, its lid
// and floor (plain_faces.h).
TEST(RibbedBox, DrawnYUpItsUpIsTheAxisOfItsPlainLidAndFloor) {
  const SweepRun run = complete_from("ribbed_box", "", Eigen::Vector3d(1.0, 0.0, 0.25),
                                     {.scan_file = true, .box_template = true, .turned = kToYUp});
  expect_scores(run, "ribbed box drawn y-up, from the side, box: template", 0.95, 0.95);
}

// The ribbed box drawn y-up, seen level with a corner, and square on its short side: no lid in view, so the plain lid
// gives no up, and +z, its front-back axis, tipped it over (F 0.736 and 0.611, unseen-detail 0.75 and 0.35). Up is
// now the axis whose faces the scan does not show where it shows two sides, else the axis the box stands on the
// origin's plane along, as drawn (plain_faces.h, ground.h): F 0.957 and 0.970.
TEST(RibbedBox, DrawnYUpAndSeenLevelItsUpIsTheAxisOfTheFacesUnseenElseOfItsGround) {
  const RunChoice y_up{.scan_file = true, .box_template = true, .turned = kToYUp};
  const SweepRun corner = complete_from("ribbed_box", "", Eigen::Vector3d(1, -1, 0.05), y_up);
  EXPECT_EQ(corner.report["symmetry"]["up_from"].get<std::string>(), "unseen_faces");
  expect_scores(corner, "ribbed box drawn y-up, level with a corner", 0.95, 0.6);
  const SweepRun square_on = complete_from("ribbed_box", "", Eigen::Vector3d(1, 0.01, 0.02), y_up);
  EXPECT_EQ(square_on.report["symmetry"]["up_from"].get<std::string>(), "ground");
  expect_scores(square_on, "ribbed box drawn y-up, square on its short side", 0.95, 0.9);
}

// The ribbed box standing turned in the scan's frame (30 degrees about z, then 20 about x), as a scanner leaves it,
// with `box:` of its mesh (square to its faces), seen from the side. The vote space's translations were measured in
// units of the world's bounding box, 44% larger for the turned box than for the box itself: modes merged across
// motions, and scaled flips about its diagonals took its far side (F 0.788, unseen-detail 0.29; 0.969 / 0.99 drawn
// square to the world). The vote space is now sized in the box's own axes, as eq. 9's axis rotations are.
TEST(RibbedBox, StandingTurnedInTheScansFrameItsSidesTakeItsOwnTurns) {
  const Eigen::Matrix3d turn = (Eigen::AngleAxisd(20 * M_PI / 180, Eigen::Vector3d::UnitX()) *
                                Eigen::AngleAxisd(30 * M_PI / 180, Eigen::Vector3d::UnitZ()))
                                   .toRotationMatrix();
  const SweepRun run = complete_from(
      "ribbed_box", "", Eigen::Vector3d(1.0, 0.0, 0.25),
      {.scan_file = true, .box_template = true, .turned = Similarity{turn, Eigen::Vector3d::Zero(), 1.0}});
  expect_scores(run, "ribbed box standing turned, from the side, box: template", 0.95, 0.95);
}

// The ribbed box in its bounding box drawn turned 10 degrees about the vertical through its centre, then 3 about the
// horizontal (a user's box, not quite square to the scan), seen from the side. ICP's turn is right, but the ribs pulled
// its move 2 cm through the box, and the far short side and the long sides landed off the model (F 0.331,
// unseen-detail 0.06; 0.969 / 0.99 in the box square to the scan). The scan is now turned in place about the box's
// centroid, flat on the layer its ribs' tops lay on the box (correspond's turned_in_place).
TEST(RibbedBox, InABoxDrawnTurnedOffTheScanItsSidesTakeItsRibs) {
  const PointSet ribbed = make_shape("ribbed_box");
  const BoundingBox b = bounding_box(ribbed.positions());
  const Eigen::Vector3d centre = (b.min + b.max) / 2;
  const Eigen::Matrix3d turn = (Eigen::AngleAxisd(3 * M_PI / 180, Eigen::Vector3d::UnitX()) *
                                Eigen::AngleAxisd(-10 * M_PI / 180, Eigen::Vector3d::UnitZ()))
                                   .toRotationMatrix();
  const SweepRun run = complete_from("ribbed_box", "", Eigen::Vector3d(1.0, 0.0, 0.25),
                                     {.scan_file = true, .box_drawn = Similarity{turn, centre - turn * centre, 1.0}});
  EXPECT_TRUE(run.report["correspondence"]["turned_in_place"].get<bool>());
  expect_scores(run, "ribbed box in a box drawn turned, from the side", 0.95, 0.95);
}

// The crate in a box drawn 8% shorter (0.6 x 0.6 x 0.736), standing on its floor, seen from seed 7070's eye 4 degrees
// above level (`--random-views 6 --view-seed 7070`'s r0): the crate's front lays 46% of the scan on that box at any
// scale from 1.08 up, a few points more or fewer as their nearest samples change. The box was scaled 1.12, its top
// 2.4 cm over the crate's (F 0.896); scaled to where the scan ends, 1.09, the lid lands on the crate's.
TEST(Crate, SeenNearlyLevelInABoxDrawnShorterItsTopLandsWhereTheScanEnds) {
  PointSet shorter = make_lowpoly_box(Eigen::Vector3d(0.6, 0.6, 0.736), Eigen::Vector3d(0, 0, 0.368));
  Matrix3Xi faces(3, 12);  // bench/heldout_shapes.py's triangles, which its samples follow
  faces << 0, 1, 4, 5, 0, 1, 2, 3, 0, 2, 1, 3, 2, 2, 5, 7, 1, 5, 6, 6, 4, 4, 3, 7, 1, 3, 6, 6, 4, 4, 3, 7, 2, 6, 5, 5;
  shorter.set_faces(std::move(faces));
  const SweepRun run =
      complete_seen("crate", "", Eigen::Vector3d(0.3240109580554123, -3.1162858609166, 0.6190233231882822),
                    Eigen::Vector3d(0, 0, 0.4), {.scan_file = true, .drawn_template = shorter});
  EXPECT_NEAR(run.report["correspondence"]["template_scale"][2].get<double>(), 0.8 / 0.736, 0.01);
  expect_scores(run, "crate in a box drawn 8% shorter, 4 degrees above level", 0.95, 0.9);
}

// A sparse scan (160 by 160 rays, some 6000 points, fewer than the template's samples, so used as they are): seen from
// the front, 11 degrees above the lid, the lid comes as scan rows 11 cm apart, 3 mm between points along each. Every
// lid point's neighbours lay on its own row, PCA turned its normal anywhere about the row, and the lid no longer
// looked plain: the box's up was read as its front-back axis, the lid's quarter turns filled the short sides with its
// few rows, and the box scored F 0.865, unseen-detail 0.39 (0.963 / 0.99 from the dense scan). Such normals now keep
// the scanner's own (features).
TEST(RibbedBox, ASparseScanFromTheFrontStillReadsItsUpFromThePlainLid) {
  const SweepRun run = complete_from("ribbed_box", "ribbed_box_template", Eigen::Vector3d(0.0, -1.0, 0.2),
                                     {.scan_file = true, .resolution = 160});
  expect_scores(run, "ribbed box, a sparse scan from the front", 0.95, 0.95);
}

// The same sparse scan from above, in the box's bounding box: the lid holds most of the scan's points, one long side's
// rib tops 8% of it, and ICP slid the scan 2 cm off the box to lay its walls between the ribs on the box (F 0.627,
// unseen-detail 0.07). Pushing a twentieth of the scan through a box that bounds it as given marked ICP's move as the
// relief's pull, and the scan was turned in place (correspond's pushed_through_its_bounding_template; F 0.879,
// unseen-detail 0.599). Since stop 66 the box, scaled 0.93 across its ribs' depth, lays as much of the scan in its own
// pose on itself as ICP's slide does, and ICP on the scaled box holds it: the scan keeps its own pose (0.885 / 0.611).
// Either way ICP's slide is not taken.
TEST(RibbedBox, ASparseScanFromAboveIsNotSlidOffItsBoundingBox) {
  const SweepRun run = complete_from("ribbed_box", "", Eigen::Vector3d(0.25, -0.35, 1.0),
                                     {.scan_file = true, .box_drawn = Similarity{}, .resolution = 160});
  EXPECT_TRUE(run.report["correspondence"]["turned_in_place"].get<bool>() ||
              run.report["correspondence"]["kept_input_pose"].get<bool>());
  expect_scores(run, "ribbed box, a sparse scan from above, in its bounding box", 0.85, 0.5);
}

// The ribbed box seen square on its short side (a random view, `--random-views 6 --view-seed 2026`), where the scan
// sees one side and nothing of the lid or the floor. Four faults stacked up (F 0.815, under template blending's
// 0.880): the quarter turns about the horizontal, the votes' best supported, laid the side's ribs on the plain lid
// and floor; the free fits of the quarter turns about the vertical turned the long sides' images 25 degrees off the
// box to fit a sliver of overlap; the phase search along a long side scored pairs across the corner, whose planes
// face 90 degrees apart, and slid the ribs half a period; and from eyes a centimetre away (F 0.973-0.977) the far
// short side took the near one flipped end over end, its plinth band at the top, since the half turn about the
// vertical, which explains the same samples, lost the duplicate rule to the flip by a few samples of support. Now a
// transform that tips the box onto its side is not feasible on its caps (label), a free fit that carries a region
// off a template that fits the scan is not taken, only pairs facing alike count in the misfit (synthesize), and the
// upright compositions of the found transforms are kept as preferred (symmetry's upright_turns).
TEST(RibbedBox, SeenSquareOnItsShortSideItsCapsStayPlainAndItsLongSidesRibsInPhase) {
  const SweepRun run = complete_from("ribbed_box", "ribbed_box_template",
                                     Eigen::Vector3d(-0.9994968097031638, 0.00660178683098511, 0.03102489006968315),
                                     {.scan_file = true});
  expect_scores(run, "ribbed box square on its short side", 0.98, 0.93);
  for (const auto& t : run.report["transforms"]) {
    if (t["labelled"].get<Index>() == 0) continue;
    const double up_after = t["rotation"][2][2].get<double>();  // the up direction's height after the turn
    EXPECT_GT(std::abs(up_after), 0.5) << "label " << t["label"] << " tips the box onto its side";
  }
}

// A beaded ring (a torus with beads on its outer equator, a shape class the sweep did not have) seen from above: its
// underside is the seen top turned end over end about a horizontal axis. On a held-out ring of this kind ICP turned
// the scan 1.1 degrees about the ring's axis (a free motion of a torus), and the registration offset fitted to the
// turned images put 7 mm on its height, raising the turned image by twice that: the underside stood 1 cm above the
// ground (F 0.876, under template blending's 0.933), though 95% of the exemplar's samples facing up sat on the
// torus as registered. An offset that would take that much of the exemplar's plain part off the template is no longer
// applied (takes_plain_part_off in synthesize.cpp): here F 0.613, unseen-detail 0.373 before, 1.000 / 0.987 now.
TEST(BeadedRing, SeenFromAboveItsUndersideLiesOnTheGround) {
  const SweepRun run = complete_from("beaded_ring", "ring_template", Eigen::Vector3d(0.25, -0.35, 1.0));
  expect_scores(run, "beaded ring from above", 0.98, 0.9);
}

// The vase in the plainest template a user has: a closed cylinder of its height (radius 0.33; the vase runs 0.28-0.40
// about it). ICP fitted the scan's bulge to the cylinder by tilting it about 10 degrees, 11 cm off the axis at its
// foot, and the turned images stood askew on the unseen side (F 0.594, unseen-detail 0.42 from the front); the scan's
// own axis of revolution is now laid on the cylinder's (correspond.cpp, onto_template_axis), and, as it spans the
// cylinder's height, at its height: ICP's stood it 3.4 cm up, and the cylinder's wall was copied below the vase's foot
// (F 0.892, now 0.912). The cylinder's caps are copied over the vase's open ends, so F stays under the procedural
// floors.
TEST(VaseInACylinder, SeenFromTheFrontItsBackGetsFlutesAndBeads) {
  const SweepRun run = complete_from("vase", "vase_cylinder", Eigen::Vector3d(0, -1, 0.2));
  EXPECT_TRUE(run.report["correspondence"]["laid_on_axis"].get<bool>());
  expect_scores(run, "vase in a plain cylinder from the front", 0.9, 0.95);
}

// The same vase in its cylinder seen from below: the scan stands off the cylinder (99% of it more than half an alpha),
// and its flips' free fits carry their images 13-25 alpha off it, onto the placed images. Held to the cylinder as a
// flip on a template that fits its scan is (the medallion barrel below), F is 0.681 and unseen-detail 0.674 here (0.633
// / 0.674 before banded_relief; 0.626 / 0.69 in the sweep, whose bounding box differs a little), free 0.729 /
// 0.696. A flip is held to the template only where the template fits the scan (template_fits_exemplar). Since stop 60
// the flips end over end that the scan's own radii refute are dropped (symmetry/profile.h; the foot's beads went round
// the lip): 0.747 / 0.673, measured with stop 60's code and stop 62's.
TEST(VaseInACylinder, SeenFromBelowTheFlipsFollowThePlacedImagesOffTheCylinder) {
  const SweepRun run = complete_from("vase", "vase_cylinder", Eigen::Vector3d(0.35, -0.25, -1.0));
  EXPECT_GT(run.report["symmetry"]["refuted_by_scan_profile"].get<Index>(), 0);
  expect_scores(run, "vase in a plain cylinder from below", 0.72, 0.66);
}

// The vase as a vessel (a wall 3 cm thick and a floor) in its plain closed cylinder, seen from the sweep's view above:
// the scan shows the cup's inside through its mouth, where the cylinder's lid was copied before stop 74, a disk of 1447
// points floating in the mouth (F 0.814 here). The scanner saw the inside through the lid, so the lid is not copied
// there (F 0.820; 0.833 in the sweep, whose bounding box differs a little).
TEST(CupInACylinder, SeenFromAboveTheCylindersLidIsNotCopiedOverTheMouth) {
  const SweepRun run = complete_from("cup", "vase_cylinder", Eigen::Vector3d(0.25, -0.35, 1.0));
  EXPECT_GT(run.report["synthesis"]["seen_through_uncopied"].get<Index>(), 300);
  Index in_mouth = 0;  // within 0.2 of the axis, above the floor: the cup has nothing there (its mouth is 0.28 wide)
  for (Index i = 0; i < run.output.size(); ++i) {
    const Eigen::Vector3d p = run.output.positions().col(i);
    in_mouth += p.z() > 0.5 && p.head<2>().norm() < 0.2;
  }
  EXPECT_LT(in_mouth, 50);
  expect_scores(run, "cup in a plain cylinder from above", 0.81, 0.72);
}

// The fluted column (16 flutes) in its 24-gon template, seen from the seeded random view (-0.61, -0.43, 0.67) of the
// sweep (`--random-views 6 --view-seed 777`, its exact eye). The scan repeats about the template's axis, and
// synthesize turns every image to those repeats: the labelling's preference for quarter and half turns
// (label.quarter_unary) would only move regions between turns that are alike, and it moved a seam onto the flutes
// (F 0.987 -> 0.933, flutes doubled along it). The engine drops the preference where the scan repeats.
TEST(FlutedColumn, SeenFromAboveBehindTheLeftTheScansRepeatsKeepItsLabelsAsTheyWere) {
  const SweepRun run = complete_seen(
      "column", "column_template24", Eigen::Vector3d(-2.315751799090191, -1.6485870260024271, 3.138629734544534),
      Eigen::Vector3d(5.558133125305176e-06, 2.03549861907959e-05, 0.6000000238418579), {.scan_file = true});
  expect_scores(run, "24-gon column from (-0.61, -0.43, 0.67)", 0.98, 0.9);
}

// The same view with the 16-gon mesh template: the plain bottom cap, flipped from the top with a sliver of fluted rim,
// turns about an axis its slippage placed 3 cm off the column's, and about that axis the scan "repeated" thrice (its
// flat top does about any axis through it): the repeats' fill laid turned copies of the flutes 5 cm off the column, 1.2
// cm proud of the model over a third of the far side (F 0.963, unseen-detail 0.83). A region turning along the
// template's own axis now turns about that axis (turning_axis in synthesize.cpp): the scan repeats there 16 times only.
TEST(FlutedColumn, SeenFromAboveBehindTheLeftTheBottomCapTurnsAboutTheColumnsAxis) {
  const SweepRun run = complete_seen(
      "column", "column_template", Eigen::Vector3d(-2.315751799090191, -1.6485870260024271, 3.138629734544534),
      Eigen::Vector3d(5.558133125305176e-06, 2.03549861907959e-05, 0.6000000238418579), {.scan_file = true});
  for (const auto& r : run.report["synthesis"]["repeats"]) EXPECT_EQ(r["order_above_cut"].get<int>(), 16);
  expect_scores(run, "16-gon column from (-0.61, -0.43, 0.67)", 0.985, 0.93);
}

// The triangular prism seen from low in front (a view drawn by `--random-views 6 --view-seed 4747`): the scan sees one
// side and the bottom. The side turned by 120 degrees onto a far side overlaps the images placed before it only along
// the creases and the caps, which are plain; the refinement's free fit slid it 2.2 alpha along that side for a 3% lower
// misfit, and its medallion and bands stood off the model's (F 0.923, under template blending's 0.938). Such a fit is
// no longer taken (slides_on_plain in synthesize.cpp): every label keeps its turn within an alpha.
TEST(TriangularPrism, SeenFromLowInFrontTheTurnedSidesKeepTheirMedallionsInPlace) {
  const SweepRun run = complete_from("medallion_prism", "prism_template", Eigen::Vector3d(0.097, -0.605, -0.790));
  const double spacing = run.report["inputs"]["scan"]["spacing"].get<double>();
  for (const auto& shift : run.report["synthesis"]["refinement_shift"]) EXPECT_LT(shift.get<double>(), spacing);
  expect_scores(run, "triangular prism from low in front", 0.97, 0.9);
}

// The triangular prism seen from above the front (a view drawn by `--random-views 6 --view-seed 2027`): its back and
// floor take the seen top and sides flipped end over end about a horizontal axis, a region with no slippable motion.
// Its free fit slid it 1.5 cm (1.8 alpha) up the sides for a 15% lower misfit of its bands, and lifted the floor 1.45
// cm off the ground (F 0.879, under template blending's 0.932; from (-0.20, -0.74, 0.64) it scored 0.991). A flip
// that turns the object's up end over end is now pinned to the template there, as a flip across the axis it turns
// about is, its landing counted within an alpha (`overturned` in synthesize.cpp).
TEST(TriangularPrism, SeenFromAboveTheFrontItsFlippedFloorStaysOnTheGround) {
  const SweepRun run =
      complete_from("medallion_prism", "prism_template",
                    Eigen::Vector3d(-0.10320343562615121, -0.751465712096989, 0.6516504695137755), {.scan_file = true});
  expect_scores(run, "triangular prism from above the front", 0.97, 0.85);
}

// The barrel with four medallions, completed with its own body of revolution, seen from nearly straight below (a view
// drawn by `--random-views 6 --view-seed 777`): the scan sees the bottom and the lower halves of the sides. The bottom
// flipped end over end onto the top turns about the axis; the free fit against the placed sides tilted it off the
// top, 4.9 alpha beyond its turn, and 5% of the output stood off the top's rim (F 0.958). Where the template fits the
// scan (9% of it stands off the barrel's body), a flip's free fit beyond its turn that lands a tenth less of it on the
// template is no longer taken (leaves_template in synthesize.cpp).
TEST(MedallionBarrel, SeenFromBelowTheBottomFlippedOntoTheTopStaysOnTheTemplate) {
  const SweepRun run = complete_seen(
      "medallion_barrel", "", Eigen::Vector3d(1.1881211689713025, 0.830184026151, -4.091470731991851),
      Eigen::Vector3d(-3.4868717193603516e-05, -0.00019052624702453613, 0.5), {.scan_file = true, .revolution = true});
  const double spacing = run.report["inputs"]["scan"]["spacing"].get<double>();
  for (const auto& shift : run.report["synthesis"]["refinement_shift"]) EXPECT_LT(shift.get<double>(), 2 * spacing);
  expect_scores(run, "medallion barrel from (0.25, 0.17, -0.95)", 0.98, 0.7);
}

// A completion with both baselines beside it: the scan alone and template blending.
struct BaselinedRun {
  SweepRun run;
  EvalResult scan_only, blend;
};

// `model` seen along `view` as the sweep sees it (2.6 diagonals out, 480 by 480 at 30 degrees), its scan read from a
// PLY file as bench/robustness.py passes it, completed with template `templ` (an input spec) and scored against the
// model beside the scan alone and template blending; its files in `dir`.
BaselinedRun complete_scan_of(const PointSet& model, const std::string& templ, const Eigen::Vector3d& view,
                              const test::TempDir& dir) {
  setup_logging(false, true);
  const PointSet scan = virtual_scan(model, test::sweep_camera(model, view)).points;
  write_ply(dir / "scan.ply", scan);
  RunConfig c;
  c.mode = RunMode::kCompletion;
  c.inputs = {test::input(Role::kScan, parse_input((dir / "scan.ply").string())),
              test::input(Role::kTemplate, parse_input(templ))};
  c.output_dir = dir / "out";
  run(c);
  const PointSet output = read_point_set(dir / "out" / "output.ply").points;
  std::ifstream in(dir / "out" / "report.json");
  const PointSet plain = load_input(parse_input(templ)).points;
  const double tau = 0.01 * bounding_box(model.positions()).diagonal();
  return {{evaluate(output, model, {}, &scan, &plain), nlohmann::json::parse(in)},
          evaluate(scan, model, {}, &scan, &plain),
          evaluate(template_blend(scan, plain, 2 * tau, {}), model, {}, &scan, &plain)};
}

// The scanned square pillar (../shared/data, drawn y-up, standing on y = 0: relief on its four sides, a capital and a
// base; its bounding box 0.20 by 0.24 across, 0.38 high) with `box:` of its mesh.
BaselinedRun pillar_seen_along(const Eigen::Vector3d& view) {
  const auto path = test::shared_data() / "models" / "threedscans_Column03.obj";
  test::TempDir dir;
  return complete_scan_of(read_point_set(path).points, "box:" + path.string(), view, dir);
}

void expect_up_y_and_above_both_baselines(const BaselinedRun& p, const char* what, const char* up_from) {
  std::printf("%s: F %.3f unseen-detail %.3f | scan only F %.3f | template blend F %.3f\n", what, p.run.result.fscore,
              p.run.result.unseen_detail_recall.value_or(0), p.scan_only.fscore, p.blend.fscore);
  const auto& symmetry = p.run.report["symmetry"];
  EXPECT_EQ(symmetry["up_from"].get<std::string>(), up_from);
  EXPECT_GT(symmetry["up"][1].get<double>(), 0.999);
  EXPECT_GT(p.run.result.fscore, p.scan_only.fscore + 0.03);
  EXPECT_GT(p.run.result.fscore, p.blend.fscore + 0.1);
}

// Seen level with a corner (the first case): its box is not square, so its symmetry gives no up, and the scan
// shows two sides and neither the lid nor the floor. Up was +z, its front-back axis, and the quarter turns about it
// laid the sides' relief on the lid and floor (F 0.469, unseen-detail 0.36, under the scan alone's 0.543). Up is now
// the axis whose faces the scan does not show (plain_faces.h): F 0.603; and the scan, which touches its box only with
// its capital's and base's edges, keeps its own pose, where ICP turned it: F 0.720, unseen-detail 0.54.
TEST(Pillar, SeenLevelWithACornerItsUpIsTheAxisWhoseFacesTheScanDoesNotShow) {
  SCANFILL_REQUIRE_SHARED_DATA();
  expect_up_y_and_above_both_baselines(pillar_seen_along(Eigen::Vector3d(1, 0.05, 1)), "pillar, level with a corner",
                                       "unseen_faces");
}

// Seen square on a side (a view drawn by `--random-views 6 --view-seed 2026`): one side, no lid. Its panel lies up to
// 10 spacings inside the box, and only its capital and base (16% of the scan) lay within escape_distance of it, so
// correspond refused it as not overlapping its template; let through, its up was +z and its relief went onto its lid
// and floor (F 0.439, under the scan alone's 0.502). A scan its template bounds now lies as near as the inputs had to
// before registration, and the pillar's up is the axis it stands on the ground along (ground.h): F 0.684,
// unseen-detail 0.58.
TEST(Pillar, SeenSquareOnASideItIsCompletedAndItsUpIsTheAxisItStandsOn) {
  SCANFILL_REQUIRE_SHARED_DATA();
  const BaselinedRun p = pillar_seen_along(Eigen::Vector3d(-1.0, 0.03, -0.01));
  expect_up_y_and_above_both_baselines(p, "pillar, square on a side", "ground");
}

// The real Vase-Lion (../shared/data, z up: its body bulging, a narrow neck, lion heads 12 cm proud) seen from the
// sweep's front, with a plain 24-sided closed cylinder a user might draw about it (radius 0.30, its height): 77% of
// the scan lies inside the cylinder as given, and ICP balanced it across the wall, tilting it 14 degrees and moving it
// 15 cm for 1.4% more of it on the cylinder; every image turned about the cylinder's axis stood askew (F 0.442). It
// keeps its own pose now (F 0.485; 0.552 where the cylinder is not copied around the neck and over the lip, where the
// scan's radii put the vase elsewhere), still under the scan alone's 0.596.
TEST(VaseLion, InAPlainCylinderSeenFromTheFrontTheScanIsNotTiltedAcrossTheWall) {
  SCANFILL_REQUIRE_SHARED_DATA();
  const auto path = test::shared_data() / "models" / "vaselion.obj";
  test::TempDir dir;
  write_ply(dir / "cylinder.ply", make_lowpoly_cylinder(0.30, -0.499072, 0.998597, 24));
  const BaselinedRun p =
      complete_scan_of(read_point_set(path).points, (dir / "cylinder.ply").string(), Eigen::Vector3d(0, -1, 0.2), dir);
  std::printf("Vase-Lion in a cylinder, front: F %.3f | scan only F %.3f\n", p.run.result.fscore, p.scan_only.fscore);
  const auto& rigid = p.run.report["correspondence"]["rigid"]["rotation"];
  EXPECT_GT(rigid[2][2].get<double>(), std::cos(3.0 * M_PI / 180));  // the cylinder's axis, z, not tilted
  EXPECT_GT(p.run.result.fscore, 0.47);
}

// The real text2mesh vase (../shared/data, drawn y-up: a wide body, a narrow neck 0.6-1.0 from its axis) seen from
// the sweep's front, with a plain 24-sided closed cylinder a user might draw about it (radius 3.45, its height): no
// image of the scan reaches the cylinder's wall around the neck, 2.4 to 2.9 units off the neck's radius, nor its lid,
// and both were copied plain (43882 copied points, 1% of them within the F-score's threshold: F 0.659, over the scan
// alone's 0.609). The scan's radii about the cylinder's axis put the object's wall elsewhere there, and the template
// is not copied where they do: F 0.808.
TEST(TextToMeshVase, InAPlainCylinderSeenFromTheFrontItsNeckIsNotWrappedInTheCylinder) {
  SCANFILL_REQUIRE_SHARED_DATA();
  const auto path = test::shared_data() / "models" / "text2mesh_vase.obj";
  test::TempDir dir;
  const Similarity about_y{kToYUp.rotation, Eigen::Vector3d(-0.05, 0, 105.79), 1.0};
  write_ply(dir / "cylinder.ply", transformed(make_lowpoly_cylinder(3.45, -0.11795, 11.57313, 24), about_y));
  const BaselinedRun p =
      complete_scan_of(read_point_set(path).points, (dir / "cylinder.ply").string(), Eigen::Vector3d(0, 0.2, 1), dir);
  std::printf("text2mesh vase in a cylinder, front: F %.3f | scan only F %.3f | %d samples not copied\n",
              p.run.result.fscore, p.scan_only.fscore, p.run.report["synthesis"]["off_profile_uncopied"].get<int>());
  EXPECT_GT(p.run.report["synthesis"]["off_profile_uncopied"].get<int>(), 1000);
  EXPECT_GT(p.run.result.fscore, 0.75);
  EXPECT_GT(p.run.result.fscore, p.scan_only.fscore + 0.1);
}

// A box of `size` standing on z = 0 whose four sides carry `rows` by `columns` round knobs (Gaussian bumps `knob` high
// and wide, evenly spaced): a shape no node of scanfill draws, a user's box with relief.
PointSet knobbed_box(const Eigen::Vector3d& size, int rows, int columns, double knob) {
  PointSet box = make_box(size, 160);
  Eigen::Matrix3Xd p = box.positions();
  // u across a side `width` wide, v up it, both in [0, 1].
  const auto height = [&](double u, double v, double width) {
    double h = 0;
    for (int r = 0; r < rows; ++r)
      for (int c = 0; c < columns; ++c) {
        const double du = (u - (c + 1.0) / (columns + 1)) * width, dv = (v - (r + 1.0) / (rows + 1)) * size.z();
        h += knob * std::exp(-(du * du + dv * dv) / (knob * knob));
      }
    return h;
  };
  for (Eigen::Index i = 0; i < p.cols(); ++i) {
    const Eigen::Vector3d x = p.col(i);
    for (int axis : {0, 1}) {
      const int across = 1 - axis;
      if (std::abs(std::abs(x(axis)) - size(axis) / 2) > 1e-9) continue;
      p(axis, i) +=
          std::copysign(height(x(across) / size(across) + 0.5, x.z() / size.z() + 0.5, size(across)), x(axis));
    }
    p(2, i) += size.z() / 2;
  }
  box.set_positions(std::move(p));
  return box;
}

// The knobbed box seen from behind, level (-1, 0.03, 0.25), with a plain 8-vertex box at its walls: ICP moves the
// scan under half a spacing, the template fits it, and its quarter and half turns about the vertical are the box's own
// symmetries. Fitted freely to the grazing knobs the scan saw on the neighbouring sides, three of them turned 1.0-1.9
// degrees off the box (F 0.863, unseen-detail 0.856, under template blending's 0.944); the template pins them now
// (0.983 / 0.987).
TEST(KnobbedBox, SeenFromBehindItsTurnsStayOnTheBox) {
  const Eigen::Vector3d size(0.6, 0.6, 0.9);
  const PointSet model = knobbed_box(size, 4, 3, 0.035);
  test::TempDir dir;
  write_ply(dir / "box.ply", make_lowpoly_box(size, Eigen::Vector3d(0, 0, size.z() / 2)));
  const BaselinedRun p = complete_scan_of(model, (dir / "box.ply").string(), Eigen::Vector3d(-1, 0.03, 0.25), dir);
  std::printf("knobbed box from behind: F %.3f unseen-detail %.3f | template blend F %.3f\n", p.run.result.fscore,
              p.run.result.unseen_detail_recall.value_or(0), p.blend.fscore);
  for (const auto& deg : p.run.report["synthesis"]["refinement_deg"]) EXPECT_LT(deg.get<double>(), 1.0);
  EXPECT_GT(p.run.result.fscore, p.blend.fscore + 0.02);
  EXPECT_GE(p.run.result.unseen_detail_recall.value_or(0), 0.9);
}

// The knobbed box seen from below (0.35, -0.25, -1), the sweep's view, in a plain box a user drew 10% wider and 5%
// taller, its floor 4.5 cm below the box's. ICP laid the scan on the template's floor and on the two sides it sees
// (4.5 cm down, 3 cm out each way), and the flips that carry the floor onto the top turned about the template's
// centre, 2.3 cm below the box's: F 0.50 on the held-out studded box (bench/heldout_shapes.py). The template scaled
// about its top and shifted lays the scan in its own pose on itself, and stands in for the template from the
// correspondence on.
TEST(KnobbedBox, SeenFromBelowInABoxDrawnLargerAndLowerTheBoxScaledToItStandsIn) {
  const Eigen::Vector3d size(0.6, 0.6, 0.9);
  const PointSet model = knobbed_box(size, 4, 3, 0.035);
  test::TempDir dir;
  write_ply(dir / "box.ply", make_lowpoly_box(Eigen::Vector3d(0.66, 0.66, 0.945), Eigen::Vector3d(0, 0, 0.4275)));
  const BaselinedRun p = complete_scan_of(model, (dir / "box.ply").string(), Eigen::Vector3d(0.35, -0.25, -1), dir);
  std::printf("knobbed box from below in a larger, lower box: F %.3f unseen-detail %.3f | template blend F %.3f\n",
              p.run.result.fscore, p.run.result.unseen_detail_recall.value_or(0), p.blend.fscore);
  EXPECT_TRUE(p.run.report["correspondence"]["template_scaled"].get<bool>());
  EXPECT_GE(p.run.result.fscore, 0.95);
  EXPECT_GT(p.run.result.fscore, p.blend.fscore + 0.1);
  EXPECT_GE(p.run.result.unseen_detail_recall.value_or(0), 0.85);
}

}  // namespace
}  // namespace scanfill
