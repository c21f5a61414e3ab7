#include "nodes/synthesize/repeats.h"

#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <vector>

#include "nodes/core/kdtree.h"

namespace scanfill {
namespace {

constexpr double kMaxTurn = 2 * M_PI / 3;     // turns tried: up to 120 degrees, where a half-seen ring still overlaps
constexpr int kMostTurns = 360;               // at most this many steps (bounds the table)
constexpr Index kMostSamples = 4000;          // the exemplar is scored on an even subsample of at most this many
constexpr double kMostTilt = 5 * M_PI / 180;  // a mirror plane's normal at most this far off square to the axis
constexpr double kMostOffset = 3;             // and the plane at most this many alphas off the axis' point
constexpr size_t kBasins = 6;                 // mirror planes refined from this many coarse basins
constexpr double kDeep = 0.25;                // a repeat's misfit is at most this share of the band's median misfit
constexpr double kRisen = 0.5;                // a repeat is sought once the misfit rose this share to the median
constexpr double kPerfectRepeat = 0.75;       // a perfect repeat's misfit, of a sample's against its neighbour's
constexpr double kMedianOfSquare = 0.455;     // a Gaussian's median squared, of its mean square
constexpr double kConfirmed = 0.5;            // a repeat seen before the median: its turns' mean misfit at most this
constexpr double kClearlyBetter = 0.9;        // of choices of bands as coarse, a later one must fit 10% better
constexpr int kLeastCheckedOrder = 8;         // repeating_samples checks the turns of bands of at least this order
constexpr double kSameFacing = 0.9;  // a repeat's normal within 25 degrees (not a bump's flank on its other flank)

// The turn by `angle` about the axis through `point` along unit `direction`.
Similarity turn(double angle, const Eigen::Vector3d& point, const Eigen::Vector3d& direction) {
  const Eigen::Matrix3d R = Eigen::AngleAxisd(angle, direction).toRotationMatrix();
  return Similarity{R, point - R * point, 1.0};
}

// The point-to-plane distance of x from the exemplar sample nearest it (`tree` holds ep), if that lies within the
// limit and, given x's normal (`facing`), faces within 60 degrees of it (or the angle whose cosine `agree` is).
std::optional<double> plane_distance(const KdTree& tree, const Eigen::Matrix3Xd& ep, const Eigen::Matrix3Xd& en,
                                     const Eigen::Vector3d& x, double limit, const Eigen::Vector3d* facing = nullptr,
                                     double agree = 0.5) {
  std::int32_t j;
  double d2;
  tree.knn(x, 1, &j, &d2);
  if (d2 > limit * limit || (facing && facing->dot(en.col(j)) < agree)) return std::nullopt;
  return (x - ep.col(j)).dot(en.col(j));
}

// The squared point-to-plane misfit of samples (sorted by height) turned by each step k (a turn of (k + 1) steps)
// against the exemplar, over pairs within the limit, as prefix sums over the samples: any band [a, b) scores at any
// step in O(1).
class TurnTable {
 public:
  TurnTable(const KdTree& tree, const Eigen::Matrix3Xd& ep, const Eigen::Matrix3Xd& en,
            const std::vector<Index>& sorted, const AxialRepeats& axis, double step, int steps, double limit)
      : n_(sorted.size()), K_(size_t(steps)), sum_((n_ + 1) * K_, 0.0), count_((n_ + 1) * K_, 0.0) {
    std::vector<Similarity> turns;
    for (size_t k = 0; k < K_; ++k) turns.push_back(turn(double(k + 1) * step, axis.part.point, axis.part.direction));
    std::vector<float> r2(n_ * K_);  // sample-major: each sample's turns in one task
    tbb::parallel_for(size_t(0), n_, [&](size_t i) {
      for (size_t k = 0; k < K_; ++k) {
        const auto d = plane_distance(tree, ep, en, turns[k].apply(ep.col(sorted[i])), limit);
        r2[i * K_ + k] = d ? float(std::pow(*d, 2)) : -1.0f;
      }
    });
    for (size_t i = 0; i < n_; ++i)
      for (size_t k = 0; k < K_; ++k) {
        const float r = r2[i * K_ + k];
        sum_[(i + 1) * K_ + k] = sum_[i * K_ + k] + std::max(0.0f, r);
        count_[(i + 1) * K_ + k] = count_[i * K_ + k] + (r >= 0);
      }
  }

