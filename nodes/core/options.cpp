#include "nodes/core/options.h"

#include "nodes/core/errors.h"

namespace scanfill {

void check_options(const OptionTable& table) {
  std::string problems;
  for (const Field& field : table.fields)
    if (const auto problem = field.check())
      problems += (problems.empty() ? "" : "\n") + table.key + "." + field.key + ": " + *problem;
  if (!problems.empty()) throw ConfigError(problems);
}

}  // namespace scanfill
