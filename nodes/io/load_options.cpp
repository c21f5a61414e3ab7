#include "nodes/io/load_options.h"

namespace scanfill {

OptionTable option_table(LoadOptions& load) {
  using namespace checks;
  return {"load",
          "reading the inputs",
          {{"morton_sort", &load.morton_sort, "reorder points by Morton code after loading (faster neighbour queries)",
            [] { return std::optional<std::string>(); }}}};
}

}  // namespace scanfill
