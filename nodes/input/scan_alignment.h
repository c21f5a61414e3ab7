// A scan-alignment file, as the Stanford 3D Scanning Repository ships one with each object's range scans (bun.conf):
// the scans' poses in one shared frame, so that a user's raw range scans are completed together.
//
//   camera tx ty tz qi qj qk qr      (the viewer's pose: ignored)
//   bmesh FILE tx ty tz qi qj qk qr  one range scan, FILE relative to the .conf's folder
//
// A scan's points go to the shared frame by the conjugate of the quaternion (qi qj qk qr, the real part last), then
// the translation; checked on bun.conf: its ten scans then lie 0.6 mm (median) from the reconstructed bunny.
#pragma once

#include <filesystem>
#include <vector>

#include "nodes/core/similarity.h"

namespace scanfill {

struct ScanPose {
  std::filesystem::path file;  // resolved against the .conf's folder
  Similarity pose;             // from the scan's frame to the shared one
  int line = 0;                // the .conf's line that lists it, for messages
};

// True for a path ending in .conf (any case).
bool is_scan_alignment(const std::filesystem::path& path);

// The .conf's scans and poses, in file order. Throws IoError naming the file and line for a line that is neither
// camera, bmesh nor blank, a pose that is not 7 finite numbers or whose quaternion is zero, or no bmesh line.
std::vector<ScanPose> read_scan_alignment(const std::filesystem::path& conf);

}  // namespace scanfill
