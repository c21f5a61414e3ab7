// label node: which transform explains each target sample (paper eq. 3), by alpha-expansion with label costs.
//
// Labels 0..L-1 are the supported transforms; label L is the self-reference (the target copies itself there).
// Corrections to the paper (DESIGN section 4), each an option here:
//  - eq. 5 in the log domain, capped: D_t(l) = min(unary_cap, d^2 / (2 (sigma_p alpha)^2) + (1 - cos theta) /
//  sigma_n^2),
//    d the point-to-plane distance of Q_l p_t to its nearest source sample (plus any excess of the point distance over
//    alpha), theta the angle between R_l n_t and that sample's normal. exp(-d^2/2 sigma_p^2) itself would underflow.
//  - eq. 7 as printed can go negative; here V(l, l') = w [l != l'] (min(pairwise_cap, |Q_l m - Q_l' m|^2 /
//    (2 (sigma_p alpha)^2) + (1 - R_l n . R_l' n) / sigma_n^2) + mu), m and n the edge's midpoint and mean normal.
//    With pairwise_cap <= mu it is a metric, as expansion needs. Self-reference against any label costs cap + mu.
//  - eq. 9 needs Euler angles, ambiguous near gimbal lock: the label prior uses the angle of the residual rotation
//    from the nearest of the 24 rotations that map the object's axes (`axes`, else the world's) to axes: h_l =
//    label_cost_per_sample N (1 + rotation_prior angle / 45 deg
//    + scale_prior |log2 s| + upright_prior (1 - cos tilt) / 2), N the number of target samples, tilt the angle
//    between R z and z. The paper's eq. 9 cannot tell a quarter turn about the vertical from a half turn that turns
//    the object upside down (both are kappa pi / 2 rotations), and on a symmetric template the data cannot either;
//    objects stand upright (along `up`: +z as the virtual scanner assumes, or the target's own axis, since many meshes
//    are drawn y-up), so turning one over costs more.
//    paper_label_costs restores eq. 8 and 9 as printed: h = 0 for the identity (rotation under 2 degrees, scale within
//    1%, translation under alpha) and h = N (ln 2 + sum_a (1 - cos 4 R_a) + (s - 1)^2) otherwise, R_a the Euler angles
//    (R = R_x R_y R_z), so N ln 2 for an axis rotation at unit scale.
//  - the self-reference label has the constant unary self_cost.
//  - each transform's unary also carries upright_unary (1 - cos tilt) / 2 at a sample where some feasible transform
//    keeps the object upright (tilts it by under 10 degrees): where the template fits a flip and a turn about the
//    vertical alike (a box's unseen sides), the label cost alone lets one flip cover the sides and the bottom
//    together, turning their style upside down; per sample, the upright turn wins where it fits. Where nothing
//    upright reaches (a box's bottom, a gear's unseen face), the flip competes with the plain copy unburdened.
//  - each also carries quarter_unary times an upright turn's angle from the nearest quarter or half turn, over 45
//    degrees, at a sample where an upright quarter or half turn is feasible: on a body of revolution every turn fits
//    the template alike, and turns of 30 to 150 degrees took the back of a vase seen from the front, carrying the
//    front's knob beside the back's. (The engine sets it to 0 where the scan repeats about the target's axis.)
//  - MRF edges join each sample to its mrf_k nearest neighbours with normals within 60 degrees (the paper's: every
//    sample within the 5-alpha ring with normals within 90 degrees: mrf_radius 5, mrf_min_normal_dot 0); the ring is
//    used by the clean-up, which moves a sample whose label disagrees with more than cleanup_majority of its
//    ring to the ring's majority label.
// Labels are sparse: label l is feasible only within `dilation` alpha of its support, and, unless caps_take_tips,
// not on the caps (samples facing within 30 degrees of up or down) where it tips the object onto its side (turns up
// more than 60 degrees from both up and down): the style of the scan's sides is not laid on a lid or a floor the scan
// did not see.
#pragma once

#include <optional>
#include <vector>

#include "nodes/core/analogy.h"
#include "nodes/core/point_set.h"
#include "nodes/graphcut/expansion.h"

