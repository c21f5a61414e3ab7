#include "engine/background.h"

#include <tbb/global_control.h>

namespace scanfill {

SerialBackground::SerialBackground()
    : at_once_(tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism) < 2) {}

SerialBackground::~SerialBackground() {
  try {
    wait();
  } catch (...) {  // NOLINT(bugprone-empty-catch): the run has failed already; a destructor must not throw
  }
}

void SerialBackground::submit(std::function<void()> work) {
  if (at_once_) return work();
  group_.wait();
  group_.run(std::move(work));
}

void SerialBackground::wait() {
  group_.wait();
}

}  // namespace scanfill
