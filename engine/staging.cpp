#include "engine/staging.h"

#include <dirent.h>
#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstring>

#include "nodes/core/errors.h"

namespace scanfill {
namespace {

// The folder a signal must remove: a fixed buffer, readable from a signal handler.
char g_staging[4096] = {0};
std::atomic<bool> g_staging_set{false};

// Removes the folder's files and the folder with async-signal-safe calls only. Not opendir/readdir: they allocate, and
// a signal that lands inside malloc (the sample stage's workers allocate all the time) left the handler waiting for the
// allocator's lock forever. Entries removed while a directory is read may be skipped, so it reads again until a pass
// removes nothing.
void remove_folder_now(const char* folder) {
  const int fd = ::open(folder, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd >= 0) {
    alignas(8) char buf[4096];
    for (bool removed = true; removed && ::lseek(fd, 0, SEEK_SET) == 0;) {
      removed = false;
      for (ssize_t n; (n = ::getdents64(fd, buf, sizeof(buf))) > 0;)
        for (ssize_t at = 0; at < n;) {
          const auto* e = reinterpret_cast<const struct dirent64*>(buf + at);
          at += e->d_reclen;
          if (std::strcmp(e->d_name, ".") != 0 && std::strcmp(e->d_name, "..") != 0)
            removed = ::unlinkat(fd, e->d_name, 0) == 0 || removed;
        }
    }
    ::close(fd);
  }
  ::rmdir(folder);
}

extern "C" void on_signal(int sig) {
  if (g_staging_set.load()) remove_folder_now(g_staging);
  _exit(128 + sig);
}

void sync_file(const std::filesystem::path& path) {
  const int fd = ::open(path.c_str(), O_RDONLY);
  if (fd < 0 || ::fsync(fd) != 0) {
    if (fd >= 0) ::close(fd);
    throw IoError(path.string() + ": cannot be flushed to disk (" + std::strerror(errno) + ")");
  }
  ::close(fd);
}

}  // namespace

Staging::Staging(const std::filesystem::path& output_dir) : output_dir_(output_dir) {
  std::error_code ec;
  if (std::filesystem::exists(output_dir_, ec) && !std::filesystem::is_directory(output_dir_, ec))
    throw IoError(output_dir_.string() + ": the output folder is a file");
  std::filesystem::path parent = std::filesystem::absolute(output_dir_, ec).parent_path();
  std::filesystem::create_directories(parent, ec);
  if (ec) throw IoError(parent.string() + ": cannot create the output folder's parent (" + ec.message() + ")");
  // Appended, not "." + string: GCC 12 warns (-Wrestrict, a false positive) on that operator+ when LTO inlines it.
  std::string hidden(".");
  hidden.append(output_dir_.filename().string()).append(".scanfill-").append(std::to_string(::getpid()));
  folder_ = parent / hidden;
  std::filesystem::remove_all(folder_, ec);
  if (!std::filesystem::create_directory(folder_, ec) || ec)
    throw IoError(folder_.string() + ": cannot create a folder beside the output folder (" + ec.message() + ")");
  if (folder_.string().size() < sizeof(g_staging)) {
    std::strcpy(g_staging, folder_.c_str());
    g_staging_set.store(true);
  }
}

Staging::~Staging() {
  g_staging_set.store(false);
  if (committed_) return;
  std::error_code ec;
  std::filesystem::remove_all(folder_, ec);
}

std::vector<std::filesystem::path> Staging::commit(const std::vector<std::string>& names) {
  for (const auto& name : names) sync_file(folder_ / name);
  std::error_code ec;
  std::filesystem::create_directories(output_dir_, ec);
  if (ec) throw IoError(output_dir_.string() + ": cannot create the output folder (" + ec.message() + ")");
  std::vector<std::filesystem::path> done;
  for (const auto& name : names) {
    std::filesystem::rename(folder_ / name, output_dir_ / name, ec);
    if (ec) throw IoError((output_dir_ / name).string() + ": cannot be moved into place (" + ec.message() + ")");
    done.push_back(output_dir_ / name);
  }
  sync_file(output_dir_);
  g_staging_set.store(false);
  std::filesystem::remove_all(folder_, ec);
  committed_ = true;
  return done;
}

void check_outputs_spare_inputs(const RunConfig& config) {
  std::vector<std::filesystem::path> written{"output.ply",  "analogy.ply",     "report.json",
                                             "preview.png", "output_mesh.ply", "correspondence.ply"};
  for (const auto& input : config.inputs) written.push_back("samples_" + role_name(input.role) + ".ply");
  std::error_code ec;
  for (const auto& input : config.inputs) {
    for (const InputSpec& spec : all_specs(input)) {
      if (spec.path.empty()) continue;
      const auto in = std::filesystem::weakly_canonical(spec.path, ec);
      for (const auto& name : written)
        if (!ec && in == std::filesystem::weakly_canonical(config.output_dir / name, ec))
          throw ConfigError("inputs." + role_name(input.role) + ": " + spec.path.string() +
                            " would be overwritten by this run's " + name.string() +
                            " (output.dir: " + config.output_dir.string() + "); choose another output.dir");
    }
  }
}

void remove_staging_on_signals() {
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
}

}  // namespace scanfill
