// The exemplar <-> source map as the paper's Figures 6 and 13c show it: the source samples and, beside them, the
// rigidly registered exemplar samples, each exemplar sample in the colour of the source sample it maps to. Colours
// follow the source sample's place in the source's bounding box (x red, y green, z blue), so matched regions read as
// the same colour on both; unmatched exemplar samples are grey. Written as correspondence.ply.
#pragma once

#include <cstdint>
#include <vector>

#include "nodes/core/image.h"
#include "nodes/core/point_set.h"
#include "nodes/correspond/correspond.h"

namespace scanfill {

struct CorrespondenceView {
  PointSet points;                 // the source samples, then the exemplar samples shifted beside them along +x
  std::vector<Rgb> colours;        // per point
  std::vector<std::uint8_t> side;  // per point: 0 source, 1 exemplar
};

CorrespondenceView correspondence_view(const PointSet& source, const CorrespondResult& map);

}  // namespace scanfill
