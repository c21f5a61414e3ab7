#include "nodes/vote/vote_options.h"

namespace scanfill {

OptionTable option_table(VoteOptions& v) {
  using namespace checks;
  return {
      "vote",
      "candidate transforms by pair voting (paper section 5.1)",
      {{"target_samples", &v.target_samples, "target points that vote; >= 1",
        range<Index>(&v.target_samples, 1, Index(1) << 40, false, "an integer >= 1")},
       {"matches_per_point", &v.matches_per_point, "source points each voting point pairs with, by signature; [1, 256]",
        range(&v.matches_per_point, 1, 256, false, "an integer in [1, 256]")},
       {"curve_matches", &v.curve_matches,
        "mode curves: matches_per_point on curves, whose one-curvature signature is not scale-free (a scaled partner "
        "lies further off in it); [1, 1024]",
        range(&v.curve_matches, 1, 1024, false, "an integer in [1, 1024]")},
       {"allow_scale", &v.allow_scale, "similarity transforms (true) or rigid motions (false); also used by support",
        any()},
       {"min_scale", &v.min_scale, "smallest scale voted for; > 0", positive(&v.min_scale)},
       {"max_scale", &v.max_scale, "largest scale voted for; >= min_scale",
        [pv = &v]() -> std::optional<std::string> {
          if (pv->max_scale >= pv->min_scale && std::isfinite(pv->max_scale)) return std::nullopt;
          return "expected a number >= vote.min_scale";
        }},
       {"completion_scale", &v.completion_scale,
        "completion: scales outside [1 / this, this] are not voted for or kept (one object's parts; a flat face takes "
        "any shrunk copy of itself); > 1",
        range(&v.completion_scale, 1.0, kInf, true, "a number > 1")},
       {"flat_curvature", &v.flat_curvature, "|k1| alpha below this: too flat for a scale or signature; >= 0",
        non_negative(&v.flat_curvature)},
       {"umbilic_ratio", &v.umbilic_ratio, "|k2/k1| above this: four rotations per pair; (0, 1]",
        range(&v.umbilic_ratio, 0.0, 1.0, true, "a number in (0, 1]")},
       {"min_curved_fraction", &v.min_curved_fraction,
        "flat target points vote only when fewer curved points than this share; [0, 1]",
        range(&v.min_curved_fraction, 0.0, 1.0, false, "a number in [0, 1]")},
       {"rotation_weight", &v.rotation_weight, "w_R of the vote embedding; > 0", positive(&v.rotation_weight)},
       {"translation_weight", &v.translation_weight, "w_t of the vote embedding (per bounding-box diagonal); > 0",
        positive(&v.translation_weight)},
       {"scale_weight", &v.scale_weight, "w_s of the vote embedding (on log scale); > 0", positive(&v.scale_weight)},
       {"seed", &v.seed, "seed choosing the voting target points", any()}}};
}

}  // namespace scanfill
