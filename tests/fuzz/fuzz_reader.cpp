// The readers of read_point_set: one binary, run through a symlink per format (fuzz_ply, fuzz_pcd, ...) whose name
// picks the file extension, so the harness is compiled and linked once. A malformed file must end in
// scanfill::Error (one line naming the file); any other exception, a crash, a sanitizer report or an allocation
// beyond libFuzzer's -malloc_limit_mb is a finding.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "nodes/core/errors.h"
#include "nodes/io/read_point_set.h"
#include "tests/fuzz/fuzz_common.h"

namespace {
std::string extension;  // ".ply", from the program name fuzz_ply
}

extern "C" int LLVMFuzzerInitialize(int* argc, char*** argv) {
  const std::string name = std::filesystem::path(*argc > 0 ? (*argv)[0] : "").filename().string();
  const size_t underscore = name.rfind('_');
  extension = underscore == std::string::npos ? "" : "." + name.substr(underscore + 1);
  if (!scanfill::is_supported_extension("input" + extension)) {
    std::fprintf(stderr,
                 "run this as fuzz_ply, fuzz_pcd, fuzz_obj, fuzz_off, fuzz_stl or fuzz_xyz (symlinks), not %s\n",
                 name.c_str());
    std::exit(1);
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = scanfill::fuzz::scratch_file(extension.c_str());
  scanfill::fuzz::write_scratch(path, data, size);
  try {
    const scanfill::LoadResult r = scanfill::read_point_set(path);
    r.points.check();
  } catch (const scanfill::Error&) {
  }
  return 0;
}
