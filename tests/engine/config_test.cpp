#include "engine/config.h"

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cmath>

#include "nodes/core/errors.h"
#include "test_util.h"

namespace scanfill {
namespace {

std::string config_error(const test::TempDir& dir, const std::string& yaml) {
  test::write_bytes(dir / "c.yaml", yaml);
  try {
    load_config(dir / "c.yaml");
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

const char* kValidHead = "mode: completion\ninputs:\n  scan: procedural:vase\n  template: procedural:vase_template\n";

TEST(Config, ReadsEveryKeyAndResolvesPathsAgainstTheConfigFile) {
  test::TempDir dir;
  test::write_bytes(dir / "scan.xyz", "0 0 0\n");
  test::write_bytes(dir / "c.yaml",
                    "mode: completion\ninputs:\n  scan: scan.xyz\n  template: procedural:cylinder\noutput:\n  dir: o\n"
                    "threads: 1\nsample:\n  count: 500\n  seed: 9\nfeatures:\n  k: 20\n  orientation: viewpoint\n"
                    "  viewpoint: [1, 2, 3]\n");
  const RunConfig c = load_config(dir / "c.yaml");
  ASSERT_EQ(c.inputs.size(), 2u);
  EXPECT_EQ(c.inputs[0].role, Role::kScan);
  EXPECT_EQ(c.inputs[0].spec.path, dir / "scan.xyz");
  EXPECT_EQ(c.inputs[1].spec.procedural, "cylinder");
  EXPECT_EQ(c.output_dir, "o");
  EXPECT_EQ(c.threads, 1);
  EXPECT_EQ(c.sample.count, 500);
  EXPECT_EQ(c.sample.seed, 9u);
  EXPECT_EQ(c.features.k, 20);
  EXPECT_EQ(c.features.orientation, NormalOrientation::kViewpoint);
  EXPECT_EQ(*c.features.viewpoint, Eigen::Vector3d(1, 2, 3));
}

TEST(Config, UnknownKeysAreRejectedListingTheValidOnesWithLineAndColumn) {
  test::TempDir dir;
  const std::string e = config_error(dir, std::string(kValidHead) + "sample:\n  cuont: 5\n");
  EXPECT_NE(e.find("c.yaml:6:3: sample.cuont: unknown key (valid: spacing, count,"), std::string::npos) << e;
  const std::string top = config_error(dir, std::string(kValidHead) + "sampel: {}\n");
  EXPECT_NE(top.find("c.yaml:5:1: sampel: unknown key (valid: mode, inputs, output,"), std::string::npos) << top;
}

TEST(Config, EveryProblemIsReportedAtOnceWithoutClamping) {
  test::TempDir dir;
  const std::string e = config_error(dir, std::string(kValidHead) +
                                              "sample:\n  count: 0\n  oversampling: 500\nfeatures:\n  k: 3\n"
                                              "  umbilic_ratio: abc\n");
  // A value that does not parse and values out of range, all in one report.
  EXPECT_NE(e.find("features.umbilic_ratio: expected a number, got 'abc'"), std::string::npos) << e;
  EXPECT_NE(e.find("sample.count: expected an integer >= 1, got 0"), std::string::npos) << e;
  EXPECT_NE(e.find("features.k: expected an integer in [6, 128], got 3"), std::string::npos) << e;
  const std::string r =
      config_error(dir, std::string(kValidHead) + "sample:\n  count: 0\n  oversampling: 500\nfeatures:\n  k: 3\n");
  EXPECT_NE(r.find("c.yaml:6:10: sample.count: expected an integer >= 1, got 0"), std::string::npos) << r;
  EXPECT_NE(r.find("sample.oversampling: expected a number in [2, 100], got 500"), std::string::npos) << r;
  EXPECT_NE(r.find("features.k: expected an integer in [6, 128], got 3"), std::string::npos) << r;
  EXPECT_EQ(std::count(r.begin(), r.end(), '\n'), 2) << r;  // three problems, one line each
}

TEST(Config, InputsAreCheckedForTheMode) {
  test::TempDir dir;
  EXPECT_NE(config_error(dir, "mode: completion\ninputs:\n  scan: procedural:vase\n")
                .find("mode 'completion' needs input 'template'"),
            std::string::npos);
  EXPECT_NE(config_error(dir, "mode: transfer\ninputs:\n  scan: procedural:vase\n").find("inputs.scan: unknown key"),
            std::string::npos);
  EXPECT_NE(config_error(dir, "mode: completion\ninputs:\n  scan: nothere.ply\n  template: procedural:vase\n")
                .find("inputs.scan: no such file: "),
            std::string::npos);
  EXPECT_NE(config_error(dir, "mode: completion\ninputs:\n  scan: procedural:cube\n  template: procedural:vase\n")
                .find("unknown procedural shape 'cube'"),
            std::string::npos);
  EXPECT_NE(config_error(dir, "mode: styling\n").find("mode: expected one of completion, transfer, analogy"),
            std::string::npos);
  test::write_bytes(dir / "x.las", "LASF");
  EXPECT_NE(config_error(dir, "mode: analogy\ninputs:\n  source: x.las\n  target: procedural:vase\n")
                .find("unknown format '.las'"),
            std::string::npos);
}

TEST(Config, BrokenYamlNamesLineAndColumn) {
  test::TempDir dir;
  const std::string e = config_error(dir, "mode: completion\ninputs: [a, b\n");
  EXPECT_NE(e.find("c.yaml:"), std::string::npos);
  EXPECT_NE(e.find("invalid YAML"), std::string::npos) << e;
  EXPECT_NE(config_error(dir, "- a\n- b\n").find("expected a map of settings"), std::string::npos);
}

TEST(Config, PrintedDefaultsAreACompleteValidConfig) {
  test::TempDir dir;
  const std::string yaml = default_config_yaml();
  test::write_bytes(dir / "d.yaml", yaml);
  const RunConfig c = load_config(dir / "d.yaml");
  EXPECT_TRUE(validate(c).empty());
  // Every field of every options struct appears.
  for (const char* key :
       {"spacing:", "count:", "oversampling:", "normal_angle_deg:", "weight_exponent:", "seed:", "k:", "orientation:",
        "viewpoint:", "umbilic_ratio:", "flat_threshold:", "smooth_directions:", "reliable_weight:", "regularization:",
        "max_iterations:", "tolerance:", "morton_sort:", "threads:"})
    EXPECT_NE(yaml.find(key), std::string::npos) << key;
  const SampleOptions defaults;
  EXPECT_EQ(c.sample.count, defaults.count);
  EXPECT_EQ(c.sample.oversampling, defaults.oversampling);
}

TEST(Config, EveryBundledConfigLoadsAndValidates) {
  int n = 0;
  for (const auto& entry : std::filesystem::directory_iterator(test::source_dir() / "configs")) {
    if (entry.path().extension() != ".yaml") continue;
    const auto uses_shared = test::read_bytes(entry.path()).find("shared/data") != std::string::npos;
    if (uses_shared && !std::filesystem::exists(test::shared_data())) continue;
    EXPECT_NO_THROW(load_config(entry.path())) << entry.path();
    ++n;
  }
  EXPECT_GE(n, 1);
}

TEST(Config, ThePaperPresetSetsThePapersValuesAndKeysStillOverrideIt) {
  test::TempDir dir;
  test::write_bytes(dir / "c.yaml", std::string(kValidHead) + "preset: paper\nlabel:\n  mu: 0.75\n");
  const RunConfig c = load_config(dir / "c.yaml");
  EXPECT_EQ(c.preset, "paper");
  EXPECT_DOUBLE_EQ(c.label.sigma_n, 0.1 * M_PI / 2);
  EXPECT_DOUBLE_EQ(c.label.mu, 0.75);  // the key wins over the preset
  EXPECT_TRUE(c.label.paper_label_costs);
  EXPECT_DOUBLE_EQ(c.label.mrf_radius, 5.0);
  EXPECT_DOUBLE_EQ(c.label.mrf_min_normal_dot, 0.0);
  EXPECT_DOUBLE_EQ(c.support.normal_angle_deg, 90.0);
  // The default preset leaves ours.
  test::write_bytes(dir / "d.yaml", kValidHead);
  const RunConfig d = load_config(dir / "d.yaml");
  EXPECT_EQ(d.preset, "scanfill");
  EXPECT_DOUBLE_EQ(d.label.mu, LabelOptions{}.mu);
  EXPECT_FALSE(d.label.paper_label_costs);
  const std::string e = config_error(dir, std::string(kValidHead) + "preset: papers\n");
  EXPECT_NE(e.find("c.yaml:5:9: preset: expected scanfill or paper, got 'papers'"), std::string::npos) << e;
}

TEST(Config, LandmarksFileTakesTwoPickedPointsFilesBesideTheConfig) {
  test::TempDir dir;
  test::write_bytes(dir / "s.pp", "<PickedPoints/>");
  test::write_bytes(dir / "t.pp", "<PickedPoints/>");
  test::write_bytes(dir / "c.yaml", std::string(kValidHead) + "correspond:\n  landmarks_file: [s.pp, t.pp]\n");
  const RunConfig c = load_config(dir / "c.yaml");
  EXPECT_EQ(c.correspond.landmarks_file.exemplar, dir / "s.pp");
  EXPECT_EQ(c.correspond.landmarks_file.source, dir / "t.pp");
  const std::string missing =
      config_error(dir, std::string(kValidHead) + "correspond:\n  landmarks_file: [s.pp, nope.pp]\n");
  EXPECT_NE(missing.find("correspond.landmarks_file: no such file: "), std::string::npos) << missing;
  const std::string one = config_error(dir, std::string(kValidHead) + "correspond:\n  landmarks_file: [s.pp]\n");
  EXPECT_NE(one.find("correspond.landmarks_file: expected two MeshLab picked-points files"), std::string::npos) << one;
}

TEST(Config, OutputColourIsAutoUnlessSaid) {
  test::TempDir dir;
  test::write_bytes(dir / "d.yaml", kValidHead);
  EXPECT_EQ(load_config(dir / "d.yaml").output_colour, ColourChoice::kAuto);
  const std::pair<const char*, ColourChoice> choices[] = {
      {"origin", ColourChoice::kOrigin}, {"label", ColourChoice::kLabel}, {"scan", ColourChoice::kScan}};
  for (const auto& [name, choice] : choices) {
    test::write_bytes(dir / "c.yaml", std::string(kValidHead) + "output:\n  colour: " + name + "\n");
    EXPECT_EQ(load_config(dir / "c.yaml").output_colour, choice) << name;
  }
  const std::string e = config_error(dir, std::string(kValidHead) + "output:\n  colour: rainbow\n");
  EXPECT_NE(e.find("c.yaml:6:11: output.colour: expected one of auto, origin, label, scan, got 'rainbow'"),
            std::string::npos)
      << e;
}

TEST(Config, ACompletionsScaleRangeMustMeetTheVotedOne) {
  test::TempDir dir;
  test::write_bytes(dir / "d.yaml", std::string(kValidHead) + "vote:\n  min_scale: 0.5\n  completion_scale: .inf\n");
  EXPECT_TRUE(std::isinf(load_config(dir / "d.yaml").vote.completion_scale));
  // At 1 the range would be one point, which no refined transform's scale hits.
  for (const char* value : {"0.9", "1"}) {
    const std::string below = config_error(dir, std::string(kValidHead) + "vote:\n  completion_scale: " + value + "\n");
    EXPECT_NE(below.find(std::string("vote.completion_scale: expected a number > 1, got ") + value), std::string::npos)
        << below;
  }
  const std::string apart =
      config_error(dir, std::string(kValidHead) + "vote:\n  min_scale: 1.5\n  max_scale: 4\n  completion_scale: 1.5\n");
  EXPECT_NE(apart.find("vote.completion_scale: completion votes for scales in [1 / 1.5, 1.5], which [vote.min_scale, "
                       "vote.max_scale] = [1.5, 4] does not overlap: raise vote.completion_scale or widen"),
            std::string::npos)
      << apart;
  // A range that is wrong on its own is said once, by its own key.
  const std::string inverted = config_error(dir, std::string(kValidHead) + "vote:\n  min_scale: 3\n  max_scale: 2\n");
  EXPECT_NE(inverted.find("vote.max_scale: expected a number >= vote.min_scale"), std::string::npos) << inverted;
  EXPECT_EQ(inverted.find("vote.completion_scale"), std::string::npos) << inverted;
  // Transfer takes the voted range as it is.
  test::write_bytes(dir / "t.yaml",
                    "mode: transfer\ninputs:\n  source: procedural:box\n  target: procedural:box\n  exemplar: "
                    "procedural:box\nvote:\n  min_scale: 2\n  max_scale: 4\n");
  EXPECT_EQ(load_config(dir / "t.yaml").vote.min_scale, 2);
}

TEST(Config, OutputSurfaceIsPoissonForCompletionsUnlessSaid) {
  test::TempDir dir;
  test::write_bytes(dir / "d.yaml", kValidHead);
  RunConfig c = load_config(dir / "d.yaml");
  EXPECT_EQ(c.output_surface, SurfaceChoice::kAuto);
  EXPECT_TRUE(makes_surface(c));  // kValidHead is a completion
  c.mode = RunMode::kTransfer;
  EXPECT_FALSE(makes_surface(c));  // auto: a transfer keeps the exemplar's own triangles, or none
  c.output_surface = SurfaceChoice::kPoisson;
  EXPECT_TRUE(makes_surface(c));
  c.mode = RunMode::kAnalogy;
  EXPECT_FALSE(makes_surface(c));  // no output.ply
  test::write_bytes(dir / "c.yaml", std::string(kValidHead) + "output:\n  surface: none\n");
  EXPECT_FALSE(makes_surface(load_config(dir / "c.yaml")));
  EXPECT_FALSE(makes_surface(load_config(dir / "d.yaml", {"output.surface=none"})));
  const std::string e = config_error(dir, std::string(kValidHead) + "output:\n  surface: marching\n");
  EXPECT_NE(e.find("c.yaml:6:12: output.surface: expected one of auto, none, poisson, got 'marching'"),
            std::string::npos)
      << e;
  const std::string analogy =
      config_error(dir,
                   "mode: analogy\ninputs:\n  source: procedural:vase_template\n  target: procedural:vase_template\n"
                   "output:\n  surface: poisson\n");
  EXPECT_NE(analogy.find("output.surface: mode analogy writes no output.ply to mesh"), std::string::npos) << analogy;
  const std::string depth = config_error(dir, std::string(kValidHead) + "surface:\n  depth: 30\n");
  EXPECT_NE(depth.find("surface.depth: expected an integer in [4, 12], got 30"), std::string::npos) << depth;
}

TEST(Config, AScanMayBeAListOfFragmentsAndEachIsChecked) {
  test::TempDir dir;
  test::write_bytes(dir / "a.xyz", "0 0 0\n");
  test::write_bytes(dir / "b.xyz", "1 0 0\n");
  test::write_bytes(dir / "c.yaml", "mode: completion\ninputs:\n  scan: [a.xyz, b.xyz]\n  template: procedural:vase\n");
  const RunConfig c = load_config(dir / "c.yaml");
  ASSERT_EQ(c.inputs.size(), 2u);
  EXPECT_EQ(c.inputs[0].spec.path, dir / "a.xyz");
  ASSERT_EQ(c.inputs[0].fragments.size(), 1u);
  EXPECT_EQ(c.inputs[0].fragments[0].path, dir / "b.xyz");
  // A missing fragment is named by its place in the list.
  const std::string missing =
      config_error(dir, "mode: completion\ninputs:\n  scan: [a.xyz, nope.xyz]\n  template: procedural:vase\n");
  EXPECT_NE(missing.find("inputs.scan[1]: no such file"), std::string::npos) << missing;
  // A list item that is not a path, an empty list, and a template given as a list.
  const std::string nested =
      config_error(dir, "mode: completion\ninputs:\n  scan: [a.xyz, [b.xyz]]\n  template: procedural:vase\n");
  EXPECT_NE(nested.find("inputs.scan[1]: expected a file path or procedural:NAME, got a list"), std::string::npos)
      << nested;
  const std::string empty = config_error(dir, "mode: completion\ninputs:\n  scan: []\n  template: procedural:vase\n");
  EXPECT_NE(empty.find("inputs.scan: expected a file path, procedural:NAME or a list of scan fragments"),
            std::string::npos)
      << empty;
  const std::string templ = config_error(dir, "mode: completion\ninputs:\n  scan: a.xyz\n  template: [a.xyz, b.xyz]\n");
  EXPECT_NE(templ.find("inputs.template: expected a file path or procedural:NAME, got a list"), std::string::npos)
      << templ;
  // Fragments are real scans: the virtual scanner does not scan them again.
  const std::string scanned =
      config_error(dir,
                   "mode: completion\ninputs:\n  scan: [a.xyz, b.xyz]\n  template: procedural:vase\nvirtual_scan:\n"
                   "  eye: [0, -3, 0]\n");
  EXPECT_NE(scanned.find("virtual_scan.eye: a scan given as fragments is not scanned again"), std::string::npos)
      << scanned;
}

}  // namespace
}  // namespace scanfill
