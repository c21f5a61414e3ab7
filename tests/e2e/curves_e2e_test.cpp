// Mode curves end to end with ground truth (issue 12): the paper's Figure 2 (configs/curves_iq.yaml), a target made
// of a rotated and a scaled copy of the source, determinism across thread counts, and drawings refused whole.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <nlohmann/json.hpp>

#include "engine/config.h"
#include "engine/console.h"
#include "engine/pipeline.h"
#include "nodes/core/errors.h"
#include "nodes/curves/curves.h"
#include "nodes/curves/sample_curves.h"
#include "nodes/eval/evaluate.h"
#include "test_util.h"

namespace scanfill {
namespace {

// Dense points along the curves (0.1 model units apart): what a Chamfer distance between drawings is taken on.
PointSet dense(const Curves& curves) {
  return sample_curves(curves, 0.1, {}).samples;
}

nlohmann::json report_of(const std::filesystem::path& dir) {
  return nlohmann::json::parse(test::read_bytes(dir / "report.json"));
}

RunConfig iq_config(const std::filesystem::path& out, int threads) {
  return load_config(test::source_dir() / "configs" / "curves_iq.yaml",
                     {"output.dir=" + out.string(), "threads=" + std::to_string(threads)});
}

TEST(CurvesE2E, IqSquaresGiveTwoWavySquaresWithTwoLabels) {
  setup_logging(false, true);
  test::TempDir dir;
  run(iq_config(dir / "out", 2));
  // Ground truth: the wavy square at each of the target's squares (the second moved by 130 along x).
  Curves truth = read_curves(test::source_dir() / "configs" / "curves" / "square_wavy.svg");
  Curves moved = truth;
  for (Polyline& c : moved) c.points.row(0).array() += 130;
  truth.insert(truth.end(), moved.begin(), moved.end());
  const PointSet reference = dense(truth);
  const Curves output = read_curves(dir / "out" / "output.txt");
  EXPECT_EQ(output.size(), 2u);
  for (const Polyline& c : output) EXPECT_TRUE(c.closed);
  const EvalResult e = evaluate(dense(output), reference, {});
  const double diagonal = bounding_box(reference.positions()).diagonal();
  EXPECT_LT(e.chamfer_l1, 0.01 * diagonal) << "Chamfer L1 " << e.chamfer_l1 << " of diagonal " << diagonal;
  std::cout << "curves_iq: Chamfer L1 " << e.chamfer_l1 << " = " << 100 * e.chamfer_l1 / diagonal
            << "% of the diagonal, F-score at 1% " << e.fscore << "\n";
  // The SVG holds the same curves.
  const Curves svg = read_curves(dir / "out" / "output.svg");
  ASSERT_EQ(svg.size(), output.size());
  EXPECT_LT(evaluate(dense(svg), reference, {}).chamfer_l1, 0.01 * diagonal);
  // Exactly two labels used: one transform per square, no self-reference.
  int used = 0;
  const nlohmann::json report = report_of(dir / "out");
  for (const auto& t : report["transforms"]) used += t["labelled"].get<Index>() > 0;
  EXPECT_EQ(used, 2);
  for (const char* name : {"analogy.svg", "preview.png", "report.json"})
    EXPECT_TRUE(std::filesystem::exists(dir / "out" / name)) << name;
}

TEST(CurvesE2E, SameBytesOnOneAndTwoThreads) {
  setup_logging(false, true);
  test::TempDir dir;
  run(iq_config(dir / "one", 1));
  run(iq_config(dir / "two", 2));
  for (const char* name : {"output.svg", "output.txt", "analogy.svg", "preview.png"})
    EXPECT_EQ(test::read_bytes(dir / "one" / name), test::read_bytes(dir / "two" / name)) << name;
}

// The same drawings as plain polyline files (written to 9 digits) give the same curves as their SVGs; a polyline may
// run the other way round (its walk starts at a tie that the last digits break).
TEST(CurvesE2E, PolylineFilesGiveWhatTheirSvgsGive) {
  setup_logging(false, true);
  test::TempDir dir;
  const auto configs = test::source_dir() / "configs" / "curves";
  for (const char* name : {"square", "two_squares", "square_wavy"})
    write_polylines(dir / (std::string(name) + ".txt"), read_curves(configs / (std::string(name) + ".svg")));
  test::write_bytes(dir / "c.yaml",
                    "mode: curves\ninputs: {source: square.txt, target: two_squares.txt, exemplar: square_wavy.txt}\n"
                    "vote: {allow_scale: false}\n");
  run(load_config(dir / "c.yaml", {"output.dir=" + (dir / "txt").string()}));
  run(iq_config(dir / "svg", 2));
  const Curves txt = read_curves(dir / "txt" / "output.txt"), svg = read_curves(dir / "svg" / "output.txt");
  EXPECT_EQ(txt.size(), svg.size());
  EXPECT_LT(evaluate(dense(txt), dense(svg), {}).hausdorff, 1e-4);
}

// An asymmetric smooth blob (curvature varies along it, so a single sample's curvature tells the scale).
std::vector<Eigen::Vector2d> blob() {
  std::vector<Eigen::Vector2d> p;
  for (int i = 0; i < 720; ++i) {
    const double t = 2 * M_PI * i / 720;
    const double r = 40 * (1 + 0.25 * std::cos(t) + 0.12 * std::sin(2 * t) + 0.05 * std::cos(3 * t));
    p.push_back(r * Eigen::Vector2d(std::cos(t), std::sin(t)));
  }
  return p;
}

std::string polygon(const std::vector<Eigen::Vector2d>& p, const Eigen::Matrix2d& A, const Eigen::Vector2d& t) {
  std::string s = "<polygon points=\"";
  for (const auto& q : p) {
    const Eigen::Vector2d x = A * q + t;
    s += std::to_string(x.x()) + "," + std::to_string(x.y()) + " ";
  }
  return s + "\"/>";
}

TEST(CurvesE2E, RotatedAndScaledCopiesGiveTheirSimilarities) {
  setup_logging(false, true);
  test::TempDir dir;
  const auto svg = [](const std::string& body) {
    return "<svg xmlns=\"http://www.w3.org/2000/svg\">" + body + "</svg>";
  };
  const double angle = 30 * M_PI / 180, scale = 1.3;
  const Eigen::Matrix2d R = Eigen::Rotation2Dd(angle).toRotationMatrix();
  test::write_bytes(dir / "S.svg", svg(polygon(blob(), Eigen::Matrix2d::Identity(), Eigen::Vector2d::Zero())));
  test::write_bytes(dir / "T.svg", svg(polygon(blob(), R, {-20, 10}) +
                                       polygon(blob(), scale * Eigen::Matrix2d::Identity(), {150, 20})));
  test::write_bytes(dir / "c.yaml", "mode: curves\ninputs: {source: S.svg, target: T.svg, exemplar: S.svg}\n");
  run(load_config(dir / "c.yaml", {"output.dir=" + (dir / "out").string()}));
  // Q maps target to source: the rotated copy by -30 degrees at scale 1, the scaled one by 1 / 1.3 unturned.
  bool rotated = false, scaled = false;
  const nlohmann::json report = report_of(dir / "out");
  for (const auto& t : report["transforms"]) {
    if (t["kind"] != "similarity" || t["labelled"].get<Index>() == 0) continue;
    const double deg = t["rotation_deg"].get<double>(), s = t["scale"].get<double>();
    rotated |= std::abs(deg - 30) < 1 && std::abs(s - 1) < 0.02;
    scaled |= deg < 1 && std::abs(s * scale - 1) < 0.02;
    EXPECT_TRUE((std::abs(deg - 30) < 1 && std::abs(s - 1) < 0.02) || (deg < 1 && std::abs(s * scale - 1) < 0.02))
        << t.dump();
  }
  EXPECT_TRUE(rotated);
  EXPECT_TRUE(scaled);
}

// The paper's Figure 8 (right): F is E's own strokes (the identity), D's stem is E's moved by 90, and D's bowl, which
// E has no counterpart for, is copied by self-reference.
TEST(CurvesE2E, LettersStyleFAndDWithSelfReferenceForTheBowl) {
  setup_logging(false, true);
  test::TempDir dir;
  run(load_config(test::source_dir() / "configs" / "curves_letters.yaml", {"output.dir=" + (dir / "out").string()}));
  const nlohmann::json report = report_of(dir / "out");
  bool identity = false, moved = false, self = false;
  for (const auto& t : report["transforms"]) {
    if (t["labelled"].get<Index>() == 0) continue;
    const double tx = t["translation"][0].get<double>();
    self |= t["kind"] == "self";
    identity |= t["kind"] == "similarity" && t["rotation_deg"].get<double>() < 1 && std::abs(tx) < 2;
    moved |= t["kind"] == "similarity" && t["rotation_deg"].get<double>() < 1 && std::abs(tx + 90) < 2;
  }
  EXPECT_TRUE(identity);
  EXPECT_TRUE(moved);
  EXPECT_TRUE(self);
  // The serifs arrive: the exemplar's slabs reach 8 left of the stems (x = -8 and 82), the plain letters' do not.
  const Curves output = read_curves(dir / "out" / "output.txt");
  double min_x = 1e9, min_x_d = 1e9;
  for (const Polyline& c : output)
    for (Eigen::Index i = 0; i < c.points.cols(); ++i) {
      min_x = std::min(min_x, c.points(0, i));
      if (c.points(0, i) > 70) min_x_d = std::min(min_x_d, c.points(0, i));
    }
  EXPECT_NEAR(min_x, -8, 1.5);
  EXPECT_NEAR(min_x_d, 82, 1.5);
}

// A drawing that cannot be read fails the run with one line naming the file and what is wrong, and leaves no output.
void expect_refused(const std::string& exemplar_svg, const std::string& expected) {
  setup_logging(false, true);
  test::TempDir dir;
  const auto configs = test::source_dir() / "configs" / "curves";
  test::write_bytes(dir / "E.svg", exemplar_svg);
  test::write_bytes(dir / "c.yaml", "mode: curves\ninputs: {source: " + (configs / "square.svg").string() +
                                        ", target: " + (configs / "two_squares.svg").string() + ", exemplar: E.svg}\n");
  try {
    run(load_config(dir / "c.yaml", {"output.dir=" + (dir / "out").string()}));
    FAIL() << "expected a refusal";
  } catch (const Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find((dir / "E.svg").string()), std::string::npos) << what;
    EXPECT_NE(what.find(expected), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "out" / "report.json"));
  EXPECT_FALSE(std::filesystem::exists(dir / "out" / "output.svg"));
}

TEST(CurvesE2E, RefusesADrawingWithNoPaths) {
  expect_refused("<svg xmlns=\"http://www.w3.org/2000/svg\"><g/></svg>", "no paths");
}

TEST(CurvesE2E, RefusesAnUnsupportedElementByName) {
  expect_refused("<svg xmlns=\"http://www.w3.org/2000/svg\"><rect width='9' height='9'/><text>E</text></svg>",
                 "unsupported SVG element <text>");
}

}  // namespace
}  // namespace scanfill
