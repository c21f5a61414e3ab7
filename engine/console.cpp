#include "engine/console.h"

#include <spdlog/cfg/env.h>
#include <spdlog/sinks/base_sink.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace scanfill {
namespace {

// stderr sink that erases the progress bar before each line.
class ConsoleSink : public spdlog::sinks::base_sink<std::mutex> {
 protected:
  void sink_it_(const spdlog::details::log_msg& msg) override {
    spdlog::memory_buf_t formatted;
    formatter_->format(msg, formatted);
    std::lock_guard<std::mutex> lock(Progress::instance().mutex());
    Progress::instance().clear_locked();
    std::fwrite(formatted.data(), 1, formatted.size(), stderr);
    std::fflush(stderr);
  }
  void flush_() override { std::fflush(stderr); }
};

std::shared_ptr<ConsoleSink>& sink() {
  static auto s = std::make_shared<ConsoleSink>();
  return s;
}

}  // namespace

Progress& Progress::instance() {
  static Progress p;
  return p;
}

Progress::Progress() : enabled_(::isatty(STDERR_FILENO) == 1) {}

void Progress::start(const std::string& stage) {
  update(stage, 0.0);
}

void Progress::update(const std::string& stage, double fraction) {
  if (!enabled_) return;
  std::lock_guard<std::mutex> lock(mutex_);
  active_[stage] = fraction;
  latest_ = stage;
  const auto now = std::chrono::steady_clock::now();
  if (now - last_draw_ < std::chrono::milliseconds(100) && drawn_) return;
  last_draw_ = now;
  draw_locked();
}

void Progress::finish(const std::string& stage) {
  if (!enabled_) return;
  std::lock_guard<std::mutex> lock(mutex_);
  active_.erase(stage);
  if (active_.empty())
    clear_locked();
  else
    draw_locked();
}

void Progress::clear_locked() {
  if (!drawn_) return;
  std::fputs("\r\033[K", stderr);
  drawn_ = false;
}

void Progress::draw_locked() {
  if (!enabled_ || active_.empty()) return;
  std::string line = "\r\033[K";
  for (const auto& [stage, fraction] : active_) line += "[" + stage + "] ";
  const auto it = active_.find(latest_);
  if (it != active_.end()) {
    constexpr int kWidth = 30;
    const int filled = int(std::clamp(it->second, 0.0, 1.0) * kWidth);
    line += it->first + " |" + std::string(size_t(filled), '#') + std::string(size_t(kWidth - filled), '-') + "| " +
            std::to_string(int(it->second * 100)) + "%";
  }
  std::fputs(line.c_str(), stderr);
  std::fflush(stderr);
  drawn_ = true;
}

void setup_logging(bool verbose, bool quiet) {
  auto logger = std::make_shared<spdlog::logger>("scanfill", sink());
  logger->set_pattern("%^%l%$ [%n] %v");
  spdlog::set_default_logger(logger);
  spdlog::set_level(spdlog::level::info);
  spdlog::cfg::load_env_levels();
  if (verbose) spdlog::set_level(spdlog::level::debug);
  if (quiet) spdlog::set_level(spdlog::level::warn);
}

std::shared_ptr<spdlog::logger> node_logger(const std::string& name) {
  static std::mutex registry;
  std::lock_guard<std::mutex> lock(registry);
  if (auto existing = spdlog::get(name)) return existing;
  auto logger = std::make_shared<spdlog::logger>(name, sink());
  logger->set_pattern("%^%l%$ [%n] %v");
  logger->set_level(spdlog::default_logger()->level());
  spdlog::register_logger(logger);
  return logger;
}

}  // namespace scanfill
