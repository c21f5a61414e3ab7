// Mode exchange end to end (issue 12, item 2): configs/exchange_castles.yaml against its known answer (each output
// against the styled target, the same castle generator on the target's layout), the box assignment it must make, and
// bad inputs refused with one line, a non-zero exit and no output.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <nlohmann/json.hpp>

#include "engine/config.h"
#include "engine/console.h"
#include "engine/pipeline.h"
#include "nodes/core/errors.h"
#include "nodes/eval/evaluate.h"
#include "nodes/io/read_point_set.h"
#include "nodes/io/write_ply.h"
#include "nodes/procedural/castle.h"
#include "nodes/procedural/shapes.h"
#include "test_util.h"

namespace scanfill {
namespace {

std::string q(const std::filesystem::path& p) {
  return test::quoted(p);
}

// Which parts of the bundled castles are towers, by layout (castle.cpp): the rest are walls.
std::vector<bool> towers_of(const std::string& name) {
  if (name == "castle_keep_a") return {true, false, true};
  if (name == "castle_fort_b") return {true, false, true, false, true};
  if (name == "castle_gate") return {true, false, true, false, true};
  return {true, false};  // bastion
}

TEST(ExchangeE2E, CastlesMatchTheStyledTargetsWithTowerStyleOnTowersAndWallStyleOnWalls) {
  setup_logging(false, true);
  test::TempDir dir;
  const auto t0 = std::chrono::steady_clock::now();
  run(load_config(test::source_dir() / "configs" / "exchange_castles.yaml",
                  {"output.dir=" + (dir / "out").string(), "threads=2"}));
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const auto report = nlohmann::json::parse(test::read_bytes(dir / "out" / "report.json"));
  ASSERT_EQ(report["pairs"].size(), 4u);
  for (const auto& pair : report["pairs"]) {
    const std::string exemplar = pair["exemplar"], target = pair["target"];
    // The styled target: the target's layout (gate, or the bastion given as boxes) in the exemplar's style.
    const std::string truth = "castle_" + std::string(target == "bastion" ? "bastion" : "gate") + "_" + exemplar.back();
    const PointSet output = read_point_set(dir / "out" / pair["output"].get<std::string>()).points;
    const EvalResult e = evaluate(output, make_shape(truth), {});
    std::cout << exemplar << " -> " << target << ": F@1% " << e.fscore << " (precision " << e.precision << ", recall "
              << e.recall << "), Chamfer L1 " << e.chamfer_l1 << "\n";
    // Issue 12 asks F >= 0.9; the right assignment gives >= 0.996 and the wrong one (every part styled as a tower)
    // still 0.91 on the gate, so the bar is 0.98 and the assignment is checked below besides.
    EXPECT_GE(e.fscore, 0.98) << exemplar << " -> " << target;
    // Tower style on towers, wall style on walls; a wall along y gets a wall along x turned a quarter.
    const std::vector<bool> source_towers = towers_of(exemplar), target_towers = towers_of(target);
    for (const auto& box : pair["target_boxes"]) {
      const size_t j = box["target_box"], i = box["source_box"];
      EXPECT_EQ(source_towers.at(i), target_towers.at(j)) << exemplar << " -> " << target << " box " << j;
      const auto& b = box["box"];
      const bool along_y =
          b[1][1].get<double>() - b[0][1].get<double>() > b[1][0].get<double>() - b[0][0].get<double>();
      const bool source_along_y = exemplar == "castle_fort_b" && i == 3;
      if (!target_towers[j]) {
        EXPECT_NEAR(box["rotation_deg"].get<double>(), along_y == source_along_y ? 0 : 90, 1e-9) << target << j;
      }
    }
  }
  std::cout << "exchange_castles: " << seconds << " s\n";
  EXPECT_LT(seconds, 10.0);
}

// A PLY's per-vertex part property gives the parts the layout gives.
TEST(ExchangeE2E, PartsFromAPlyPropertyAreTheLayoutsBoxes) {
  setup_logging(false, true);
  test::TempDir dir;
  PointSet mesh;
  std::vector<double> part;
  const std::vector<CastlePart> layout{{{Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(2, 2, 6)}, true},
                                       {{Eigen::Vector3d(2, 0.5, 0), Eigen::Vector3d(8, 1.5, 4)}, false}};
  for (size_t p = 0; p < layout.size(); ++p) {
    const PointSet piece = make_castle_part(layout[p], CastleStyle{});
    mesh = mesh.empty() ? piece : merged(mesh, piece);
    part.insert(part.end(), size_t(piece.size()), double(p) + 7);
  }
  write_ply(dir / "castle.ply", mesh, {{"segment_id", PlyProperty::Type::kInt32, part}});
  test::write_bytes(dir / "c.yaml",
                    "mode: exchange\ninputs:\n  exemplar: castle.ply\n  target:\n    - name: t\n"
                    "      boxes: [[[0, 0, 0], [1, 8, 3]], [[1, 0, 0], [3, 2, 7]]]\n"
                    "output:\n  dir: " +
                        (dir / "out").string() + "\n");
  run(load_config(dir / "c.yaml"));
  const auto report = nlohmann::json::parse(test::read_bytes(dir / "out" / "report.json"));
  const auto& exemplar = report["inputs"]["exemplars"][0];
  EXPECT_EQ(exemplar["parts_from"], "PLY vertex property 'segment_id'");
  EXPECT_EQ(exemplar["part_labels"], nlohmann::json({7, 8}));
  for (size_t p = 0; p < layout.size(); ++p)
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(exemplar["boxes"][p][0][k].get<double>(), layout[p].box.min(k), 1e-6);
      EXPECT_NEAR(exemplar["boxes"][p][1][k].get<double>(), layout[p].box.max(k), 1e-6);
    }
  // The wall (along x) turned onto the target's wall along y, the tower onto the tower.
  const auto& boxes = report["pairs"][0]["target_boxes"];
  EXPECT_EQ(boxes[0]["source_box"], 1);
  EXPECT_NEAR(boxes[0]["rotation_deg"].get<double>(), 90, 1e-9);
  EXPECT_EQ(boxes[1]["source_box"], 0);
  EXPECT_NEAR(boxes[1]["rotation_deg"].get<double>(), 0, 1e-9);
}

TEST(ExchangeE2E, SameBytesOnOneAndTwoThreads) {
  setup_logging(false, true);
  test::TempDir dir;
  for (const char* threads : {"1", "2"})
    run(load_config(test::source_dir() / "configs" / "exchange_castles.yaml",
                    {"output.dir=" + (dir / threads).string(), std::string("threads=") + threads}));
  for (const auto& entry : std::filesystem::directory_iterator(dir / "1")) {
    if (entry.path().filename() == "report.json") continue;  // holds wall times
    EXPECT_EQ(test::read_bytes(entry.path()), test::read_bytes(dir / "2" / entry.path().filename())) << entry.path();
  }
}

// Config errors of the exchange inputs, all in one message with their places.
TEST(ExchangeE2E, InputProblemsAreReportedTogether) {
  test::TempDir dir;
  test::write_bytes(dir / "c.yaml",
                    "mode: exchange\ninputs:\n  exemplar:\n    - {name: a, boxes: [[[0, 0, 0], [1, 1, 1]]]}\n"
                    "    - procedural:vase\n  target:\n    - {name: t, boxes: [[[0, 0, 0], [1, 1, 1]]]}\n"
                    "    - {name: t, boxes: [[[0, 0, 0], [1, 1]]], colour: red}\n");
  try {
    load_config(dir / "c.yaml");
    FAIL() << "accepted";
  } catch (const ConfigError& e) {
    const std::string m = e.what();
    for (const char* part :
         {"inputs.exemplar[0]: an exemplar needs its shape", "inputs.exemplar[1]: procedural:vase has no parts",
          "inputs.target[1].colour: unknown key (valid: path, name, boxes)",
          "inputs.target[1].boxes[0]: expected a box [[x, y, z], [x, y, z]]",
          "inputs.target[1].name: 't' is also target[0]'s"})
      EXPECT_NE(m.find(part), std::string::npos) << part << "\n" << m;
  }
}

// Everything in `folder`, or nothing when it does not exist.
size_t entries(const std::filesystem::path& folder) {
  if (!std::filesystem::exists(folder)) return 0;
  return size_t(std::distance(std::filesystem::directory_iterator(folder), {}));
}

// One bad input: a non-zero exit, one line naming what is wrong, no output folder's content.
void expect_refused(const test::TempDir& dir, const std::string& inputs, const std::string& message) {
  test::write_bytes(dir / "c.yaml",
                    "mode: exchange\ninputs:\n" + inputs + "output:\n  dir: " + (dir / "out").string() + "\n");
  const auto r = test::run_scanfill("--config " + q(dir / "c.yaml") + " --quiet");
  EXPECT_NE(r.exit_code, 0) << r.out;
  EXPECT_NE(r.out.find(message), std::string::npos) << r.out;
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << "one line:\n" << r.out;
  EXPECT_EQ(entries(dir / "out"), 0u) << r.out;
}

TEST(ExchangeE2E, BadPartsAreRefusedWithOneLineAndNoOutput) {
  test::TempDir dir;
  write_ply(dir / "plain.ply", make_shape("castle_keep_a"));  // no part property
  expect_refused(dir, "  exemplar: plain.ply\n  target: procedural:castle_gate\n",
                 (dir / "plain.ply").string() + ": no vertex property 'part' or 'part_id'");
  test::write_bytes(dir / "c.yaml", "");
  expect_refused(dir,
                 "  exemplar: procedural:castle_keep_a\n  target:\n    - name: flat\n"
                 "      boxes: [[[0, 0, 0], [1, 1, 1]], [[0, 0, 0], [2, 0, 3]]]\n",
                 "c.yaml:6:39: inputs.target[0].boxes[1]: a box with zero volume: [[0, 0, 0], [2, 0, 3]]");
  expect_refused(dir, "  exemplar: procedural:castle_keep_a\n  target:\n    - name: empty\n      boxes: []\n",
                 "inputs.target[0].boxes: no parts: expected at least one box");
  // A part property on vertices without z, and parts that are all "no part": refused, not read out of bounds.
  test::write_bytes(dir / "noz.ply",
                    "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                    "property int part\nend_header\n0 0 1\n");
  expect_refused(dir, "  exemplar: procedural:castle_keep_a\n  target: noz.ply\n",
                 "noz.ply: PLY vertex element lacks x, y or z");
  test::write_bytes(dir / "none.ply",
                    "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                    "property float z\nproperty int part\nend_header\n0 0 0 -1\n");
  expect_refused(dir, "  exemplar: procedural:castle_keep_a\n  target: none.ply\n",
                 "gives no part (every label is negative)");
  // The property named by exchange.part_property, absent: named with the file.
  test::write_bytes(dir / "c.yaml", "");
  expect_refused(dir, "  exemplar: plain.ply\n  target: procedural:castle_gate\nexchange:\n  part_property: region\n",
                 "plain.ply: no vertex property 'region' with the parts");
}

}  // namespace
}  // namespace scanfill
