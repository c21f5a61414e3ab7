#include "engine/fields.h"

#include "nodes/align/align_options.h"
#include "nodes/correspond/correspond_options.h"
#include "nodes/curves/curves_options.h"
#include "nodes/exchange/exchange_options.h"
#include "nodes/features/features_options.h"
#include "nodes/io/load_options.h"
#include "nodes/label/label_options.h"
#include "nodes/modes/modes_options.h"
#include "nodes/sample/sample_options.h"
#include "nodes/scan/virtual_scan_options.h"
#include "nodes/support/support_options.h"
#include "nodes/surface/surface_options.h"
#include "nodes/symmetry/symmetry_options.h"
#include "nodes/synthesize/synthesize_options.h"
#include "nodes/vote/vote_options.h"

namespace scanfill {
const std::vector<std::pair<std::string, NormalOrientation>>& orientation_names() {
  static const std::vector<std::pair<std::string, NormalOrientation>> names{
      {"auto", NormalOrientation::kAuto},
      {"input", NormalOrientation::kInput},
      {"viewpoint", NormalOrientation::kViewpoint},
      {"propagate", NormalOrientation::kPropagate}};
  return names;
}

std::string to_string(NormalOrientation o) {
  for (const auto& [name, value] : orientation_names())
    if (value == o) return name;
  return "auto";
}

std::vector<Section> option_sections(RunConfig& c) {
  // Completion's coverage is filed under correspond (its keys predate CoverOptions): correspond.cover_*.
  Section correspond = option_table(c.correspond);
  for (Field& f : option_table(c.cover).fields) correspond.fields.push_back(std::move(f));
  return {option_table(c.load),    option_table(c.sample),     option_table(c.features), option_table(c.vote),
          option_table(c.modes),   option_table(c.support),    option_table(c.symmetry), option_table(c.label),
          std::move(correspond),   option_table(c.synthesize), option_table(c.align),    option_table(c.virtual_scan),
          option_table(c.surface), option_table(c.curves),     option_table(c.exchange)};
}

void use_paper_parameters(RunConfig& config) {
  use_paper_parameters(config.label);
  use_paper_parameters(config.support);
}

}  // namespace scanfill
