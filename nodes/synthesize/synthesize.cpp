#include "nodes/synthesize/synthesize.h"

#include <tbb/parallel_for.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <tuple>
#include <unordered_map>

#include "nodes/core/errors.h"
#include "nodes/core/kdtree.h"
#include "nodes/synthesize/repeats.h"
#include "nodes/synthesize/synthesize_options.h"

namespace scanfill {
namespace {

// Appends points to a synthesis under construction.
struct Builder {
  std::vector<Eigen::Vector3d> p, n;
  Synthesis& out;
  void add(const Eigen::Vector3d& position, const Eigen::Vector3d& normal, Origin origin, int label, int patch,
           int base, bool ring) {
    p.push_back(position);
    n.push_back(normal);
    out.origin.push_back(origin);
    out.label.push_back(label);
    out.patch.push_back(patch);
    out.base.push_back(base);
    out.ring.push_back(ring ? 1 : 0);
  }
};

// The rigid motions along which a target region slides on itself, as (w, tau) 6-vectors about `centre`, positions in
// units of `radius`: the motion exp(s v) displaces p by s (w x (p - centre) + radius tau) to first order.
struct Slippage {
  std::vector<Eigen::Matrix<double, 6, 1>> motions;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  double radius = 1;
};

// The point-to-plane Hessian of the target samples in `part` for twists (w, tau) about `centre`, positions in units of
// `radius` (Gelfand and Guibas 2004): v^T A v is how far motion v moves them off their own surface.
Eigen::Matrix<double, 6, 6> slippage_hessian(const PointSet& target, const std::vector<std::uint8_t>& part,
                                             const Eigen::Vector3d& centre, double radius) {
  Eigen::Matrix<double, 6, 6> A = Eigen::Matrix<double, 6, 6>::Zero();
  for (Index t = 0; t < target.size(); ++t) {
    if (!part[size_t(t)]) continue;
    const Eigen::Vector3d q = (target.positions().col(t) - centre) / radius, nn = target.normals().col(t);
    Eigen::Matrix<double, 6, 1> J;
    J << q.cross(nn), nn;
    A += J * J.transpose();
  }
  return A;
}

// The centroid and RMS radius of the target samples in `part`, and their number.
std::tuple<Eigen::Vector3d, double, Index> part_frame(const PointSet& target, const std::vector<std::uint8_t>& part) {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  Index n = 0;
  for (Index t = 0; t < target.size(); ++t)
    if (part[size_t(t)]) {
      centre += target.positions().col(t);
      ++n;
    }
  if (n == 0) return {centre, 1.0, 0};
  centre /= double(n);
  double radius = 0;
  for (Index t = 0; t < target.size(); ++t)
    if (part[size_t(t)]) radius += (target.positions().col(t) - centre).squaredNorm();
  return {centre, std::sqrt(radius / double(n)), n};
}

// The rigid motions along which the target samples in `part` slide on themselves (slippage analysis): the
// eigenvectors of their point-to-plane Hessian with eigenvalues below 2% of the largest (at most two), as (w, tau)
// 6-vectors about `centre`, with positions in units of the part's RMS radius so that rotations and translations
// compare.
Slippage slippable_motions(const PointSet& target, const std::vector<std::uint8_t>& part) {
  Slippage out;
  Index n;
  std::tie(out.centre, out.radius, n) = part_frame(target, part);
  if (n < 30) return out;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> eig(
      slippage_hessian(target, part, out.centre, out.radius));
  for (int i = 0; i < 2; ++i)  // ascending eigenvalues: at most the two most slippable motions
    if (eig.eigenvalues()(i) < 0.02 * eig.eigenvalues()(5)) out.motions.push_back(eig.eigenvectors().col(i));
  return out;
}

// `slip` without the motions along which the target samples in `part` do not slide (by the same 2% of the largest
// eigenvalue of their Hessian): each motion is re-expressed about their centroid, in their radius.
Slippage sliding_also_on(Slippage slip, const PointSet& target, const std::vector<std::uint8_t>& part) {
  const auto [centre, radius, n] = part_frame(target, part);
  if (n < 30) return slip;
  const Eigen::Matrix<double, 6, 6> A = slippage_hessian(target, part, centre, radius);
  const double largest =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>>(A, Eigen::EigenvaluesOnly).eigenvalues()(5);
  std::erase_if(slip.motions, [&](const Eigen::Matrix<double, 6, 1>& v) {
    Eigen::Matrix<double, 6, 1> u;  // the same velocity field about `centre`, in units of `radius`
    u << v.head<3>(), (v.tail<3>() * slip.radius + v.head<3>().cross(centre - slip.centre)) / radius;
    return u.squaredNorm() > 0 && u.dot(A * u) / u.squaredNorm() >= 0.02 * largest;
  });
  return slip;
}

// The motion exp(s v) about `centre` (v in radius units) as a similarity.
Similarity motion(const Eigen::Matrix<double, 6, 1>& v, double s, const Eigen::Vector3d& centre, double radius) {
  const Eigen::Vector3d w = v.head<3>() * s, tau = v.tail<3>() * s * radius;
  const Eigen::Matrix3d R =
      w.norm() > 1e-15 ? Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix() : Eigen::Matrix3d::Identity();
  return Similarity{R, centre - R * centre + tau, 1.0};
}

// The exemplar images placed so far by the refinement (the reference the next image is fitted to), with a kd-tree.
class PlacedImages {
 public:
  PlacedImages(const Eigen::Matrix3Xd& ep, const Eigen::Matrix3Xd& en, double limit2)
      : ep_(ep), en_(en), limit2_(limit2) {}

  // The exemplar carried by q.
  void image(const Similarity& q, Eigen::Matrix3Xd& p, Eigen::Matrix3Xd& n) const {
    p.resize(3, ep_.cols());
    n.resize(3, ep_.cols());
    for (Index e = 0; e < ep_.cols(); ++e) {
      p.col(e) = q.apply(ep_.col(e));
      n.col(e) = q.apply_normal(en_.col(e));
    }
  }

  void place(const Eigen::Matrix3Xd& p, const Eigen::Matrix3Xd& n) {
    Eigen::Matrix3Xd np(3, ref_p_.cols() + p.cols()), nn(3, ref_n_.cols() + n.cols());
    np << ref_p_, p;
    nn << ref_n_, n;
    ref_p_ = std::move(np);
    ref_n_ = std::move(nn);
    indexed_ = false;  // the tree held the old matrix
  }

  void place(const Similarity& q) {
    Eigen::Matrix3Xd p, n;
    image(q, p, n);
    place(p, n);
  }

  // Builds the kd-tree over the placed points, unless it holds them already (nothing placed since).
  void index() {
    if (indexed_) return;
    tree_.build(ref_p_);
    indexed_ = true;
  }
  double limit2() const { return limit2_; }

  // Calls f(image point, placed point, placed normal) for each exemplar sample whose image under q has a placed
  // partner (as `matches` pairs them), in exemplar order.
  template <class F>
  void for_each_pair(const Similarity& q, F&& f) const {
    Eigen::Matrix3Xd p, n;
    image(q, p, n);
    const std::vector<std::int32_t> match = matches(p, n);
    for (Index e = 0; e < p.cols(); ++e)
      if (const std::int32_t i = match[size_t(e)]; i >= 0) f(p.col(e), ref_p_.col(i), ref_n_.col(i));
  }

  // Exemplar samples whose image under q lies within the limit of a placed point with a normal within 60 degrees.
  Index overlap(const Similarity& q) const {
    Eigen::Matrix3Xd p, n;
    image(q, p, n);
    const std::vector<std::int32_t> match = matches(p, n);
    return Index(std::count_if(match.begin(), match.end(), [](std::int32_t i) { return i >= 0; }));
  }

  // The overlap (as `overlap` counts it) and how many of its exemplar samples are `raised`.
  std::pair<Index, Index> raised_overlap(const Similarity& q, const std::vector<std::uint8_t>& raised) const {
    Eigen::Matrix3Xd p, n;
    image(q, p, n);
    const std::vector<std::int32_t> match = matches(p, n);
    Index overlap = 0, of_raised = 0;
    for (size_t e = 0; e < match.size(); ++e)
      if (match[e] >= 0) {
        ++overlap;
        of_raised += raised[e];
      }
    return {overlap, of_raised};
  }

  // Per exemplar sample in `subset`, the squared point-to-plane distance of its image under q to the nearest placed
  // point, or -1 beyond the limit.
  void residuals(const Similarity& q, const std::vector<std::int32_t>& subset, float* r2) const {
    tbb::parallel_for(size_t(0), subset.size(), [&](size_t i) {
      std::int32_t j;
      double d2;
      const Eigen::Vector3d x = q.apply(ep_.col(subset[i]));
      tree_.knn(x, 1, &j, &d2);
      r2[i] = d2 <= limit2_ ? float(std::pow((x - ref_p_.col(j)).dot(ref_n_.col(j)), 2)) : -1.0f;
    });
  }

  // Point-to-plane misfit of the image under q (every second sample), over the overlap: (sum of squares, overlap).
  // With `facing_alike`, a pair counts only where the normals agree within 60 degrees, as `matches` pairs them.
  std::pair<double, Index> misfit(const Similarity& q, bool facing_alike = false) const {
    double sum = 0;
    Index overlap = 0;
    for (Index e = 0; e < ep_.cols(); e += 2) {
      std::int32_t j;
      double d2;
      const Eigen::Vector3d x = q.apply(ep_.col(e));
      tree_.knn(x, 1, &j, &d2);
      // Point-to-plane: tangential sampling offsets do not count, misplaced detail does.
      if (d2 <= limit2_ && (!facing_alike || q.apply_normal(en_.col(e)).dot(ref_n_.col(j)) > 0.5)) {
        sum += std::pow((x - ref_p_.col(j)).dot(ref_n_.col(j)), 2);
        ++overlap;
      }
    }
    return {sum, overlap};
  }

  // Point-to-plane ICP of the image under c o q onto the placed images, on the overlap only (pairs within the limit
  // with normals within 60 degrees; at least 30), by any rigid motion or only along the region's slippable motions.
  // Returns the refined c.
  Similarity fit_along(const Similarity& q, Similarity c, const Slippage& slip, bool rigid, int iterations) const {
    if (!rigid && slip.motions.empty()) return c;  // nothing to move along
    Eigen::Matrix3Xd p, n;
    for (int it = 0; it < iterations; ++it) {
      image(c.compose(q), p, n);
      const std::optional<Twist> v = motion_step(p, matches(p, n), slip, rigid);
      if (!v) break;
      c = motion(*v, 1.0, slip.centre, slip.radius).compose(c);
    }
    return c;
  }

 private:
  using Twist = Eigen::Matrix<double, 6, 1>;

  // Per image point (positions p, normals n), its placed partner: the nearest placed point when within the limit and
  // with a normal within 60 degrees, else -1.
  std::vector<std::int32_t> matches(const Eigen::Matrix3Xd& p, const Eigen::Matrix3Xd& n) const {
    std::vector<std::int32_t> match(size_t(p.cols()), -1);
    tbb::parallel_for(Index(0), p.cols(), [&](Index e) {
      std::int32_t i;
      double d2;
      tree_.knn(p.col(e), 1, &i, &d2);
      if (d2 <= limit2_ && n.col(e).dot(ref_n_.col(i)) > 0.5) match[size_t(e)] = i;
    });
    return match;
  }

  // The least-squares point-to-plane step of the matched image points, as a twist about the region's centre, within
  // step_basis: none with fewer than 30 pairs. In a fixed order: the same on any thread count.
  std::optional<Twist> motion_step(const Eigen::Matrix3Xd& p, const std::vector<std::int32_t>& match,
                                   const Slippage& slip, bool rigid) const {
    Eigen::Matrix<double, 6, 6> A = Eigen::Matrix<double, 6, 6>::Zero();
    Twist b = Twist::Zero();
    Index pairs = 0;
    for (Index e = 0; e < p.cols(); ++e) {
      const std::int32_t i = match[size_t(e)];
      if (i < 0) continue;
      const Eigen::Vector3d nq = ref_n_.col(i);
      Twist g;
      g << (p.col(e) - slip.centre).cross(nq), slip.radius * nq;
      A.noalias() += g * g.transpose();
      b -= g * nq.dot(p.col(e) - ref_p_.col(i));
      ++pairs;
    }
    if (pairs < 30) return std::nullopt;
    const Eigen::MatrixXd B = step_basis(slip, rigid);
    if (B.cols() == 0) return Twist::Zero();
    Eigen::MatrixXd Ab = B.transpose() * A * B;
    Ab.diagonal().array() += 1e-6 * Ab.trace() / double(B.cols()) + 1e-300;
    const Eigen::VectorXd y = Ab.ldlt().solve(B.transpose() * b);
    if (!y.allFinite()) return std::nullopt;
    return Twist(B * y);
  }

  // An orthonormal basis of the motions a step may take (columns): every rigid motion, or the region's slippable ones
  // (eigenvectors of a symmetric matrix: orthonormal already).
  static Eigen::MatrixXd step_basis(const Slippage& slip, bool rigid) {
    if (rigid) return Eigen::MatrixXd::Identity(6, 6);
    Eigen::MatrixXd V(6, Index(slip.motions.size()));
    for (size_t j = 0; j < slip.motions.size(); ++j) V.col(Index(j)) = slip.motions[j];
    return V;
  }

