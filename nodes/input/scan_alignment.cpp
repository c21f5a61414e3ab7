#include "nodes/input/scan_alignment.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include "nodes/core/errors.h"
#include "nodes/io/read_point_set.h"

namespace scanfill {
namespace {

[[noreturn]] void fail(const std::filesystem::path& conf, int line, const std::string& what) {
  throw IoError(conf.string() + ":" + std::to_string(line) + ": " + what);
}

// "tx ty tz qi qj qk qr" from the stream: the pose conj(q) then t.
Similarity pose_of(std::istringstream& in, const std::filesystem::path& conf, int line) {
  double v[7];
  for (double& x : v)
    if (!(in >> x) || !std::isfinite(x)) fail(conf, line, "expected 7 numbers after the name: tx ty tz qi qj qk qr");
  std::string extra;
  if (in >> extra) fail(conf, line, "unexpected '" + extra + "' after the pose's 7 numbers");
  const Eigen::Quaterniond q(v[6], v[3], v[4], v[5]);
  if (!(q.norm() > 1e-12)) fail(conf, line, "the quaternion qi qj qk qr is zero");
  Similarity s;
  s.rotation = q.normalized().conjugate().toRotationMatrix();
  s.translation = Eigen::Vector3d(v[0], v[1], v[2]);
  return s;
}

}  // namespace

bool is_scan_alignment(const std::filesystem::path& path) {
  return lower_extension(path) == ".conf";
}

std::vector<ScanPose> read_scan_alignment(const std::filesystem::path& conf) {
  std::ifstream file(conf);
  if (!file) throw IoError(conf.string() + ": cannot be opened");
  std::vector<ScanPose> scans;
  std::string text;
  for (int line = 1; std::getline(file, text); ++line) {
    if (!text.empty() && text.back() == '\r') text.pop_back();
    std::istringstream in(text);
    std::string kind;
    if (!(in >> kind) || kind[0] == '#') continue;
    if (kind == "camera") continue;
    if (kind != "bmesh") fail(conf, line, "expected 'camera' or 'bmesh', got '" + kind + "'");
    std::string name;
    if (!(in >> name)) fail(conf, line, "a bmesh line needs a file name and 7 numbers");
    ScanPose s;
    s.file = conf.parent_path() / name;
    s.pose = pose_of(in, conf, line);
    s.line = line;
    scans.push_back(std::move(s));
  }
  if (scans.empty()) throw IoError(conf.string() + ": lists no range scan (no 'bmesh FILE tx ty tz qi qj qk qr' line)");
  return scans;
}

}  // namespace scanfill
