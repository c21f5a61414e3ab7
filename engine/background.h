// Work done one piece after another beside the graph's nodes (issue 13): output.ply's runs are encoded and written
// while the transfer computes the next run, and the last one beside whatever nodes still run.
#pragma once

#include <tbb/task_group.h>

#include <functional>

namespace scanfill {

// Pieces of work run in submission order, each beside its caller: at most one is pending, and submit() waits for it
// before starting the next. With one thread (max_allowed_parallelism 1) each piece runs at once, inside submit(): a
// task left in the graph's arena after the graph has finished would have no thread to run it.
class SerialBackground {
 public:
  SerialBackground();
  SerialBackground(const SerialBackground&) = delete;
  SerialBackground& operator=(const SerialBackground&) = delete;
  ~SerialBackground();  // waits; a failure not collected by wait() is dropped with the run that failed anyway

  // Waits for the pending piece (rethrowing its failure), then starts `work`.
  void submit(std::function<void()> work);
  // Waits for the pending piece, rethrowing its failure.
  void wait();

 private:
  bool at_once_;
  tbb::task_group group_;
};

}  // namespace scanfill
