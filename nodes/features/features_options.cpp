#include "nodes/features/features_options.h"

namespace scanfill {

OptionTable option_table(FeaturesOptions& f) {
  using namespace checks;
  return {"features",
          "normals, signed principal curvatures and directions",
          {{"k", &f.k, "neighbours for PCA normals and the shape-operator fit; [6, 128]",
            range(&f.k, 6, 128, false, "an integer in [6, 128]")},
           {"orientation", &f.orientation,
            "normal orientation: auto | input (agree with the file's normals) | viewpoint (towards the sensor) | "
            "propagate (spanning tree, closed models)",
            [] { return std::optional<std::string>(); }},
           {"viewpoint", &f.viewpoint, "sensor position [x, y, z] for orientation 'viewpoint'; ~ = the file's own",
            [] { return std::optional<std::string>(); }},
           {"umbilic_ratio", &f.umbilic_ratio, "|k2/k1| above this makes the k1 direction unreliable; (0, 1]",
            range(&f.umbilic_ratio, 0.0, 1.0, true, "a number in (0, 1]")},
           {"flat_threshold", &f.flat_threshold,
            "|k1| times the neighbourhood radius below this makes the direction unreliable; >= 0",
            range(&f.flat_threshold, 0.0, kInf, false, "a number >= 0")},
           {"smooth_directions", &f.smooth_directions, "replace unreliable directions by a smooth 4-fold cross field",
            [] { return std::optional<std::string>(); }},
           {"reliable_weight", &f.reliable_weight, "weight holding reliable directions in the cross-field solve; > 0",
            range(&f.reliable_weight, 0.0, kInf, true, "a number > 0")},
           {"regularization", &f.regularization, "pull of unreliable directions to their raw estimate; > 0",
            range(&f.regularization, 0.0, kInf, true, "a number > 0")},
           {"max_iterations", &f.max_iterations, "conjugate-gradient iterations of the cross-field solve; >= 1",
            range(&f.max_iterations, 1, 1000000, false, "an integer in [1, 1000000]")},
           {"tolerance", &f.tolerance, "relative residual at which the cross-field solve stops; (0, 1)",
            [p = &f.tolerance]() -> std::optional<std::string> {
              if (*p > 0 && *p < 1) return std::nullopt;
              return "expected a number in (0, 1)";
            }}}};
}

}  // namespace scanfill
