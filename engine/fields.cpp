#include "engine/fields.h"

#include <limits>

namespace scanfill {
namespace {

template <class T>
std::function<std::optional<std::string>()> range(const T* v, T lo, T hi, bool lo_open, const std::string& what) {
  return [=]() -> std::optional<std::string> {
    const bool ok = (lo_open ? *v > lo : *v >= lo) && *v <= hi;
    if (ok) return std::nullopt;
    return "expected " + what;
  };
}

}  // namespace

const std::vector<std::pair<std::string, NormalOrientation>>& orientation_names() {
  static const std::vector<std::pair<std::string, NormalOrientation>> names{
      {"auto", NormalOrientation::kAuto},
      {"input", NormalOrientation::kInput},
      {"viewpoint", NormalOrientation::kViewpoint},
      {"propagate", NormalOrientation::kPropagate}};
  return names;
}

std::string to_string(NormalOrientation o) {
  for (const auto& [name, value] : orientation_names())
    if (value == o) return name;
  return "auto";
}

std::vector<Section> option_sections(RunConfig& c) {
  const double inf = std::numeric_limits<double>::infinity();
  SampleOptions& s = c.sample;
  FeaturesOptions& f = c.features;
  return {
      {"load",
       "reading the inputs",
       {{"morton_sort", &c.load.morton_sort, "reorder points by Morton code after loading (faster neighbour queries)",
         [] { return std::optional<std::string>(); }}}},
      {"sample",
       "Poisson-disk sampling by weighted sample elimination (Yuksel 2015)",
       {{"spacing", &s.spacing, "target mean nearest-neighbour distance (alpha), model units; 0 = use count; >= 0",
         range(&s.spacing, 0.0, inf, false, "a number >= 0")},
        {"count", &s.count, "number of samples per input when spacing is 0; >= 1",
         range<Index>(&s.count, 1, Index(1) << 40, false, "an integer >= 1")},
        {"oversampling", &s.oversampling, "mesh candidates per output sample; [2, 100]",
         range(&s.oversampling, 2.0, 100.0, false, "a number in [2, 100]")},
        {"normal_angle_deg", &s.normal_angle_deg,
         "neighbours whose normals differ by more than this do not repel (keeps both sides of thin parts); (0, 180]",
         range(&s.normal_angle_deg, 0.0, 180.0, true, "a number in (0, 180]")},
        {"weight_exponent", &s.weight_exponent, "exponent of (1 - d/d_max) in the elimination weight; (0, 64]",
         range(&s.weight_exponent, 0.0, 64.0, true, "a number in (0, 64]")},
        {"seed", &s.seed, "seed of the random mesh candidates; any non-negative integer",
         [] { return std::optional<std::string>(); }}}},
      {"features",
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
         range(&f.flat_threshold, 0.0, inf, false, "a number >= 0")},
        {"smooth_directions", &f.smooth_directions, "replace unreliable directions by a smooth 4-fold cross field",
         [] { return std::optional<std::string>(); }},
        {"reliable_weight", &f.reliable_weight, "weight holding reliable directions in the cross-field solve; > 0",
         range(&f.reliable_weight, 0.0, inf, true, "a number > 0")},
        {"regularization", &f.regularization, "pull of unreliable directions to their raw estimate; > 0",
         range(&f.regularization, 0.0, inf, true, "a number > 0")},
        {"max_iterations", &f.max_iterations, "conjugate-gradient iterations of the cross-field solve; >= 1",
         range(&f.max_iterations, 1, 1000000, false, "an integer in [1, 1000000]")},
        {"tolerance", &f.tolerance, "relative residual at which the cross-field solve stops; (0, 1)",
         [p = &f.tolerance]() -> std::optional<std::string> {
           if (*p > 0 && *p < 1) return std::nullopt;
           return "expected a number in (0, 1)";
         }}}},
  };
}

}  // namespace scanfill
