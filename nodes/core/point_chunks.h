// Points that come a run at a time (issue 13): a scan too large to hold whole is read from its file in chunks by the
// sampler's grid thinning and by the full-resolution transfer, each pass from the first point (DESIGN section 10:
// memory bounded by the samples plus one chunk).
#pragma once

#include "nodes/core/point_set.h"

namespace scanfill {

class PointChunks {
 public:
  virtual ~PointChunks() = default;
  // Rows of the source (a file's declared points, the non-finite ones included): source_index is below this.
  virtual Index rows() const = 0;
  // Back to the first point (a new pass, which gives the same points in the same runs).
  virtual void rewind() = 0;
  // The next run of at most `max_points` points (positions, normals when known, source_index: the point's row in its
  // file); false once every point has been given. A run may be empty (its rows were all dropped).
  virtual bool next(Index max_points, PointSet& out) = 0;
};

}  // namespace scanfill
