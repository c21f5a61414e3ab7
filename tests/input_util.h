// An input of a run's config, built in the tests (engine/config.h's Input has more fields than a test sets, and GCC 12
// warns about designated initialisers that leave some out).
#pragma once

#include <utility>

#include "engine/config.h"

namespace scanfill::test {

inline Input input(Role role, InputSpec spec) {
  Input in;
  in.role = role;
  in.spec = std::move(spec);
  return in;
}

}  // namespace scanfill::test
