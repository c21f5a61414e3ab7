// One reader of read_point_set (the format is chosen by SCANFILL_FUZZ_EXTENSION, set per target in CMakeLists.txt).
// A malformed file must end in scanfill::Error (one line naming the file); any other exception, a crash, a sanitizer
// report or an allocation beyond libFuzzer's -malloc_limit_mb is a finding.
#include <cstddef>
#include <cstdint>

#include "nodes/core/errors.h"
#include "nodes/io/read_point_set.h"
#include "tests/fuzz/fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = scanfill::fuzz::scratch_file(SCANFILL_FUZZ_EXTENSION);
  scanfill::fuzz::write_scratch(path, data, size);
  try {
    const scanfill::LoadResult r = scanfill::read_point_set(path);
    r.points.check();
  } catch (const scanfill::Error&) {
  }
  return 0;
}
