// The config section `virtual_scan` (nodes/core/options.h): key, doc line and range of each VirtualScanOptions field.
#pragma once

#include "nodes/core/options.h"
#include "nodes/scan/virtual_scan.h"

namespace scanfill {

OptionTable option_table(VirtualScanOptions& vs);

}  // namespace scanfill
