#include "nodes/symmetry/profile.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace scanfill {

namespace {

constexpr Index kBandSamples = 8;         // a band's radius needs at least this many samples
constexpr double kOutward = 0.7;          // a sample counts when its normal lies within 45 degrees of straight out
constexpr Index kMostBands = 100000;      // more bands than this: no profile
constexpr double kOffProfile = 0.15;      // outside_the_profile: share of the template's radius
constexpr double kOffProfileLeast = 4.0;  // ... and at least this many alpha
constexpr double kOtherProfile = 0.5;     // of_another_profile: share of the judged samples off
constexpr int kNearBands = 5;             // ... and past the profile's ends by the end band, so many bands on

double lower_quartile_of(std::vector<double>& v) {
  const auto at = v.begin() + Index(v.size()) / 4;
  std::nth_element(v.begin(), at, v.end());
  return *at;
}

// The profile's radius at `height`, NaN outside it or where its band holds too few samples.
double radius_at(const RadialProfile& p, double height) {
  const double b = std::floor((height - p.lowest) / p.band);
  if (!(b >= 0 && b < double(p.radius.size()))) return std::numeric_limits<double>::quiet_NaN();
  return p.radius[std::size_t(b)];
}

// The first and last bands of a profile that hold a radius; none where no band does.
struct HeldBands {
  std::ptrdiff_t first = 0, last = -1;
};

HeldBands held_bands(const RadialProfile& p) {
  const auto held = [](double r) { return !std::isnan(r); };
  const auto first = std::find_if(p.radius.begin(), p.radius.end(), held);
  if (first == p.radius.end()) return {};
  const auto last = std::find_if(p.radius.rbegin(), p.radius.rend(), held);
  return {first - p.radius.begin(), p.radius.rend() - last - 1};
}

// The profile's radius at `height`, or, beyond the first or last band that holds one (`held`) by at most kNearBands
// bands, that band's (a lip whose normals face up has no radius of its own); NaN elsewhere. Between the ends a band
// without one is not filled from its neighbours: a vase's foot seen below its hidden underside is no radius for the
// body above.
double radius_at_or_past_the_ends(const RadialProfile& p, const HeldBands& held, double height) {
  if (const double own = radius_at(p, height); !std::isnan(own)) return own;
  if (held.last < held.first) return std::numeric_limits<double>::quiet_NaN();
  const double b = std::floor((height - p.lowest) / p.band);
  const double before = double(held.first) - b, after = b - double(held.last);
  if (before > 0 && before <= kNearBands) return p.radius[std::size_t(held.first)];
  if (after > 0 && after <= kNearBands) return p.radius[std::size_t(held.last)];
  return std::numeric_limits<double>::quiet_NaN();
}

enum Judgement { kUnjudged, kOn, kOff };

// Target sample t against the profile: unjudged where radius_at_or_past_the_ends has none; off where it lies outside
// that radius by more than kOffProfile of its own distance from the axis and
// kOffProfileLeast alpha. Inside it is not judged: relief standing out of the body (a teapot's spout and handle, seen
// from below where the body's own wall is hidden) raises a band's radius.
Judgement judged(const RadialProfile& profile, const HeldBands& held, const PointSet& target, Index t, double spacing) {
  if (profile.radius.empty()) return kUnjudged;
  const Eigen::Vector3d& d = profile.axis.direction;
  const Eigen::Vector3d x = target.positions().col(t) - profile.axis.centre;
  const double r = (x - d * d.dot(x)).norm(), seen = radius_at_or_past_the_ends(profile, held, d.dot(x));
  if (std::isnan(seen)) return kUnjudged;
  return r > seen + std::max(kOffProfile * r, kOffProfileLeast * spacing) ? kOff : kOn;
}

}  // namespace

RadialProfile radial_profile(const PointSet& exemplar, const Similarity& to_template, const SymmetryAxis& axis,
                             double spacing) {
  RadialProfile p;
  p.axis = axis;
  p.band = 2 * spacing;
  std::vector<double> heights, radii;
  for (Index e = 0; e < exemplar.size(); ++e) {
    const Eigen::Vector3d x = to_template.apply(exemplar.positions().col(e)) - axis.centre;
    const double h = axis.direction.dot(x);
    const Eigen::Vector3d across = x - axis.direction * h;
    if (exemplar.has_normals() &&
        to_template.apply_normal(exemplar.normals().col(e)).dot(across) <= kOutward * across.norm())
      continue;
    heights.push_back(h);
    radii.push_back(across.norm());
  }
  if (heights.empty() || !(p.band > 0)) return p;
  const auto [lo, hi] = std::minmax_element(heights.begin(), heights.end());
  // A stray point far along the axis would ask for bands by the million, nearly all empty: such a scan is not judged.
  if (!((*hi - *lo) / p.band < double(kMostBands))) return p;
  p.lowest = *lo;
  const std::size_t bands = std::size_t((*hi - *lo) / p.band) + 1;
  std::vector<std::vector<double>> in_band(bands);
  for (std::size_t e = 0; e < heights.size(); ++e)
    in_band[std::min(bands - 1, std::size_t((heights[e] - p.lowest) / p.band))].push_back(radii[e]);
  p.radius.assign(bands, std::numeric_limits<double>::quiet_NaN());
  for (std::size_t b = 0; b < bands; ++b)
    if (Index(in_band[b].size()) >= kBandSamples) p.radius[b] = lower_quartile_of(in_band[b]);
  return p;
}

bool profile_refutes(const RadialProfile& profile, const Similarity& q, double tolerance) {
  const Eigen::Vector3d& d = profile.axis.direction;
  if (std::abs((q.rotation * d).dot(d)) < std::cos(M_PI / 6)) return false;  // not along the axis: not judged
  Index compared = 0, disagreeing = 0;
  for (std::size_t b = 0; b < profile.radius.size(); ++b) {
    if (std::isnan(profile.radius[b])) continue;
    const double h = profile.lowest + (double(b) + 0.5) * profile.band;
    const double image = d.dot(q.apply(profile.axis.centre + h * d) - profile.axis.centre);
    const double r = radius_at(profile, image);
    if (std::isnan(r)) continue;
    ++compared;
    disagreeing += std::abs(r / q.scale - profile.radius[b]) > tolerance;
  }
  return compared >= 3 && 4 * disagreeing >= compared;
}

std::vector<std::uint8_t> outside_the_profile(const RadialProfile& profile, const PointSet& target, double spacing) {
  std::vector<std::uint8_t> off(std::size_t(target.size()), 0);
  const HeldBands held = held_bands(profile);
  for (Index t = 0; t < target.size(); ++t) off[std::size_t(t)] = judged(profile, held, target, t, spacing) == kOff;
  return off;
}

bool of_another_profile(const RadialProfile& profile, const PointSet& target, double spacing) {
  return share_off_the_profile(profile, target, spacing) >= kOtherProfile;
}

double share_off_the_profile(const RadialProfile& profile, const PointSet& target, double spacing) {
  Index judged_samples = 0, off = 0;
  const HeldBands held = held_bands(profile);
  for (Index t = 0; t < target.size(); ++t) {
    const Judgement j = judged(profile, held, target, t, spacing);
    judged_samples += j != kUnjudged;
    off += j == kOff;
  }
  return judged_samples == 0 ? 0.0 : double(off) / double(judged_samples);
}

}  // namespace scanfill