  size_t steps() const { return K_; }
  double sum(size_t a, size_t b, size_t k) const { return sum_[b * K_ + k] - sum_[a * K_ + k]; }
  double count(size_t a, size_t b, size_t k) const { return count_[b * K_ + k] - count_[a * K_ + k]; }
  double mean(size_t a, size_t b, size_t k) const { return sum(a, b, k) / std::max(1.0, count(a, b, k)); }

 private:
  size_t n_, K_;
  std::vector<double> sum_, count_;
};

struct BandRepeat {
  int order = 0;     // 0: none
  double sum = 0;    // the band's squared misfit at the repeat's turn (at its median turn for none)
  double count = 0;  // over this many pairs
};

// The order of band [a, b). Past the first turn that reaches the median misfit (a small turn barely moves anything),
// the first dip deeper than kDeep times the median gives a guess, 360 degrees over its lowest turn; of the three orders
// nearest it, the one whose turns by multiples of 360 / n (up to the largest turn tried) fit best on average (16
// flutes, not 17: 21.2 degrees is within a step or two of 22.5, but 5 x 21.2 is far from 5 x 22.5). Turns
// where less than a fifth of the band (or 30 samples) pairs are not scored. A band whose median misfit is below
// `floor2` is plain: no repeat. Misfits are measured above `noise2`, what a perfect repeat leaves (noise_floor), and
// a repeat is sought from where the misfit has risen halfway to the median (kRisen): under noise the misfit grows with
// the turn, and the noisy vase's flutes reached their median only past their first repeat. A dip found before the
// misfit reached the median must be confirmed by the order's turns: their mean misfit at most half the median
// (kConfirmed). About an axis 1.8 cm off the fluted column's, the misfit dips at 21 degrees and grows past it, and no
// later turn fits (20-degree turns: 0.88 of the median; the noisy vase's 30-degree turns: 0.4).
BandRepeat band_repeat(const TurnTable& t, size_t a, size_t b, double step, double floor2, double noise2) {
  const double least = std::max(30.0, double(b - a) / 5);
  const auto scored = [&](size_t k) { return k < t.steps() && t.count(a, b, k) >= least; };
  std::vector<double> means;
  for (size_t k = 0; k < t.steps(); ++k)
    if (scored(k)) means.push_back(t.mean(a, b, k));
  if (means.size() < 5) return {0, 0, 0};
  std::nth_element(means.begin(), means.begin() + Index(means.size() / 2), means.end());
  const double median = means[means.size() / 2], deep = noise2 + kDeep * (median - noise2);
  const BandRepeat none{0, median * double(b - a), double(b - a)};
  if (median - noise2 < floor2) return none;
  size_t k = 0;
  bool reached_median = false;
  for (bool started = false; k < t.steps(); ++k) {
    if (!scored(k)) continue;
    if (started && t.mean(a, b, k) <= deep) break;
    started = started || t.mean(a, b, k) - noise2 >= kRisen * (median - noise2);
    reached_median = reached_median || t.mean(a, b, k) >= median;
  }
  size_t lowest = k;
  for (; scored(k) && t.mean(a, b, k) <= deep; ++k)
    if (t.mean(a, b, k) < t.mean(a, b, lowest)) lowest = k;
  if (lowest >= t.steps()) return none;
  const int guess = int(std::lround(2 * M_PI / (double(lowest + 1) * step)));
  BandRepeat best = none;
  double best_mean = std::numeric_limits<double>::infinity();
  for (int order = std::max(2, guess - 1); order <= guess + 1; ++order) {
    double sum = 0, count = 0;
    for (int j = 1; 2 * M_PI * j / order <= kMaxTurn; ++j) {
      const long turn_step = std::lround(2 * M_PI * j / order / step) - 1;
      if (turn_step < 0 || !scored(size_t(turn_step))) continue;
      sum += t.sum(a, b, size_t(turn_step));
      count += t.count(a, b, size_t(turn_step));
    }
    if (count > 0 && sum / count < best_mean) {
      best_mean = sum / count;
      best = {order, sum, count};
    }
  }
  if (!reached_median && best_mean - noise2 > kConfirmed * (median - noise2)) return none;
  return best;
}

// What a perfect repeat still leaves: the scan's noise along the normal (on both samples) and the surface's bend. A
// range scan with noise of a third of a groove's depth misfits by that at every turn, and its repeats' dips are
// measured above it, not above zero (the vase under noise of 0.005: its 16 beads not found, its flutes as 3-fold).
// Estimated as kPerfectRepeat times the mean squared point-to-plane misfit of each of `samples` against its nearest
// other exemplar sample within the limit: a turned sample lands nearer a sample than its neighbour stands, and the
// bend and the normals' error grow with that distance (the vase's flutes repeat to 0.84 of it under that noise).
double noise_floor(const KdTree& tree, const Eigen::Matrix3Xd& ep, const Eigen::Matrix3Xd& en,
                   const std::vector<Index>& samples, double limit) {
  double sum = 0, count = 0;
  for (const Index e : samples) {
    std::array<std::int32_t, 2> j;
    std::array<double, 2> d2;
    if (tree.knn(ep.col(e), 2, j.data(), d2.data()) < 2 || d2[1] > limit * limit) continue;
    const std::int32_t other = j[0] == std::int32_t(e) ? j[1] : j[0];
    sum += std::pow((ep.col(e) - ep.col(other)).dot(en.col(other)), 2);
    ++count;
  }
  return count > 0 ? kPerfectRepeat * sum / count : 0.0;
}

// The median point-to-plane misfit of `samples` turned by `angle` about the axis through `point` against the exemplar
// (its nearest sample within the limit), and the number of samples that pair.
std::pair<double, size_t> median_misfit(const KdTree& tree, const Eigen::Matrix3Xd& ep, const Eigen::Matrix3Xd& en,
                                        const std::vector<Index>& samples, const Eigen::Vector3d& point,
                                        const Eigen::Vector3d& direction, double angle, double limit) {
  const Similarity q = turn(angle, point, direction);
  std::vector<double> r;
  for (const Index e : samples)
    if (const auto d = plane_distance(tree, ep, en, q.apply(ep.col(e)), limit)) r.push_back(std::abs(*d));
  if (r.empty()) return {std::numeric_limits<double>::infinity(), 0};
  std::nth_element(r.begin(), r.begin() + Index(r.size() / 2), r.end());
  return {r[r.size() / 2], r.size()};
}

// A bounded part (a table's turned leg) that is a body of revolution about its axis. The axis is first moved, within
// an alpha across it (quarter-alpha steps), to where the part's samples turned by 30 and 60 degrees fit the exemplar
// best (the median misfit: its foot and its top meet the floor and the table top): the template's leg axis was 4 mm
// off its scan's. About that axis every turn by 15 .. 120 degrees that pairs at least a fifth of the samples (at least
// 5 of the 8 must) leaves a median misfit under 0.35 alpha; a turn of the vase's flutes leaves a groove's depth.
std::optional<AxialRepeats> revolution_about(const KdTree& tree, const Eigen::Matrix3Xd& ep, const Eigen::Matrix3Xd& en,
                                             const std::vector<Index>& sorted, AxialRepeats out, double spacing,
                                             double limit) {
  std::vector<Index> samples;
  for (size_t i = 0; i < sorted.size(); i += std::max<size_t>(1, sorted.size() / 1000)) samples.push_back(sorted[i]);
  const Eigen::Vector3d a = out.part.direction;
  const Eigen::Vector3d u = a.unitOrthogonal(), v = a.cross(u);
  Eigen::Vector3d best_point = out.part.point;
  double best = std::numeric_limits<double>::infinity();
  for (int i = -4; i <= 4; ++i)
    for (int j = -4; j <= 4; ++j) {
      const Eigen::Vector3d p = out.part.point + 0.25 * spacing * (i * u + j * v);
      const double fit = median_misfit(tree, ep, en, samples, p, a, M_PI / 6, limit).first +
                         median_misfit(tree, ep, en, samples, p, a, M_PI / 3, limit).first;
      if (fit < best) {
        best = fit;
        best_point = p;
      }
    }
  int scored = 0;
  for (int k = 1; k <= 8; ++k) {
    const auto [median, pairs] = median_misfit(tree, ep, en, samples, best_point, a, k * M_PI / 12, limit);
    if (5 * pairs < samples.size()) continue;
    if (median > 0.35 * spacing) return std::nullopt;
    ++scored;
  }
  if (scored < 5) return std::nullopt;
  out.part.point = best_point;
  out.continuous = true;
  out.order = {0, 0};
  return out;
}

// The exemplar samples scored (an even subsample), sorted by height along the axis, with their heights.
std::pair<std::vector<Index>, std::vector<double>> by_height(const Eigen::Matrix3Xd& ep, const AxialRepeats& axis) {
  std::vector<Index> in_part;
  for (Index e = 0; e < ep.cols(); ++e)
    if (axis.part.contains(ep.col(e))) in_part.push_back(e);
  const size_t stride = std::max<size_t>(1, (in_part.size() + kMostSamples - 1) / kMostSamples);
  std::vector<Index> order;
  for (size_t i = 0; i < in_part.size(); i += stride) order.push_back(in_part[i]);
  std::vector<double> h(size_t(ep.cols()));
  for (Index e : order) h[size_t(e)] = axis.part.direction.dot(ep.col(e) - axis.part.point);
  std::stable_sort(order.begin(), order.end(), [&](Index x, Index y) { return h[size_t(x)] < h[size_t(y)]; });
  std::vector<double> heights;
  for (Index e : order) heights.push_back(h[size_t(e)]);
  return {order, heights};
}

// The RMS distance of the samples from the axis.
double rms_radius(const Eigen::Matrix3Xd& ep, const std::vector<Index>& samples, const AxialRepeats& axis) {
  double s = 0;
  for (Index e : samples) {
    const Eigen::Vector3d x = ep.col(e) - axis.part.point;
    s += (x - axis.part.direction * axis.part.direction.dot(x)).squaredNorm();
  }
  return std::sqrt(s / double(std::max<size_t>(1, samples.size())));
}

// The median point-to-plane misfit, against the exemplar, of `samples` at least `off` from the plane, mirrored across
// it, over the pairs within the limit whose normals agree; and the number of pairs.
std::pair<double, size_t> mirror_misfit(const KdTree& tree, const Eigen::Matrix3Xd& ep, const Eigen::Matrix3Xd& en,
                                        const std::vector<Index>& samples, const MirrorPlane& plane, double off,
                                        double limit) {
  const Similarity m = reflection_across(plane);
  std::vector<double> r;
  for (const Index e : samples) {
    if (std::abs(plane.normal.dot(ep.col(e) - plane.point)) < off) continue;
    const Eigen::Vector3d normal = m.apply_normal(en.col(e));
    if (const auto d = plane_distance(tree, ep, en, m.apply(ep.col(e)), limit, &normal)) r.push_back(std::abs(*d));
  }
  if (r.size() < 2) return {std::numeric_limits<double>::infinity(), r.size()};
  std::nth_element(r.begin(), r.begin() + Index(r.size() / 2), r.end());
  return {r[r.size() / 2], r.size()};
}

// The exemplar samples in the part that say where a mirror plane through its axis lies: those that a turn about the
// axis by 2 alpha of arc moves off the exemplar's surface by more than half an alpha (relief: a lion's mane, a bump),
// not the plain body of revolution, the flat ends or a sphere's cap, which every such plane maps onto themselves.
std::vector<Index> relief_about(const KdTree& tree, const Eigen::Matrix3Xd& ep, const Eigen::Matrix3Xd& en,
                                const TurningPart& part, double spacing, double limit) {
  const Eigen::Vector3d a = part.direction.normalized();
  std::vector<std::uint8_t> relief(size_t(ep.cols()), 0);
  tbb::parallel_for(Index(0), ep.cols(), [&](Index e) {
    if (!part.contains(ep.col(e))) return;
    const Eigen::Vector3d x = ep.col(e) - part.point;
    const double r = (x - a * a.dot(x)).norm();
    if (r < 2 * spacing) return;
    const Similarity q = turn(2 * spacing / r, part.point, a);
    const auto d = plane_distance(tree, ep, en, q.apply(ep.col(e)), limit);
    relief[size_t(e)] = d && std::abs(*d) > 0.5 * spacing;
  });
  std::vector<Index> out;
  for (Index e = 0; e < ep.cols(); ++e)
    if (relief[size_t(e)]) out.push_back(e);
  return out;
}

// A plane through the axis: its normal's angle about the axis from u (towards v = axis x u), and its offset along the
// normal from the axis' point, in alphas.
struct PlaneAt {
  double angle = 0;
  double offset = 0;
};

MirrorPlane plane_at(const Eigen::Vector3d& point, const Eigen::Vector3d& u, const Eigen::Vector3d& v, const PlaneAt& x,
                     double spacing) {
  MirrorPlane p;
  p.normal = (std::cos(x.angle) * u + std::sin(x.angle) * v).normalized();
  p.point = point + x.offset * spacing * p.normal;
  return p;
}

// Whether a fit (median misfit, pairs) of at least 100 pairs is better than another.
bool better_fit(const std::pair<double, size_t>& f, const std::pair<double, size_t>& than) {
  return f.second >= 100 && (than.second < 100 || f.first < than.first);
}

// The coarse fits' (angle-major, a circle of angles, `offsets` per angle) local minima of at least 100 pairs, at most
// `most`, best first: each the best of its angle's offsets, and no worse than the neighbouring angles' best.
std::vector<int> coarse_basins(const std::vector<std::pair<double, size_t>>& fits, int angles, int offsets,
                               size_t most) {
  std::vector<int> at(size_t(angles), -1);  // per angle, its best offset's fit
  for (int k = 0; k < angles * offsets; ++k)
    if (int& b = at[size_t(k / offsets)]; b < 0 || better_fit(fits[size_t(k)], fits[size_t(b)])) b = k;
  const auto value = [&](int angle) {
    const auto& f = fits[size_t(at[size_t((angle + angles) % angles)])];
    return f.second >= 100 ? f.first : std::numeric_limits<double>::infinity();
  };
  std::vector<int> out;
  for (int k = 0; k < angles; ++k)
    if (std::isfinite(value(k)) && value(k) <= value(k + 1) && value(k) < value(k - 1)) out.push_back(at[size_t(k)]);
  std::sort(out.begin(), out.end(), [&](int x, int y) { return fits[size_t(x)].first < fits[size_t(y)].first; });
  if (out.size() > most) out.resize(most);
  return out;
}

// The plane moved by point-to-plane ICP of the mirrored samples (at least `off` from it) onto the exemplar: per step,
// each pairs with its nearest exemplar sample within the limit whose normal agrees, and one Gauss-Newton step turns the
// normal (both ways, about the plane's point) and moves the plane along it, the pairs Cauchy-weighted at half an alpha;
// 20 steps or until it moves less than a hundredth of a degree and of an alpha.
MirrorPlane icp_refined(const KdTree& tree, const Eigen::Matrix3Xd& ep, const Eigen::Matrix3Xd& en,
                        const std::vector<Index>& samples, MirrorPlane plane, double spacing, double off,
                        double limit) {
  for (int step = 0; step < 20; ++step) {
    const Eigen::Vector3d n = plane.normal, t1 = n.unitOrthogonal(), t2 = n.cross(t1);
    Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
    Eigen::Vector3d g = Eigen::Vector3d::Zero();
    for (const Index e : samples) {
      const Eigen::Vector3d x = ep.col(e) - plane.point;
      const double h = x.dot(n);  // signed distance from the plane
      if (std::abs(h) < off) continue;
      const Eigen::Vector3d m = ep.col(e) - 2 * h * n, mn = en.col(e) - 2 * en.col(e).dot(n) * n;
      std::int32_t j;
      double d2;
      tree.knn(m, 1, &j, &d2);
      if (d2 > limit * limit || mn.dot(en.col(j)) < 0.5) continue;
      const Eigen::Vector3d& ny = en.col(j);
      const double r = (m - ep.col(j)).dot(ny);
      const Eigen::Vector3d J(-2 * (x.dot(t1) * n.dot(ny) + h * t1.dot(ny)),
                              -2 * (x.dot(t2) * n.dot(ny) + h * t2.dot(ny)), 2 * n.dot(ny));
      const double w = 1 / (1 + std::pow(r / (0.5 * spacing), 2));
      A += w * J * J.transpose();
      g += w * J * r;
    }
    if (A.determinant() <= 0) break;
    const Eigen::Vector3d delta = -A.ldlt().solve(g);
    plane.normal = (n + delta(0) * t1 + delta(1) * t2).normalized();
    plane.point += delta(2) * n;
    if (delta.head<2>().norm() < 0.01 * M_PI / 180 && std::abs(delta(2)) < 0.01 * spacing) break;
  }
  return plane;
}

// Each start refined by icp_refined, and the best fit (mirror_misfit) of those that stay planes through the part's
// axis (within kMostTilt of square to it and kMostOffset alphas of its point); none if none does.
std::pair<std::optional<MirrorPlane>, std::pair<double, size_t>> best_refined(
    const KdTree& tree, const Eigen::Matrix3Xd& ep, const Eigen::Matrix3Xd& en, const std::vector<Index>& samples,
    const TurningPart& part, const std::vector<MirrorPlane>& starts, double spacing, double off, double limit) {
  const Eigen::Vector3d a = part.direction.normalized();
  std::vector<MirrorPlane> refined(starts.size());
  std::vector<std::pair<double, size_t>> fits(starts.size());
  tbb::parallel_for(size_t(0), starts.size(), [&](size_t i) {
    refined[i] = icp_refined(tree, ep, en, samples, starts[i], spacing, off, limit);
    fits[i] = mirror_misfit(tree, ep, en, samples, refined[i], off, limit);
  });
  std::optional<MirrorPlane> best;
  std::pair<double, size_t> best_fit{std::numeric_limits<double>::infinity(), 0};
  for (size_t i = 0; i < starts.size(); ++i) {
    const MirrorPlane& x = refined[i];
    const bool through_axis = std::abs(x.normal.dot(a)) <= std::sin(kMostTilt) &&
                              std::abs(x.normal.dot(x.point - part.point)) <= kMostOffset * spacing;
    if (through_axis && better_fit(fits[i], best_fit)) best_fit = fits[i], best = x;
  }
  return {best, best_fit};
}

}  // namespace

std::optional<AxialRepeats> axial_repeats(const Eigen::Matrix3Xd& ep, const Eigen::Matrix3Xd& en,
                                          const TurningPart& part, double spacing, double limit) {
  AxialRepeats out;
  out.part = part;
  out.part.direction.normalize();
  const auto [sorted, h] = by_height(ep, out);
  const size_t n = sorted.size(), least = std::max<size_t>(60, n / 20);
  const double radius = out.radius = rms_radius(ep, sorted, out);
  if (n < 2 * least || !(radius > spacing)) return std::nullopt;
  const double step = std::max(0.5 * spacing / radius, kMaxTurn / kMostTurns);
  KdTree tree;  // the exemplar, which every turn is scored against
  tree.build(ep);
  const TurnTable table(tree, ep, en, sorted, out, step, int(std::ceil(kMaxTurn / step)), limit);
  const double floor2 = std::pow(0.25 * spacing, 2);
  // One band, or two of different orders split by a cut (tried every 2 alpha of height) that fits at least as well
  // (mean misfit over the bands' pairs at their repeats): of those, the one whose coarser band is finest, then the
  // clearly best fit (kClearlyBetter). The vase's lower half, beads and flutes, also repeats every 90 degrees, where
  // both do, and fits that turn best; but the labels can reach the repeats of 30 and 22.5 degrees. The fluted column
  // seen obliquely from behind fitted 16 flutes over its whole height as well as 17 below a cut and 16 above (0.3%
  // apart): its lower band's labels then turned by 21.2 degrees, not 22.5.
  struct Choice {
    double cut, score;
    std::array<int, 2> order;
  };
  std::vector<Choice> choices;
  const auto score = [](const BandRepeat& lo, const BandRepeat& hi) {
    return (lo.sum + hi.sum) / std::max(1.0, lo.count + hi.count);
  };
  const double noise2 = noise_floor(tree, ep, en, sorted, limit);
  const BandRepeat whole = band_repeat(table, 0, n, step, floor2, noise2);
  if (whole.order > 0) choices.push_back({h.front(), score(whole, whole), {whole.order, whole.order}});
  const double most = whole.order > 0 ? choices.front().score : std::numeric_limits<double>::infinity();
  double next_height = h[least];
  for (size_t cut = least; cut + least <= n; ++cut) {
    if (h[cut] < next_height) continue;
    next_height = h[cut] + 2 * spacing;
    const BandRepeat lo = band_repeat(table, 0, cut, step, floor2, noise2),
                     hi = band_repeat(table, cut, n, step, floor2, noise2);
    if (lo.order != hi.order && lo.order > 0 && hi.order > 0 && score(lo, hi) <= most)
      choices.push_back({h[cut], score(lo, hi), {lo.order, hi.order}});
  }
  out.cut = h.front();
  if (choices.empty())
    return std::isfinite(part.radius) ? revolution_about(tree, ep, en, sorted, out, spacing, limit) : std::nullopt;
  const auto coarser = [](const Choice& c) { return std::min(c.order[0], c.order[1]); };
  const Choice* chosen = &choices.front();
  for (const Choice& c : choices)
    if (coarser(c) > coarser(*chosen) ||
        (coarser(c) == coarser(*chosen) && c.score - noise2 < kClearlyBetter * (chosen->score - noise2)))
      chosen = &c;
  out.cut = chosen->cut;
  out.order = chosen->order;
  return out;
}

bool repeats_about(const PointSet& exemplar, const Similarity& to_template, const Eigen::Vector3d& point,
                   const Eigen::Vector3d& direction, double spacing, double limit) {
  if (!exemplar.has_normals()) return false;
  Eigen::Matrix3Xd ep(3, exemplar.size()), en(3, exemplar.size());
  for (Index e = 0; e < exemplar.size(); ++e) {
    ep.col(e) = to_template.apply(exemplar.positions().col(e));
    en.col(e) = to_template.apply_normal(exemplar.normals().col(e));
  }
  TurningPart part;
  part.point = point;
  part.direction = direction;
  const std::optional<AxialRepeats> r = axial_repeats(ep, en, part, spacing, limit);
  return r && !r->continuous && (r->order[0] > 0 || r->order[1] > 0);
}

TurningPart part_holding(const Eigen::Vector3d& point, const Eigen::Vector3d& direction,
                         const Eigen::Matrix3Xd& positions, const std::vector<std::int32_t>& samples, double margin) {
  TurningPart part{point, direction.normalized(), 0, std::numeric_limits<double>::infinity(),
                   -std::numeric_limits<double>::infinity()};
  for (const std::int32_t i : samples) {
    const Eigen::Vector3d x = positions.col(i) - part.point;
    const double h = part.direction.dot(x);
    part.radius = std::max(part.radius, (x - part.direction * h).norm() + margin);
    part.low = std::min(part.low, h - margin);
    part.high = std::max(part.high, h + margin);
  }
  return part;
}

Similarity turn_about(const AxialRepeats& r, double angle) {
  return turn(angle, r.part.point, r.part.direction);
}

std::vector<std::uint8_t> repeating_samples(const KdTree& tree, const Eigen::Matrix3Xd& ep, const Eigen::Matrix3Xd& en,
                                            const AxialRepeats& r, double spacing, double limit) {
  std::vector<std::uint8_t> repeats(size_t(ep.cols()), 0);
  tbb::parallel_for(Index(0), ep.cols(), [&](Index e) {
    const int order = r.order[size_t(band_of(r, ep.col(e)))];
    if (!r.part.contains(ep.col(e)) || (!r.continuous && order < 2)) return;
    // Unchecked: turns of 90 degrees or more, which from one view often land where the scan saw nothing on both sides
    // (the text2mesh vase's fourfold relief seen from below), and a body of revolution (a table's leg seen from above,
    // in slivers under the top).
    if (r.continuous || order < kLeastCheckedOrder) {
      repeats[size_t(e)] = 1;
      return;
    }
    const double step = 2 * M_PI / order;
    for (const double angle : {step, -step}) {
      const Similarity q = turn_about(r, angle);
      const Eigen::Vector3d facing = q.apply_normal(en.col(e));
      const auto d = plane_distance(tree, ep, en, q.apply(ep.col(e)), limit, &facing, kSameFacing);
      if (d && std::abs(*d) <= 0.5 * spacing) {
        repeats[size_t(e)] = 1;
        return;
      }
    }
  });
  return repeats;
}

std::optional<Similarity> turn_to_repeat(const AxialRepeats& r, int order, const Similarity& q, double most,
                                         double spacing) {
  if (order < 2 || r.continuous || std::abs(q.scale - 1) > 0.01) return std::nullopt;
  const Eigen::Vector3d moved = q.apply(r.part.point) - r.part.point;  // a turn about the axis keeps its points
  if (moved.norm() > 0.5 * spacing) return std::nullopt;
  const double angle = rotation_angle(q.rotation);
  const double along = rotation_axis(q.rotation).dot(r.part.direction);
  if (angle > 1e-9 && std::abs(along) < std::cos(2 * M_PI / 180)) return std::nullopt;  // not about this axis
  const double theta = along < 0 ? -angle : angle, period = 2 * M_PI / order;
  const double delta = std::round(theta / period) * period - theta;
  if (std::abs(delta) * r.radius > most) return std::nullopt;
  return turn(delta, r.part.point, r.part.direction);
}

Similarity reflection_across(const MirrorPlane& m) {
  const Eigen::Matrix3d R = Eigen::Matrix3d::Identity() - 2 * m.normal * m.normal.transpose();
  return Similarity{R, 2 * m.normal.dot(m.point) * m.normal, 1.0};
}

std::optional<MirrorPlane> mirror_plane(const KdTree& tree, const Eigen::Matrix3Xd& ep, const Eigen::Matrix3Xd& en,
                                        const TurningPart& part, double spacing, double limit) {
  const Eigen::Vector3d a = part.direction.normalized(), u = a.unitOrthogonal(), v = a.cross(u);
  const std::vector<Index> samples = relief_about(tree, ep, en, part, spacing, limit);
  if (samples.size() < 200) return std::nullopt;
  const double off = 1.5 * spacing;
  const auto fit = [&](const MirrorPlane& p) { return mirror_misfit(tree, ep, en, samples, p, off, limit); };
  // Coarse: planes 3 degrees apart over a half turn, each up to 2 alpha either side of the axis.
  constexpr int kAngles = 60, kOffsets = 9;
  std::vector<std::pair<double, size_t>> coarse(kAngles * kOffsets);
  const auto coarse_at = [&](int k) {
    return plane_at(part.point, u, v, PlaneAt{(k / kOffsets) * M_PI / kAngles, (k % kOffsets - 4) * 0.5}, spacing);
  };
  tbb::parallel_for(0, kAngles * kOffsets, [&](int k) { coarse[size_t(k)] = fit(coarse_at(k)); });
  std::vector<MirrorPlane> starts;
  for (const int k : coarse_basins(coarse, kAngles, kOffsets, kBasins)) starts.push_back(coarse_at(k));
  const auto [best, best_fit] = best_refined(tree, ep, en, samples, part, starts, spacing, off, limit);
  const auto [misfit, pairs] = best_fit;
  const double most =
      std::sqrt(std::pow(0.25 * spacing, 2) + kMedianOfSquare * noise_floor(tree, ep, en, samples, limit));
  if (!best || 5 * pairs < samples.size() || misfit > most) return std::nullopt;
  MirrorPlane out = *best;
  out.misfit = misfit;
  out.pairs = std::int64_t(pairs);
  return out;
}

}  // namespace scanfill
