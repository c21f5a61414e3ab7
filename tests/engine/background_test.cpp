#include "engine/background.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <stdexcept>
#include <vector>

namespace scanfill {
namespace {

// Pieces run one at a time in submission order, on one thread and on two.
TEST(SerialBackground, RunsPiecesInOrderOnOneAndTwoThreads) {
  for (const size_t threads : {1, 2}) {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, threads);
    std::vector<int> order;
    {
      SerialBackground pieces;
      for (int i = 0; i < 50; ++i) pieces.submit([&order, i] { order.push_back(i); });
      pieces.wait();
    }
    ASSERT_EQ(order.size(), 50u) << threads << " threads";
    for (int i = 0; i < 50; ++i) EXPECT_EQ(order[size_t(i)], i) << threads << " threads";
  }
}

// A failed piece is reported by the next wait (or submit), not lost.
TEST(SerialBackground, WaitRethrowsAFailedPiece) {
  for (const size_t threads : {1, 2}) {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, threads);
    SerialBackground pieces;
    if (threads == 1) {
      EXPECT_THROW(pieces.submit([] { throw std::runtime_error("disk full"); }), std::runtime_error);
    } else {
      pieces.submit([] { throw std::runtime_error("disk full"); });
      EXPECT_THROW(pieces.wait(), std::runtime_error);
    }
  }
}

}  // namespace
}  // namespace scanfill
