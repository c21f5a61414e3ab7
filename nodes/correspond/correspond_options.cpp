#include "nodes/correspond/correspond_options.h"

namespace scanfill {

OptionTable option_table(CorrespondOptions& co) {
  using namespace checks;
  return {
      "correspond",
      "dense exemplar <-> source map (paper section 4): rigid ICP, then embedded deformation (block-sparse "
      "Levenberg-Marquardt) alternating "
      "with a min-cost-flow assignment (LEMON)",
      {{"rigid", &co.rigid,
        "rigid pre-alignment by ICP (inputs must be roughly aligned: a turn over 20 degrees is warned); false keeps "
        "the scan as given, on the template",
        any()},
       {"rigid_iterations", &co.rigid_iterations, "ICP steps; [1, 500]",
        range(&co.rigid_iterations, 1, 500, false, "an integer in [1, 500]")},
       {"rigid_trim", &co.rigid_trim, "ICP ignores pairs farther than this times the median distance; >= 1",
        range(&co.rigid_trim, 1.0, kInf, false, "a number >= 1")},
       {"rigid_fine_trim", &co.rigid_fine_trim,
        "the same in the point-to-plane steps: the scan's plain parts register on the template, not its relief; > 0",
        positive(&co.rigid_fine_trim)},
       {"outer_iterations", &co.outer_iterations,
        "assignment / deformation alternations, stiffness halved each time (0 = rigid only); [0, 20]",
        range(&co.outer_iterations, 0, 20, false, "an integer in [0, 20]")},
       {"deformation_nodes", &co.deformation_nodes, "nodes of the embedded-deformation graph; [4, 5000]",
        range(&co.deformation_nodes, 4, 5000, false, "an integer in [4, 5000]")},
       {"deformation_samples", &co.deformation_samples,
        "data terms of each deformation solve (an even subset of the matched samples); >= 100",
        range<Index>(&co.deformation_samples, 100, Index(1) << 40, false, "an integer >= 100")},
       {"node_neighbors", &co.node_neighbors, "edges per deformation node; [2, 16]",
        range(&co.node_neighbors, 2, 16, false, "an integer in [2, 16]")},
       {"stiffness", &co.stiffness, "initial weight of the rotation and smoothness terms; > 0",
        positive(&co.stiffness)},
       {"robust_scale", &co.robust_scale, "Huber scale of the data terms, in alpha; > 0", positive(&co.robust_scale)},
       {"candidates", &co.candidates, "nearest source samples each exemplar sample may match; [1, 64]",
        range(&co.candidates, 1, 64, false, "an integer in [1, 64]")},
       {"normal_weight", &co.normal_weight, "eq. 1 weight of (1 - n.n') against squared distance in alpha; >= 0",
        non_negative(&co.normal_weight)},
       {"escape_distance", &co.escape_distance,
        "cost of leaving an exemplar sample unmatched, as a distance in alpha; > 0", positive(&co.escape_distance)},
       {"many_to_one", &co.many_to_one, "exemplar samples one source sample may take; [1, 64]",
        range(&co.many_to_one, 1, 64, false, "an integer in [1, 64]")},
       {"landmark_weight", &co.landmark_weight, "weight of a landmark against one data term; > 0",
        positive(&co.landmark_weight)},
       {"landmarks", &co.landmarks,
        "user landmarks: a list of [[x, y, z] on the scan or exemplar, [x, y, z] on the template or source]", any()},
       {"landmarks_file", &co.landmarks_file,
        "more landmarks from MeshLab picked-points files [SCAN.pp, TEMPLATE.pp], paired by point name", any()},
       {"min_overlap", &co.min_overlap, "share of exemplar samples that must lie near the source after ICP; [0, 1]",
        range(&co.min_overlap, 0.0, 1.0, false, "a number in [0, 1]")},
       {"max_scale_ratio", &co.max_scale_ratio, "bounding-box diagonals may differ by at most this factor; > 1",
        range(&co.max_scale_ratio, 1.0, kInf, true, "a number > 1")}}};
}

OptionTable option_table(CoverOptions& cover) {
  using namespace checks;
  return {"correspond",
          "",
          {{"cover_distance", &cover.distance,
            "completion: template samples within this many alpha of the registered scan form the source; > 0",
            positive(&cover.distance)},
           {"cover_relief", &cover.relief,
            "completion: template samples with a scan sample this far (alpha) along their normal are seen; >= 0",
            non_negative(&cover.relief)},
           {"cover_min_samples", &cover.min_samples,
            "completion: fewer covered template samples are too little to learn from; >= 1",
            range<Index>(&cover.min_samples, 1, Index(1) << 40, false, "an integer >= 1")}}};
}

}  // namespace scanfill