namespace scanfill {

struct LabelOptions {
  double sigma_p = 0.1;                 // position scale of eq. 5 and 7, in alpha; > 0
  double sigma_n = 0.5;                 // normal scale of eq. 5 and 7 (on 1 - cos); > 0
  bool point_to_plane = true;           // point-to-plane (true) or point-to-point distance in eq. 5
  double unary_cap = 20.0;              // cap of the log-domain unary; > 0
  double self_cost = 8.0;               // unary of the self-reference label; >= 0
  double pairwise_weight = 1.0;         // w; >= 0
  double mu = 1.0;                      // constant cost of a label change; >= 0
  double pairwise_cap = 1.0;            // cap of V's data part (<= mu keeps V a metric); >= 0
  double label_cost_per_sample = 0.05;  // base h_l of a transform label, per target sample (h scales with the
                                        // sampling density, as the unary sums it competes with do); >= 0
  double rotation_prior = 0.5;          // eq. 9 weight of the residual rotation; >= 0
  double upright_prior = 1.0;           // weight of the tilt of +z, (1 - cos tilt) / 2: a turn about the vertical
                                        // before a flip that turns the object over; >= 0
  double upright_unary = 0.6;           // per-sample unary of the tilt of +z, (1 - cos tilt) / 2: where a flip and
                                        // an upright turn fit the template alike, each sample prefers the upright
                                        // one; >= 0
  double quarter_unary = 1.0;           // per-sample unary of an upright turn's angle from the nearest quarter or
                                        // half turn, over 45 degrees, where such a turn is feasible; >= 0
  double scale_prior = 0.5;             // eq. 9 weight of |log2 scale|; >= 0
  std::optional<Eigen::Vector3d> up;    // the object's up direction for the upright terms; unset: +z (the engine
                                        // sets it from the target's symmetry axis or the scan's plain faces when
                                        // the config does not)
  std::optional<Eigen::Matrix3d> axes;  // the object's own axes (columns) whose quarter turns eq. 9 prefers; unset:
                                        // the world's (the engine sets them from the target's symmetry and up, for
                                        // an object standing turned in the scan's frame)
  bool caps_take_tips = true;           // whether a transform that tips the object onto its side may label its caps;
                                        // not a config key: the engine sets false in completion with upright_unary
                                        // > 0 (a scan's unseen lid or floor), and keeps true in analogy and transfer,
                                        // where a part of T may stand as S's lies (an L of two boxes)
  int mrf_k = 6;                        // MRF neighbours per sample; [1, 32]
  double mrf_radius = 0.0;              // if > 0: MRF neighbours are all samples within this many alpha (the paper's
                                        // 5-alpha ring, Euclidean for geodesic) instead of the mrf_k nearest; >= 0
  double mrf_min_normal_dot = 0.5;      // MRF neighbours' normals must have a dot product above this (0.5: within 60
                                        // degrees; the paper's 90 degrees is 0); [-1, 1)
  bool paper_label_costs = false;       // eq. 8 and 9 as printed instead of ours (see above)
  double dilation = 2.0;                // a label is feasible within this many alpha of its support; >= 0
  double cleanup_ring = 5.0;            // clean-up ring radius in alpha; >= 0 (0 = no clean-up)
  double cleanup_majority = 0.9;        // fraction of the ring that must disagree; (0.5, 1]
  int max_cycles = 10;                  // expansion sweeps; >= 1
};

struct LabelResult {
  std::vector<int> labels;   // per target sample: 0..L-1 a transform, L the self-reference
  int self_label = 0;        // L
  double energy_before = 0;  // eq. 3 of the all-self labelling
  double energy_after = 0;   // eq. 3 after expansion (before the clean-up)
  Index cleaned = 0;         // samples moved by the clean-up
  Index truncated_terms = 0;
  int cycles = 0;
  std::vector<double> label_costs;  // h_l per transform label
};

LabelResult label_target(const PointSet& source, const PointSet& target,
                         const std::vector<SupportedTransform>& transforms, double spacing,
                         const LabelOptions& options);

// Angle (radians) between R and the nearest of the 24 rotations that map axes to axes.
double residual_axis_angle(const Eigen::Matrix3d& R);

}  // namespace scanfill