  const Eigen::Matrix3Xd &ep_, &en_;
  double limit2_;
  Eigen::Matrix3Xd ref_p_ = Eigen::Matrix3Xd(3, 0), ref_n_ = Eigen::Matrix3Xd(3, 0);
  KdTree tree_;
  bool indexed_ = false;  // whether the tree holds the placed points
};

// The step along slippable motion v (in units of `step`, tried 0, 1, -1, 2, -2, ... up to +-steps) that best fits the
// image of c o q to the placed images: mean squared point-to-plane distance over the overlap, which must stay at least
// half of the start's, and a move must clearly beat the start (motions the detail does not fix, flutes along their
// own length, stay 0). Only pairs facing alike count: the ribbed box seen square on its short side turns that side
// onto a long one, whose image meets the scan only across the corner, and the pairs there, planes 90 degrees apart,
// scored a slide of half a rib period best (F 0.934, 0.992 counted so). The refinement's choice between its fits
// still counts every pair: the medallion barrel from (0.43, -0.69, -0.59) needs a medallion's steep walls paired
// with the plain body it would stand on to turn its image onto the medallion's place (F 0.955 without them, 0.997).
int best_phase_step(const PlacedImages& placed, const Eigen::Matrix<double, 6, 1>& v, double step, int steps,
                    const Eigen::Vector3d& centre, double radius, const Similarity& c, const Similarity& q) {
  auto offset = [](int k) { return k == 0 ? 0 : (k % 2 ? (k + 1) / 2 : -(k / 2)); };  // 0, 1, -1, 2, -2, ...
  // The trials are independent: scored in parallel (each sum in its own fixed order), chosen in order below.
  std::vector<std::pair<double, Index>> trials(static_cast<size_t>(2 * steps + 1));
  tbb::parallel_for(0, 2 * steps + 1, [&](int k) {
    trials[size_t(k)] = placed.misfit(motion(v, offset(k) * step, centre, radius).compose(c).compose(q), true);
  });
  double best_score = 0, start_score = 0;
  Index start_overlap = 0;
  int best_step = 0;
  for (int k = 0; k <= 2 * steps; ++k) {
    const auto [sum, overlap] = trials[size_t(k)];
    if (k == 0) {
      start_overlap = overlap;
      start_score = overlap > 0 ? sum / double(overlap) : 0.0;
    }
    if (overlap < 15 || 2 * overlap < start_overlap) continue;
    const double score = sum / double(overlap);
    if (k == 0 || score < std::min(best_score, 0.85 * start_score)) {
      best_score = score;
      best_step = offset(k);
    }
  }
  return best_step;
}

// The phase search's step along slippable motion v (half an alpha for the point it moves fastest) and the number of
// steps each way (+-search_distance alpha); none for a motion that moves nothing.
std::optional<std::pair<double, int>> phase_steps(const Eigen::Matrix<double, 6, 1>& v, const Slippage& slip,
                                                  double spacing, const SynthesisOptions& o) {
  const double rate = std::max(v.head<3>().norm() * 2 * slip.radius, v.tail<3>().norm() * slip.radius);  // per s
  if (!(rate > 0)) return std::nullopt;
  const double step = 0.5 * spacing / rate;
  return std::pair{step, int(std::ceil(o.search_distance * spacing / rate / step))};
}

// Where the template slides on itself, the template cannot tell the phase of the exemplar's detail: searches each
// slippable motion of region `label` over +-search_distance alpha for the best fit of the image's detail to the
// placed images. Returns the correction c (applied after q).
Similarity phase_correction(const PlacedImages& placed, const Similarity& q, const Slippage& slip, double spacing,
                            const SynthesisOptions& o) {
  Similarity c;
  for (const auto& v : slip.motions) {
    const auto search = phase_steps(v, slip, spacing, o);
    if (!search) continue;
    const auto [step, steps] = *search;
    c = motion(v, best_phase_step(placed, v, step, steps, slip.centre, slip.radius, c, q) * step, slip.centre,
               slip.radius)
            .compose(c);
  }
  return c;
}

// How far a free fit may move a region the template pins before its landing on the template is checked, in alpha.
constexpr double kFarSlide = 5.0;
// The same where the scan is as given (`as_given`): no registration moved it, so it stands on the template.
constexpr double kAsGivenSlide = 1.0;
// A free fit that moves a region more than kAsGivenSlide needs one in this many of its overlap's exemplar samples
// raised off the template (ExemplarRelief::raised; see `refinement`).
constexpr Index kLeastRaisedShare = 20;
// An image is plain when every exemplar sample it carries into its region (1% spared) lies within this many alpha of
// the template's plane under it (plain_images).
constexpr double kPlainHeight = 0.5;

// The least registration offset applied, in alpha (applied_offset), and the least that has the refinement score its
// candidates by truncated least squares (refine). Between the two, the offset is applied but the candidates are
// scored by their mean misfit: the fluted column seen from straight above, 0.5 alpha off, kept its flips on the
// bottom face that way (F 0.951), where truncated scoring slid them 2.7 cm up off it (0.715).
constexpr double kLeastOffset = 0.3;
constexpr double kTruncatingOffset = 1.25;

// How far off the template, in alpha, the scan's relief stands where it is its own when the scan repeats about no
// axis (unrepeated_relief): a teapot's spout stands 20 alpha off its body, a gear's teeth 4.
constexpr double kUnrepeatedRelief = 8.0;
constexpr std::uint8_t kUnrepeatedFoot = 2;  // unrepeated_relief's mark of a part's foot, under kUnrepeatedRelief

// How far correction c moves a region (centre, radius): its centre's move plus its turn times its radius.
double region_move(const Similarity& c, const Slippage& slip) {
  return (c.apply(slip.centre) - slip.centre).norm() + rotation_angle(c.rotation) * slip.radius;
}

// Truncated least squares of a misfit (sum of squares over `pairs`), over `most` pairs: each pair it lacks costs the
// pairing limit squared.
double truncated_misfit(double sum, Index pairs, Index most, double limit2) {
  return sum + double(most - pairs) * limit2;
}

// The slippable motion that turns the region about an axis (rotation rather than translation), if it has one.
const Eigen::Matrix<double, 6, 1>* turn_about_axis(const Slippage& slip) {
  for (const auto& v : slip.motions)
    if (v.head<3>().norm() * 2 > v.tail<3>().norm()) return &v;
  return nullptr;
}

// Whether q turns `axis` (unit) end over end: more than 120 degrees from itself.
bool turns_end_over_end(const Similarity& q, const Eigen::Vector3d& axis) {
  return axis.dot(q.rotation * axis) < -0.5;
}

// Whether q turns the axis of the region's slippable turn end over end (a flip: a body's bottom onto its top).
bool flips_turn_axis(const Similarity& q, const Slippage& slip) {
  const auto* v = turn_about_axis(slip);
  return v && turns_end_over_end(q, v->head<3>().normalized());
}

// Whether the template fits the exemplar: fewer than half its samples stand off it (`raised`; empty in a transfer).
bool template_fits_exemplar(const std::vector<std::uint8_t>& raised) {
  return raised.empty() || 2 * std::count(raised.begin(), raised.end(), std::uint8_t(1)) < std::ssize(raised);
}

// The correction c (applied after q) that fits the image's detail to the placed images best of three: the phase along
// the region's slippable motions; that phase refined by ICP along them only; and that phase refined by free rigid ICP.
// The labelled transform already fits the template, so only its slippable motions are in doubt; a free fit corrects
// the exemplar's registration where its relief pulled it off, but on an overlap that fixes little (a table's top) it
// slides and carries the detail off its part (the legs' bulbs, issue 10). ICP can also end above the phase it started
// from: its pairs (normals within 60 degrees) are not the misfit's. Scored by mean misfit over the overlap, a fit that
// keeps less than 90% of the phase's overlap is not taken: a mean over a shrinking overlap rewards sliding off the
// placed images (the table seen from behind: a flip slid 9 cm for a 20% lower misfit on 15% less overlap).
// Where the exemplar sits on the template (no registration offset) and the region has no slippable motion, the
// template pins where its detail goes: a free fit that slides it more than 5 alpha and carries its image off the
// template, landing (`landed`) under half the samples the phase does, is not taken. On an overlap that is mostly flat
// top (the table seen from (-0.2, -0.6, 0.9)) it slid two labels' legs 19 alpha off the legs for a 30% lower mean.
// So too where the region slides on the template but the template fits the exemplar: its slippable motions keep it on
// the template, and a free fit that leaves it is not a better phase. The ribbed box seen square on its short side
// ((-1, 0.01, 0.03)): the quarter turns onto its long sides overlapped the scan in a sliver at the corners, and their
// free fits turned them 25 degrees about the vertical, 12-18 alpha off the box (landing 6-18% against 99%).
// Kept: the crate's fits of 2-3 alpha across its relief (landing 5-26%: the relief's depth), a fit of 9 alpha the
// table seen from above needs (landing 56%), and Vase-Lion's turns, whose body of revolution fits it loosely. Those
// fits correct a registration the relief pulled off the template. Where no registration moved the scan
// (`as_given`), there is nothing to correct, and a fit that moves such a region more than an alpha and lands a
// tenth less of it is not taken: the crate in its own pose seen from below, whose flip of the floor onto the lid also
// turns the seen walls' relief upside down onto itself, slid 2 alpha up for a lower misfit of the walls, the lid off
// the box (landing 100% -> 56%, F 0.742; 0.981 kept). There a sample lands within an alpha of the template (`landed`
// as synthesize builds it), not the regions' 2: seen from nearly straight below, (0.25, 0.17, -0.95), the same flip
// slid 1.8 alpha up and its lid still landed within 2 (F 0.705; 0.978 kept).
// `truncated`, where the shared registration offset already moved the transforms: truncated least squares over the
// largest overlap of the three, each sample a fit leaves out costing the pairing limit squared. Once every image
// turns about the exemplar's own axis, the fits differ in phase, and a phase half a tooth off, where the flanks the
// scanner did not see drop out of the overlap, has the lower mean (the gear from the front and from the side). The
// first wins a tie.
// A flip that turns about the axis it is flipped across (a body's bottom end over end onto its top) is pinned by the
// template across that turn: a free fit that moves it more than an alpha beyond its fit along the turn and lands a
// tenth less of it on the template is not taken, scan moved or not. The medallion barrel seen from nearly straight
// below ((0.25, 0.17, -0.95)): its flipped bottom's overlap with the placed sides tilted it off the top, 4.9 alpha
// beyond its turn (landing 88%), and 5% of the output stood off the top's rim (F 0.958; 0.991 kept). Turns about the
// axis keep their free fits: the Vase-Lion's template, its body of revolution, fits its head loosely, and the fits
// that carry a turn's head 10-13 alpha off it (landing 18-69%) are what its unseen side gains (mean unseen-detail
// 0.425, 0.372 without them).
// So too a flip that turns the object's `up` end over end on a region with no slippable motion (`overturns`, where the
// template fits the exemplar), its landing counted within an alpha: the triangular prism seen from above the front
// ((-0.10, -0.75, 0.65)), whose back and floor take the seen top and sides flipped about a horizontal axis, slid 1.8
// alpha up the sides for a 15% lower misfit of its bands, within the regions' 2-alpha landing, and lifted its floor
// 1.45 cm off the ground (F 0.879; 0.983 pinned). Upright regions keep their fits: the table seen from above needs one
// of 9 alpha (unseen-detail 0.73; 0.59 with every region without slippable motion pinned so).
// Nor is a flip pinned where the template does not fit the exemplar (half of it stands off the template): a plain
// cylinder round a vase lies off it (97-99% of the scan), and the free fits that carry its flipped parts 13-25 alpha
// onto the placed images, off the cylinder, are better evidence than the template (from below, F 0.626 pinned, 0.654
// free). The medallion barrel's scan stands 9% off its body of revolution, the Vase-Lion's 83-90% off its. Nor is a
// free fit that moves a region more than an alpha taken where under a twentieth of the phase's overlap is raised off
// the template (`slides_on_plain`; `raised` empty in a transfer): creases and caps pin plain on plain only loosely, and
// a slide along a side fits a neighbour's small misfit. The triangular prism seen from low in front: its side turned by
// 120 degrees overlapped the images before it only there (3% raised), and slid 2.2 alpha along the far side for a 3%
// lower misfit, its medallion off the model's (F 0.923, 0.988 kept).
Similarity refinement(const PlacedImages& placed, const Similarity& q, const Slippage& slip, double spacing,
                      const SynthesisOptions& o, bool truncated, bool as_given, bool overturns,
                      const std::function<double(const Similarity&, bool)>& landed,
                      const std::vector<std::uint8_t>& raised) {
  const Similarity phase = phase_correction(placed, q, slip, spacing, o);
  const std::array<Similarity, 3> fits{phase, placed.fit_along(q, phase, slip, false, o.refine_iterations),
                                       placed.fit_along(q, phase, slip, true, o.refine_iterations)};
  std::array<std::pair<double, Index>, 3> misfit;
  Index most = 0;
  for (size_t i = 0; i < fits.size(); ++i) {
    misfit[i] = placed.misfit(fits[i].compose(q));
    most = std::max(most, misfit[i].second);
  }
  const bool leaves_template = [&] {
    const bool fitting = template_fits_exemplar(raised), flip = flips_turn_axis(q, slip) && fitting;
    if (truncated || (!slip.motions.empty() && !fitting)) return false;
    const bool overturned = overturns && slip.motions.empty() && fitting;
    const bool pinned = as_given || flip || overturned;
    if (region_move(fits[2].compose(fits[1].inverse()), slip) <= (pinned ? kAsGivenSlide : kFarSlide) * spacing)
      return false;
    const double landing = landed(fits[2].compose(q), overturned), phase_landing = landed(phase.compose(q), overturned);
    return pinned ? 10 * landing < 9 * phase_landing : 2 * landing < phase_landing;
  }();
  const bool slides_on_plain = [&] {
    if (raised.empty() || region_move(fits[2].compose(phase.inverse()), slip) <= kAsGivenSlide * spacing) return false;
    const auto [overlap, of_raised] = placed.raised_overlap(phase.compose(q), raised);
    return of_raised * kLeastRaisedShare < overlap;
  }();
  const auto score = [&](size_t i) {
    const auto [sum, overlap] = misfit[i];
    if (truncated) return truncated_misfit(sum, overlap, most, placed.limit2());
    const bool kept =
        overlap > 0 && 10 * overlap >= 9 * misfit[0].second && !(i == 2 && (leaves_template || slides_on_plain));
    return kept ? sum / double(overlap) : std::numeric_limits<double>::infinity();
  };
  size_t best = 0;
  for (size_t i = 1; i < fits.size(); ++i)
    if (score(i) < score(best)) best = i;
  return fits[best];
}

// A region's image in two parts across a rotational slippable motion's axis, each with its own phase about the axis.
struct PhaseSplit {
  std::vector<std::uint8_t> part;  // per used exemplar sample: 0 below the cut, 1 above
  std::array<Similarity, 2> inv;   // per part
};

// Squared point-to-plane misfit and overlap of samples (in a fixed order) at each phase step k of a turn, as prefix
// sums over the samples: any run of samples [a, b) scores at any step in O(1). Steps are k - zero half-alpha steps.
class PhaseTable {
 public:
  // at_step(k): the image's transform at step k of 2 steps + 1.
  PhaseTable(const PlacedImages& placed, const std::vector<std::int32_t>& samples, int steps,
             const std::function<Similarity(size_t)>& at_step)
      : n_(samples.size()),
        K_(size_t(2 * steps + 1)),
        zero_(size_t(steps)),
        sum_((n_ + 1) * K_, 0.0),
        count_((n_ + 1) * K_, 0.0) {
    std::vector<float> r2(n_);
    for (size_t k = 0; k < K_; ++k) {
      placed.residuals(at_step(k), samples, r2.data());
      for (size_t i = 0; i < n_; ++i) {
        sum_[(i + 1) * K_ + k] = sum_[i * K_ + k] + std::max(0.0f, r2[i]);
        count_[(i + 1) * K_ + k] = count_[i * K_ + k] + (r2[i] >= 0);
      }
    }
  }

