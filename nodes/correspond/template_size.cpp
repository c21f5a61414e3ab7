#include "nodes/correspond/template_size.h"

#include <tbb/parallel_for.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <numeric>
#include <optional>
#include <utility>
#include <vector>

namespace scanfill {
namespace {

constexpr double kSmallest = 0.80, kLargest = 1.25, kStep = 0.01;
constexpr double kNoSmaller = 1.0;  // scaling_at_one_end's smallest scale
constexpr double kEqualSpread = 0.03;
constexpr int kPasses = 2;
constexpr double kClearlyMore = 0.01;  // share of the points
constexpr double kAsMuchOn = 0.01;     // share of the points laid on "as much" by a trim
constexpr double kClearlyLess = 0.01;  // how far a trim must lower the misfit (uncovered facing share + share off)
constexpr double kPastNoise = 0.001;   // share of the points: as few past the template's ends
constexpr double kFacing = 0.1;        // cosine between a template normal and the direction towards the sensor
constexpr int kEndSteps = 4;           // scaling_at_one_end: steps at one end, one after the other

Eigen::Matrix3d scaling_matrix(const TemplateScaling& s, bool inverse) {
  const Eigen::Vector3d d = inverse ? Eigen::Vector3d(s.scale.cwiseInverse()) : s.scale;
  return s.axes * d.asDiagonal() * s.axes.transpose();
}

// The principal axes of the source's samples about their centroid, spread ascending, and which of them share a scale.
TemplateScaling principal_axes(const PointSet& source, std::vector<std::vector<int>>& groups) {
  TemplateScaling s;
  const Eigen::Matrix3Xd& p = source.positions();
  s.centre = p.rowwise().mean();
  const Eigen::Matrix3Xd d = p.colwise() - s.centre;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(d * d.transpose() / double(std::max<Index>(1, p.cols())));
  s.axes = eig.eigenvectors();
  const Eigen::Vector3d spread = eig.eigenvalues().cwiseMax(0).cwiseSqrt();
  for (int k = 0; k < 3; ++k) {
    auto same = std::find_if(groups.begin(), groups.end(), [&](const std::vector<int>& g) {
      return spread[k] > 0 && std::abs(spread[g.front()] / spread[k] - 1) < kEqualSpread;
    });
    if (same != groups.end())
      same->push_back(k);
    else
      groups.push_back({k});
  }
  return s;
}

// `s` scaled along its axes `group` to `scale`, about the place where `s` lays the template's point `pivot` (principal
// coordinates about its centre: the centre, or the template's near or far end along each axis), which stays.
TemplateScaling scaled_about(const TemplateScaling& s, const std::vector<int>& group, double scale,
                             const Eigen::Vector3d& pivot) {
  TemplateScaling t = s;
  for (const int k : group) {
    t.scale[k] = scale;
    t.shift += s.axes.col(k) * ((s.scale[k] - scale) * pivot[k]);
  }
  return t;
}

// The points a group of axes is scaled about: the template's centroid, and for a single axis either end along it. Axes
// scaled alike (a square box's sides) are scaled about the centroid only: about a corner, a square box seen from the
// front lays its face as well on itself at any width behind it (a box 10% wider standing on the crate's floor, seen
// from the front, took 1.09 about a corner, not 0.91 about its centroid, and ICP on it moved the scan 2.4 spacings).
std::vector<Eigen::Vector3d> pivots_of(const std::vector<int>& group, const Eigen::Vector3d& low,
                                       const Eigen::Vector3d& high) {
  if (group.size() > 1) return {Eigen::Vector3d::Zero()};
  return {Eigen::Vector3d::Zero(), low, high};
}

// The template's ends along the axes of `s`: the lowest and highest principal coordinates of its samples about the
// centre of `s`.
void ends_along_axes(const PointSet& source, const TemplateScaling& s, Eigen::Vector3d& low, Eigen::Vector3d& high) {
  const Eigen::Matrix3Xd along = s.axes.transpose() * (source.positions().colwise() - s.centre);
  low = along.rowwise().minCoeff();
  high = along.rowwise().maxCoeff();
}

// The template's ends along the axes of `s` once scaled by it (`low`, `high`: the unscaled template's ends, principal
// coordinates about its centroid): its lowest and highest principal coordinates.
std::pair<Eigen::Vector3d, Eigen::Vector3d> scaled_ends(const TemplateScaling& s, const Eigen::Vector3d& low,
                                                        const Eigen::Vector3d& high) {
  const Eigen::Vector3d along = s.axes.transpose() * s.shift;
  return {s.scale.cwiseProduct(low) + along, s.scale.cwiseProduct(high) + along};
}

// How far the scaling moves each of the template's six ends along its axes (`low`, `high`: principal coordinates about
// its centroid): the low and high end of the first axis, then of the second and the third.
std::array<double, 6> moves_of_ends(const TemplateScaling& s, const Eigen::Vector3d& low, const Eigen::Vector3d& high) {
  std::array<double, 6> moves{};
  for (int k = 0; k < 3; ++k) {
    const double along = s.axes.col(k).dot(s.shift);
    moves[size_t(2 * k)] = std::abs((s.scale[k] - 1) * low[k] + along);
    moves[size_t(2 * k + 1)] = std::abs((s.scale[k] - 1) * high[k] + along);
  }
  return moves;
}

// How far the scaling moves the template's ends, summed over both ends of every axis.
double end_moves(const TemplateScaling& s, const Eigen::Vector3d& low, const Eigen::Vector3d& high) {
  const std::array<double, 6> moves = moves_of_ends(s, low, high);
  double sum = 0;
  for (size_t k = 0; k < 3; ++k) sum += moves[2 * k] + moves[2 * k + 1];
  return sum;
}

// The trials of a group of axes from `s`: scaled `smallest` to 1.25 in steps of 0.01 about `pivot`.
std::vector<TemplateScaling> trials_about(const TemplateScaling& s, const std::vector<int>& group,
                                          const Eigen::Vector3d& pivot, double smallest) {
  const int steps = int(std::lround((kLargest - smallest) / kStep));
  std::vector<TemplateScaling> trials;
  for (int k = 0; k <= steps; ++k) trials.push_back(scaled_about(s, group, smallest + k * kStep, pivot));
  return trials;
}

// Each group's trials from `s`: its axes scaled `smallest` to 1.25 in steps of 0.01 about each of its pivots.
std::vector<TemplateScaling> trials_of(const TemplateScaling& s, const std::vector<int>& group,
                                       const Eigen::Vector3d& low, const Eigen::Vector3d& high, double smallest) {
  std::vector<TemplateScaling> trials;
  for (const Eigen::Vector3d& pivot : pivots_of(group, low, high))
    for (const TemplateScaling& t : trials_about(s, group, pivot, smallest)) trials.push_back(t);
  return trials;
}

// The share of the source's samples that `s` lays facing the sensor with no scan point (`seen`: their tree) within two
// spacings. Every sample is asked: every fourth left the share a few thousandths noisy, as much as a trim of 1 cm
// changes it.
double uncovered_facing(const KdTree& seen, const Eigen::Vector3d& towards_sensor, const PointSet& source,
                        const TemplateScaling& s, double spacing) {
  const Eigen::Matrix3d forward = scaling_matrix(s, false), back = scaling_matrix(s, true);
  std::vector<std::uint8_t> facing(size_t(source.size()), 0), uncovered(size_t(source.size()), 0);
  tbb::parallel_for(Index(0), source.size(), [&](Index j) {
    if ((back * source.normals().col(j)).normalized().dot(towards_sensor) <= kFacing) return;
    facing[size_t(j)] = 1;
    std::int32_t k;
    double d2;
    seen.knn(s.centre + s.shift + forward * (source.positions().col(j) - s.centre), 1, &k, &d2);
    uncovered[size_t(j)] = d2 > 4 * spacing * spacing;
  });
  const auto count = [](const std::vector<std::uint8_t>& v) { return double(std::count(v.begin(), v.end(), 1)); };
  return count(uncovered) / std::max(1.0, count(facing));
}

// The shares of `points` on the source scaled by `s` (its samples in `tree`; as share_on_scaled), and near it (within
// two spacings of a sample) but past its ends along its axes by over half a spacing (`low`, `high`: the unscaled
// template's ends, principal coordinates about the centre of `s`). A point within two spacings of a sample may lie up
// to two spacings past the template's end and still be on it: a scan running on past an end it sees only at a grazing
// angle (the top rows of a box's sides, seen from below) lies as much on a template scaled a step short of it. And how
// far past its ends the points run at all, at any distance from it (`beyond`): the share past each axis's ends, summed
// over the axes. Relief standing out of the template runs past its ends there; a crate's frame, 2 cm proud of its
// front and running on 4 cm below a template's floor, lies past two ends, and scaling that floor down to the crate's
// takes it past one only.
struct OnScaled {
  double on = 0, past = 0, beyond = 0;
};

OnScaled on_and_past(const Eigen::Matrix3Xd& points, const PointSet& source, const KdTree& tree,
                     const TemplateScaling& s, double spacing, const Eigen::Vector3d& low,
                     const Eigen::Vector3d& high) {
  if (points.cols() == 0) return {};
  const Eigen::Matrix3d forward = scaling_matrix(s, false), back = scaling_matrix(s, true);
  const auto [low_end, high_end] = scaled_ends(s, low, high);
  const Eigen::Vector3d lowest = low_end - Eigen::Vector3d::Constant(0.5 * spacing);
  const Eigen::Vector3d highest = high_end + Eigen::Vector3d::Constant(0.5 * spacing);
  std::vector<std::uint8_t> on(size_t(points.cols()), 0), past(size_t(points.cols()), 0);
  std::vector<std::uint8_t> beyond(size_t(points.cols()), 0);
  tbb::parallel_for(Index(0), points.cols(), [&](Index i) {
    const Eigen::Vector3d x = points.col(i);
    std::int32_t j;
    double d2;
    tree.knn(s.centre + back * (x - s.centre - s.shift), 1, &j, &d2);
    const Eigen::Vector3d d = x - (s.centre + s.shift + forward * (source.positions().col(j) - s.centre));
    const Eigen::Vector3d n = (back * source.normals().col(j)).normalized();
    const bool near = d.squaredNorm() <= 4 * spacing * spacing;
    on[size_t(i)] = near && std::abs(d.dot(n)) <= 0.5 * spacing;
    const Eigen::Vector3d u = s.axes.transpose() * (x - s.centre);
    past[size_t(i)] = near && ((u.array() < lowest.array()).any() || (u.array() > highest.array()).any());
    beyond[size_t(i)] = std::uint8_t(((u.array() < low_end.array()) || (u.array() > high_end.array())).count());
  });
  const auto share = [&](const std::vector<std::uint8_t>& v) {
    return double(std::count(v.begin(), v.end(), 1)) / double(points.cols());
  };
  return {share(on), share(past), double(std::accumulate(beyond.begin(), beyond.end(), 0)) / double(points.cols())};
}

// The shares `s` lays on the source and leaves past its ends (on_and_past) for each of `trials`.
std::vector<OnScaled> shares_of(const Eigen::Matrix3Xd& points, const PointSet& source, const KdTree& tree,
                                double spacing, const Eigen::Vector3d& low, const Eigen::Vector3d& high,
                                const std::vector<TemplateScaling>& trials) {
  std::vector<OnScaled> on(trials.size());
  for (size_t t = 0; t < trials.size(); ++t) on[t] = on_and_past(points, source, tree, trials[t], spacing, low, high);
  return on;
}

// The least `value` of the trials `admitted` (infinity where none is).
template <class Admitted, class Value>
double least_of(size_t trials, Admitted admitted, Value value) {
  double least = std::numeric_limits<double>::infinity();
  for (size_t t = 0; t < trials; ++t)
    if (admitted(t)) least = std::min(least, value(t));
  return least;
}

// The most of the points any trial lays on the source.
double most_on(const std::vector<OnScaled>& on) {
  double most = 0;
  for (const OnScaled& o : on) most = std::max(most, o.on);
  return most;
}

// Of the trials `admitted`, the one moving the template's ends least (`low`, `high`: the unscaled template's ends).
template <class Admitted>
std::optional<size_t> least_moving(const std::vector<TemplateScaling>& trials, const Eigen::Vector3d& low,
                                   const Eigen::Vector3d& high, Admitted admitted) {
  std::optional<size_t> taken;
  for (size_t t = 0; t < trials.size(); ++t)
    if (admitted(t) && (!taken || end_moves(trials[t], low, high) < end_moves(trials[*taken], low, high))) taken = t;
  return taken;
}

// Of `trials` (their shares `on`), those laying as much of the points on the source as the best of them (within
// kClearlyMore) and leaving as few of them past the template's ends (within kPastNoise), the one moving the
// template's ends least; none where it lays no more than kClearlyMore over `share`. A few samples more on are no
// evidence of a size, and an end the scan does not see stays where it is drawn (a box drawn shorter than the crate, on
// its floor, seen from above: scaled about its floor, not its centroid, which would sink the floor as far as it lifts
// the top). An end the scan runs past is moved to where the scan ends: the plain box seen from below in a box drawn 8%
// shorter, scaled 1.07 up, lays 99.3% of the scan on itself and leaves 0.5% past its top; scaled 1.08, 99.7% and none.
std::optional<size_t> laying_more_on(const std::vector<TemplateScaling>& trials, const std::vector<OnScaled>& on,
                                     const Eigen::Vector3d& low, const Eigen::Vector3d& high, double share) {
  const double most = most_on(on);
  const auto as_much = [&](size_t t) { return on[t].on >= most - kClearlyMore && on[t].on > share + kClearlyMore; };
  const double fewest_past = least_of(on.size(), as_much, [&](size_t t) { return on[t].past; });
  return least_moving(trials, low, high,
                      [&](size_t t) { return as_much(t) && on[t].past <= fewest_past + kPastNoise; });
}

// Of `trials` at one end (their shares `on`), where the best of them lays kClearlyMore more of the points on the
// source than `share`, those laying as much as it (within kClearlyMore) and leaving fewest points past the template's
// ends at all (`beyond`), the one moving the template's ends least: the end moved to where the scan ends. The crate's
// sides seen from 70 degrees below, in its box drawn 8% shorter, lay as much on that box scaled 1.07 as 1.09, and the
// top of their sparse last rows lies within half a spacing of either. Seen from 4 degrees above level, the crate's
// front lays 46% of the scan on that box at any scale from 1.08 up, a few points more or fewer as their nearest
// samples change, as many as the near points past its ends change; the share of the scan past its ends stops falling
// at 1.09 (the frames proud of its sides stay past them), and 1.09 is taken (1.12 where each trial had to lay a
// hundredth more than `share`, and the fewest near points past its ends came first).
std::optional<size_t> reaching_the_scans_end(const std::vector<TemplateScaling>& trials,
                                             const std::vector<OnScaled>& on, const Eigen::Vector3d& low,
                                             const Eigen::Vector3d& high, double share) {
  const double most = most_on(on);
  if (most <= share + kClearlyMore) return std::nullopt;
  const auto as_much = [&](size_t t) { return on[t].on >= most - kClearlyMore; };
  const double fewest_beyond = least_of(on.size(), as_much, [&](size_t t) { return on[t].beyond; });
  return least_moving(trials, low, high, [&](size_t t) { return as_much(t) && on[t].beyond <= fewest_beyond; });
}

// Of `trials` (their shares `on`), those laying as much of the points on the source as `share` does unscaled (within
// kClearlyMore) and leaving kClearlyMore fewer of them past its ends at all than it does (`unscaled`), the one leaving
// fewest and of those the one moving the template's ends least; none if no trial does. A scan that sees where it runs
// on past an end only as relief standing out of the template (the crate's raised frames, seen from below, in a box
// drawn 8% shorter) lays no more of itself on a template scaled to reach there.
std::optional<size_t> leaving_fewer_beyond(const std::vector<TemplateScaling>& trials, const std::vector<OnScaled>& on,
                                           const OnScaled& unscaled, const Eigen::Vector3d& low,
                                           const Eigen::Vector3d& high, double share) {
  const auto fewer = [&](size_t t) {
    return on[t].on >= share - kClearlyMore && on[t].beyond <= unscaled.beyond - kClearlyMore;
  };
  const double fewest = least_of(on.size(), fewer, [&](size_t t) { return on[t].beyond; });
  return least_moving(trials, low, high, [&](size_t t) { return fewer(t) && on[t].beyond <= fewest; });
}

// The shares of `points` past each of the six ends of the template scaled by `s` (`low`, `high`: the unscaled
// template's ends): the low and high end of the first axis, then of the second and the third.
std::array<double, 6> shares_past_ends(const Eigen::Matrix3Xd& points, const TemplateScaling& s,
                                       const Eigen::Vector3d& low, const Eigen::Vector3d& high) {
  const auto [low_end, high_end] = scaled_ends(s, low, high);
  const Eigen::Matrix3Xd u = s.axes.transpose() * (points.colwise() - s.centre);
  std::array<double, 6> past{};
  for (int k = 0; k < 3; ++k) {
    past[size_t(2 * k)] = double((u.row(k).array() < low_end[k]).count()) / double(std::max<Index>(1, u.cols()));
    past[size_t(2 * k + 1)] = double((u.row(k).array() > high_end[k]).count()) / double(std::max<Index>(1, u.cols()));
  }
  return past;
}

// The trials of scaling_at_one_end from `s`: each axis of a spread of its own scaled up about either of its ends,
// where a hundredth of `points` runs on past the other end, which moves.
std::vector<TemplateScaling> trials_at_one_end(const Eigen::Matrix3Xd& points, const TemplateScaling& s,
                                               const std::vector<std::vector<int>>& groups, const Eigen::Vector3d& low,
                                               const Eigen::Vector3d& high) {
  const std::array<double, 6> past = shares_past_ends(points, s, low, high);
  std::vector<TemplateScaling> trials;
  for (const std::vector<int>& g : groups) {
    if (g.size() > 1) continue;
    const auto k = size_t(g.front());
    for (const auto& [pivot, moved] : {std::pair{low, 2 * k + 1}, std::pair{high, 2 * k}})
      if (past[moved] >= kClearlyMore)
        for (const TemplateScaling& t : trials_about(s, g, pivot, kNoSmaller)) trials.push_back(t);
  }
  return trials;
}

// The scaling by coordinate descent from `s` (laying `share` of `points` on the source): each group of axes in turn,
// twice over, its trials from the scaling before them, taken by laying_more_on.
TemplateScaling descended_from(const Eigen::Matrix3Xd& points, const PointSet& source, const KdTree& tree,
                               double spacing, const std::vector<std::vector<int>>& groups, double smallest,
                               TemplateScaling s, double& share) {
  Eigen::Vector3d low, high;
  ends_along_axes(source, s, low, high);
  for (int pass = 0; pass < kPasses; ++pass)
    for (const std::vector<int>& g : groups) {
      const std::vector<TemplateScaling> trials = trials_of(s, g, low, high, smallest);
      const std::vector<OnScaled> on = shares_of(points, source, tree, spacing, low, high, trials);
      if (const auto taken = laying_more_on(trials, on, low, high, share)) {
        s = trials[*taken];
        share = on[*taken].on;
      }
    }
  return s;
}

}  // namespace

double share_on_scaled(const Eigen::Matrix3Xd& points, const PointSet& source, const KdTree& tree,
                       const TemplateScaling& s, double spacing) {
  const Eigen::Vector3d endless = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  return on_and_past(points, source, tree, s, spacing, -endless, endless).on;
}

TemplateScaling scaling_that_fits(const Eigen::Matrix3Xd& points, const PointSet& source, const KdTree& tree,
                                  double spacing, double& share) {
  std::vector<std::vector<int>> groups;
  const TemplateScaling unscaled = principal_axes(source, groups);
  share = share_on_scaled(points, source, tree, unscaled, spacing);
  return descended_from(points, source, tree, spacing, groups, kSmallest, unscaled, share);
}

TemplateScaling scaling_at_one_end(const Eigen::Matrix3Xd& points, const PointSet& source, const KdTree& tree,
                                   double spacing, double& share) {
  std::vector<std::vector<int>> groups;
  const TemplateScaling unscaled = principal_axes(source, groups);
  Eigen::Vector3d low, high;
  ends_along_axes(source, unscaled, low, high);
  share = share_on_scaled(points, source, tree, unscaled, spacing);
  TemplateScaling s = unscaled;
  bool scaled = false;
  for (int step = 0; step < kEndSteps; ++step) {
    const std::vector<TemplateScaling> trials = trials_at_one_end(points, s, groups, low, high);
    const std::vector<OnScaled> on = shares_of(points, source, tree, spacing, low, high, trials);
    auto taken = reaching_the_scans_end(trials, on, low, high, share);
    if (!taken)
      taken =
          leaving_fewer_beyond(trials, on, on_and_past(points, source, tree, s, spacing, low, high), low, high, share);
    if (!taken) break;
    s = trials[*taken];
    share = on[*taken].on;
    scaled = true;
  }
  return scaled ? descended_from(points, source, tree, spacing, groups, kNoSmaller, s, share) : unscaled;
}

TemplateScaling trimmed_to_the_seen(const Eigen::Matrix3Xd& points, const Eigen::Vector3d& towards_sensor,
                                    const PointSet& source, const KdTree& tree, double spacing, TemplateScaling s) {
  std::vector<std::vector<int>> groups;
  principal_axes(source, groups);
  Eigen::Vector3d low, high;
  ends_along_axes(source, s, low, high);
  KdTree seen;
  seen.build(points);
  // The misfit both ways: the facing template the scan leaves uncovered, and the scan the template leaves off itself.
  // The second stops a trim at the scan's own end: trimmed further, the scan's last row goes off the template.
  const double share = share_on_scaled(points, source, tree, s, spacing);
  double misfit = uncovered_facing(seen, towards_sensor, source, s, spacing) + 1 - share;
  for (const std::vector<int>& g : groups) {
    const std::vector<TemplateScaling> trials = trials_of(s, g, low, high, kSmallest);
    std::vector<double> left(trials.size(), misfit);
    for (size_t t = 0; t < trials.size(); ++t)
      if (const double on = share_on_scaled(points, source, tree, trials[t], spacing); on >= share - kAsMuchOn)
        left[t] = uncovered_facing(seen, towards_sensor, source, trials[t], spacing) + 1 - on;
    const double least = *std::min_element(left.begin(), left.end());
    if (least > misfit - kClearlyLess) continue;
    size_t taken = trials.size();
    for (size_t t = 0; t < trials.size(); ++t)
      if (left[t] <= least + 0.1 * kClearlyLess &&
          (taken == trials.size() || end_moves(trials[t], low, high) < end_moves(trials[taken], low, high)))
        taken = t;
    s = trials[taken];
    misfit = left[taken];
  }
  return s;
}

PointSet scaled_source(const PointSet& source, const TemplateScaling& s) {
  const Eigen::Matrix3d forward = scaling_matrix(s, false), back = scaling_matrix(s, true);
  PointSet out = source;
  out.set_positions((forward * (source.positions().colwise() - s.centre)).colwise() + (s.centre + s.shift));
  if (source.has_normals()) out.set_normals((back * source.normals()).colwise().normalized());
  return out;
}

double largest_scaling_move(const PointSet& source, const TemplateScaling& s) {
  const Eigen::Matrix3d change = scaling_matrix(s, false) - Eigen::Matrix3d::Identity();
  return (change * (source.positions().colwise() - s.centre)).colwise().norm().maxCoeff();
}

}  // namespace scanfill
