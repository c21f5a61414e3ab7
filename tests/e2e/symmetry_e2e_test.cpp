// Issue 10, end to end: symmetric sources and targets. Two bodies in T, equal or scaled, each get the exemplar's
// detail (the source's continuous symmetry must not fill the mode budget, and a scaled copy must be found); a box
// template offers its quarter turns on a crate seen from one corner, and the report lists them as axis rotations.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "engine/config.h"
#include "engine/console.h"
#include "engine/pipeline.h"
#include "input_util.h"
#include "nodes/eval/evaluate.h"
#include "nodes/input/input.h"
#include "nodes/io/read_point_set.h"
#include "nodes/procedural/shapes.h"
#include "test_util.h"

namespace scanfill {
namespace {

nlohmann::json read_report(const std::filesystem::path& dir) {
  std::ifstream in(dir / "report.json");
  return nlohmann::json::parse(in);
}

// Transfer S = one plain disk, T = two plain disks, E = the gear; scored against the two gears.
void two_disks_get_the_teeth(const std::string& target, const std::string& styled) {
  setup_logging(false, true);
  test::TempDir dir;
  RunConfig c;
  c.mode = RunMode::kTransfer;
  c.inputs = {test::input(Role::kSource, parse_input("procedural:gear_template")),
              test::input(Role::kTarget, parse_input("procedural:" + target)),
              test::input(Role::kExemplar, parse_input("procedural:gear"))};
  c.output_dir = dir / "out";
  run(c);
  const PointSet output = read_point_set(dir / "out" / "output.ply").points;
  const PointSet exemplar = make_shape("gear"), plain = make_shape(target), reference = make_shape(styled);
  // Detail: the reference's teeth (away from the plain target); "unseen": away from the exemplar, which sits at the
  // origin between the two bodies, so both bodies' teeth count.
  const EvalResult r = evaluate(output, reference, {}, &exemplar, &plain);
  const EvalResult blend = evaluate(plain, reference, {}, &exemplar, &plain);
  std::printf("%s: F %.3f detail %.3f | the plain target F %.3f\n", target.c_str(), r.fscore,
              r.unseen_detail_recall.value_or(0), blend.fscore);
  EXPECT_GE(r.fscore, 0.95);
  EXPECT_GE(r.unseen_detail_recall.value_or(0), 0.9);  // one body alone holds half of the teeth
  const auto report = read_report(dir / "out");
  EXPECT_TRUE(report["symmetry"]["votes_quotiented"].get<bool>());
}

TEST(Symmetry, TwoEqualDisksBothGetTheGearsTeeth) {
  two_disks_get_the_teeth("disk_pair", "gear_pair");
}

TEST(Symmetry, ADiskScaledBy07IsFoundAndGetsTheTeethToo) {
  two_disks_get_the_teeth("disk_pair_scaled", "gear_pair_scaled");
}

TEST(Symmetry, ABoxTemplateGivesQuarterTurnsOnACrateSeenFromOneCorner) {
  setup_logging(false, true);
  test::TempDir dir;
  RunConfig c;
  c.mode = RunMode::kCompletion;
  c.inputs = {test::input(Role::kScan, parse_input("procedural:crate")),
              test::input(Role::kTemplate, parse_input("procedural:crate_template"))};
  c.output_dir = dir / "out";
  c.virtual_scan.eye = Eigen::Vector3d(2.1, -2.1, 1.6);  // the -y and +x sides and the top
  c.virtual_scan.target = Eigen::Vector3d(0, 0, 0.4);
  c.virtual_scan.width = c.virtual_scan.height = 480;
  c.virtual_scan.fov_deg = 30;
  run(c);
  const auto report = read_report(dir / "out");
  EXPECT_EQ(report["symmetry"]["target_rotations"].get<int>(), 7);  // the box's group D4, identity excluded
  int turns = 0;
  for (const auto& t : report["transforms"]) {
    if (t["kind"] != "similarity" || t["labelled"].get<Index>() == 0) continue;
    EXPECT_TRUE(t["axis_rotation"].get<bool>()) << t.dump();
    const double deg = t["rotation_deg"].get<double>();
    turns += deg > 45;  // a quarter or half turn that carries a seen side to an unseen one
  }
  EXPECT_GE(turns, 1);
  // The unseen sides are made, not copied from the 8-vertex box.
  const auto& o = report["output"];
  EXPECT_LT(o["copied_points"].get<double>(), 0.1 * o["points"].get<double>());
}

}  // namespace
}  // namespace scanfill