  size_t zero() const { return zero_; }
  bool inside(size_t k) const { return k > 0 && k + 1 < K_; }  // not at the search range's edge
  double sum(size_t a, size_t b, size_t k) const { return sum_[b * K_ + k] - sum_[a * K_ + k]; }
  double count(size_t a, size_t b, size_t k) const { return count_[b * K_ + k] - count_[a * K_ + k]; }
  double mean(size_t a, size_t b, size_t k) const { return sum(a, b, k) / std::max(1.0, count(a, b, k)); }

  // The step of least mean misfit for samples [a, b), with at least half the overlap of step zero (q's own phase).
  size_t best_step(size_t a, size_t b) const {
    size_t best = zero_;
    for (size_t k = 0; k < K_; ++k) {
      const double c = count(a, b, k);
      if (c >= 15 && 2 * c >= count(a, b, zero_) && sum(a, b, k) / c < mean(a, b, best)) best = k;
    }
    return best;
  }

 private:
  size_t n_, K_, zero_;
  std::vector<double> sum_, count_;
};

// The cut of the samples (sorted by height h, ascending) into [0, cut) and [cut, n), with one part at step zero and
// the other at its own best step, that fits best: (cut, lower step, upper step), or none. Cuts are tried every
// 2 spacings of height and leave each part at least `least` samples. The part that moves must be the smaller one
// (q's phase was fitted to the whole image, so it is the larger part's), move to a minimum inside the search range
// (not to its edge), and fit clearly better itself (at most half its mean misfit at step zero); and the two phases
// together must beat the one by 10% over the whole.
std::optional<std::array<size_t, 3>> best_cut(const PhaseTable& table, const std::vector<double>& h, size_t least,
                                              double spacing) {
  const size_t n = h.size(), zero = table.zero();
  double best_score = 0.9 * table.mean(0, n, zero);
  std::optional<std::array<size_t, 3>> best;
  double next_height = h[least];
  for (size_t cut = least; cut + least <= n; ++cut) {
    if (h[cut] < next_height) continue;
    next_height = h[cut] + 2 * spacing;
    const size_t lo = table.best_step(0, cut), hi = table.best_step(cut, n);
    if ((lo == zero) == (hi == zero)) continue;  // exactly one part moves
    const bool lower_moves = hi == zero;
    const size_t a = lower_moves ? 0 : cut, b = lower_moves ? cut : n, moved = lower_moves ? lo : hi;
    if (2 * (b - a) > n || !table.inside(moved) || table.mean(a, b, moved) > 0.5 * table.mean(a, b, zero)) continue;
    const double score = (table.sum(0, cut, lo) + table.sum(cut, n, hi)) /
                         std::max(1.0, table.count(0, cut, lo) + table.count(cut, n, hi));
    if (score < best_score) {
      best_score = score;
      best = {cut, lo, hi};
    }
  }
  return best;
}

// A region that turns on itself about an axis can carry detail of two periods at two heights (a vase's 12 flutes above
// its ring of 16 beads): one phase about the axis fits the one that covers more of the image, and the other lands
// between its own kind. Searches for a second phase, over the phase search's range (+-search_distance alpha in
// half-alpha steps), for the samples on one side of a cut across the axis (best_cut's rules): none for a region that
// does not turn on itself, has fewer than 120 used samples, or gains too little from a cut (a single period, as on a
// fluted column or a gear). Each part keeps at least 5% of the samples (and 60).
std::optional<PhaseSplit> phase_split(const PlacedImages& placed, const Eigen::Matrix3Xd& ep,
                                      const std::vector<std::int32_t>& used, const Similarity& q, const Slippage& slip,
                                      double spacing, const SynthesisOptions& o) {
  const Eigen::Matrix<double, 6, 1>* turn = turn_about_axis(slip);
  const size_t n = used.size(), least = std::max<size_t>(60, n / 20);
  if (turn == nullptr || n < 2 * least) return std::nullopt;
  const Eigen::Vector3d axis = turn->head<3>().normalized();
  std::vector<double> height(n);
  for (size_t i = 0; i < n; ++i) height[i] = axis.dot(q.apply(ep.col(used[i])) - slip.centre);
  std::vector<std::int32_t> order(n);  // the used samples by height
  for (size_t i = 0; i < n; ++i) order[i] = std::int32_t(i);
  std::stable_sort(order.begin(), order.end(), [&](auto a, auto b) { return height[size_t(a)] < height[size_t(b)]; });
  std::vector<std::int32_t> sorted(n);
  std::vector<double> h(n);
  for (size_t i = 0; i < n; ++i) {
    sorted[i] = used[size_t(order[i])];
    h[i] = height[size_t(order[i])];
  }
  const auto [step, steps] = *phase_steps(*turn, slip, spacing, o);  // a turn moves its points: a step exists
  const auto at_step = [&, step = step, steps = steps](size_t k) {
    return motion(*turn, (int(k) - steps) * step, slip.centre, slip.radius).compose(q);
  };
  const std::optional<std::array<size_t, 3>> cut =
      best_cut(PhaseTable(placed, sorted, steps, at_step), h, least, spacing);
  if (!cut) return std::nullopt;
  PhaseSplit out;
  out.part.assign(n, 0);
  for (size_t i = (*cut)[0]; i < n; ++i) out.part[size_t(order[i])] = 1;
  for (size_t p = 0; p < 2; ++p) out.inv[p] = at_step((*cut)[1 + p]);
  return out;
}

// The distance of x from the axis through `point` along the unit `direction`.
double distance_from_axis(const Eigen::Vector3d& x, const Eigen::Vector3d& point, const Eigen::Vector3d& direction) {
  const Eigen::Vector3d r = x - point;
  return (r - direction * direction.dot(r)).norm();
}

// The axis region `slip` turns about, moved by the exemplar's registration offset d (the images turn about it). Where
// it runs along one of the template's own axes (`parts`, within kSameAxisTilt, and inside that part's radius), that
// axis: a region's slippage places the axis only as well as its shape pins it. A fluted column's plain bottom cap,
// flipped from its top with a sliver of fluted rim, turned about an axis 3 cm off the column's, about which the scan
// "repeated" thrice (its flat top does about any axis through it); the repeats' fill laid turned copies of the flutes
// 5 cm off the column (F 0.963 from (-0.61, -0.43, 0.67)).
constexpr double kSameAxisTilt = 5 * M_PI / 180;

std::optional<std::pair<Eigen::Vector3d, Eigen::Vector3d>> turning_axis(const Slippage& slip, const Eigen::Vector3d& d,
                                                                        const std::vector<TurningPart>* parts) {
  const Eigen::Matrix<double, 6, 1>* v = turn_about_axis(slip);
  if (v == nullptr) return std::nullopt;
  const Eigen::Vector3d w = v->head<3>(), tau = v->tail<3>() * slip.radius;
  const Eigen::Vector3d point = slip.centre + w.cross(tau) / w.squaredNorm() + d, a = w.normalized();
  std::pair axis{point, a};
  if (!parts) return axis;
  double nearest = std::numeric_limits<double>::infinity();
  for (const TurningPart& part : *parts) {
    const double distance = distance_from_axis(point, part.point + d, part.direction);
    if (std::abs(part.direction.dot(a)) >= std::cos(kSameAxisTilt) && distance <= part.radius && distance < nearest) {
      nearest = distance;
      axis = {part.point + d, part.direction};
    }
  }
  return axis;
}

// The exemplar's repeats about each axis the regions turn about (completion), found once per axis: axes within a
// degree and half an alpha of one another are one.
class RepeatsByAxis {
 public:
  RepeatsByAxis(const Eigen::Matrix3Xd& ep, const Eigen::Matrix3Xd& en, double spacing, double limit)
      : ep_(ep), en_(en), spacing_(spacing), limit_(limit) {}

  // The repeats about part's axis; an axis found before (with any extent) is not searched again.
  const AxialRepeats* about(const TurningPart& part) {
    for (const Entry& e : found_) {
      if (std::abs(e.direction.dot(part.direction)) >= std::cos(M_PI / 180) &&
          distance_from_axis(part.point, e.point, e.direction) <= 0.5 * spacing_)
        return e.repeats ? &*e.repeats : nullptr;
    }
    found_.push_back({part.point, part.direction, axial_repeats(ep_, en_, part, spacing_, limit_)});
    return found_.back().repeats ? &*found_.back().repeats : nullptr;
  }

  std::vector<AxialRepeats> repeats() const {
    std::vector<AxialRepeats> out;
    for (const Entry& e : found_)
      if (e.repeats) out.push_back(*e.repeats);
    return out;
  }

