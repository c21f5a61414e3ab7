// Issue 11, item 4: a run fails whole. A full disk during the output phase, SIGTERM mid-run and an input stored where
// the run writes leave nothing of the run's own behind (and the input unchanged).
#include <gtest/gtest.h>
#include <sys/mount.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <thread>

#include "test_util.h"

namespace scanfill {
namespace {

using test::run_scanfill;

std::string q(const std::filesystem::path& p) {
  return test::quoted(p);
}

// A small completion of the procedural vase: a few seconds.
void write_config(const std::filesystem::path& cfg, const std::filesystem::path& out, const std::string& scan) {
  test::write_bytes(cfg, "mode: completion\ninputs:\n  scan: " + scan +
                             "\n  template: procedural:vase_template\noutput:\n  dir: " + out.string() +
                             "\nvirtual_scan:\n  eye: [0, -3, 0.6]\n  width: 240\n  height: 240\n  fov_deg: 30\n"
                             "sample:\n  count: 4000\n");
}

// Everything in `folder`, hidden files included.
std::vector<std::string> entries(const std::filesystem::path& folder) {
  std::vector<std::string> out;
  for (const auto& e : std::filesystem::directory_iterator(folder)) out.push_back(e.path().filename().string());
  return out;
}

TEST(RunFailsWhole, AnInputWhereTheRunWritesIsRefusedAndUnchanged) {
  test::TempDir dir;
  std::filesystem::create_directories(dir / "out");
  // A scan stored as the run's own output.ply: a real PLY, made by `scan`.
  ASSERT_EQ(run_scanfill("scan --input procedural:vase --output " + q(dir / "out" / "output.ply") +
                         " --eye 0,-3,0.6 --resolution 120,120")
                .exit_code,
            0);
  const std::string before = test::read_bytes(dir / "out" / "output.ply");
  write_config(dir / "c.yaml", dir / "out", (dir / "out" / "output.ply").string());
  const auto r = run_scanfill("--config " + q(dir / "c.yaml"));
  EXPECT_EQ(r.exit_code, 2) << r.out;
  EXPECT_NE(r.out.find("would be overwritten"), std::string::npos) << r.out;
  EXPECT_EQ(test::read_bytes(dir / "out" / "output.ply"), before);
  EXPECT_EQ(entries(dir / "out").size(), 1u);
}

TEST(RunFailsWhole, AnOutputFolderThatIsAFileIsRefusedBeforeAnyWork) {
  test::TempDir dir;
  test::write_bytes(dir / "out", "not a folder");
  write_config(dir / "c.yaml", dir / "out", "procedural:vase");
  const auto t0 = std::chrono::steady_clock::now();
  const auto r = run_scanfill("--config " + q(dir / "c.yaml"));
  EXPECT_EQ(r.exit_code, 1) << r.out;
  EXPECT_NE(r.out.find("the output folder is a file"), std::string::npos) << r.out;
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 2.0);
  EXPECT_EQ(test::read_bytes(dir / "out"), "not a folder");
}

TEST(RunFailsWhole, AFullDiskDuringTheOutputPhaseLeavesNoFile) {
  if (::geteuid() != 0) GTEST_SKIP() << "mounting a small tmpfs needs root";
  test::TempDir dir;
  const auto mnt = dir / "mnt";
  std::filesystem::create_directories(mnt);
  // 256 KiB: the inputs are procedural, the samples and output.ply of this run need several MB.
  if (::mount("tmpfs", mnt.c_str(), "tmpfs", 0, "size=256k") != 0) GTEST_SKIP() << "tmpfs mount refused here";
  write_config(dir / "c.yaml", mnt / "out", "procedural:vase");
  const auto r = run_scanfill("--config " + q(dir / "c.yaml"));
  const auto left = entries(mnt);
  ::umount(mnt.c_str());
  EXPECT_EQ(r.exit_code, 1) << r.out;
  EXPECT_TRUE(left.empty()) << left.front();
}

TEST(RunFailsWhole, SigtermMidRunLeavesNothingBehind) {
  test::TempDir dir;
  write_config(dir / "c.yaml", dir / "run" / "out", "procedural:vase");
  std::filesystem::create_directories(dir / "run");
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    const std::string cfg = (dir / "c.yaml").string();
    ::execl(SCANFILL_BINARY, SCANFILL_BINARY, "--config", cfg.c_str(), "-q", static_cast<char*>(nullptr));
    ::_exit(127);
  }
  // Wait for the staging folder (made before any work), then stop the run while it computes.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (entries(dir / "run").empty() && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  ASSERT_FALSE(entries(dir / "run").empty()) << "the run made no staging folder";
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  ::kill(pid, SIGTERM);
  int status = 0;
  ::waitpid(pid, &status, 0);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 128 + SIGTERM) << status;
  EXPECT_TRUE(entries(dir / "run").empty());
}

}  // namespace
}  // namespace scanfill
