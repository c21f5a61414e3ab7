// A point set given a run at a time, as a file read in chunks gives it (rows: its columns): the tests' PointChunks.
#pragma once

#include <algorithm>
#include <vector>

#include "nodes/core/point_chunks.h"

namespace scanfill::test {

class RunsOf : public PointChunks {
 public:
  explicit RunsOf(const PointSet& points) : points_(points) {}
  Index rows() const override { return points_.size(); }
  void rewind() override { at_ = 0; }
  bool next(Index max_points, PointSet& out) override {
    if (at_ >= points_.size()) return false;
    const Index n = std::min(max_points, points_.size() - at_);
    std::vector<std::int32_t> rows(static_cast<size_t>(n));
    for (Index i = 0; i < n; ++i) rows[size_t(i)] = std::int32_t(at_ + i);
    out = subset(points_, rows);
    VectorXi64 source(n);
    for (Index i = 0; i < n; ++i) source(i) = at_ + i;
    out.set_source_index(std::move(source));
    at_ += n;
    return true;
  }

 private:
  const PointSet& points_;
  Index at_ = 0;
};

}  // namespace scanfill::test