 private:
  struct Entry {
    Eigen::Vector3d point, direction;
    std::optional<AxialRepeats> repeats;
  };
  const Eigen::Matrix3Xd &ep_, &en_;
  double spacing_, limit_;
  std::vector<Entry> found_;
};

// Turns region l's image (inv) to the exemplar's repeats r, band by band (turn_to_repeat, to the nearest repeat however
// far: the phase search reaches search_distance only, and an image it leaves between repeats of a low order puts
// detail beside detail, a barrel's medallion 27 degrees off its place): the used samples of two bands that turn
// differently become two parts, and inv becomes the turn of the band with more of them. Returns the per-band images
// when they differ, else none (inv turned as a whole, or unchanged when no band's turn applies).
constexpr double kAnyPhase = std::numeric_limits<double>::infinity();

std::optional<std::array<Similarity, 2>> turn_to_repeats(const AxialRepeats& r, const Eigen::Matrix3Xd& ep,
                                                         const std::vector<std::int32_t>& used, double spacing,
                                                         Similarity& inv, std::optional<PhaseSplit>& split) {
  std::array<Similarity, 2> band_inv{inv, inv};
  bool any = false;
  for (size_t b = 0; b < 2; ++b)
    if (const auto c = turn_to_repeat(r, r.order[b], inv, kAnyPhase, spacing)) {
      band_inv[b] = c->compose(inv);
      any = true;
    }
  if (!any) return std::nullopt;
  PhaseSplit s{std::vector<std::uint8_t>(used.size()), band_inv};
  size_t above = 0;
  for (size_t i = 0; i < used.size(); ++i) above += s.part[i] = std::uint8_t(band_of(r, ep.col(used[i])));
  inv = band_inv[2 * above >= used.size() ? 1 : 0];
  const bool same = r.order[0] == r.order[1] || above == 0 || above == used.size();
  split.reset();
  if (same) return std::nullopt;
  split = std::move(s);
  return band_inv;
}

// Whether the exemplar's repeats r fix the phase of the image q: q turns about their axis (turn_to_repeat applies with
// either band's order, at any phase).
bool turns_about_repeats(const AxialRepeats& r, const Similarity& q, double spacing) {
  return turn_to_repeat(r, r.order[0], q, kAnyPhase, spacing) || turn_to_repeat(r, r.order[1], q, kAnyPhase, spacing);
}

// For an image q that turns the repeats' axis end over end (a half turn about a line across it: a gear's top face to
// its bottom), q turned first about the axis, within half a period, to the phase whose image best meets the placed
// images (truncated least squares, in 36ths of a period). The image itself may meet them nowhere: from the front, the
// gear's flip carries its seen teeth to the back, where the scan saw nothing, and the refinement left its phase as
// voted, teeth in the gaps (F 0.913). The exemplar's turns by whole periods carry it onto itself, so the image is
// scored where one of them carries it back: the repeat that meets the placed images most. None when q does not
// reverse the axis or the bands turn with different orders.
std::optional<Similarity> flip_phase(const PlacedImages& placed, const AxialRepeats& r, const Similarity& q,
                                     double spacing) {
  const int order = r.order[0];
  if (order < 2 || r.order[1] != order || r.continuous || std::abs(q.scale - 1) > 0.01) return std::nullopt;
  const Eigen::Vector3d a = r.part.direction.normalized();
  if ((q.rotation * a).dot(a) > -std::cos(2 * M_PI / 180)) return std::nullopt;
  const Eigen::Vector3d moved = q.apply(r.part.point) - r.part.point;
  if ((moved - a * a.dot(moved)).norm() > 0.5 * spacing) return std::nullopt;
  const double period = 2 * M_PI / order;
  Similarity back = q;
  Index most = -1;
  for (int k = 0; k < order; ++k) {
    const Similarity c = turn_about(r, -k * period).compose(q);
    if (const Index overlap = placed.overlap(c); overlap > most) {
      most = overlap;
      back = c;
    }
  }
  constexpr int kSteps = 18;  // each way
  const double step = period / (2 * kSteps);
  // The trials are independent: scored in parallel (each sum in its own fixed order), as best_phase_step's are.
  std::array<std::pair<double, Index>, 2 * kSteps + 1> misfit;
  tbb::parallel_for(0, 2 * kSteps + 1, [&](int j) {
    misfit[size_t(j)] = placed.misfit(back.compose(turn_about(r, (j - kSteps) * step)));
  });
  Index pairs = 0;
  for (const auto& m : misfit) pairs = std::max(pairs, m.second);
  if (pairs < 30) return std::nullopt;
  const auto score = [&](int j) {
    return truncated_misfit(misfit[size_t(j)].first, misfit[size_t(j)].second, pairs, placed.limit2());
  };
  int best = 0;
  for (int j = 1; j <= 2 * kSteps; ++j)
    if (score(j) < score(best)) best = j;
  return q.compose(turn_about(r, (best - kSteps) * step));
}

// The exemplar's image with each sample carried by its band's transform.
void place_by_band(PlacedImages& placed, const Eigen::Matrix3Xd& ep, const Eigen::Matrix3Xd& en, const AxialRepeats& r,
                   const std::array<Similarity, 2>& band_inv) {
  Eigen::Matrix3Xd p(3, ep.cols()), n(3, ep.cols());
  for (Index e = 0; e < ep.cols(); ++e) {
    const Similarity& q = band_inv[size_t(band_of(r, ep.col(e)))];
    p.col(e) = q.apply(ep.col(e));
    n.col(e) = q.apply_normal(en.col(e));
  }
  placed.place(p, n);
}

// The unplaced transform whose image overlaps the placed images most, with that overlap.
std::pair<size_t, Index> most_overlapping(const PlacedImages& placed, const std::vector<Similarity>& inv,
                                          const std::vector<Index>& region_size, const std::vector<char>& is_placed) {
  size_t best = inv.size();
  Index best_overlap = -1;
  for (size_t l = 0; l < inv.size(); ++l) {
    if (is_placed[l] || region_size[l] == 0) continue;
    const Index overlap = placed.overlap(inv[l]);
    if (overlap > best_overlap) {
      best_overlap = overlap;
      best = l;
    }
  }
  return {best, best_overlap};
}

// q followed by the translation d: x -> q(x) + d.
Similarity shifted_by(const Eigen::Vector3d& d, const Similarity& q) {
  return Similarity{q.rotation, q.translation + d, q.scale};
}

// q conjugated by the translation d: x -> q(x - d) + d.
Similarity offset_by(const Eigen::Vector3d& d, const Similarity& q) {
  return Similarity{q.rotation, q.translation + d - q.scale * (q.rotation * d), q.scale};
}

// The offset fit's normal equations: d's three columns, then each fitted label's slippable motions.
struct OffsetSystem {
  Eigen::MatrixXd A;
  Eigen::VectorXd b;
  Index pairs = 0;
  double r2 = 0;  // the pairs' squared residuals
};

// Adds the point-to-plane pairs of the image under q (the label's transform and phase, conjugated by the offset d)
// onto the exemplar: moving d by delta moves the image by (I - s R) delta, and the label's motion k (column first + k)
// by its field, about the slippage's centre moved by d (the phase acts inside the conjugation).
void add_offset_pairs(const PlacedImages& exemplar, const Similarity& q, const Slippage& slip, const Eigen::Vector3d& d,
                      Index first, OffsetSystem& sys) {
  const Eigen::Matrix3d M = Eigen::Matrix3d::Identity() - q.scale * q.rotation;
  const Index m = Index(slip.motions.size());
  const Index at[5] = {0, 1, 2, first, first + 1};
  exemplar.for_each_pair(q, [&](const Eigen::Vector3d& p, const Eigen::Vector3d& y, const Eigen::Vector3d& n) {
    Eigen::Matrix<double, 5, 1> g;
    g.head<3>() = M.transpose() * n;
    Eigen::Matrix<double, 6, 1> twist;
    twist << (p - d - slip.centre).cross(n), slip.radius * n;
    for (Index k = 0; k < m; ++k) g(3 + k) = twist.dot(slip.motions[size_t(k)]);
    const double r = n.dot(p - y);
    sys.r2 += r * r;
    for (Index u = 0; u < 3 + m; ++u) {
      sys.b(at[u]) -= g(u) * r;
      for (Index v = 0; v < 3 + m; ++v) sys.A(at[u], at[v]) += g(u) * g(v);
    }
    ++sys.pairs;
  });
}

// The least-squares step of the offset fit, with d only along the directions the pairs fix (eigenvalues of d's Schur
// complement at least 2% of the largest, as for slippage): a box's quarter turns see nothing of d along their axis.
Eigen::VectorXd offset_step(OffsetSystem& sys, const Eigen::Matrix3Xd& relief) {
  Eigen::MatrixXd& A = sys.A;
  const Index cols = A.cols(), m = cols - 3;
  A.diagonal().array() += 1e-6 * A.trace() / double(cols) + 1e-300;
  Eigen::Matrix3d S = A.topLeftCorner(3, 3);
  if (m > 0) S -= A.topRightCorner(3, m) * A.bottomRightCorner(m, m).ldlt().solve(A.bottomLeftCorner(m, 3));
  Eigen::Matrix3Xd fixed(3, 0);
  if (relief.cols() > 0) {
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(relief.transpose() * S * relief);
    const Index k = relief.cols();
    for (Index j = 0; j < k; ++j)
      if (eig.eigenvalues()(j) >= 0.02 * eig.eigenvalues()(k - 1)) {
        fixed.conservativeResize(3, fixed.cols() + 1);
        fixed.col(fixed.cols() - 1) = relief * eig.eigenvectors().col(j);
      }
  }
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(cols, fixed.cols() + m);
  B.topLeftCorner(3, fixed.cols()) = fixed;
  if (m > 0) B.bottomRightCorner(m, m).setIdentity();
  return B * (B.transpose() * A * B).ldlt().solve(B.transpose() * sys.b);
}

// A fitted registration offset, with the misfit of the images it was fitted to.
struct OffsetFit {
  Eigen::Vector3d d = Eigen::Vector3d::Zero();
  double r2 = 0;    // the fitted images' squared point-to-plane residuals
  Index pairs = 0;  // and their pairs
};

// The exemplar's offset from the template: one translation d, shared by every label, that the relief's pull left in
// its registration (a gear seen from one side registers towards its teeth, 3 cm off the plain annulus's axis). The
// template's transforms hold about the template's frame, so each label's image must be its transform conjugated by d
// (moved by (I - s R_l) d). Each label's own free fit would find that too, but on a small overlap it can end a tooth
// off instead (the gear), or follow faces the scanner did not see (the crate from below): one d seen by every label
// is fixed better. Fitted jointly with each label's phase along its slippable motions (which d must not absorb), by
// point-to-plane ICP onto the exemplar of the images of the turned transforms that land mostly on the template (a
// leg's own turn carries the table's top off it), whether a region took them or not: d is the exemplar's, not the
// labelling's (a crate seen from a low side takes only the identity and a half turn, whose image meets the exemplar
// nowhere; the quarter turns carry one seen face onto the other). With fewer than two, none. d moves only within
// `relief`'s span (relief_directions): with an empty basis it stays zero and only the phases are fitted, the misfit to
// compare with.
OffsetFit registration_offset(const PlacedImages& exemplar, const std::vector<Similarity>& inv,
                              const std::vector<std::uint8_t>& on_template, const std::vector<Slippage>& slips,
                              int iterations, const Eigen::Matrix3Xd& relief) {
  std::vector<size_t> turned;  // the fitted transforms
  std::vector<Index> first;    // per fitted transform: the column of its first motion
  Index cols = 3;
  for (size_t l = 0; l < inv.size(); ++l)
    if (on_template[l] && rotation_angle(inv[l].rotation) > 1e-3) {
      turned.push_back(l);
      first.push_back(cols);
      cols += Index(slips[l].motions.size());
    }
  if (turned.size() < 2) return {};  // one turn's image fixes d only with its own phase: its free fit finds as much
  Eigen::Vector3d d = Eigen::Vector3d::Zero();
  std::vector<Similarity> phase(inv.size());
  OffsetSystem sys;
  for (int it = 0; it <= iterations; ++it) {
    sys = {Eigen::MatrixXd::Zero(cols, cols), Eigen::VectorXd::Zero(cols)};
    for (size_t i = 0; i < turned.size(); ++i)
      add_offset_pairs(exemplar, offset_by(d, phase[turned[i]].compose(inv[turned[i]])), slips[turned[i]], d, first[i],
                       sys);
    if (sys.pairs < 30 || it == iterations) break;
    const Eigen::VectorXd x = offset_step(sys, relief);
    if (!x.allFinite()) break;
    d += x.head<3>();
    for (size_t i = 0; i < turned.size(); ++i) {
      const Slippage& slip = slips[turned[i]];
      Eigen::Matrix<double, 6, 1> v = Eigen::Matrix<double, 6, 1>::Zero();
      for (size_t k = 0; k < slip.motions.size(); ++k) v += x(first[i] + Index(k)) * slip.motions[k];
      phase[turned[i]] = motion(v, 1.0, slip.centre, slip.radius).compose(phase[turned[i]]);
    }
  }
  return {d, sys.r2, sys.pairs};
}

// The exemplar's heights over the template: per exemplar sample whose normal is within 37 degrees of (or against) the
// nearest target sample's (not off a tooth's flank, or an edge's other face), that target sample's normal n and the
// exemplar sample's height h above its plane. With the directions the relief can pull the registration along
// (eigenvectors of sum h^2 n n^T with eigenvalues at least 10% of the largest): a gear's teeth stand out of its wall,
// sideways; its plain top and bottom pull nothing, and the offset stays zero along its axis (seen from the front, the
// offset fit's flips put 5 mm there, from the edges' pairs: 2% of the largest).
struct ExemplarRelief {
  Eigen::Matrix3Xd normal = Eigen::Matrix3Xd(3, 0);
  Eigen::VectorXd height;
  Eigen::Matrix3Xd directions = Eigen::Matrix3Xd(3, 0);
  std::vector<std::uint8_t> raised;  // per exemplar sample: off the nearest target sample's plane by kPlainHeight
};

Eigen::Matrix3Xd relief_directions(const Eigen::Matrix3Xd& normal, const Eigen::VectorXd& height) {
  Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
  for (Index e = 0; e < height.size(); ++e) M += height(e) * height(e) * normal.col(e) * normal.col(e).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(M);
  Eigen::Matrix3Xd out(3, 0);
  for (Index k = 0; k < 3; ++k)
    if (eig.eigenvalues()(2) > 0 && eig.eigenvalues()(k) >= 0.1 * eig.eigenvalues()(2)) {
      out.conservativeResize(3, out.cols() + 1);
      out.col(out.cols() - 1) = eig.eigenvectors().col(k);
    }
  return out;
}

ExemplarRelief exemplar_relief(const Eigen::Matrix3Xd& ep, const Eigen::Matrix3Xd& en, const PointSet& T,
                               const KdTree& target_tree, double spacing) {
  ExemplarRelief r;
  r.normal.resize(3, ep.cols());
  r.height.resize(ep.cols());
  r.raised.assign(size_t(ep.cols()), 0);
  Index kept = 0;
  for (Index e = 0; e < ep.cols(); ++e) {
    std::int32_t t;
    double d2;
    target_tree.knn(ep.col(e), 1, &t, &d2);
    const Eigen::Vector3d n = T.normals().col(t);
    r.raised[size_t(e)] = std::abs(n.dot(ep.col(e) - T.positions().col(t))) > kPlainHeight * spacing;
    if (std::abs(n.dot(en.col(e))) < 0.8) continue;
    r.normal.col(kept) = n;
    r.height(kept++) = n.dot(ep.col(e) - T.positions().col(t));
  }
  r.normal.conservativeResize(3, kept);
  r.height.conservativeResize(kept);
  r.directions = relief_directions(r.normal, r.height);
  return r;
}

// Whether offset d would take the exemplar's plain part off the template: of the exemplar samples whose template
// normal faces along d (within 60 degrees), at least three quarters lie on the template as registered (within
// kPlainHeight alpha) and fewer than half as many would, moved by d. A relief's pull leaves the plain part off by d; a
// part that sits on the template says the registration is right there. A ring seen from above sits on its torus (95%
// of those samples), and ICP had turned it about its axis: the offset fit to its flipped underside, meeting the
// exemplar only in a thin band, found 7 mm upward (0.3% would sit on the template), which lifted the underside 1.4 cm.
// A ribbed box's faces are half ribs (54% on its box seen from below, 1% moved), and there the offset, 1.25 alpha
// across, lifts F 0.891 -> 0.921: kept.
bool takes_plain_part_off(const ExemplarRelief& relief, const Eigen::Vector3d& d, double spacing) {
  const Eigen::Vector3d along = d.normalized();
  const double plain = kPlainHeight * spacing;
  Index facing = 0, on = 0, on_moved = 0;
  for (Index e = 0; e < relief.height.size(); ++e) {
    const Eigen::Vector3d n = relief.normal.col(e);
    if (std::abs(n.dot(along)) < 0.5) continue;
    ++facing;
    on += std::abs(relief.height(e)) < plain;
    on_moved += std::abs(relief.height(e) - n.dot(d)) < plain;
  }
  return facing > 0 && 4 * on >= 3 * facing && 2 * on_moved < on;
}

// The registration offset the refinement applies: registration_offset's, where it is at least kLeastOffset alpha and
// explains at least a third of the labels' misfit (truncated, against the same fit with d held at zero). The fluted
// column seen obliquely from behind registers 6.4 mm outward, pulled towards the template's wall from its flutes'
// bottoms, and the fit finds 4.2 mm of it (0.42 alpha). A turn by 157.5 degrees doubles that on the far side, and
// that label's own free fit, on its small overlap, ran off the template: F 0.959 with the 1.25 alpha this threshold
// was, 1.000 now. Where the exemplar's detail does not repeat under the template's turns (Vase-Lion's lion heads),
// the fit only moves misfit about: 0.98-1.84 of it, against 0.03-0.07 on the gear and 0.36-0.51 on the crate seen
// from above and below. Nor where it would take the exemplar's plain part off the template (takes_plain_part_off): a
// fit that meets the exemplar only in a thin band can find an offset by overlapping more of it, which the truncated
// misfit rewards.
Eigen::Vector3d applied_offset(const PlacedImages& exemplar, const std::vector<Similarity>& inv,
                               const std::vector<std::uint8_t>& on_template, const std::vector<Slippage>& slips,
                               const ExemplarRelief& relief, double spacing, const SynthesisOptions& o) {
  const double limit2 = exemplar.limit2();
  const OffsetFit with = registration_offset(exemplar, inv, on_template, slips, o.refine_iterations, relief.directions);
  if (with.d.norm() < kLeastOffset * spacing || takes_plain_part_off(relief, with.d, spacing))
    return Eigen::Vector3d::Zero();
  const OffsetFit without =
      registration_offset(exemplar, inv, on_template, slips, o.refine_iterations, Eigen::Matrix3Xd(3, 0));
  const Index most = std::max(with.pairs, without.pairs);
  const bool explains = 3 * truncated_misfit(with.r2, with.pairs, most, limit2) <=
                        2 * truncated_misfit(without.r2, without.pairs, most, limit2);
  return explains ? with.d : Eigen::Vector3d::Zero();
}

// The share of a label's carried exemplar samples (`used`) whose source samples an inverse carries onto the template.
using LandedShare =
    std::function<double(const Similarity& inv, const std::vector<std::int32_t>& used, bool within_alpha)>;

// A rigid registration that moves no exemplar sample this many alpha has the scan stand on the template as given.
constexpr double kBarelyMoved = 0.5;
// The share of the template's samples (every fourth) a transform lays within an alpha of the template for it to be
// one of the template's own symmetries.
constexpr double kOwnSymmetry = 0.9;

// Whether inv (source -> target) lays the template on itself (kOwnSymmetry): a box's quarter turn, not a table leg's
// slide down the leg.
bool template_symmetry(const PointSet& S, const KdTree& target_tree, const Similarity& inv, double spacing) {
  Index on = 0, tried = 0;
  for (Index i = 0; i < S.size(); i += 4, ++tried) {
    std::int32_t t;
    double d2;
    target_tree.knn(inv.apply(S.positions().col(i)), 1, &t, &d2);
    on += d2 <= spacing * spacing;
  }
  return tried > 0 && double(on) >= kOwnSymmetry * double(tried);
}

// Per label: whether the template pins its images as it pins a scan given on it (`as_given` in `refinement`, landing
// counted within an alpha): the registration barely moved the scan (kBarelyMoved), the template fits it, and the
// label's transform is one of the template's own symmetries. Its image then already stands where the template says,
// and a free fit to the images placed before it follows only their misfit. The held-out studded box seen from the
// side, moved 0.25 alpha by ICP: its quarter turns, fitted to the grazing studs the scan saw on the neighbouring faces,
// turned 1.6-2.9 degrees and slid 1.3-2.0 cm, 0.77-0.86 of them landing on the box (F 0.884, under template
// blending's 0.944; 0.978 pinned). A scan given on its template was pinned so already; this extends it to a scan ICP
// moved less than it can tell. Where the scan's detail does not follow the template (the Vase-Lion in its body of
// revolution, 83-90% of it off the body) nothing is pinned, nor a transform the template does not lie on itself
// under: the table seen from above keeps the free fit of 9 alpha that its slide down a leg needs (unseen-detail 0.73).
std::vector<std::uint8_t> pinned_symmetries(const SynthesisInputs& in, const KdTree& target_tree,
                                            const std::vector<Similarity>& inverse,
                                            const std::vector<Index>& region_size, const ExemplarRelief& relief,
                                            double spacing) {
  std::vector<std::uint8_t> pinned(inverse.size(), 0);
  if (!in.covered || in.scan_as_given || !template_fits_exemplar(relief.raised) ||
      largest_displacement(in.exemplar.positions(), in.exemplar_to_working) >= kBarelyMoved * spacing)
    return pinned;
  for (size_t l = 0; l < inverse.size(); ++l)
    pinned[l] = region_size[l] > 0 && template_symmetry(in.source, target_tree, inverse[l], spacing);
  return pinned;
}

// Per label: whether its image is plain (kPlainHeight): the exemplar samples it carries into its region, not its ring,
// land on the template under its labelled `inverse` (at least 30 of them, and 1% spared): no relief, and no misfit
// for the refinement to correct. Completion only (`ep` in the template's frame).
std::vector<std::uint8_t> plain_images(const Eigen::Matrix3Xd& ep, const PointSet& T, const KdTree& target_tree,
                                       const std::vector<Similarity>& inverse,
                                       const std::vector<std::vector<std::int32_t>>& used,
                                       const std::vector<std::vector<std::uint8_t>>& in_ring, double spacing) {
  std::vector<std::uint8_t> plain(used.size(), 0);
  for (size_t l = 0; l < used.size(); ++l) {
    Index region = 0, standing = 0;
    for (size_t i = 0; i < used[l].size(); ++i) {
      if (in_ring[l][i]) continue;
      std::int32_t t;
      double d2;
      const Eigen::Vector3d p = inverse[l].apply(ep.col(used[l][i]));
      target_tree.knn(p, 1, &t, &d2);
      ++region;
      standing += std::abs(T.normals().col(t).dot(p - T.positions().col(t))) > kPlainHeight * spacing;
    }
    plain[l] = region >= 30 && 100 * standing <= region;
  }
  return plain;
}

// Refines each used transform's inverse (source -> target) against the exemplar images already placed: the anchor
// (the exemplar itself, or the biggest region's image) first, then the most overlapping image each time, corrected
// in phase along its slippable motions (`slips`, per label) and by rigid point-to-plane ICP on the overlap. With the
// exemplar as the anchor, every transform is first conjugated by the exemplar's registration offset (none for a scan
// `as_given`, which no registration moved: the offset undoes the relief's pull on a registration, and fitted to the
// table in its own pose seen from the side it found 1.55 cm across the seen legs, which laid the turned images of the
// legs' far halves onto their near halves: F 0.793, 0.981 without); where that is
// at least kTruncatingOffset, the refinement's candidates are scored by truncated least squares (see `refinement`). The
// slippable motions stay about the template's centres: moved by the offset too, as the images' axes are, they were
// neutral on the sweep but lost the gear seen from (-1, -0.3, 0.1), F 0.938 -> 0.833 (one label's phase 11.7 degrees,
// not 2.9, and the labels fitted after it followed it). A plain image (`plain`: a box's plain lid flipped onto its
// plain floor, lying on the template) has nothing to fit: only its ring overlaps detail, and fitting that slid the
// ribbed box's flipped lid 1.5 cm along its floor, the sides' strips with it (F 0.909); it keeps the analogy's
// transform. An image off the template (a blob's, 0.6 alpha off) is not plain: its shape fits it back.
void refine(const Eigen::Matrix3Xd& ep, const Eigen::Matrix3Xd& en, const std::vector<Index>& region_size,
            const std::vector<std::vector<std::int32_t>>& used, const std::vector<std::uint8_t>* on_template,
            const ExemplarRelief& relief, double spacing, const SynthesisOptions& o, const std::vector<Slippage>& slips,
            std::vector<Similarity>& inv, std::vector<std::optional<PhaseSplit>>& splits,
            const std::vector<TurningPart>* turning_parts, const LandedShare& landed_share, bool as_given,
            const std::optional<Eigen::Vector3d>& up, const std::vector<std::uint8_t>& plain,
            const std::vector<std::uint8_t>& pinned, Synthesis& out) {
  const size_t L = inv.size();
  out.refinement_deg.assign(L, 0.0);
  out.refinement_shift.assign(L, 0.0);
  out.second_phase_deg.assign(L, 0.0);
  if (o.refine_iterations <= 0) return;
  std::vector<char> is_placed(L, 0);
  PlacedImages placed(ep, en, std::pow(o.refine_distance * spacing, 2));
  size_t remaining = 0;
  for (size_t l = 0; l < L; ++l) remaining += region_size[l] > 0;
  if (on_template) {  // the exemplar is the anchor
    placed.place(ep, en);
    placed.index();
    if (!as_given) out.registration_offset = applied_offset(placed, inv, *on_template, slips, relief, spacing, o);
    for (Similarity& q : inv) q = offset_by(out.registration_offset, q);
  } else if (remaining > 0) {
    const size_t biggest = size_t(std::max_element(region_size.begin(), region_size.end()) - region_size.begin());
    placed.place(inv[biggest]);
    is_placed[biggest] = 1;
    --remaining;
  }
  const bool truncated = out.registration_offset.norm() >= kTruncatingOffset * spacing;
  RepeatsByAxis repeats(ep, en, spacing, o.refine_distance * spacing);
  // The template's own axes place the regions' turns where the template fits the exemplar (a vase's plain cylinder,
  // 96-99% of the scan off it, keeps its regions' axes: taken from the template's, it lost 0.02 F from three views).
  const std::vector<TurningPart>* own_axes = template_fits_exemplar(relief.raised) ? turning_parts : nullptr;
  for (; remaining > 0; --remaining) {
    placed.index();
    const auto [best, best_overlap] = most_overlapping(placed, inv, region_size, is_placed);
    is_placed[best] = 1;
    const Slippage& slip = slips[best];
    const Similarity labelled = inv[best];
    // Completion: the exemplar's own repeats about the axis fix the phase where they are clear.
    const auto axis = on_template && o.repeats ? turning_axis(slip, out.registration_offset, own_axes) : std::nullopt;
    const AxialRepeats* r = axis ? repeats.about({axis->first, axis->second}) : nullptr;
    if (const auto flipped = r ? flip_phase(placed, *r, labelled, spacing) : std::nullopt) {
      inv[best] = *flipped;
    } else if (!plain[best] && best_overlap >= std::max<Index>(30, ep.cols() / 20)) {  // too little says nothing
      const auto landed = [&, best = best](const Similarity& image, bool within_alpha) {
        return landed_share(image, used[best], within_alpha || pinned[best]);
      };
      const bool overturns = up && turns_end_over_end(inv[best], up->normalized());
      inv[best] = refinement(placed, inv[best], slip, spacing, o, truncated, on_template && (as_given || pinned[best]),
                             overturns, landed, relief.raised)
                      .compose(inv[best]);
      splits[best] = phase_split(placed, ep, used[best], inv[best], slip, spacing, o);
      // The refinement can turn an image about a point off the axis to fit a small overlap (the gear from the front:
      // 122.5 to 111.4 degrees, its axis moved 7.6 mm, teeth 3.4 degrees off on the far side); the repeats then fix
      // the labelled transform's phase instead (126 degrees).
      if (r && !turns_about_repeats(*r, inv[best], spacing) && turns_about_repeats(*r, labelled, spacing)) {
        inv[best] = labelled;
        splits[best].reset();
      }
    }
    const auto band_inv = r ? turn_to_repeats(*r, ep, used[best], spacing, inv[best], splits[best]) : std::nullopt;
    if (splits[best]) {
      const auto& inv2 = splits[best]->inv;
      out.second_phase_deg[best] = rotation_angle(inv2[1].rotation * inv2[0].rotation.transpose()) * 180 / M_PI;
    }
    const Similarity c = inv[best].compose(labelled.inverse());
    out.refinement_deg[best] = rotation_angle(c.rotation) * 180 / M_PI;
    out.refinement_shift[best] = c.translation.norm();
    if (band_inv)
      place_by_band(placed, ep, en, *r, *band_inv);
    else
      placed.place(inv[best]);
  }
  if (on_template && o.repeats && turning_parts)
    for (TurningPart part : *turning_parts) {  // the template's own axes: a body of revolution, a table's legs
      part.point += out.registration_offset;
      repeats.about(part);
    }
  out.repeats = repeats.repeats();
}

// The points as the columns of a matrix.
Eigen::Matrix3Xd as_columns(const std::vector<Eigen::Vector3d>& points) {
  Eigen::Matrix3Xd m(3, Index(points.size()));
  for (size_t i = 0; i < points.size(); ++i) m.col(Index(i)) = points[i];
  return m;
}

// Per target sample: whether a carried source sample landed within `distance` of it.
std::vector<std::uint8_t> reached_targets(const std::vector<Eigen::Vector3d>& landed, const PointSet& T,
                                          double distance) {
  std::vector<std::uint8_t> reached(size_t(T.size()), 0);
  if (landed.empty()) return reached;
  const Eigen::Matrix3Xd landing = as_columns(landed);
  KdTree tree;
  tree.build(landing);
  std::vector<std::int32_t> nearest;
  std::vector<double> d2;
  nearest_each(tree, T.positions(), nearest, d2);
  for (Index t = 0; t < T.size(); ++t) reached[size_t(t)] = d2[size_t(t)] <= distance * distance;
  return reached;
}

// The target sample nearest where `inv` carries exemplar sample e's source sample, if within `reach` (else -1).
std::int32_t landing_target(const SynthesisInputs& in, const Similarity& inv, const KdTree& target_tree, double reach,
                            Index e) {
  const auto s = in.exemplar_source[size_t(e)];
  if (s < 0) return -1;
  std::int32_t t;
  double d2;
  target_tree.knn(inv.apply(in.source.positions().col(s)), 1, &t, &d2);
  return d2 <= reach * reach ? t : -1;
}

// Per exemplar sample: landing_target.
std::vector<std::int32_t> landing_targets(const SynthesisInputs& in, const Similarity& inv, const KdTree& target_tree,
                                          double reach) {
  std::vector<std::int32_t> nearest(size_t(in.exemplar.size()), -1);
  tbb::parallel_for(Index(0), in.exemplar.size(),
                    [&](Index e) { nearest[size_t(e)] = landing_target(in, inv, target_tree, reach, e); });
  return nearest;
}

// The share of `used` (exemplar samples) whose source sample `inv` carries within `reach` of a target sample.
double landed_share(const SynthesisInputs& in, const KdTree& target_tree, double reach, const Similarity& inv,
                    const std::vector<std::int32_t>& used) {
  const auto landed = std::count_if(
      used.begin(), used.end(), [&](std::int32_t e) { return landing_target(in, inv, target_tree, reach, e) >= 0; });
  return used.empty() ? 0.0 : double(landed) / double(used.size());
}

// Per exemplar sample: the flag in `on` of the target sample nearest where `inv` carries its source sample, if within
// `reach` (else 0). Returns whether any is non-zero.
bool landing_on(const SynthesisInputs& in, const Similarity& inv, const KdTree& target_tree, double reach,
                const std::vector<std::uint8_t>& on, std::vector<std::uint8_t>& hit) {
  const std::vector<std::int32_t> nearest = landing_targets(in, inv, target_tree, reach);
  for (size_t e = 0; e < nearest.size(); ++e) hit[e] = nearest[e] >= 0 ? on[size_t(nearest[e])] : std::uint8_t(0);
  return std::any_of(hit.begin(), hit.end(), [](std::uint8_t h) { return h != 0; });
}

// The slippable motions of region `label` that its labelled transform's image may take: those along which the
// template also slides where the image lands (the nearest target sample within `reach` of where it carries each
// exemplar sample's source). A box's flip labels a strip of two walls, which slide up and down, but it carries the lid
// onto the floor, which does not; the crate seen from above: the phase search slid that flip 2.7 cm down its walls,
// taking the floor with it, and the floor's own flip was fitted onto that image (F 0.73). An image that lands mostly
// off the template (a leg's own turn carries the table top off the table) moves only its region: its motions stay.
// A transform no region took (a candidate the registration offset is fitted with) slides as the template does where
// its image lands. `lands_on_template`: whether at least half the exemplar's source samples land within `reach` of the
// template.
Slippage image_slippage(const SynthesisInputs& in, const Similarity& inv, const KdTree& target_tree, double reach,
                        int label, std::uint8_t& lands_on_template) {
  std::vector<std::uint8_t> footprint(in.labels.size());
  for (size_t t = 0; t < footprint.size(); ++t) footprint[t] = in.labels[t] == label;
  const std::vector<std::int32_t> nearest = landing_targets(in, inv, target_tree, reach);
  const auto landed = std::count_if(nearest.begin(), nearest.end(), [](std::int32_t t) { return t >= 0; });
  lands_on_template = 2 * landed >= std::ssize(nearest);
  if (std::find(footprint.begin(), footprint.end(), 1) == footprint.end()) {  // no region: the landing's motions
    for (const std::int32_t t : nearest)
      if (t >= 0) footprint[size_t(t)] = 1;
    return slippable_motions(in.target, footprint);
  }
  const Slippage slip = slippable_motions(in.target, footprint);  // the region's
  if (slip.motions.empty() || !lands_on_template) return slip;
  for (const std::int32_t t : nearest)
    if (t >= 0) footprint[size_t(t)] = 1;
  return sliding_also_on(slip, in.target, footprint);
}

// Per target sample: whether the output points `p` (moved by the exemplar's registration `offset`, as the images are)
// lie over it (kOver), under it in a sunk relief (kUnder), or neither (kBare). synthesize copies the target where a
// sample is bare, or over but reached by no landed source sample. Reaching judges where source samples land, which a
// correspondence that gives few exemplar samples to a face leaves sparse; this judges the output itself: the crate
// seen from the front, its lid scanned in stripes at a grazing angle, flipped onto the floor as stripes 2-3 alpha
// apart, which reaching (4 alpha) let through: 56% of the floor missed.
// - Over: one of its 32 nearest lies within `across` of its normal line and `along` of its plane; or the median height
//   above its plane of those within `along` is more than `plain`, so that a copy of the plain template would be a pit
//   in the relief (the gear's teeth).
// - Under: a relief sunk deeper than `along`, at most kSunkRelief times that, has a point within `across` of the normal
//   line (on either side) that faces the same way (a thin plate's other face does not). A real pillar's panels lie
//   5-11 alpha behind its bounding box, where the correspondence gives them few source samples: copies of the box's
//   faces were laid over their images and hid them. Near a frame on the template the 32 nearest points are the
//   frame's, so the line is probed step by step.
enum : std::uint8_t { kBare = 0, kOver = 1, kUnder = 2 };  // overlaid_targets' answers

bool relief_on_normal_line(const KdTree& tree, const Eigen::Matrix3Xd& points, const std::vector<Eigen::Vector3d>& n,
                           const Eigen::Vector3d& x, const Eigen::Vector3d& normal, double across, double along) {
  constexpr double kSunkRelief = 3.0, kSameWay = 0.5;
  constexpr int kNearest = 4;
  std::int32_t index[kNearest];
  double d2[kNearest];
  for (const double side : {-1.0, 1.0})
    for (double depth = along + 0.5 * across; depth < kSunkRelief * along + across; depth += across) {
      const int k = tree.knn(x + side * depth * normal, kNearest, index, d2);
      for (int j = 0; j < k; ++j) {
        const Eigen::Vector3d v = points.col(index[j]) - x;
        const double h = std::abs(normal.dot(v));
        if (h > along && h <= kSunkRelief * along && v.squaredNorm() - h * h <= across * across &&
            normal.dot(n[size_t(index[j])]) > kSameWay)
          return true;
      }
    }
  return false;
}

std::vector<std::uint8_t> overlaid_targets(const std::vector<Eigen::Vector3d>& p, const std::vector<Eigen::Vector3d>& n,
                                           const PointSet& T, const Eigen::Vector3d& offset, double across,
                                           double along, double plain) {
  std::vector<std::uint8_t> over(size_t(T.size()), kBare);
  if (p.empty()) return over;
  const Eigen::Matrix3Xd points = as_columns(p);
  KdTree tree;
  tree.build(points);
  tbb::parallel_for(Index(0), T.size(), [&](Index t) {
    constexpr int kNearest = 32;
    std::int32_t index[kNearest];
    double d2[kNearest], height[kNearest];
    const Eigen::Vector3d x = T.positions().col(t) + offset, normal = T.normals().col(t);
    const int k = tree.knn(x, kNearest, index, d2);
    int m = 0;
    for (int j = 0; j < k; ++j) {
      const double h = std::abs(normal.dot(points.col(index[j]) - x));
      if (h > along) continue;
      if (d2[j] - h * h <= across * across) {
        over[size_t(t)] = kOver;
        return;
      }
      height[m++] = h;
    }
    std::nth_element(height, height + m / 2, height + m);
    if (m > 0 && height[m / 2] > plain)
      over[size_t(t)] = kOver;
    else if (relief_on_normal_line(tree, points, n, x, normal, across, along))
      over[size_t(t)] = kUnder;
  });
  return over;
}

// How far x stands out of the target T along the normal of its nearest sample (negative: under it).
double height_over_template(const PointSet& T, const KdTree& target_tree, const Eigen::Vector3d& x) {
  std::int32_t j;
  double d2;
  target_tree.knn(x, 1, &j, &d2);
  return T.normals().col(j).dot(x - T.positions().col(j));
}

// Grows `marked` through the samples' 8 nearest neighbours (`tree` holds `points`) closer than `link`, to every sample
// standing more than `foot` out (`over`), marking them kUnrepeatedFoot: a part standing out (a spout) down to where it
// meets the body.
void grow_to_foot(const Eigen::Matrix3Xd& points, const KdTree& tree, const std::vector<double>& over, double foot,
                  double link, std::vector<std::uint8_t>& marked) {
  constexpr int k = 8;
  const std::vector<std::int32_t> graph = knn_graph(tree, points, k);
  std::vector<Index> stack;
  for (Index e = 0; e < points.cols(); ++e)
    if (marked[size_t(e)]) stack.push_back(e);
  while (!stack.empty()) {
    const Index e = stack.back();
    stack.pop_back();
    for (int j = 0; j < k; ++j) {
      const std::int32_t n = graph[size_t(e * k + j)];
      if (n < 0 || marked[size_t(n)] || over[size_t(n)] <= foot) continue;
      if ((points.col(n) - points.col(e)).squaredNorm() >= link * link) continue;
      marked[size_t(n)] = kUnrepeatedFoot;
      stack.push_back(n);
    }
  }
}

// Completion, when the scan repeats about no axis (no repeats found): per exemplar sample, 1 where it stands more than
// `height` out of the template, along the nearest template sample's normal (moved by the registration `offset`; sunk
// relief, a pillar's panels behind its box, does not count). Such relief is the scan's own, not a style that
// repeats (a teapot's spout 20 alpha off its body, seen from below), and no turn carries it (CarriedRelief): turned
// about the body, it put spouts where the teapot has none (F 0.902, below template blending's 0.958). Its foot, the
// samples linked to it (closer than `link`) standing more than `foot` out (grow_to_foot), is marked too and carried
// by quarter and half turns only (turn_carries_unrepeated): seen from straight below, the spout's and handle's roots,
// under `height`, were turned round the body by turns of 100-160 degrees, in arcs over a hole the copy rule left them
// (F 0.922; template blending 0.960). Empty when the scan repeats or in transfer.
std::vector<std::uint8_t> unrepeated_relief(const SynthesisInputs& in, const Eigen::Matrix3Xd& ep,
                                            const KdTree& exemplar_tree, const Eigen::Vector3d& offset,
                                            const KdTree& target_tree, const Synthesis& out, double height, double foot,
                                            double link) {
  if (!in.covered || !out.repeats.empty()) return {};
  std::vector<double> over(size_t(ep.cols()));
  tbb::parallel_for(Index(0), ep.cols(), [&](Index e) {
    over[size_t(e)] = height_over_template(in.target, target_tree, ep.col(e) - offset);
  });
  std::vector<std::uint8_t> off(size_t(ep.cols()), 0);
  for (Index e = 0; e < ep.cols(); ++e) off[size_t(e)] = over[size_t(e)] > height;
  grow_to_foot(ep, exemplar_tree, over, foot, link, off);
  return off;
}

// Completion, where the scan repeats about one axis in two bands of different orders across a cut (a vase's ring of 16
// beads at its foot, its 12 flutes above): per exemplar sample, 1 + its band where it stands more than `height` out of
// the template (moved by the registration `offset`), else 0. Empty otherwise. The bands hold different detail, and an
// image carries a band's relief only into that band (CarriedRelief): the vase seen from nearly straight below, in its
// mesh template, had three flips turn the scan end over end about a height of 0.375, which put the foot's beads on
// the shoulder, where the vase has none (2756 output points 1.5-4 cm off it; F 0.961, template blending 0.965).
std::vector<std::uint8_t> banded_relief(const SynthesisInputs& in, const Eigen::Matrix3Xd& ep,
                                        const Eigen::Vector3d& offset, const KdTree& target_tree, const Synthesis& out,
                                        double height) {
  if (!in.covered || out.repeats.size() != 1 || out.repeats[0].order[0] == out.repeats[0].order[1]) return {};
  const AxialRepeats& r = out.repeats[0];
  std::vector<std::uint8_t> band(size_t(ep.cols()), 0);
  tbb::parallel_for(Index(0), ep.cols(), [&](Index e) {
    const bool relief = height_over_template(in.target, target_tree, ep.col(e) - offset) > height;
    if (relief && r.part.contains(ep.col(e))) band[size_t(e)] = std::uint8_t(1 + band_of(r, ep.col(e)));
  });
  return band;
}

// Whether a turn carries an unrepeated sample (unrepeated_relief): a part's foot (2) only by a quarter or half turn,
// within 5 degrees (eq. 9's kappa pi / 2, the analogy's guess for a scan that repeats about nothing: a vase's knob in
// front has one behind), the part above it (1) by no turn.
bool turn_carries_unrepeated(const Similarity& inv, std::uint8_t unrepeated) {
  constexpr double kDegree = M_PI / 180;
  const double angle = rotation_angle(inv.rotation);
  if (angle <= kDegree) return true;
  return unrepeated == kUnrepeatedFoot && std::abs(std::remainder(angle, M_PI / 2)) < 5 * kDegree;
}

// Which exemplar samples an image carries (completion): every sample, but relief the scan shows once only where the
// image does not turn (unrepeated_relief), and a band's relief only into that band (banded_relief).
struct CarriedRelief {
  std::vector<std::uint8_t> unrepeated, banded;
  std::optional<AxialRepeats> bands;  // the repeats whose bands `banded` holds (a copy: out.repeats may grow)

