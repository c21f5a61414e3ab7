// The config section `exchange` (nodes/core/options.h): key, doc line and range of each ExchangeOptions field.
#pragma once

#include "nodes/core/options.h"
#include "nodes/exchange/exchange.h"

namespace scanfill {

OptionTable option_table(ExchangeOptions& e);

}  // namespace scanfill
