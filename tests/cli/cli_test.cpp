// The command line as a user meets it: exit codes, one-line errors, no partial outputs, determinism, and `info` on
// every file of ../shared/data.
#include <gtest/gtest.h>

#include <fstream>

#include <nlohmann/json.hpp>

#include "test_util.h"

namespace scanfill {
namespace {

using test::run_scanfill;

std::string q(const std::filesystem::path& p) {
  return test::quoted(p);
}

TEST(Cli, VersionHelpAndNothingToDo) {
  EXPECT_EQ(run_scanfill("--version").exit_code, 0);
  const auto help = run_scanfill("--help");
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_NE(help.out.find("info"), std::string::npos);
  EXPECT_NE(run_scanfill("").exit_code, 0);
  EXPECT_NE(run_scanfill("frobnicate").exit_code, 0);
}

TEST(Cli, InfoOnEverySharedFileMatchesTheReaderCounts) {
  SCANFILL_REQUIRE_SHARED_DATA();
  // Counts checked independently in io_test; here the CLI path and its JSON contract.
  const std::pair<const char*, std::array<long, 2>> files[] = {
      {"scans/stanford_bunny/bun000.ply", {40256, 0}},
      {"scans/stanford_bunny/bun_zipper_res2.ply", {8171, 16301}},
      {"scans/pcl_kinect/table_scene_mug_stereo_textured.pcd", {209280, 0}},
      {"scans/pcl_kinect/milk.pcd", {13704, 0}},
      {"scans/cgal_hippo/hippo1.ply", {6104, 0}},
      {"models/vaselion.obj", {30610, 61216}},
      {"models/threedscans_Column03.obj", {6992, 13980}},
      {"furniture/meshlab_office_chair.obj", {3476, 6893}},
  };
  for (const auto& [file, counts] : files) {
    const auto r = run_scanfill("info --full --json " + q(test::shared_data() / file));
    ASSERT_EQ(r.exit_code, 0) << r.out;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["read"], "full");
    EXPECT_EQ(j["points"].get<long>(), counts[0]) << file;
    EXPECT_EQ(j["faces"].get<long>(), counts[1]) << file;
    EXPECT_EQ(j["bbox"].size(), 2u);
    EXPECT_TRUE(j["attributes"].is_array());
    // Without --full, PLY and PCD are read from their header: the points declared (non-finite ones included).
    const auto h = nlohmann::json::parse(run_scanfill("info --json " + q(test::shared_data() / file)).out);
    const bool has_header = std::string(file).ends_with(".ply") || std::string(file).ends_with(".pcd");
    EXPECT_EQ(h["read"], has_header ? "header" : "full") << file;
    if (has_header) {
      EXPECT_EQ(h["points"].get<long>(), j["file_points"].get<long>()) << file;
      EXPECT_FALSE(h.contains("bbox")) << file;
      EXPECT_LT(h["header_bytes"].get<long>(), 4096) << file;
    }
  }
  // Every file in the folder loads.
  int n = 0;
  for (const auto& e : std::filesystem::recursive_directory_iterator(test::shared_data())) {
    const auto ext = e.path().extension();
    if (ext != ".ply" && ext != ".pcd" && ext != ".obj") continue;
    const auto r = run_scanfill("info " + q(e.path()));
    EXPECT_EQ(r.exit_code, 0) << e.path() << "\n" << r.out;
    ++n;
  }
  EXPECT_EQ(n, 30);
}

// `info` reads only the header of PLY and PCD files and says so; --full reads the points. Files whose points are all
// NaN tell them apart: their header is fine, their points are not.
TEST(Cli, InfoReadsTheHeaderOnlyUnlessToldToReadThePoints) {
  test::TempDir dir;
  const std::string nan4(4, '\xff');  // 0xffffffff: a float NaN
  std::string ply =
      "ply\nformat binary_little_endian 1.0\ncomment end_header in a comment\nelement vertex 1000\n"
      "property float x\nproperty float y\nproperty float z\nproperty uchar red\nproperty uchar green\n"
      "property uchar blue\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n";
  for (int i = 0; i < 1000; ++i) ply += nan4 + nan4 + nan4 + "abc";
  test::write_bytes(dir / "nan.ply", ply);
  std::string pcd =
      "VERSION 0.7\nFIELDS x y z rgb\nSIZE 4 4 4 4\nTYPE F F F U\nCOUNT 1 1 1 1\nWIDTH 50\nHEIGHT 20\n"
      "VIEWPOINT 1 2 3 1 0 0 0\nPOINTS 1000\nDATA binary\n";
  for (int i = 0; i < 1000; ++i) pcd += nan4 + nan4 + nan4 + nan4;
  test::write_bytes(dir / "nan.pcd", pcd);

  const auto ply_json = run_scanfill("info --json " + q(dir / "nan.ply"));
  ASSERT_EQ(ply_json.exit_code, 0) << ply_json.out;
  const auto p = nlohmann::json::parse(ply_json.out);
  EXPECT_EQ(p["read"], "header");
  EXPECT_EQ(p["format"], "ply");
  EXPECT_EQ(p["encoding"], "binary_little_endian");
  EXPECT_EQ(p["points"].get<long>(), 1000);
  EXPECT_EQ(p["faces"].get<long>(), 0);
  EXPECT_EQ(p["elements"], nlohmann::json({"vertex 1000", "face 0"}));
  EXPECT_EQ(p["properties"][3], "vertex.red uchar");
  EXPECT_EQ(p["properties"][6], "face.vertex_indices list uchar int");
  EXPECT_EQ(p["file_bytes"].get<long>(), long(ply.size()));
  EXPECT_EQ(p["header_bytes"].get<long>(), long(ply.size() - 15000));
  const auto ply_text = run_scanfill("info " + q(dir / "nan.ply"));
  EXPECT_NE(ply_text.out.find("  read        header only (" + std::to_string(ply.size() - 15000) + " of " +
                              std::to_string(ply.size()) + " bytes; --full reads the points"),
            std::string::npos)
      << ply_text.out;
  EXPECT_NE(ply_text.out.find("  points      1000 declared\n"), std::string::npos) << ply_text.out;

  const auto pcd_json = run_scanfill("info --json " + q(dir / "nan.pcd"));
  ASSERT_EQ(pcd_json.exit_code, 0) << pcd_json.out;
  const auto c = nlohmann::json::parse(pcd_json.out);
  EXPECT_EQ(c["read"], "header");
  EXPECT_EQ(c["points"].get<long>(), 1000);
  EXPECT_EQ(c["elements"], nlohmann::json({"50 x 20"}));
  EXPECT_EQ(c["properties"], nlohmann::json({"x F4", "y F4", "z F4", "rgb U4"}));
  EXPECT_EQ(c["viewpoint"], nlohmann::json({1.0, 2.0, 3.0}));

  // --full reads the points: none is finite.
  for (const char* name : {"nan.ply", "nan.pcd"}) {
    const auto full = run_scanfill("info --full " + q(dir / name));
    EXPECT_EQ(full.exit_code, 1) << name;
    EXPECT_NE(full.out.find(name + std::string(": has no point with finite coordinates")), std::string::npos)
        << full.out;
  }
  // The header's counts are still checked against the file's size.
  test::write_bytes(dir / "short.ply", ply.substr(0, ply.size() - 1));
  const auto truncated = run_scanfill("info " + q(dir / "short.ply"));
  EXPECT_EQ(truncated.exit_code, 1);
  EXPECT_NE(truncated.out.find("short.ply: truncated: element 'vertex' declares 1000 records"), std::string::npos)
      << truncated.out;
  // Formats without a header are read whole, and say so.
  test::write_bytes(dir / "p.xyz", "0 0 0\n1 0 0\n0 1 0\n");
  const auto xyz = run_scanfill("info " + q(dir / "p.xyz"));
  ASSERT_EQ(xyz.exit_code, 0) << xyz.out;
  EXPECT_NE(xyz.out.find("  read        all points (the format has no header)\n"), std::string::npos) << xyz.out;
  EXPECT_NE(xyz.out.find("  bbox max    1 1 0\n"), std::string::npos) << xyz.out;
  EXPECT_EQ(nlohmann::json::parse(run_scanfill("info --json " + q(dir / "p.xyz")).out)["read"], "full");
}

TEST(Cli, BadInputsExitNonZeroWithOneLineAndWriteNothing) {
  test::TempDir dir;
  test::write_bytes(dir / "empty.ply", "");
  test::write_bytes(dir / "tiny.xyz", "0 0 0\n1 0 0\n0 1 0\n");
  test::write_bytes(dir / "bad.yaml",
                    "mode: completion\ninputs:\n  scan: empty.ply\n  template: procedural:vase\n"
                    "output:\n  dir: " +
                        (dir / "out").string() + "\nsample:\n  cuont: 3\n");
  test::write_bytes(dir / "run.yaml",
                    "mode: completion\ninputs:\n  scan: empty.ply\n  template: procedural:vase\n"
                    "output:\n  dir: " +
                        (dir / "out").string() + "\n");
  struct Case {
    std::string args, message;
  } cases[] = {
      {"info " + q(dir / "empty.ply"), "empty.ply: file is empty"},
      {"info " + q(dir / "missing.ply"), "missing.ply: no such file"},
      {"sample --input " + q(dir / "empty.ply") + " --output " + q(dir / "out.ply"), "file is empty"},
      {"sample --input " + q(dir / "tiny.xyz") + " --output " + q(dir / "out.ply") + " --count 2",
       "features need at least"},
      {"sample --input " + q(dir / "tiny.xyz") + " --output " + q(dir / "out.ply") + " --count 10",
       "cannot draw 10 samples from a cloud of 3 points"},
      {"sample --input " + q(dir / "tiny.xyz") + " --output " + q(dir / "out.ply") + " --count 0", "--count"},
      {"crop --input " + q(dir / "tiny.xyz") + " --output " + q(dir / "out.ply"), "crop: nothing to do"},
      {"crop --input " + q(dir / "tiny.xyz") + " --output " + q(dir / "out.ply") + " --box 1,2,3", "--box expects"},
      {"crop --input " + q(dir / "tiny.xyz") + " --output " + q(dir / "out.ply") + " --box 1,0,0,0,1,1",
       "minimum exceeds"},
      {"crop --input " + q(dir / "tiny.xyz") + " --output " + q(dir / "out.ply") + " --box 5,5,5,6,6,6",
       "tiny.xyz: crop: no point is left inside the box"},
      {"crop --input " + q(dir / "missing.ply") + " --output " + q(dir / "out.ply") + " --largest-part",
       "missing.ply: no such file"},
      {"--config " + q(dir / "bad.yaml"), "sample.cuont: unknown key"},
      {"--config " + q(dir / "run.yaml"), "node 'load:scan' failed"},
      {"--config " + q(dir / "run.yaml") + " --threads 0", "--threads"},
  };
  for (const Case& c : cases) {
    const auto r = run_scanfill(c.args);
    EXPECT_NE(r.exit_code, 0) << c.args;
    EXPECT_NE(r.out.find(c.message), std::string::npos) << c.args << "\n" << r.out;
    EXPECT_FALSE(std::filesystem::exists(dir / "out.ply")) << c.args;
    EXPECT_FALSE(std::filesystem::exists(dir / "out")) << c.args;
  }
  // Runtime errors are a single line.
  const auto r = run_scanfill("info " + q(dir / "empty.ply"));
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
}

TEST(Cli, SetOverridesAnyConfigKeyAndErrorsNameIt) {
  test::TempDir dir;
  const std::string config = q(std::filesystem::path(SCANFILL_SOURCE_DIR) / "configs" / "analogy_l.yaml");
  // A run with two keys overridden: the output folder and the sample spacing.
  const auto ok =
      run_scanfill("--config " + config + " --set output.dir=" + q(dir / "out") + " --set sample.spacing=0.05 -q");
  ASSERT_EQ(ok.exit_code, 0) << ok.out;
  std::ifstream in(dir / "out" / "report.json");
  const auto report = nlohmann::json::parse(in);
  // The measured mean spacing of samples drawn at 0.05 (the file says 0.025).
  EXPECT_NEAR(report["inputs"]["source"]["spacing"].get<double>(), 0.05, 0.01);
  struct Case {
    std::string args, message;
    int exit_code;
  } cases[] = {
      {"--set sample.count=abc", "--set sample.count=abc: sample.count: expected an integer, got 'abc'", 2},
      {"--set sample.cuont=3", "--set sample.cuont=3: sample.cuont: unknown key", 2},
      {"--set preset=papers", "--set preset=papers: preset: expected scanfill or paper, got 'papers'", 2},
      {"--set sample", "--set sample: expected KEY=VALUE", 2},
      {"--set a.b.c=1", "--set a.b.c=1: expected KEY=VALUE", 2},
      {"--set mode.x=1", "--set mode.x=1: mode is not a section of the config", 2},
  };
  for (const Case& c : cases) {
    const auto r = run_scanfill("--config " + config + " --set output.dir=" + q(dir / "bad") + " " + c.args);
    EXPECT_EQ(r.exit_code, c.exit_code) << c.args << "\n" << r.out;
    EXPECT_NE(r.out.find(c.message), std::string::npos) << c.args << "\n" << r.out;
    EXPECT_FALSE(std::filesystem::exists(dir / "bad")) << c.args;
  }
  const auto alone = run_scanfill("--set preset=paper");
  EXPECT_EQ(alone.exit_code, 2);
  EXPECT_NE(alone.out.find("--set needs --config FILE"), std::string::npos) << alone.out;
}

TEST(Cli, ScanWritesASingleViewAndRefusesBadOptions) {
  test::TempDir dir;
  const auto ok = run_scanfill("scan --input procedural:vase --output " + q(dir / "s.ply") +
                               " --eye 0,-3,0.5 --target 0,0,0.5 --resolution 320,240 --noise 0.001 --quiet");
  ASSERT_EQ(ok.exit_code, 0) << ok.out;
  const auto info = nlohmann::json::parse(run_scanfill("info --full --json " + q(dir / "s.ply")).out);
  EXPECT_GT(info["points"].get<long>(), 5000);
  EXPECT_LT(info["bbox"][1][1].get<double>(), 0.25);  // only the side facing the eye at y = -3 (the far side is y > 0)
  const auto bad = run_scanfill("scan --input procedural:vase --output " + q(dir / "b.ply") + " --eye 0,-3");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.out.find("--eye expects X,Y,Z, got '0,-3'"), std::string::npos) << bad.out;
  EXPECT_FALSE(std::filesystem::exists(dir / "b.ply"));
}