  bool carries(const Similarity& inv, const Eigen::Matrix3Xd& ep, Index e) const {
    if (!unrepeated.empty() && unrepeated[size_t(e)] && !turn_carries_unrepeated(inv, unrepeated[size_t(e)]))
      return false;
    if (banded.empty() || !banded[size_t(e)]) return true;
    const Eigen::Vector3d x = inv.apply(ep.col(e));
    return !bands->part.contains(x) || band_of(*bands, x) + 1 == banded[size_t(e)];
  }
};

CarriedRelief carried_relief(const SynthesisInputs& in, const Eigen::Matrix3Xd& ep, const KdTree& exemplar_tree,
                             const Eigen::Vector3d& offset, const KdTree& target_tree, const Synthesis& out,
                             double spacing) {
  constexpr double kRelief = 1.0;  // how far out of the template, in alpha, a sample stands to be relief
  CarriedRelief c{unrepeated_relief(in, ep, exemplar_tree, offset, target_tree, out, kUnrepeatedRelief * spacing,
                                    kRelief * spacing, 3 * spacing),
                  banded_relief(in, ep, offset, target_tree, out, kRelief * spacing), std::nullopt};
  if (!c.banded.empty()) c.bands = out.repeats[0];
  return c;
}

// Holes: target samples (not covered, not self-referenced) with no carried source sample within `reach`, because the
// exemplar has nothing where their own transform maps them (a tooth flank the scanner did not see). Before they are
// copied plain from the target, each used transform in turn, the largest region's first, carries the exemplar samples
// whose source sample it lands within `reach` of a hole, as a patch of its own (issue 10: coverage before copies).
// Appends to `landed` where their source samples land, in the template's frame: each transform followed by minus the
// exemplar's registration `offset` (see synthesize).
void fill_holes(const SynthesisInputs& in, const Eigen::Matrix3Xd& ep, const Eigen::Matrix3Xd& en,
                const std::vector<Similarity>& inverse, const Eigen::Vector3d& offset,
                const std::vector<Index>& region_size, const KdTree& target_tree, double spacing,
                const SynthesisOptions& o, const CarriedRelief& carried, std::vector<Eigen::Vector3d>& landed,
                Builder& b) {
  const PointSet& T = in.target;
  const double reach = o.reach * spacing;
  std::vector<std::uint8_t> hole = reached_targets(landed, T, reach);
  for (Index t = 0; t < T.size(); ++t)
    hole[size_t(t)] =
        !hole[size_t(t)] && in.labels[size_t(t)] != in.self_label && !(in.covered && (*in.covered)[size_t(t)] != 0);
  std::vector<int> order;
  for (int l = 0; l < int(region_size.size()); ++l)
    if (region_size[size_t(l)] > 0) order.push_back(l);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int c) { return region_size[size_t(a)] > region_size[size_t(c)]; });
  std::vector<std::uint8_t> hit(size_t(in.exemplar.size()));
  std::vector<Neighbor> near;
  for (const int l : order) {
    if (std::find(hole.begin(), hole.end(), 1) == hole.end()) return;
    const Similarity& inv = inverse[size_t(l)];
    const Similarity landing = shifted_by(-offset, inv);
    if (!landing_on(in, landing, target_tree, reach, hole, hit)) continue;
    const int patch = int(b.out.patches.size());
    b.out.patches.push_back({l, Origin::kSynthesized, false, inv});
    ++b.out.filled_patches;
    for (Index e = 0; e < in.exemplar.size(); ++e) {
      if (!hit[size_t(e)] || !carried.carries(inv, ep, e)) continue;
      b.add(inv.apply(ep.col(e)), inv.apply_normal(en.col(e)), Origin::kSynthesized, l, patch, int(e), false);
      landed.push_back(landing.apply(in.source.positions().col(in.exemplar_source[size_t(e)])));
      target_tree.radius(landed.back(), reach, near);
      for (const Neighbor& q : near) hole[size_t(q.index)] = 0;
    }
  }
}

