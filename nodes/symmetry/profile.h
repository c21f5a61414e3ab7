// The scan's own profile about a round template's axis, which tells whether the object is symmetric end over end
// (DESIGN section 9: the target's symmetries, fixed against the exemplar).
//
// A plain cylinder lies on itself turned end over end, so its half turns about lines across its axis are candidates
// (composed_candidates, and voting finds them too), and they fit the template as well as the turns about its axis.
// The object need not be symmetric so: a vase seen from below has its foot's beads carried to its neck by them, and
// its flared lip below its foot. Only the scan can tell. Where it saw both ends of a height that a flip pairs (the
// flip's image of height h comes from height h' of the scan), its radii there say whether the flip is the object's.
#pragma once

#include <cstdint>
#include <vector>

#include "nodes/core/point_set.h"
#include "nodes/core/similarity.h"
#include "nodes/symmetry/symmetry.h"

namespace scanfill {

// Per band of heights along the axis, 2 alpha thick from `lowest`, the lower quartile of the distances from the axis
// of the exemplar's outer wall there (carried into the template's frame by `to_template`): its samples whose normal
// lies within 45 degrees of straight out from the axis. A cap (a flat end seen from one side only), a vase's inside
// seen through its mouth and a ring's inner side are left out, and the quartile is the body under relief that stands
// out of it: a band's radius would otherwise depend on how much of each the view shows (a ring's beads seen from
// below show their lower halves only). NaN where a band holds fewer than 8. No bands (nothing judged) where the
// samples span more than 100000 of them along the axis (a stray point far off).
struct RadialProfile {
  SymmetryAxis axis;
  double lowest = 0;  // height of the first band's lower edge along axis.direction, from axis.centre
  double band = 0;    // the bands' thickness
  std::vector<double> radius;
};

RadialProfile radial_profile(const PointSet& exemplar, const Similarity& to_template, const SymmetryAxis& axis,
                             double spacing);

// Whether the profile refutes q (target -> source, both in the template's frame), which keeps the axis along itself
// (within 30 degrees either way; others are not judged): over the bands whose height and its image's source height
// (the height q carries a point of the axis to) both hold a radius, at least 3, a quarter or more disagree by more
// than `tolerance` (the source's radius taken back by q's scale). A symmetry of the object holds at every height the
// scan saw; a vase's middle can be nearly symmetric about its belly while its foot and lip are not. A turn about the
// axis pairs each band with itself and is never refuted; a flip or a slide along the axis the scan cannot judge (too
// few such bands) is not refuted either.
bool profile_refutes(const RadialProfile& profile, const Similarity& q, double tolerance);

// Per target sample (the template's, in the profile's frame), 1 where the profile puts the object's surface inside it:
// the sample lies outside the radius of its height's band (or, past the profile's ends by at most 5 bands, 10 alpha,
// the end band's: a lip whose normals face up has none) by more than 15% of its own distance from the axis and 4
// alpha. A plain cylinder drawn about a vase with a narrow neck (the text2mesh vase's neck 0.6-1.0 from the axis, in a
// cylinder of radius 3.45) is not the object around the neck, nor is its lid, and a copy of them is no completion. A
// template inside the radius is not judged: relief standing out of the body (a teapot's spout and handle) raises it.
// A template of the object's profile lies within 3% of the scan's radii (the fluted column's cylinders, the vase's
// body of revolution), a gear's disk within 6.3% (its teeth).
std::vector<std::uint8_t> outside_the_profile(const RadialProfile& profile, const PointSet& target, double spacing);

// Of the target samples outside_the_profile judges, the share it finds off; 0 where it judges none.
double share_off_the_profile(const RadialProfile& profile, const PointSet& target, double spacing);

// Whether the target is of another profile than the scan's: half or more of the samples judged are off it.
bool of_another_profile(const RadialProfile& profile, const PointSet& target, double spacing);

}  // namespace scanfill
