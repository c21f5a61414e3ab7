// The config loader: any YAML text must load or end in ConfigError (file:line: key: problem); any other exception
// (a yaml-cpp conversion escaping, say), a crash or a sanitizer report is a finding.
#include <cstddef>
#include <cstdint>

#include "engine/config.h"
#include "nodes/core/errors.h"
#include "tests/fuzz/fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = scanfill::fuzz::scratch_file(".yaml");
  scanfill::fuzz::write_scratch(path, data, size);
  try {
    (void)scanfill::load_config(path);
  } catch (const scanfill::Error&) {
  }
  return 0;
}