// Points kept at least `distance` apart, in a hash grid of cells `distance` wide.
class SpacedPoints {
 public:
  explicit SpacedPoints(double distance) : distance_(distance) {}

  // Keeps p unless a kept point lies within the distance; returns whether it was kept.
  bool add(const Eigen::Vector3d& p) {
    const Eigen::Array3i cell = (p.array() / distance_).floor().cast<int>();
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz)
          if (const auto it = cells_.find(key(cell + Eigen::Array3i(dx, dy, dz))); it != cells_.end())
            for (const Eigen::Vector3d& q : it->second)
              if ((q - p).squaredNorm() < distance_ * distance_) return false;
    cells_[key(cell)].push_back(p);
    return true;
  }

 private:
  static std::uint64_t key(const Eigen::Array3i& c) {
    const auto bits = [](int v) { return std::uint64_t(std::uint32_t(v) & 0x1FFFFFu); };
    return bits(c.x()) << 42 | bits(c.y()) << 21 | bits(c.z());
  }
  double distance_;
  std::unordered_map<std::uint64_t, std::vector<Eigen::Vector3d>> cells_;
};

// The label most of the target samples `lands` holds for the exemplar samples `kept` carry (the smallest on a tie).
int most_common_label(const SynthesisInputs& in, const std::vector<std::int32_t>& lands,
                      const std::vector<Index>& kept) {
  std::map<int, Index> count;
  for (const Index e : kept) ++count[in.labels[size_t(lands[size_t(e)])]];
  return std::max_element(count.begin(), count.end(), [](const auto& a, const auto& b) { return a.second < b.second; })
      ->first;
}

