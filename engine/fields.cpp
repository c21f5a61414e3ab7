#include "engine/fields.h"

#include <cmath>
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
  VoteOptions& v = c.vote;
  ModesOptions& m = c.modes;
  SupportOptions& su = c.support;
  LabelOptions& l = c.label;
  CorrespondOptions& co = c.correspond;
  SynthesisOptions& sy = c.synthesize;
  AlignOptions& al = c.align;
  VirtualScanConfig& vs = c.virtual_scan;
  const auto any = [] { return std::optional<std::string>(); };
  const auto positive = [](const double* p) {
    return [p]() -> std::optional<std::string> {
      if (*p > 0 && std::isfinite(*p)) return std::nullopt;
      return "expected a number > 0";
    };
  };
  const auto non_negative = [](const double* p) {
    return [p]() -> std::optional<std::string> {
      if (*p >= 0 && std::isfinite(*p)) return std::nullopt;
      return "expected a number >= 0";
    };
  };
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
      {"vote",
       "candidate transforms by pair voting (paper section 5.1)",
       {{"target_samples", &v.target_samples, "target points that vote; >= 1",
         range<Index>(&v.target_samples, 1, Index(1) << 40, false, "an integer >= 1")},
        {"matches_per_point", &v.matches_per_point,
         "source points each voting point pairs with, by signature; [1, 256]",
         range(&v.matches_per_point, 1, 256, false, "an integer in [1, 256]")},
        {"allow_scale", &v.allow_scale, "similarity transforms (true) or rigid motions (false); also used by support",
         any},
        {"min_scale", &v.min_scale, "smallest scale voted for; > 0", positive(&v.min_scale)},
        {"max_scale", &v.max_scale, "largest scale voted for; >= min_scale",
         [&v]() -> std::optional<std::string> {
           if (v.max_scale >= v.min_scale && std::isfinite(v.max_scale)) return std::nullopt;
           return "expected a number >= vote.min_scale";
         }},
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
        {"seed", &v.seed, "seed choosing the voting target points", any}}},
      {"modes",
       "mean shift on the votes",
       {{"bandwidth", &m.bandwidth, "flat kernel radius in the vote embedding; > 0", positive(&m.bandwidth)},
        {"max_seeds", &m.max_seeds, "most populated bins used as seeds; >= 1",
         range(&m.max_seeds, 1, 1 << 30, false, "an integer >= 1")},
        {"max_iterations", &m.max_iterations, "mean-shift steps per seed; >= 1",
         range(&m.max_iterations, 1, 1 << 20, false, "an integer >= 1")},
        {"max_modes", &m.max_modes, "modes kept, by support; >= 1",
         range(&m.max_modes, 1, 1 << 20, false, "an integer >= 1")},
        {"min_votes", &m.min_votes, "modes with fewer votes are dropped; >= 1",
         range<Index>(&m.min_votes, 1, Index(1) << 40, false, "an integer >= 1")}}},
      {"support",
       "target samples each transform explains (paper eq. 2), with similarity ICP",
       {{"distance", &su.distance, "explained within this many alpha of a source sample; > 0", positive(&su.distance)},
        {"normal_angle_deg", &su.normal_angle_deg, "and with normals within this angle; (0, 180]",
         range(&su.normal_angle_deg, 0.0, 180.0, true, "a number in (0, 180]")},
        {"graph_k", &su.graph_k, "neighbours of the target graph the support grows over; [2, 64]",
         range(&su.graph_k, 2, 64, false, "an integer in [2, 64]")},
        {"icp_iterations", &su.icp_iterations, "similarity ICP steps per transform; >= 0",
         range(&su.icp_iterations, 0, 1000, false, "an integer in [0, 1000]")},
        {"icp_samples", &su.icp_samples, "ICP uses at most this many support samples (an even subsample); >= 3",
         range<Index>(&su.icp_samples, 3, Index(1) << 40, false, "an integer >= 3")},
        {"min_support", &su.min_support, "transforms explaining fewer samples are dropped; >= 1",
         range<Index>(&su.min_support, 1, Index(1) << 40, false, "an integer >= 1")},
        {"duplicate_angle_deg", &su.duplicate_angle_deg, "transforms this close in rotation ...; >= 0",
         non_negative(&su.duplicate_angle_deg)},
        {"duplicate_distance", &su.duplicate_distance,
         "... and moving the support less than this (alpha) are merged; >= 0", non_negative(&su.duplicate_distance)},
        {"redundant_overlap", &su.redundant_overlap,
         "a transform whose support lies this much inside a stronger one's is dropped; (0, 1]",
         range(&su.redundant_overlap, 0.0, 1.0, true, "a number in (0, 1]")}}},
      {"label",
       "multi-label graph cut with label costs (paper eq. 3, corrected eq. 5, 7, 9)",
       {{"sigma_p", &l.sigma_p, "position scale of eq. 5 and 7, in alpha; > 0", positive(&l.sigma_p)},
        {"sigma_n", &l.sigma_n, "normal scale of eq. 5 and 7 (on 1 - cos); > 0", positive(&l.sigma_n)},
        {"point_to_plane", &l.point_to_plane, "point-to-plane (true) or point-to-point distance in eq. 5", any},
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
         range(&l.max_cycles, 1, 10000, false, "an integer >= 1")}}},
      {"correspond",
       "dense exemplar <-> source map (paper section 4): rigid ICP, then embedded deformation (Ceres) alternating "
       "with a min-cost-flow assignment (LEMON)",
       {{"rigid", &co.rigid, "rigid pre-alignment by ICP (inputs must be roughly aligned)", any},
        {"rigid_iterations", &co.rigid_iterations, "ICP steps; [1, 500]",
         range(&co.rigid_iterations, 1, 500, false, "an integer in [1, 500]")},
        {"rigid_trim", &co.rigid_trim, "ICP ignores pairs farther than this times the median distance; >= 1",
         range(&co.rigid_trim, 1.0, inf, false, "a number >= 1")},
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
         "user landmarks: a list of [[x, y, z] on the scan or exemplar, [x, y, z] on the template or source]", any},
        {"min_overlap", &co.min_overlap, "share of exemplar samples that must lie near the source after ICP; [0, 1]",
         range(&co.min_overlap, 0.0, 1.0, false, "a number in [0, 1]")},
        {"max_scale_ratio", &co.max_scale_ratio, "bounding-box diagonals may differ by at most this factor; > 1",
         range(&co.max_scale_ratio, 1.0, inf, true, "a number > 1")},
        {"cover_distance", &c.cover.distance,
         "completion: template samples within this many alpha of the registered scan form the source; > 0",
         positive(&c.cover.distance)},
        {"cover_min_samples", &c.cover.min_samples,
         "completion: fewer covered template samples are too little to learn from; >= 1",
         range<Index>(&c.cover.min_samples, 1, Index(1) << 40, false, "an integer >= 1")}}},
      {"synthesize",
       "A* = M A M^-1: the exemplar carried by each region's transform",
       {{"reach", &sy.reach, "a mapped source sample belongs to a region within this many alpha; > 0",
         positive(&sy.reach)},
        {"ring_k", &sy.ring_k, "kNN graph defining each region's overlap ring; [0, 32]",
         range(&sy.ring_k, 0, 32, false, "an integer in [0, 32]")},
        {"refine_iterations", &sy.refine_iterations,
         "ICP steps refining each transform against the exemplar's overlapping images (0 = no refinement); >= 0",
         range(&sy.refine_iterations, 0, 1000, false, "an integer in [0, 1000]")},
        {"refine_distance", &sy.refine_distance, "refinement pairs closer than this, in alpha; > 0",
         positive(&sy.refine_distance)},
        {"search_distance", &sy.search_distance,
         "each slippable motion of the template is searched this far (alpha) for the exemplar's phase; >= 0",
         non_negative(&sy.search_distance)},
        {"gap_distance", &sy.gap_distance,
         "a target sample no patch comes this close to (alpha) is copied from the target; > 0",
         positive(&sy.gap_distance)}}},
      {"align",
       "seam removal, paper eq. 10 (Ceres)",
       {{"neighbors", &al.neighbors, "kNN graph of the synthesised samples; [2, 32]",
         range(&al.neighbors, 2, 32, false, "an integer in [2, 32]")},
        {"pair_distance", &al.pair_distance, "seam pairs closer than this, in alpha; > 0", positive(&al.pair_distance)},
        {"gap_weight", &al.gap_weight, "weight of the normal gap across patches; >= 0", non_negative(&al.gap_weight)},
        {"keep_weight", &al.keep_weight, "weight keeping each patch's shape; >= 0", non_negative(&al.keep_weight)},
        {"pull", &al.pull, "v of eq. 10, the pull to the start; > 0", positive(&al.pull)},
        {"thin_distance", &al.thin_distance,
         "overlap-ring samples this close (alpha) to another patch are dropped; >= 0 (0 = keep)",
         non_negative(&al.thin_distance)}}},
      {"virtual_scan",
       "completion: replace the scan input by a single-view virtual range scan of it (a mesh)",
       {{"eye", &vs.eye, "camera position [x, y, z]; ~ = no virtual scan", any},
        {"target", &vs.target, "looked-at point [x, y, z]; ~ = the centre of the input's bounding box", any},
        {"up", &vs.up, "image up [x, y, z]; ~ = +z (+y when looking within 8 degrees of z)", any},
        {"width", &vs.width, "image columns; [1, 16384]",
         range(&vs.width, 1, 16384, false, "an integer in [1, 16384]")},
        {"height", &vs.height, "image rows; [1, 16384]",
         range(&vs.height, 1, 16384, false, "an integer in [1, 16384]")},
        {"fov_deg", &vs.fov_deg, "vertical field of view; (0, 180)",
         [p = &vs.fov_deg]() -> std::optional<std::string> {
           if (*p > 0 && *p < 180) return std::nullopt;
           return "expected a number in (0, 180)";
         }},
        {"noise", &vs.noise, "Gaussian noise along the ray, model units; >= 0", non_negative(&vs.noise)},
        {"seed", &vs.seed, "seed of the noise", any}}},
  };
}

}  // namespace scanfill
