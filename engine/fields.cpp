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
        {"min_support", &su.min_support, "transforms explaining fewer samples are dropped; >= 1",
         range<Index>(&su.min_support, 1, Index(1) << 40, false, "an integer >= 1")},
        {"duplicate_angle_deg", &su.duplicate_angle_deg, "transforms this close in rotation ...; >= 0",
         non_negative(&su.duplicate_angle_deg)},
        {"duplicate_distance", &su.duplicate_distance,
         "... and moving the support less than this (alpha) are merged; >= 0", non_negative(&su.duplicate_distance)}}},
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
  };
}

}  // namespace scanfill
