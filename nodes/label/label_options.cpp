#include "nodes/label/label_options.h"

namespace scanfill {

OptionTable option_table(LabelOptions& l) {
  using namespace checks;
  return {
      "label",
      "multi-label graph cut with label costs (paper eq. 3, corrected eq. 5, 7, 9)",
      {{"sigma_p", &l.sigma_p, "position scale of eq. 5 and 7, in alpha; > 0", positive(&l.sigma_p)},
       {"sigma_n", &l.sigma_n, "normal scale of eq. 5 and 7 (on 1 - cos); > 0", positive(&l.sigma_n)},
       {"point_to_plane", &l.point_to_plane, "point-to-plane (true) or point-to-point distance in eq. 5", any()},
       {"unary_cap", &l.unary_cap, "cap of the log-domain unary; > 0", positive(&l.unary_cap)},
       {"self_cost", &l.self_cost, "unary of the self-reference label; >= 0", non_negative(&l.self_cost)},
       {"pairwise_weight", &l.pairwise_weight, "weight of the pairwise term; >= 0", non_negative(&l.pairwise_weight)},
       {"mu", &l.mu, "constant cost of a label change (eq. 7); >= 0", non_negative(&l.mu)},
       {"pairwise_cap", &l.pairwise_cap, "cap of eq. 7's data part; <= mu keeps it a metric; >= 0",
        non_negative(&l.pairwise_cap)},
       {"label_cost_per_sample", &l.label_cost_per_sample,
        "base cost of using a transform label, per target sample; >= 0", non_negative(&l.label_cost_per_sample)},
       {"rotation_prior", &l.rotation_prior,
        "eq. 9 weight of the rotation's angle from the nearest axis-aligned one; >= 0",
        non_negative(&l.rotation_prior)},
       {"upright_prior", &l.upright_prior,
        "weight of the tilt of +z, (1 - cos tilt) / 2: turning the object over costs more than a turn about the "
        "vertical; >= 0",
        non_negative(&l.upright_prior)},
       {"scale_prior", &l.scale_prior, "eq. 9 weight of |log2 scale|; >= 0", non_negative(&l.scale_prior)},
       {"mrf_k", &l.mrf_k, "MRF neighbours per sample; [1, 32]",
        range(&l.mrf_k, 1, 32, false, "an integer in [1, 32]")},
       {"dilation", &l.dilation, "a label is feasible within this many alpha of its support; >= 0",
        non_negative(&l.dilation)},
       {"cleanup_ring", &l.cleanup_ring, "clean-up ring radius in alpha; 0 = no clean-up; >= 0",
        non_negative(&l.cleanup_ring)},
       {"cleanup_majority", &l.cleanup_majority, "share of the ring that must disagree to relabel; (0.5, 1]",
        range(&l.cleanup_majority, 0.5, 1.0, true, "a number in (0.5, 1]")},
       {"max_cycles", &l.max_cycles, "alpha-expansion sweeps; >= 1",
        range(&l.max_cycles, 1, 10000, false, "an integer >= 1")}}};
}

}  // namespace scanfill
