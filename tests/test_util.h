// Helpers shared by the tests: scratch folders, files with given bytes, running the CLI.
#pragma once

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace scanfill::test {

inline std::filesystem::path shared_data() {
  return SCANFILL_SHARED_DATA;
}
inline std::filesystem::path source_dir() {
  return SCANFILL_SOURCE_DIR;
}

// Skips the current test with a clear message when ../shared/data is absent.
#define SCANFILL_REQUIRE_SHARED_DATA()                                               \
  do {                                                                               \
    if (!std::filesystem::exists(::scanfill::test::shared_data()))                   \
      GTEST_SKIP() << "shared data not found at " << ::scanfill::test::shared_data() \
                   << " (clone the project beside shared/ to run this test)";        \
  } while (0)

// A fresh folder per test, removed afterwards.
class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = std::filesystem::temp_directory_path() / ("scanfill_" + std::string(info->test_suite_name()) + "_" +
                                                      info->name() + "_" + std::to_string(::getpid()));
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() { std::filesystem::remove_all(path_); }
  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

 private:
  std::filesystem::path path_;
};

inline void write_bytes(const std::filesystem::path& p, const std::string& bytes) {
  std::ofstream out(p, std::ios::binary);
  out.write(bytes.data(), std::streamsize(bytes.size()));
}

inline std::string read_bytes(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

struct CommandResult {
  int exit_code = -1;
  std::string out;  // stdout and stderr together
};

// Shell-quoted path, built with += (GCC 12 warns falsely on "'" + std::string&&, PR 105329).
inline std::string quoted(const std::filesystem::path& p) {
  std::string s = "'";
  s += p.string();
  s += "'";
  return s;
}

// Runs the scanfill binary with `args` (a shell-quoted string), capturing its output.
inline CommandResult run_scanfill(const std::string& args) {
  const std::string cmd = std::string("'") + SCANFILL_BINARY + "' " + args + " 2>&1";
  CommandResult r;
  FILE* pipe = ::popen(cmd.c_str(), "r");
  if (!pipe) return r;
  std::array<char, 4096> buf;
  while (size_t n = std::fread(buf.data(), 1, buf.size(), pipe)) r.out.append(buf.data(), n);
  const int status = ::pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

// An integer vertex property of a PLY that write_ply wrote (binary little-endian, float/uchar/int properties).
inline std::vector<int> ply_property(const std::filesystem::path& file, const char* name) {
  const std::string data = read_bytes(file);
  const size_t end = data.find("end_header\n") + std::strlen("end_header\n");
  std::istringstream header(data.substr(0, end));
  std::string line;
  long long n = 0;
  size_t stride = 0, offset = 0, size = 0;
  bool in_vertex = false;
  while (std::getline(header, line)) {
    std::istringstream words(line);
    std::string word, type, prop;
    words >> word;
    if (word == "element") {
      std::string element;
      words >> element;
      in_vertex = element == "vertex";
      if (in_vertex) words >> n;
    } else if (word == "property" && in_vertex) {
      words >> type >> prop;
      const size_t bytes = type == "uchar" ? 1 : 4;
      if (prop == name) offset = stride, size = bytes;
      stride += bytes;
    }
  }
  std::vector<int> values;
  if (size == 0) return values;
  for (long long i = 0; i < n; ++i) {
    const char* p = data.data() + end + size_t(i) * stride + offset;
    std::int32_t v = 0;
    if (size == 1)
      v = std::uint8_t(*p);
    else
      std::memcpy(&v, p, 4);
    values.push_back(v);
  }
  return values;
}

}  // namespace scanfill::test