// Completion: the exemplar turned to its own repeats fills what neither it nor any image put a point near (within
// an alpha): the hidden halves of a vase's beads seen from below, which other turns show whole, and the holes its
// images left. Each band with an order n is turned by k 360 / n degrees (k = 1 .. n - 1), one patch per turn (labelled
// as the region most of it lands on); a turned sample is added where it repeats (repeating_samples: not a teapot's
// spout), its source sample lands on the target (within `reach`) and no earlier addition lies within the same alpha.
void fill_by_repeats(const SynthesisInputs& in, const Eigen::Matrix3Xd& ep, const Eigen::Matrix3Xd& en,
                     const KdTree& exemplar_tree, const Eigen::Vector3d& offset, const KdTree& target_tree,
                     double spacing, const SynthesisOptions& o, std::vector<Eigen::Vector3d>& landed, Builder& b) {
  const double fill = 1.0 * spacing, reach = o.reach * spacing;
  const Eigen::Matrix3Xd placed = as_columns(b.p);
  KdTree placed_tree;
  placed_tree.build(placed);
  SpacedPoints added(fill);
  for (const AxialRepeats& r : b.out.repeats) {
    const std::vector<std::uint8_t> repeating =
        repeating_samples(exemplar_tree, ep, en, r, spacing, o.refine_distance * spacing);
    for (int band = 0; band < 2; ++band) {
      const int turns = r.continuous ? (band == 1 ? kRevolutionTurns : 0) : r.order[size_t(band)];
      for (int k = 1; k < turns; ++k) {
        const Similarity turn = turn_about(r, 2 * M_PI * k / turns);
        const Similarity landing = shifted_by(-offset, turn);
        std::vector<std::int32_t> lands(size_t(ep.cols()), -1);  // the target sample a candidate lands on
        tbb::parallel_for(Index(0), ep.cols(), [&](Index e) {
          const auto s = in.exemplar_source[size_t(e)];
          if (s < 0 || !repeating[size_t(e)] || band_of(r, ep.col(e)) != band) return;
          std::int32_t j;
          double d2;
          placed_tree.knn(turn.apply(ep.col(e)), 1, &j, &d2);
          if (d2 <= fill * fill) return;
          target_tree.knn(landing.apply(in.source.positions().col(s)), 1, &j, &d2);
          if (d2 <= reach * reach) lands[size_t(e)] = j;
        });
        std::vector<Index> kept;
        for (Index e = 0; e < ep.cols(); ++e)
          if (lands[size_t(e)] >= 0 && added.add(turn.apply(ep.col(e)))) kept.push_back(e);
        if (kept.empty()) continue;
        const int label = most_common_label(in, lands, kept);
        const int patch = int(b.out.patches.size());
        b.out.patches.push_back({label, Origin::kSynthesized, false, turn});
        for (const Index e : kept) {
          b.add(turn.apply(ep.col(e)), turn.apply_normal(en.col(e)), Origin::kSynthesized, label, patch, int(e), false);
          landed.push_back(landing.apply(in.source.positions().col(in.exemplar_source[size_t(e)])));
        }
        b.out.repeat_fill += Index(kept.size());
      }
    }
  }
}

// Keeps the points where `keep` is 1, and the landings of the synthesised ones (`landed`, one per point after the
// exemplar's `first`).
void keep_points(const std::vector<std::uint8_t>& keep, Index first, std::vector<Eigen::Vector3d>& landed, Builder& b) {
  size_t w = 0;
  Synthesis& out = b.out;
  for (size_t i = 0; i < keep.size(); ++i) {
    if (!keep[i]) continue;
    b.p[w] = b.p[i];
    b.n[w] = b.n[i];
    out.origin[w] = out.origin[i];
    out.label[w] = out.label[i];
    out.patch[w] = out.patch[i];
    out.base[w] = out.base[i];
    out.ring[w] = out.ring[i];
    if (Index(i) >= first) landed[w - size_t(first)] = landed[i - size_t(first)];
    ++w;
  }
  for (auto* v : {&b.p, &b.n}) v->resize(w);
  out.origin.resize(w);
  out.label.resize(w);
  out.patch.resize(w);
  out.base.resize(w);
  out.ring.resize(w);
  landed.resize(w - size_t(first));
}

