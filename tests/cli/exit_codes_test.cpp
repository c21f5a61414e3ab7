// The exit-code contract (README, "Hardening"): 0 success, 1 a run or input error, 2 a usage or config error; every
// error one line naming the option, the file, or file:line. The reproducers of issue 11 as the user meets them.
#include <gtest/gtest.h>
#include <sys/resource.h>

#include <chrono>
#include <sstream>

#include "test_util.h"

namespace scanfill {
namespace {

using test::run_scanfill;

std::string q(const std::filesystem::path& p) {
  return test::quoted(p);
}

struct Expect {
  std::string args;
  int code;
  std::string message;  // must appear in the one line of output
};

void check(const Expect& e) {
  const auto start = std::chrono::steady_clock::now();
  const auto r = run_scanfill(e.args);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(r.exit_code, e.code) << e.args << "\n" << r.out;
  EXPECT_NE(r.out.find(e.message), std::string::npos) << e.args << "\n" << r.out;
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << "one line: " << e.args << "\n" << r.out;
  EXPECT_LT(r.out.size(), 400u) << e.args << "\n" << r.out;
  EXPECT_LT(seconds, 5.0) << e.args;
}

TEST(ExitCodes, UsageErrorsExitTwoWithOneLineNamingTheOption) {
  test::TempDir dir;
  test::write_bytes(dir / "tri.xyz", "0 0 0\n1 0 0\n0 1 0\n");
  const std::string s = "sample --input " + q(dir / "tri.xyz") + " --output " + q(dir / "o.ply");
  const Expect cases[] = {
      {"--threads -1", 2, "--threads"},  // CLI11 printed a range with 300 digits and exited 105
      {"--threads 0", 2, "--threads"},
      {"--threads nan", 2, "--threads"},
      {"sample", 2, "--input"},             // 106
      {"--frobnicate", 2, "--frobnicate"},  // 109
      {"info", 2, "file"},
      {"info a.ply b.ply", 2, "b.ply"},
      {s + " --spacing nan", 2, "--spacing"},  // was accepted
      {s + " --spacing inf", 2, "--spacing"},
      {s + " --spacing -1", 2, "--spacing"},
      {s + " --count 1e300", 2, "--count"},
      {s + " --count 1 --spacing 1", 2, "--spacing"},
      {s + " --k 3", 2, "--k"},
      {"eval --output procedural:vase --reference procedural:vase --threshold nan", 2, "--threshold"},
      {"eval --output procedural:vase --reference procedural:vase --samples 0", 2, "--samples"},
      {"scan --input procedural:vase --output " + q(dir / "s.ply") + " --eye 0,-3,0 --fov nan", 2, "--fov"},
      {"scan --input procedural:vase --output " + q(dir / "s.ply") + " --eye 0,-3,0 --noise -1", 2, "--noise"},
      {"", 2, "nothing to do"},
  };
  for (const Expect& e : cases) {
    if (e.args.empty()) {  // prints the help before its one error line
      const auto r = run_scanfill("");
      EXPECT_EQ(r.exit_code, 2) << r.out;
      EXPECT_NE(r.out.find(e.message), std::string::npos) << r.out;
      continue;
    }
    check(e);
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "o.ply"));
  EXPECT_FALSE(std::filesystem::exists(dir / "s.ply"));
}

TEST(ExitCodes, HelpAndVersionExitZero) {
  for (const char* args : {"--help", "--version", "sample --help", "info --help"})
    EXPECT_EQ(run_scanfill(args).exit_code, 0) << args;
}

TEST(ExitCodes, ConfigErrorsExitTwoWithFileAndLine) {
  test::TempDir dir;
  const std::string head = "mode: completion\ninputs:\n  scan: procedural:vase\n  template: procedural:vase_template\n";
  test::write_bytes(dir / "mapkey.yaml", head + "{a: 1}: 2\n");
  test::write_bytes(dir / "seqkey.yaml", head + "? [a, b]\n: 2\n");
  test::write_bytes(dir / "inputkey.yaml",
                    "mode: completion\ninputs:\n  [scan]: procedural:vase\n  scan: procedural:vase\n"
                    "  template: procedural:vase_template\n");
  test::write_bytes(dir / "unknown.yaml", head + "sample:\n  cuont: 3\n");
  test::write_bytes(dir / "invalid.yaml", head + "sample: [\n");
  test::write_bytes(dir / "range.yaml", head + "sample:\n  count: .nan\n");
  std::filesystem::create_directories(dir / "folder.yaml");
  const auto f = [&](const char* name) { return (dir / name).string(); };
  const Expect cases[] = {
      {"--config " + q(dir / "mapkey.yaml"), 2, f("mapkey.yaml") + ":5:"},  // was exit 1 "unexpected: yaml-cpp ..."
      {"--config " + q(dir / "seqkey.yaml"), 2, f("seqkey.yaml") + ":5:"},
      {"--config " + q(dir / "inputkey.yaml"), 2, f("inputkey.yaml") + ":3:"},
      {"--config " + q(dir / "unknown.yaml"), 2, f("unknown.yaml") + ":6:"},
      {"--config " + q(dir / "invalid.yaml"), 2, f("invalid.yaml") + ":"},
      {"--config " + q(dir / "range.yaml"), 2, "sample.count"},
      {"--config " + q(dir / "folder.yaml"), 2, "folder.yaml"},  // was exit 105
      {"--config " + q(dir / "missing.yaml"), 2, "missing.yaml"},
  };
  for (const Expect& e : cases) check(e);
}

// Each file reproducer of issue 11 through the command line: exit 1, one line naming the file, under 5 s and 300 MB.
TEST(ExitCodes, MalformedInputsExitOneInOneLineNamingTheFile) {
  test::TempDir dir;
  const std::pair<const char*, std::string> files[] = {
      {"version.pcd", "VERSION 0.7\n"},
      {"fields.pcd", "FIELDS"},
      {"data.pcd", "DATA"},
      {"size1.pcd", "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 1\nTYPE F F F\nWIDTH 1\nHEIGHT 1\nPOINTS 1\nDATA binary\n" +
                        std::string(9, '\0')},
      {"tera.ply",
       "ply\nformat ascii 1.0\nelement vertex 1000000000000\nproperty float x\nproperty float y\nproperty float z\n"
       "end_header\n0 0 0\n"},
      {"exa.ply",
       "ply\nformat ascii 1.0\nelement vertex 4000000000000000000\nproperty float x\nproperty float y\n"
       "property float z\nend_header\n0 0 0\n"},
      {"list.ply",
       "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
       "element face 1\nproperty list uint int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n200000000 0 1 2\n"},
      {"face.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n200000000 0 1 2\n"},
      {"float.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n1e300 0 1 2\n"},
  };
  for (const auto& [name, bytes] : files) {
    test::write_bytes(dir / name, bytes);
    check({"info --full " + q(dir / name), 1, (dir / name).string() + ": "});  // the reader on every byte
  }
  rusage children{};
  getrusage(RUSAGE_CHILDREN, &children);
  EXPECT_LT(children.ru_maxrss, 300 * 1024) << "KiB, the largest of the runs above";
}

// 1000 copies of one point gave `sample --count 100` 100 copies of it, with exit 0.
TEST(ExitCodes, DuplicatePointsAreMergedWithAWarningOrRefused) {
  test::TempDir dir;
  std::string same;
  for (int i = 0; i < 1000; ++i) same += "0.5 0.5 0.5\n";
  test::write_bytes(dir / "same.xyz", same);
  const auto r =
      run_scanfill("sample --input " + q(dir / "same.xyz") + " --output " + q(dir / "o.ply") + " --count 100");
  EXPECT_EQ(r.exit_code, 1) << r.out;
  EXPECT_NE(r.out.find("at least 3 distinct points, the cloud has 1 (999 duplicates merged)"), std::string::npos)
      << r.out;
  EXPECT_FALSE(std::filesystem::exists(dir / "o.ply"));
  // A 30 x 30 grid written twice: merged, with the count in a warning, then sampled as the grid alone.
  std::ostringstream grid;
  for (int twice = 0; twice < 2; ++twice)
    for (int i = 0; i < 30; ++i)
      for (int j = 0; j < 30; ++j) grid << i * 0.01 << " " << j * 0.01 << " 0\n";
  test::write_bytes(dir / "grid.xyz", grid.str());
  const auto g =
      run_scanfill("sample --input " + q(dir / "grid.xyz") + " --output " + q(dir / "g.ply") + " --count 200");
  EXPECT_EQ(g.exit_code, 0) << g.out;
  EXPECT_NE(g.out.find("900 of the cloud's 1800 points repeat another point's position"), std::string::npos) << g.out;
  const std::string ply = test::read_bytes(dir / "g.ply");
  EXPECT_NE(ply.find("element vertex 200\n"), std::string::npos);
}

}  // namespace
}  // namespace scanfill
