// Shared by the fuzz targets: the readers and the config loader take a path, so each input is written to one scratch
// file per process (in /dev/shm when it exists: no disk traffic) and read back from there.
#pragma once

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

namespace scanfill::fuzz {

inline std::filesystem::path scratch_file(const char* extension) {
  static const std::filesystem::path path = [extension] {
    std::error_code ec;
    const std::filesystem::path dir = std::filesystem::is_directory("/dev/shm", ec)
                                          ? std::filesystem::path("/dev/shm")
                                          : std::filesystem::temp_directory_path();
    auto p = dir / ("scanfill_fuzz_" + std::to_string(::getpid()) + extension);
    static std::string to_remove = p.string();
    std::atexit([] { std::remove(to_remove.c_str()); });
    return p;
  }();
  return path;
}

inline void write_scratch(const std::filesystem::path& path, const unsigned char* data, size_t size) {
  FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) std::abort();
  if (size && std::fwrite(data, 1, size, f) != size) std::abort();
  std::fclose(f);
}

}  // namespace scanfill::fuzz