// Completion: where the exemplar does not repeat under turns about the template's axis but is its own mirror image
// about a plane through it (mirror_plane: a lion's head), the exemplar mirrored takes the template's region it lands
// on from the images, whose turns carry the lion's head where the model has its mane. Mirrored samples are added where
// their source sample lands on the target (within `reach`) and no exemplar sample lies within an alpha, so they also
// fill the scan's own occlusion holes; the images' points that land within `reach` of them are removed.
void replace_by_mirror(const SynthesisInputs& in, const Eigen::Matrix3Xd& ep, const Eigen::Matrix3Xd& en,
                       const KdTree& exemplar_tree, const Eigen::Vector3d& offset, const KdTree& target_tree,
                       double spacing, const SynthesisOptions& o, std::vector<Eigen::Vector3d>& landed, Builder& b) {
  if (!in.mirror_axis) return;
  TurningPart axis = *in.mirror_axis;
  axis.point += offset;
  for (const AxialRepeats& r : b.out.repeats)
    if (std::abs(r.part.direction.dot(axis.direction)) >= std::cos(M_PI / 180)) return;  // turns do it
  const auto plane = mirror_plane(exemplar_tree, ep, en, axis, spacing, o.refine_distance * spacing);
  if (!plane) return;
  b.out.mirror = plane;
  const Similarity m = reflection_across(*plane), landing = shifted_by(-offset, m);
  const double reach = o.reach * spacing, near = 1.0 * spacing;
  std::vector<std::int32_t> lands(size_t(ep.cols()), -1);
  tbb::parallel_for(Index(0), ep.cols(), [&](Index e) {
    const auto s = in.exemplar_source[size_t(e)];
    if (s < 0) return;
    std::int32_t j;
    double d2;
    exemplar_tree.knn(m.apply(ep.col(e)), 1, &j, &d2);
    if (d2 <= near * near) return;
    target_tree.knn(landing.apply(in.source.positions().col(s)), 1, &j, &d2);
    if (d2 <= reach * reach) lands[size_t(e)] = j;
  });
  std::vector<Index> kept;
  std::vector<Eigen::Vector3d> kept_landed;
  for (Index e = 0; e < ep.cols(); ++e)
    if (lands[size_t(e)] >= 0) {
      kept.push_back(e);
      kept_landed.push_back(landing.apply(in.source.positions().col(in.exemplar_source[size_t(e)])));
    }
  if (kept.empty()) return;
  const Eigen::Matrix3Xd mirrored_landing = as_columns(kept_landed);  // the tree refers to it
  KdTree mirrored;
  mirrored.build(mirrored_landing);
  const Index first = ep.cols();  // the exemplar's points come first, without landings
  std::vector<std::uint8_t> keep(b.p.size(), 1);
  for (size_t i = size_t(first); i < keep.size(); ++i) {
    std::int32_t j;
    double d2;
    mirrored.knn(landed[i - size_t(first)], 1, &j, &d2);
    if (d2 <= reach * reach) keep[i] = 0;
  }
  b.out.mirror_replaced = Index(std::count(keep.begin(), keep.end(), 0));
  keep_points(keep, first, landed, b);
  const int label = most_common_label(in, lands, kept);
  const int patch = int(b.out.patches.size());
  b.out.patches.push_back({label, Origin::kSynthesized, false, m});
  for (size_t k = 0; k < kept.size(); ++k) {
    b.add(m.apply(ep.col(kept[k])), m.apply_normal(en.col(kept[k])), Origin::kSynthesized, label, patch, int(kept[k]),
          false);
    landed.push_back(kept_landed[k]);
  }
  b.out.mirror_fill = Index(kept.size());
}

// Per transform label, the exemplar samples it carries into its region (2) or the region's ring (1) on the target:
// those whose source sample, carried by the labelled transform, lands within `reach` of a target sample of the region
// or ring. Membership is the analogy's; the refinement moves only where they land.
void carried_samples(const SynthesisInputs& in, const PointSet& T, const KdTree& target_tree,
                     const std::vector<std::int32_t>& graph, int k, const std::vector<Similarity>& labelled_inverse,
                     const std::vector<Index>& region_size, double reach, std::vector<std::vector<std::int32_t>>& used,
                     std::vector<std::vector<std::uint8_t>>& in_ring) {
  const auto covered = [&](Index t) { return in.covered && (*in.covered)[size_t(t)] != 0; };
  const Index E = in.exemplar.size();
  std::vector<std::uint8_t> member(size_t(T.size()));  // 2 = region, 1 = ring, 0 = neither
  std::vector<std::uint8_t> hit(static_cast<size_t>(E));
  for (int l = 0; l < int(region_size.size()); ++l) {
    if (region_size[size_t(l)] == 0) continue;
    for (Index t = 0; t < T.size(); ++t) member[size_t(t)] = (in.labels[size_t(t)] == l && !covered(t)) ? 2 : 0;
    for (Index t = 0; t < T.size(); ++t) {
      if (member[size_t(t)] != 0 || covered(t)) continue;
      for (int a = 0; a < k; ++a)
        if (member[size_t(graph[size_t(t) * size_t(k) + size_t(a)])] == 2) {
          member[size_t(t)] = 1;
          break;
        }
    }
    landing_on(in, labelled_inverse[size_t(l)], target_tree, reach, member, hit);
    for (Index e = 0; e < E; ++e)
      if (hit[size_t(e)]) {
        used[size_t(l)].push_back(std::int32_t(e));
        in_ring[size_t(l)].push_back(hit[size_t(e)] == 1);
      }
  }
}

}  // namespace

Synthesis synthesize(const SynthesisInputs& in, double spacing, const SynthesisOptions& o) {
  check_options(o);  // the config checks these too; a direct caller gets the same checks
  const PointSet& E = in.exemplar;
  const PointSet& T = in.target;
  if (!E.has_normals() || !T.has_normals()) throw InvariantError("synthesize needs exemplar and target normals");
  if (in.labels.size() != size_t(T.size())) throw InvariantError("synthesize: one label per target sample expected");
  for (const std::vector<std::uint8_t>* flags : {in.off_profile, in.seen_through})
    if (flags && flags->size() != size_t(T.size()))
      throw InvariantError("synthesize: one off-profile and seen-through flag per target sample expected");
  Synthesis out;
  Builder b{{}, {}, out};
  const auto covered = [&](Index t) { return in.covered && (*in.covered)[size_t(t)] != 0; };

  // The exemplar in the working frame.
  Eigen::Matrix3Xd ep(3, E.size()), en(3, E.size());
  for (Index e = 0; e < E.size(); ++e) {
    ep.col(e) = in.exemplar_to_working.apply(E.positions().col(e));
    en.col(e) = in.exemplar_to_working.apply_normal(E.normals().col(e));
  }
  if (in.covered) {
    out.patches.push_back({-1, Origin::kExemplar, false, Similarity{}});
    for (Index e = 0; e < E.size(); ++e) b.add(ep.col(e), en.col(e), Origin::kExemplar, -1, 0, int(e), false);
  }

  KdTree target_tree;
  target_tree.build(T.positions());
  const int k = int(std::max<Index>(0, std::min<Index>(o.ring_k, T.size() - 1)));
  const std::vector<std::int32_t> graph = knn_graph(target_tree, T.positions(), k);

  // Transform labels: the exemplar carried by Q_l^-1 into region l and its ring, after refinement.
  std::vector<Similarity> inverse;
  std::vector<Index> region_size(in.transforms.size(), 0);
  for (const auto& q : in.transforms) inverse.push_back(q.inverse());
  for (Index t = 0; t < T.size(); ++t) {
    const int l = in.labels[size_t(t)];
    if (l >= 0 && l < int(in.transforms.size()) && !covered(t)) ++region_size[size_t(l)];
  }
  // Membership in a region is the analogy's (the labelled transform); the refinement only moves the exemplar's
  // image to fit its detail to the images already placed (a relief can pull it off the template by its height).
  const std::vector<Similarity> labelled_inverse = inverse;
  std::vector<std::vector<std::int32_t>> used(in.transforms.size());     // per label: the exemplar samples it carries
  std::vector<std::vector<std::uint8_t>> in_ring(in.transforms.size());  // per label and used sample: in the ring
  carried_samples(in, T, target_tree, graph, k, labelled_inverse, region_size, spacing * o.reach, used, in_ring);
  std::vector<std::optional<PhaseSplit>> splits(in.transforms.size());
  std::vector<Slippage> slips(in.transforms.size());
  std::vector<std::uint8_t> on_template(in.transforms.size(), 0);
  for (size_t l = 0; l < slips.size(); ++l)
    if (region_size[l] > 0 || in.covered)  // completion: every transform may fix the registration offset
      slips[l] = image_slippage(in, labelled_inverse[l], target_tree, spacing * o.reach, int(l), on_template[l]);
  const ExemplarRelief relief = in.covered ? exemplar_relief(ep, en, T, target_tree, spacing) : ExemplarRelief{};
  // Where no registration moved the scan, its images land on the template exactly: within an alpha (see refinement).
  const LandedShare share_landed = [&](const Similarity& inv, const std::vector<std::int32_t>& carried,
                                       bool within_alpha) {
    const double reach = in.scan_as_given || within_alpha ? kAsGivenSlide : o.reach;
    return landed_share(in, target_tree, spacing * reach, inv, carried);
  };
  const std::vector<std::uint8_t> plain =
      in.covered ? plain_images(ep, T, target_tree, labelled_inverse, used, in_ring, spacing)
                 : std::vector<std::uint8_t>(in.transforms.size(), 0);
  out.pinned_by_template = pinned_symmetries(in, target_tree, labelled_inverse, region_size, relief, spacing);
  refine(ep, en, region_size, used, in.covered ? &on_template : nullptr, relief, spacing, o, slips, inverse, splits,
         in.turning_parts, share_landed, in.scan_as_given, in.up, plain, out.pinned_by_template, out);
  // Per synthesised sample: where its source sample lands on the target. The images sit the exemplar's registration
  // offset d off the template (the exemplar does), and a source sample lies on its exemplar sample up to relief (the
  // correspondence deforms the template onto the scan): so in the template's frame, each transform followed by -d.
  std::vector<Eigen::Vector3d> landed;
  KdTree exemplar_tree;  // what the scan's own relief, its repeats and its mirror are measured on (completion)
  if (in.covered) exemplar_tree.build(ep);
  const CarriedRelief carried =
      carried_relief(in, ep, exemplar_tree, out.registration_offset, target_tree, out, spacing);
  for (int l = 0; l < int(in.transforms.size()); ++l) {
    if (region_size[size_t(l)] == 0) continue;
    const auto& split = splits[size_t(l)];
    for (std::uint8_t part = 0; part < (split ? 2 : 1); ++part) {
      const Similarity& inv = split ? split->inv[part] : inverse[size_t(l)];
      const Similarity landing = shifted_by(-out.registration_offset, inv);
      const int patch = int(out.patches.size());
      out.patches.push_back({l, Origin::kSynthesized, false, inv});
      for (size_t i = 0; i < used[size_t(l)].size(); ++i) {
        if (split && split->part[i] != part) continue;
        const Index e = used[size_t(l)][i];
        if (!carried.carries(inv, ep, e)) continue;
        b.add(inv.apply(ep.col(e)), inv.apply_normal(en.col(e)), Origin::kSynthesized, l, patch, int(e),
              in_ring[size_t(l)][i] != 0);
        landed.push_back(landing.apply(in.source.positions().col(in.exemplar_source[size_t(e)])));
      }
    }
  }

  if (in.covered && o.repeats)
    fill_by_repeats(in, ep, en, exemplar_tree, out.registration_offset, target_tree, spacing, o, landed, b);
  if (in.covered && o.mirror)
    replace_by_mirror(in, ep, en, exemplar_tree, out.registration_offset, target_tree, spacing, o, landed, b);
  fill_holes(in, ep, en, inverse, out.registration_offset, region_size, target_tree, spacing, o, carried, landed, b);
  const std::vector<std::uint8_t> reached = reached_targets(landed, T, o.gap_distance * spacing);
  const std::vector<std::uint8_t> overlaid = overlaid_targets(
      b.p, b.n, T, out.registration_offset, o.overlay_distance * spacing, o.gap_distance * spacing, spacing);

  // Self-referenced regions, and target samples no patch reached: copies of the target.
  const int self_patch = int(out.patches.size());
  out.patches.push_back({in.self_label, Origin::kTarget, true, Similarity{}});
  for (Index t = 0; t < T.size(); ++t) {
    if (covered(t)) continue;
    const bool self = in.labels[size_t(t)] == in.self_label;
    if (!self && (overlaid[size_t(t)] == kUnder || (reached[size_t(t)] && overlaid[size_t(t)] == kOver))) continue;
    if (in.off_profile && (*in.off_profile)[size_t(t)] != 0) {
      ++out.off_profile;
      continue;
    }
    if (in.seen_through && (*in.seen_through)[size_t(t)] != 0) {
      ++out.seen_through;
      continue;
    }
    if (!self) ++out.gap_copies;
    b.add(T.positions().col(t), T.normals().col(t), Origin::kTarget, in.self_label, self_patch, int(t), false);
  }

  out.points = PointSet(as_columns(b.p));
  out.points.set_normals(as_columns(b.n));
  return out;
}

PointSet kept_points(const Synthesis& s, const std::vector<std::uint8_t>& keep, const Similarity& to_output) {
  if (keep.size() != size_t(s.points.size()) || !s.points.has_normals())
    throw InvariantError("kept_points: one flag per synthesis point, and points with normals");
  std::vector<Index> kept;
  for (Index i = 0; i < s.points.size(); ++i)
    if (keep[size_t(i)]) kept.push_back(i);
  Eigen::Matrix3Xd p(3, Index(kept.size())), n(3, Index(kept.size()));
  for (Index k = 0; k < Index(kept.size()); ++k) {
    p.col(k) = to_output.apply(s.points.positions().col(kept[size_t(k)]));
    n.col(k) = to_output.apply_normal(s.points.normals().col(kept[size_t(k)]));
  }
  PointSet out(std::move(p));
  out.set_normals(std::move(n));
  return out;
}

}  // namespace scanfill
