// Issue 14, item 4: a surface for completions. The bundled vase example (configs/vase.yaml: procedural:vase scanned
// from one side, completed with its body of revolution) writes output_mesh.ply by default; the surface scores F@1%
// within 0.01 of output.ply's points, against the complete vase.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>
#include <random>

#include "engine/config.h"
#include "engine/console.h"
#include "engine/pipeline.h"
#include "nodes/eval/evaluate.h"
#include "nodes/io/read_point_set.h"
#include "nodes/io/write_ply.h"
#include "nodes/procedural/shapes.h"
#include "nodes/scan/virtual_scan.h"
#include "test_util.h"

namespace scanfill {
namespace {

TEST(SurfaceEndToEnd, TheVaseSurfaceScoresAsItsPointsDo) {
  setup_logging(false, true);
  test::TempDir dir;
  RunConfig c = load_config(test::source_dir() / "configs" / "vase.yaml");
  c.output_dir = dir / "out";
  run(c);
  const PointSet reference = make_shape("vase");
  const PointSet points = read_point_set(dir / "out" / "output.ply").points;
  const PointSet mesh = read_point_set(dir / "out" / "output_mesh.ply").points;
  ASSERT_GT(mesh.faces().cols(), 10000);
  const EvalResult of_points = evaluate(points, reference, {}), of_mesh = evaluate(mesh, reference, {});
  const auto report = nlohmann::json::parse(test::read_bytes(dir / "out" / "report.json"));
  const auto& surface = report.at("surface");
  std::printf(
      "vase: points F %.4f (P %.4f R %.4f), surface F %.4f (P %.4f R %.4f); %ld vertices, %ld triangles, "
      "%ld trimmed, %.2f s\n",
      of_points.fscore, of_points.precision, of_points.recall, of_mesh.fscore, of_mesh.precision, of_mesh.recall,
      long(mesh.size()), long(mesh.faces().cols()), surface.at("trimmed").get<long>(),
      surface.at("seconds").get<double>());
  // The mesh loses a little to the lid Poisson puts over the open top (what trimming leaves of it: 4 cm high, some 400
  // vertices): measured points 0.988, mesh 0.968 (0.980 and 0.972 before holes were filled from other transforms).
  EXPECT_NEAR(of_mesh.fscore, of_points.fscore, 0.025);
  EXPECT_GT(of_mesh.fscore, 0.95);
  EXPECT_EQ(surface.at("faces").get<Index>(), mesh.faces().cols());
  EXPECT_EQ(surface.at("vertices").get<Index>(), mesh.size());
  EXPECT_GT(surface.at("trimmed").get<Index>(), 0);  // the open top Poisson closes
  EXPECT_GT(surface.at("seconds").get<double>(), 0);
}

// The surface is made beside the transfer from the synthesis, in the working frame, and mapped to the output's like
// output.ply. A scan turned 9 degrees and moved 5 cm off the template registers far from the identity: the mesh
// must still lie on output.ply's points (F@1% of the mesh's vertices against them), in the scan's own frame.
TEST(SurfaceEndToEnd, AMovedScansSurfaceLiesOnItsOutputPoints) {
  setup_logging(false, true);
  test::TempDir dir;
  ScanOptions camera;
  camera.eye = Eigen::Vector3d(0, -3, 0.6);
  camera.target = Eigen::Vector3d(0, 0, 0.5);
  const Eigen::Matrix3d turn = (Eigen::AngleAxisd(5 * M_PI / 180, Eigen::Vector3d::UnitX()) *
                                Eigen::AngleAxisd(8 * M_PI / 180, Eigen::Vector3d::UnitZ()))
                                   .toRotationMatrix();
  const Similarity moved{turn, Eigen::Vector3d(0.03, -0.02, 0.04), 1};
  write_ply(dir / "scan.ply", transformed(virtual_scan(make_shape("vase"), camera).points, moved));
  test::write_bytes(dir / "c.yaml", "mode: completion\ninputs:\n  scan: " + (dir / "scan.ply").string() +
                                        "\n  template: procedural:vase_template\nsample:\n  count: 8000\n");
  RunConfig c = load_config(dir / "c.yaml");
  c.output_dir = dir / "out";
  run(c);
  const auto report = nlohmann::json::parse(test::read_bytes(dir / "out" / "report.json"));
  Eigen::Matrix3d rigid;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) rigid(i, j) = report.at("correspondence").at("rigid").at("rotation")[i][j];
  EXPECT_GT(Eigen::AngleAxisd(rigid).angle(), 5 * M_PI / 180);  // the registration is far from the identity
  const PointSet points = read_point_set(dir / "out" / "output.ply").points;
  const PointSet mesh = read_point_set(dir / "out" / "output_mesh.ply").points;
  const EvalResult on_points = evaluate(PointSet(mesh.positions()), points, {});
  std::printf("moved scan: the mesh's vertices against output.ply: precision %.4f\n", on_points.precision);
  EXPECT_GT(on_points.precision, 0.9);
}

TEST(SurfaceEndToEnd, OutputSurfaceNoneWritesNoMesh) {
  setup_logging(false, true);
  test::TempDir dir;
  RunConfig c = load_config(test::source_dir() / "configs" / "vase.yaml", {"output.surface=none", "sample.count=3000"});
  c.output_dir = dir / "out";
  const RunOutcome outcome = run(c);
  EXPECT_FALSE(std::filesystem::exists(dir / "out" / "output_mesh.ply"));
  EXPECT_EQ(outcome.outputs.size(), 7u);  // samples x 2, output, correspondence, analogy, preview, report
  const auto report = nlohmann::json::parse(test::read_bytes(dir / "out" / "report.json"));
  EXPECT_FALSE(report.contains("surface"));
  for (const auto& n : report.at("nodes")) EXPECT_NE(n.at("name"), "surface");
}

// PoissonRecon prints "Vertex pair not in list 2 ..." with printf where it cannot pair iso-surface edges. Points whose
// normals disagree make it do so: a scan file whose normals were flipped at random (half of them), taken as they are
// (features.orientation: input), gives 23 such lines at the default depth. A finer input that gives a few lines on
// one machine gave none on another (the vase at depth 8 with 1.5x10^4 points: 3 on CI, 0 on a fresh machine). The
// surface node captures those lines: nothing of them reaches stdout, the report counts them and a warning says what
// they mean; the summary, printed after, is whole.
TEST(SurfaceEndToEnd, PoissonReconsStdoutLinesBecomeACountAndAWarning) {
  test::TempDir dir;
  ScanOptions camera;
  camera.eye = Eigen::Vector3d(0, -3, 0.6);
  camera.target = Eigen::Vector3d(0, 0, 0.5);
  PointSet scan = virtual_scan(make_shape("vase"), camera).points;
  Eigen::Matrix3Xd normals = scan.normals();
  std::mt19937 rng(1);
  for (Index i = 0; i < normals.cols(); ++i)
    if (rng() % 2) normals.col(i) = -normals.col(i);
  scan.set_normals(std::move(normals));
  write_ply(dir / "scan.ply", scan);
  test::write_bytes(dir / "c.yaml", "mode: completion\ninputs:\n  scan: " + (dir / "scan.ply").string() +
                                        "\n  template: procedural:vase_template\nfeatures:\n  orientation: input\n");
  const auto r = test::run_scanfill("--config " + test::quoted(dir / "c.yaml") +
                                    " --set output.dir=" + test::quoted(dir / "out") + " --threads 1");
  ASSERT_EQ(r.exit_code, 0) << r.out;
  const auto report = nlohmann::json::parse(test::read_bytes(dir / "out" / "report.json"));
  const long diagnostics = report.at("surface").at("poisson_diagnostics").get<long>();
  std::printf("PoissonRecon diagnostics captured: %ld\n", diagnostics);
  EXPECT_GT(diagnostics, 0) << "the input no longer makes PoissonRecon print: pick another to test the capture";
  EXPECT_EQ(r.out.find("\nVertex pair not in list"), std::string::npos) << r.out;
  EXPECT_NE(r.out.rfind("Vertex pair not in list", 0), 0u) << r.out;
  EXPECT_NE(r.out.find("PoissonRecon could not pair " + std::to_string(diagnostics) + " iso-surface edges"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("scanfill: completed scan:"), std::string::npos) << r.out;
}

}  // namespace
}  // namespace scanfill