TEST(Cli, EvalPrintsTheContractedScores) {
  const auto r = run_scanfill(
      "eval --output procedural:vase --reference procedural:vase --scan procedural:vase "
      "--template procedural:vase_template --samples 20000 --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.out;
  const auto j = nlohmann::json::parse(r.out);
  for (const char* key : {"chamfer_l1", "chamfer_l2", "fscore", "precision", "recall", "hausdorff",
                          "normal_consistency", "unseen_detail_recall"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_DOUBLE_EQ(j["fscore"].get<double>(), 1.0);
  test::TempDir dir;
  test::write_bytes(dir / "empty.ply", "");
  const auto bad = run_scanfill("eval --output " + q(dir / "empty.ply") + " --reference procedural:vase");
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_NE(bad.out.find("empty.ply: file is empty"), std::string::npos) << bad.out;
  const auto half = run_scanfill("eval --output procedural:vase --reference procedural:vase --scan procedural:vase");
  EXPECT_EQ(half.exit_code, 2);
  EXPECT_NE(half.out.find("--scan and --template go together"), std::string::npos) << half.out;
}

TEST(Cli, ReadmeListsTheCurrentDefaults) {
  // The README's config reference is --print-defaults verbatim: an option added without it fails here.
  test::TempDir dir;
  ASSERT_EQ(run_scanfill("--print-defaults > " + q(dir / "d.yaml")).exit_code, 0);
  const std::string readme = test::read_bytes(std::filesystem::path(SCANFILL_SOURCE_DIR) / "README.md");
  EXPECT_NE(readme.find("```yaml\n" + test::read_bytes(dir / "d.yaml") + "```"), std::string::npos)
      << "README.md's config block differs from `scanfill --print-defaults`; paste the new output there";
}

TEST(Cli, SampleWritesTheFixedPropertiesAndIsIdenticalOnOneAndTwoThreads) {
  test::TempDir dir;
  ASSERT_EQ(run_scanfill("--print-defaults > " + q(dir / "d.yaml")).exit_code, 0);
  // A procedural vase through the main run, then `sample` on its output, on 1 and 2 threads.
  const std::string cfg = test::read_bytes(dir / "d.yaml");
  test::write_bytes(dir / "v.yaml", cfg.substr(0, cfg.find("output:")) + "output:\n  dir: " + (dir / "run").string() +
                                        "\nsample:\n  count: 4000\n");
  const auto run = run_scanfill("--config " + q(dir / "v.yaml") + " --quiet --threads 2");
  ASSERT_EQ(run.exit_code, 0) << run.out;
  const std::string output_two_threads = test::read_bytes(dir / "run" / "output.ply");
  const auto input = dir / "run" / "samples_scan.ply";
  for (int t : {1, 2}) {
    const auto r =
        run_scanfill("sample --input " + q(input) + " --output " + q(dir / ("s" + std::to_string(t) + ".ply")) +
                     " --count 1500 --threads " + std::to_string(t));
    ASSERT_EQ(r.exit_code, 0) << r.out;
  }
  const std::string one = test::read_bytes(dir / "s1.ply"), two = test::read_bytes(dir / "s2.ply");
  EXPECT_EQ(one, two);
  EXPECT_NE(one.find("property float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\n"
                     "property float nz\nproperty float k1\nproperty float k2\nproperty float d1x\nproperty float "
                     "d1y\nproperty float d1z\n"),
            std::string::npos);
  EXPECT_NE(one.find("element vertex 1500\n"), std::string::npos);
  // The whole completion run is deterministic too: the same output.ply, byte for byte, on 1 and 2 threads.
  const auto again = run_scanfill("--config " + q(dir / "v.yaml") + " --quiet --threads 1");
  ASSERT_EQ(again.exit_code, 0);
  EXPECT_FALSE(output_two_threads.empty());
  EXPECT_EQ(test::read_bytes(dir / "run" / "output.ply"), output_two_threads);
}

}  // namespace
}  // namespace scanfill
