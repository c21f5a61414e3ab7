#include "nodes/scan/virtual_scan_options.h"

namespace scanfill {

OptionTable option_table(VirtualScanOptions& vs) {
  using namespace checks;
  return {
      "virtual_scan",
      "completion: replace the scan input by a single-view virtual range scan of it (a mesh)",
      {{"eye", &vs.eye, "camera position [x, y, z]; ~ = no virtual scan", any()},
       {"target", &vs.target, "looked-at point [x, y, z]; ~ = the centre of the input's bounding box", any()},
       {"up", &vs.up, "image up [x, y, z]; ~ = +z (+y when looking within 8 degrees of z)", any()},
       {"width", &vs.width, "image columns; [1, 16384]", range(&vs.width, 1, 16384, false, "an integer in [1, 16384]")},
       {"height", &vs.height, "image rows; [1, 16384]", range(&vs.height, 1, 16384, false, "an integer in [1, 16384]")},
       {"fov_deg", &vs.fov_deg, "vertical field of view; (0, 180)",
        [p = &vs.fov_deg]() -> std::optional<std::string> {
          if (*p > 0 && *p < 180) return std::nullopt;
          return "expected a number in (0, 180)";
        }},
       {"noise", &vs.noise, "Gaussian noise along the ray, model units; >= 0", non_negative(&vs.noise)},
       {"seed", &vs.seed, "seed of the noise", any()}}};
}

}  // namespace scanfill
