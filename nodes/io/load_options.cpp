#include "nodes/io/load_options.h"

namespace scanfill {

OptionTable option_table(LoadOptions& load) {
  using namespace checks;
  return {"load",
          "reading the inputs",
          {{"morton_sort", &load.morton_sort, "reorder points by Morton code after loading (faster neighbour queries)",
            [] { return std::optional<std::string>(); }},
           {"stream_above", &load.stream_above,
            "a scan or exemplar that is one binary PLY of more points than this is read in chunks, never whole "
            "(points in file order); 0 = never; >= 0",
            range<Index>(&load.stream_above, 0, Index(1) << 50, false, "an integer >= 0")}}};
}

}  // namespace scanfill
