// Logging and progress on stderr, owned by the engine (CONVENTIONS: errors, logging, progress).
//
// spdlog writes through one sink that first clears the progress line, so log lines and the bar never mix. The bar is
// drawn only when stderr is a terminal: stage names of every running node, and the fraction of the latest one.
#pragma once

#include <spdlog/spdlog.h>

#include <chrono>
#include <map>
#include <memory>
#include <mutex>
#include <string>

namespace scanfill {

class Progress {
 public:
  static Progress& instance();

  void start(const std::string& stage);
  void update(const std::string& stage, double fraction);
  void finish(const std::string& stage);
  // Erase the bar (before other output); the next update redraws it.
  void clear_locked();
  std::mutex& mutex() { return mutex_; }
  bool enabled() const { return enabled_; }
  void set_enabled(bool on) { enabled_ = on; }

 private:
  Progress();
  void draw_locked();
  std::mutex mutex_;
  bool enabled_ = false;
  bool drawn_ = false;
  std::map<std::string, double> active_;
  std::string latest_;
  std::chrono::steady_clock::time_point last_draw_{};
};

// Sets up the default logger on stderr. Level: `verbose` -> debug, `quiet` -> warn, else SPDLOG_LEVEL or info.
void setup_logging(bool verbose, bool quiet);

// A named logger per node ("sample", "features", ...), sharing the sink.
std::shared_ptr<spdlog::logger> node_logger(const std::string& name);

}  // namespace scanfill
