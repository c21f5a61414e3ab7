// The config section `surface` (nodes/core/options.h): key, doc line and range of each SurfaceOptions field.
#pragma once

#include "nodes/core/options.h"
#include "nodes/surface/surface.h"

namespace scanfill {

OptionTable option_table(SurfaceOptions& s);

}  // namespace scanfill
