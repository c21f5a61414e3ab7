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
        "weight of the tilt of the up direction, (1 - cos tilt) / 2: turning the object over costs more than a turn "
        "about the "
        "vertical; >= 0",
        non_negative(&l.upright_prior)},
       {"upright_unary", &l.upright_unary,
        "per-sample unary of the tilt of the up direction, (1 - cos tilt) / 2, where an upright transform is "
        "feasible: where a flip and an upright turn fit the template alike, each sample prefers the upright one; >= 0",
        non_negative(&l.upright_unary)},
       {"quarter_unary", &l.quarter_unary,
        "per-sample unary of an upright turn's angle from the nearest quarter or half turn, over 45 degrees, where "
        "such "
        "a turn is feasible: where turns of 150 and 180 degrees fit the template alike, each sample prefers the half "
        "turn; >= 0",
        non_negative(&l.quarter_unary)},
       {"up", &l.up,
        "the object's up direction [x, y, z] for the upright terms; ~ = the target's axis of rotational symmetry "
        "(continuous, else the one of highest order when it is unique), else (completion) its axis whose faces the "
        "scan shows plainest, else its axis whose faces the scan does not show (two sides seen), else the axis it "
        "stands on the origin's plane along, else +z",
        [p = &l.up]() -> std::optional<std::string> {
          if (!*p || (p->value().allFinite() && p->value().norm() > 1e-12)) return std::nullopt;
          return "expected a non-zero direction [x, y, z] or ~";
        }},
       {"scale_prior", &l.scale_prior, "eq. 9 weight of |log2 scale|; >= 0", non_negative(&l.scale_prior)},
       {"mrf_k", &l.mrf_k, "MRF neighbours per sample; [1, 32]",
        range(&l.mrf_k, 1, 32, false, "an integer in [1, 32]")},
       {"mrf_radius", &l.mrf_radius,
        "if > 0, MRF neighbours are every sample within this many alpha (the paper: 5) instead of the mrf_k nearest; "
        ">= 0",
        non_negative(&l.mrf_radius)},
       {"mrf_min_normal_dot", &l.mrf_min_normal_dot,
        "MRF neighbours' normals have a dot product above this (0.5: within 60 degrees; the paper: 0); [-1, 1)",
        range(&l.mrf_min_normal_dot, -1.0, 1.0 - 1e-12, false, "a number in [-1, 1)")},
       {"paper_label_costs", &l.paper_label_costs,
        "label costs as the paper's eq. 8 and 9 (identity 0, N ln 2 for an axis rotation) instead of ours", any()},
       {"dilation", &l.dilation, "a label is feasible within this many alpha of its support; >= 0",
        non_negative(&l.dilation)},
       {"cleanup_ring", &l.cleanup_ring, "clean-up ring radius in alpha; 0 = no clean-up; >= 0",
        non_negative(&l.cleanup_ring)},
       {"cleanup_majority", &l.cleanup_majority, "share of the ring that must disagree to relabel; (0.5, 1]",
        range(&l.cleanup_majority, 0.5, 1.0, true, "a number in (0.5, 1]")},
       {"max_cycles", &l.max_cycles, "alpha-expansion sweeps; >= 1",
        range(&l.max_cycles, 1, 10000, false, "an integer >= 1")}}};
}

void use_paper_parameters(LabelOptions& l) {
  l.sigma_n = 0.1 * M_PI / 2;
  l.mu = 0.5;
  l.pairwise_cap = 0.5;
  l.paper_label_costs = true;
  l.mrf_radius = 5.0;
  l.mrf_min_normal_dot = 0.0;
  l.upright_unary = 0.0;
  l.quarter_unary = 0.0;
}

}  // namespace scanfill
