// synthesize -> align -> transfer on constructed inputs with known answers (issue 4).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <functional>

#include "nodes/align/align.h"
#include "nodes/core/errors.h"
#include "nodes/core/kdtree.h"
#include "nodes/procedural/shapes.h"
#include "nodes/sample/sample.h"
#include "nodes/synthesize/synthesize.h"
#include "nodes/transfer/transfer.h"

namespace scanfill {
namespace {

// Synthesis with one translation: the exemplar's image lands on the region of the target labelled with it, and the
// transfer carries every original point and triangle.
TEST(SynthesizeTransfer, ATranslatedRegionGetsTheExemplarAtFullResolution) {
  // Target: two unit squares side by side (x in [0, 1] and [1.5, 2.5]); source = exemplar = the first square.
  const PointSet square = make_plane(1.0, 40);  // centred at the origin
  const Similarity to_first{Eigen::Matrix3d::Identity(), Eigen::Vector3d(0.5, 0.5, 0), 1};
  const Similarity to_second{Eigen::Matrix3d::Identity(), Eigen::Vector3d(2.0, 0.5, 0), 1};
  const PointSet first = transformed(square, to_first), both = merged(first, transformed(square, to_second));
  const auto samples = [](const PointSet& mesh, double h) {
    // Grid samples of the mesh's vertices every other one: enough for a known answer.
    std::vector<std::int32_t> keep;
    for (Index i = 0; i < mesh.size(); i += 2) keep.push_back(std::int32_t(i));
    PointSet s = subset(mesh, keep);
    s.set_normals(Eigen::Matrix3Xd::Zero(3, s.size()).colwise() + Eigen::Vector3d::UnitZ());
    (void)h;
    return s;
  };
  PointSet first_n = first;
  first_n.set_normals(Eigen::Matrix3Xd::Zero(3, first.size()).colwise() + Eigen::Vector3d::UnitZ());
  const PointSet E = samples(first_n, 0), S = E, T = samples(both, 0);
  const double alpha = 1.0 / 40 * std::sqrt(2.0);
  // Labels: target samples of the second square take label 0 (Q: target -> source = translation by -1.5 in x), the
  // first square label 1 (identity).
  std::vector<int> labels;
  for (Index t = 0; t < T.size(); ++t) labels.push_back(T.positions()(0, t) > 1.25 ? 0 : 1);
  const std::vector<Similarity> transforms{Similarity{Eigen::Matrix3d::Identity(), Eigen::Vector3d(-1.5, 0, 0), 1},
                                           Similarity{}};
  std::vector<std::int32_t> exemplar_source(size_t(E.size()));
  for (Index e = 0; e < E.size(); ++e) exemplar_source[size_t(e)] = std::int32_t(e);
  SynthesisOptions so;
  so.refine_iterations = 0;
  const Synthesis syn = synthesize({E, Similarity{}, exemplar_source, S, T, labels, 2, transforms, nullptr}, alpha, so);
  EXPECT_EQ(syn.gap_copies, 0);
  Index in_second = 0;
  for (Index i = 0; i < syn.points.size(); ++i)
    if (syn.label[size_t(i)] == 0) {
      EXPECT_GT(syn.points.positions()(0, i), 1.4);
      ++in_second;
    }
  EXPECT_GE(in_second, E.size() * 9 / 10);
  const AlignResult al = align(syn, alpha, {});
  const TransferResult out = transfer({first_n, E, both, T, Similarity{}, syn, al, Similarity{}});
  // Both squares at full resolution: every exemplar vertex twice (ring overlaps thinned), triangles carried.
  EXPECT_GE(out.points.size(), 2 * first.size() * 95 / 100);
  EXPECT_LE(out.points.size(), 2 * first.size() * 115 / 100);
  EXPECT_GE(out.points.faces().cols(), 2 * first.faces().cols() * 90 / 100);
  out.points.check();
}

// The unit square [0, 1]^2 at z = 0, facing +z, 40 segments a side, and its right half (x > 0.5) as the exemplar.
struct HalfSquare {
  PointSet square =
      facing_up(transformed(make_plane(1.0, 40), {Eigen::Matrix3d::Identity(), Eigen::Vector3d(0.5, 0.5, 0), 1}));
  std::vector<std::int32_t> right = right_of(square, 0.5);
  PointSet exemplar = subset(square, right);

  static PointSet facing_up(PointSet p) {
    p.set_normals(Eigen::Matrix3Xd::Zero(3, p.size()).colwise() + Eigen::Vector3d::UnitZ());
    return p;
  }
  static std::vector<std::int32_t> right_of(const PointSet& p, double x) {
    std::vector<std::int32_t> out;
    for (Index i = 0; i < p.size(); ++i)
      if (p.positions()(0, i) > x) out.push_back(std::int32_t(i));
    return out;
  }
};

// A template the scan's own radii put elsewhere (SynthesisInputs.off_profile), or that the scanner saw through
// (SynthesisInputs.seen_through), is not copied where nothing reached it: the exemplar is a square's right half, every
// target sample takes the identity, and the left half, which nothing of the exemplar reaches, is copied plain, but for
// the strip flagged, counted instead.
TEST(SynthesizeTransfer, ATargetSampleOffTheScansProfileOrSeenThroughIsNotCopied) {
  const HalfSquare h;
  const PointSet &E = h.exemplar, &S = h.square, &T = h.square;
  const std::vector<std::int32_t>& right = h.right;
  const double alpha = 1.0 / 40;
  const std::vector<int> labels(size_t(T.size()), 0);
  const std::vector<Similarity> transforms{Similarity{}};
  std::vector<std::uint8_t> off(size_t(T.size()), 0);
  Index flagged = 0;
  for (Index t = 0; t < T.size(); ++t) flagged += off[size_t(t)] = T.positions()(0, t) < 0.2;
  SynthesisOptions so;
  so.refine_iterations = 0;
  const Synthesis all = synthesize({E, Similarity{}, right, S, T, labels, 1, transforms, nullptr}, alpha, so);
  const Synthesis some = synthesize(
      {E, Similarity{}, right, S, T, labels, 1, transforms, nullptr, nullptr, nullptr, false, std::nullopt, &off},
      alpha, so);
  EXPECT_GT(all.gap_copies, flagged);
  EXPECT_EQ(all.off_profile, 0);
  EXPECT_EQ(some.off_profile, flagged);
  EXPECT_EQ(some.gap_copies, all.gap_copies - flagged);
  for (Index i = 0; i < some.points.size(); ++i)
    if (some.origin[size_t(i)] == Origin::kTarget) EXPECT_GE(some.points.positions()(0, i), 0.2);
  const Synthesis seen = synthesize({E, Similarity{}, right, S, T, labels, 1, transforms, nullptr, nullptr, nullptr,
                                     false, std::nullopt, nullptr, &off},
                                    alpha, so);
  EXPECT_EQ(all.seen_through, 0);
  EXPECT_EQ(seen.seen_through, flagged);
  EXPECT_EQ(seen.off_profile, 0);
  EXPECT_EQ(seen.points.positions(), some.points.positions());
}

// A hole: the exemplar is a square's right half; the left half's region takes the identity, which lands on nothing of
// the exemplar, and a strip at its edge takes a shift by half the square. That shift's image fills the hole before
// anything is copied plain from the target (issue 10: coverage before copies).
TEST(SynthesizeTransfer, AnotherRegionsTransformFillsAHoleBeforeTheTargetIsCopied) {
  const HalfSquare h;
  const PointSet &E = h.exemplar, &S = h.square, &T = h.square;
  const std::vector<std::int32_t>& right = h.right;
  const double alpha = 1.0 / 40;
  std::vector<int> labels;
  for (Index t = 0; t < T.size(); ++t) labels.push_back(T.positions()(0, t) < 0.1 ? 1 : 0);
  const std::vector<Similarity> transforms{Similarity{},
                                           Similarity{Eigen::Matrix3d::Identity(), Eigen::Vector3d(0.5, 0, 0), 1}};
  SynthesisOptions so;
  so.refine_iterations = 0;
  const Synthesis syn = synthesize({E, Similarity{}, right, S, T, labels, 2, transforms, nullptr}, alpha, so);
  EXPECT_EQ(syn.gap_copies, 0);
  EXPECT_EQ(syn.filled_patches, 1);
  std::vector<Eigen::Vector3d> shifted;
  for (Index i = 0; i < syn.points.size(); ++i) {
    EXPECT_NE(syn.origin[size_t(i)], Origin::kTarget) << "a copy at x = " << syn.points.positions()(0, i);
    if (syn.label[size_t(i)] == 1) shifted.push_back(syn.points.positions().col(i));
  }
  Eigen::Matrix3Xd shifted_points(3, Index(shifted.size()));
  for (size_t i = 0; i < shifted.size(); ++i) shifted_points.col(Index(i)) = shifted[i];
  KdTree tree;
  tree.build(shifted_points);
  for (Index t = 0; t < T.size(); ++t) {  // the whole left half, the hole included, carries the shifted exemplar
    if (T.positions()(0, t) > 0.45) continue;
    std::int32_t j;
    double d2;
    tree.knn(T.positions().col(t), 1, &j, &d2);
    EXPECT_LT(std::sqrt(d2), 1.5 * alpha) << "at x = " << T.positions()(0, t);
  }
}

// The surface's points: the synthesis as align's thinning leaves it at zero offsets, mapped to the output frame. Two
// patches side by side on a line (x = 0..5 and 6..11, normals +z); patch 0's ring sample at x = 6.2 lies on patch 1's
// region sample at x = 6 and goes; its ring sample at x = 20 has no other patch near and stays, as does every region
// sample.
TEST(KeptPoints, AreTheSynthesisAlignsThinningKeepsInTheOutputFrame) {
  Synthesis s;
  Eigen::Matrix3Xd p(3, 14);
  for (int i = 0; i < 6; ++i) p.col(i) = Eigen::Vector3d(i, 0, 0);
  for (int i = 0; i < 6; ++i) p.col(6 + i) = Eigen::Vector3d(6 + i, 0, 0);
  p.col(12) = Eigen::Vector3d(6.2, 0, 0);
  p.col(13) = Eigen::Vector3d(20, 0, 0);
  s.points = PointSet(p);
  s.points.set_normals(Eigen::Matrix3Xd::Zero(3, 14).colwise() + Eigen::Vector3d::UnitZ());
  s.patch = {0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 1, 1, 0, 0};
  s.ring = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 1};
  const std::vector<double> zero(14, 0.0);
  const std::vector<std::uint8_t> keep = thinned_overlaps(s, zero, 1.0, 0.75);
  for (int i = 0; i < 14; ++i) EXPECT_EQ(keep[size_t(i)], i == 12 ? 0 : 1) << "point " << i;
  // Moved 1 along its normal, the ring sample is no longer on patch 1's sample; with no thinning, every sample stays.
  std::vector<double> lifted = zero;
  lifted[12] = 1.0;
  EXPECT_EQ(thinned_overlaps(s, lifted, 1.0, 0.75)[12], 1);
  EXPECT_EQ(thinned_overlaps(s, zero, 1.0, 0.0)[12], 1);

  const Similarity w{Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY()).toRotationMatrix(), Eigen::Vector3d(1, 2, 3), 2};
  const PointSet out = kept_points(s, keep, w);
  ASSERT_EQ(out.size(), 13);
  for (Index i = 0, k = 0; i < 14; ++i) {
    if (!keep[size_t(i)]) continue;
    EXPECT_LT((out.positions().col(k) - w.apply(s.points.positions().col(i))).norm(), 1e-12);
    EXPECT_LT((out.normals().col(k) - w.apply_normal(s.points.normals().col(i))).norm(), 1e-12);
    ++k;
  }
  EXPECT_THROW(kept_points(s, std::vector<std::uint8_t>(3, 1), w), InvariantError);
}

// Completion-mode synthesis of `exemplar` onto `target` (also the source), each target sample labelled by `label_of`
// with one of `transforms`, none covered: the exemplar itself is the anchor each transform is refined against.
}  // namespace

// A body, egg-shaped in section (radius 0.3 + 0.02 cos), 0.8 high, with one head on it (a bump 0.08 high, 20 degrees
// wide, at -y): mirror-symmetric about the plane x = 0 through its axis and the head, which no turn maps onto itself.
// Without the head: its plain template. (Used by repeats_test.cpp too.)
PointSet one_headed_body(bool head) {
  return make_prism(
      [head](double phi) {
        const double off = std::remainder(phi + M_PI / 2, 2 * M_PI);  // from the head's direction, -y
        return 0.3 + (head ? 0.08 * std::exp(-std::pow(off / 0.35, 2)) : 0.0) + 0.02 * std::cos(off);
      },
      0.0, 0.8, 256);
}

namespace {

Synthesis refine_transforms(const PointSet& exemplar, const PointSet& target, const std::vector<Similarity>& transforms,
                            const std::function<int(const Eigen::Vector3d&)>& label_of, double alpha,
                            const SynthesisOptions& options = {}, const TurningPart* mirror_axis = nullptr) {
  KdTree tree;
  tree.build(target.positions());
  std::vector<std::int32_t> exemplar_source;
  std::vector<double> d2;
  nearest_each(tree, exemplar.positions(), exemplar_source, d2);
  std::vector<int> labels;
  for (Index t = 0; t < target.size(); ++t) labels.push_back(label_of(target.positions().col(t)));
  const std::vector<std::uint8_t> covered(size_t(target.size()), 0);
  return synthesize({exemplar, Similarity{}, exemplar_source, target, target, labels, int(transforms.size()),
                     transforms, &covered, nullptr, mirror_axis},
                    alpha, options);
}

// As refine_transforms, with every target sample labelled 0 with transform q.
Synthesis refine_one_transform(const PointSet& exemplar, const PointSet& target, const Similarity& q, double alpha) {
  return refine_transforms(
      exemplar, target, {q}, [](const Eigen::Vector3d&) { return 0; }, alpha);
}

// A free rigid refinement is kept where it fits the exemplar's images clearly better (it corrects the exemplar's
// registration): a blob slides on nothing, yet a transform 0.6 alpha off the exemplar comes back onto it.
TEST(SynthesizeRefinement, BringsATransformOffTheExemplarBackOntoIt) {
  const PointSet blob = make_blob();
  const Index n = 6000;
  const double alpha = std::sqrt(0.64 * surface_area(blob.positions(), blob.faces()) / double(n));
  const Similarity q{Eigen::Matrix3d::Identity(), Eigen::Vector3d(0.6 * alpha, 0, 0), 1};
  const Synthesis syn =
      refine_one_transform(random_surface_points(blob, n, 7), random_surface_points(blob, n, 11), q, alpha);
  EXPECT_NEAR(syn.refinement_shift[0], 0.6 * alpha, 0.15 * alpha);
  EXPECT_LT(syn.refinement_deg[0], 0.5);
}

// Along the region's slippable motions the refinement finds the exemplar's phase: a fluted column's exemplar carried by
// a turn 5 degrees off its flutes (every 22.5 degrees) comes back onto them, by a turn about the column's own axis.
TEST(SynthesizeRefinement, TurnsAFlutedColumnsImageBackOntoItsFlutesAboutTheAxis) {
  const PointSet column = make_column(), plain = make_column_template();
  const Index n = 12000;
  const double alpha = std::sqrt(0.64 * surface_area(column.positions(), column.faces()) / double(n));
  const Similarity q{Eigen::AngleAxisd(5 * M_PI / 180, Eigen::Vector3d::UnitZ()).toRotationMatrix(),
                     Eigen::Vector3d::Zero(), 1};
  const Synthesis syn =
      refine_one_transform(random_surface_points(column, n, 7), random_surface_points(plain, n, 11), q, alpha);
  EXPECT_NEAR(syn.refinement_deg[0], 5.0, 1.0);
  EXPECT_LT(syn.refinement_shift[0], 0.2 * alpha);  // a turn about the axis itself (x = y = 0)
}

// The samples of `all` (with normals) whose position passes `keep`.
PointSet samples_where(const PointSet& all, const std::function<bool(const Eigen::Vector3d&)>& keep) {
  std::vector<Index> kept;
  for (Index i = 0; i < all.size(); ++i)
    if (keep(all.positions().col(i))) kept.push_back(i);
  PointSet out(all.positions()(Eigen::all, kept));
  out.set_normals(all.normals()(Eigen::all, kept));
  return out;
}

// Half a vase (y < 0: a one-sided scan), from 2 n random points over the whole vase, with normals.
PointSet half_vase(Index n) {
  const PointSet all = random_surface_points(make_vase(), 2 * n, 7);
  return samples_where(all, [](const Eigen::Vector3d& p) { return p(1) < 0; });
}

// The synthesised points of `label` (any label: -2) that are detail (more than half an alpha off the plain body), by
// height: beads below z = 0.1, flutes above; each as its distance to the vase, in alpha.
struct VaseDetail {
  std::vector<double> beads, flutes;
};
VaseDetail vase_detail(const Synthesis& syn, double alpha, int label) {
  KdTree truth, body;
  const PointSet dense = random_surface_points(make_vase(), 400000, 5);
  const PointSet dense_plain = random_surface_points(make_vase_template(), 400000, 5);
  truth.build(dense.positions());
  body.build(dense_plain.positions());
  VaseDetail out;
  for (Index i = 0; i < syn.points.size(); ++i) {
    if (syn.origin[size_t(i)] != Origin::kSynthesized || (label != -2 && syn.label[size_t(i)] != label)) continue;
    const Eigen::Vector3d p = syn.points.positions().col(i);
    std::int32_t j;
    double d2;
    body.knn(p, 1, &j, &d2);
    if (d2 < std::pow(0.5 * alpha, 2)) continue;
    truth.knn(p, 1, &j, &d2);
    (p.z() < 0.1 ? out.beads : out.flutes).push_back(std::sqrt(d2) / alpha);
  }
  return out;
}

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + long(v.size() / 2), v.end());
  return v[v.size() / 2];
}

// A vase's 12 flutes and its ring of 16 beads (below them) repeat with different periods: a turn of 60 degrees about
// its axis carries flutes onto flutes but beads halfway between beads (60 = 2 x 30 = 2.67 x 22.5). The image of half
// the vase under that turn, fitted to the half itself, takes one phase for the flutes, which cover most of it, and a
// second one for the band of beads: the synthesised beads lie on the vase's beads (median distance 0.14 alpha;
// 1.35 alpha with one phase for the whole image), and the flutes on its flutes.
TEST(SynthesizeRefinement, GivesTheBeadsBelowAVasesFlutesAPhaseOfTheirOwn) {
  const PointSet vase = make_vase();
  const Index n = 16000;
  const double alpha = std::sqrt(0.64 * surface_area(vase.positions(), vase.faces()) / double(n));
  const Similarity q{Eigen::AngleAxisd(60 * M_PI / 180, Eigen::Vector3d::UnitZ()).toRotationMatrix(),
                     Eigen::Vector3d::Zero(), 1};
  const Synthesis syn =
      refine_one_transform(half_vase(n), random_surface_points(make_vase_template(), n, 11), q, alpha);
  const auto [beads, flutes] = vase_detail(syn, alpha, -2);
  std::printf("beads: %zu points, median distance %.3f alpha; flutes: %zu points, %.3f alpha; %zu patches\n",
              beads.size(), median(beads), flutes.size(), median(flutes), syn.patches.size());
  ASSERT_GT(beads.size(), 500u);
  EXPECT_LT(median(beads), 0.35);
  EXPECT_LT(median(flutes), 0.35);
}

// Per synthesised point of `label` (any label: -2): its distance, in alpha, to the model moved by `offset`.
std::vector<double> distances_to_shifted(const Synthesis& syn, const PointSet& model, const Eigen::Vector3d& offset,
                                         double alpha, int label) {
  KdTree truth;
  const PointSet dense = random_surface_points(model, 400000, 5);
  const Eigen::Matrix3Xd shifted = dense.positions().colwise() + offset;
  truth.build(shifted);
  std::vector<double> distance;
  for (Index i = 0; i < syn.points.size(); ++i) {
    if (syn.origin[size_t(i)] != Origin::kSynthesized || (label != -2 && syn.label[size_t(i)] != label)) continue;
    std::int32_t j;
    double d2;
    truth.knn(syn.points.positions().col(i), 1, &j, &d2);
    distance.push_back(std::sqrt(d2) / alpha);
  }
  return distance;
}

// The share of the points that `counted` selects (by index) whose nearest point in `tree` lies within `distance`.
double share_near(const KdTree& tree, const Eigen::Matrix3Xd& points, double distance,
                  const std::function<bool(Index)>& counted) {
  Index total = 0, near = 0;
  for (Index i = 0; i < points.cols(); ++i) {
    if (!counted(i)) continue;
    std::int32_t j;
    double d2;
    tree.knn(points.col(i), 1, &j, &d2);
    ++total;
    near += d2 <= distance * distance;
  }
  return double(near) / double(std::max<Index>(1, total));
}

double ninetieth_percentile(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + long(v.size() * 9 / 10), v.end());
  return v[v.size() * 9 / 10];
}

// Where the images overlap too little to tell a second phase, the exemplar's own repeats do: half a vase (y < 0), and
// the other half's region labelled with a turn of 121 degrees about the axis (voting leaves the phase free on a body
// of revolution). Its image meets the half over 60 degrees. The refinement turns it to 120 degrees, where the 12
// flutes fit, and the overlap's beads do not halve their misfit at a phase of their own (the vase from the side, issue
// 10): one phase left the synthesised beads 1.28 alpha (median) off the vase. The half repeats every 22.5 degrees
// below z = 0.1 and every 30 above, so the beads turn to 112.5 degrees and the flutes stay at 120.
TEST(SynthesizeRefinement, TurnsEachBandToTheExemplarsOwnRepeats) {
  const PointSet vase = make_vase();
  const Index n = 16000;
  const double alpha = std::sqrt(0.64 * surface_area(vase.positions(), vase.faces()) / double(n));
  const auto turn = [](double deg) {
    return Similarity{Eigen::AngleAxisd(deg * M_PI / 180, Eigen::Vector3d::UnitZ()).toRotationMatrix(),
                      Eigen::Vector3d::Zero(), 1};
  };
  const Synthesis syn = refine_transforms(
      half_vase(n), random_surface_points(make_vase_template(), n, 11), {turn(0), turn(121)},
      [](const Eigen::Vector3d& p) { return p.y() < 0 ? 0 : 1; }, alpha);
  ASSERT_EQ(syn.repeats.size(), 1u);
  EXPECT_EQ(syn.repeats[0].order[0] + syn.repeats[0].order[1], 28);  // 16 and 12, in the order of the axis found
  const auto [beads, flutes] = vase_detail(syn, alpha, 1);           // label 1's
  std::printf("beads: %zu points, median distance %.3f alpha; flutes: %zu points, %.3f alpha\n", beads.size(),
              median(beads), flutes.size(), median(flutes));
  ASSERT_GT(beads.size(), 300u);
  ASSERT_GT(flutes.size(), 300u);
  EXPECT_LT(median(beads), 0.35);
  EXPECT_LT(median(flutes), 0.35);
}

// A scan sees the beads of a vase whole only on one side: below z = 0.06 they are cut away over a quarter of the
// ring (the half y < 0, between 180 and 270 degrees), as the vase's belly hides them from above. No image of the
// exemplar carries the missing halves there; its own turns by 22.5 degrees do, and they fill them: 90% of the vase's
// bead points there lie within an alpha of the synthesis (98% measured; 55% without the repeats).
TEST(SynthesizeRepeats, FillsTheHiddenHalvesOfAVasesBeadsWithItsOwnTurns) {
  const PointSet vase = make_vase(), plain = make_vase_template();
  const Index n = 16000;
  const double alpha = std::sqrt(0.64 * surface_area(vase.positions(), vase.faces()) / double(n));
  const PointSet all = random_surface_points(vase, 2 * n, 7);
  const auto hidden = [](const Eigen::Vector3d& p) {  // the beads' lower halves over a quarter of the ring
    const double angle = std::atan2(p.y(), p.x());
    return p.z() < 0.06 && p.head<2>().norm() > 0.31 && angle < -M_PI / 2;
  };
  const PointSet exemplar = samples_where(all, [&](const Eigen::Vector3d& p) { return p(1) < 0 && !hidden(p); });
  const auto turn = [](double deg) {
    return Similarity{Eigen::AngleAxisd(deg * M_PI / 180, Eigen::Vector3d::UnitZ()).toRotationMatrix(),
                      Eigen::Vector3d::Zero(), 1};
  };
  const PointSet target = random_surface_points(plain, n, 11), dense = random_surface_points(vase, 400000, 5);
  const auto share_filled = [&](const Synthesis& syn) {
    KdTree tree;
    tree.build(syn.points.positions());
    return share_near(tree, dense.positions(), alpha, [&](Index i) {
      const Eigen::Vector3d p = dense.positions().col(i);
      return p.y() < 0 && hidden(p);
    });
  };
  const auto label_of = [](const Eigen::Vector3d& p) { return p.y() < 0 ? 0 : 1; };
  const Synthesis with = refine_transforms(exemplar, target, {turn(0), turn(180)}, label_of, alpha);
  SynthesisOptions off;
  off.repeats = false;
  const Synthesis without = refine_transforms(exemplar, target, {turn(0), turn(180)}, label_of, alpha, off);
  std::printf("hidden bead points within an alpha: %.3f with the repeats (%lld added), %.3f without\n",
              share_filled(with), static_cast<long long>(with.repeat_fill), share_filled(without));
  EXPECT_GT(with.repeat_fill, 0);
  EXPECT_GT(share_filled(with), 0.9);
  EXPECT_LT(share_filled(without), 0.7);
}

// A one-sided scan of a gear registers towards its teeth, off the plain annulus's axis: the template's turns hold about
// the template's axis, and the exemplar's image must turn about its own. Half a gear, 3 cm off the annulus (the
// registration error), carried by a quarter turn (x > 0) and a half turn (x < 0) about the annulus's axis: the
// refinement finds the one offset both share, and the images' teeth land on the shifted gear's teeth.
TEST(SynthesizeRefinement, TurnsAGearsImageAboutTheExemplarsOwnAxisNotTheTemplates) {
  const PointSet gear = make_gear(), plain = make_gear_template();
  const Index n = 12000;
  const double alpha = std::sqrt(0.64 * surface_area(gear.positions(), gear.faces()) / double(n));
  const Eigen::Vector3d offset(0.03, -0.01, 0);
  const PointSet all = random_surface_points(gear, 2 * n, 7);
  std::vector<Index> half;
  for (Index i = 0; i < all.size(); ++i)
    if (all.positions()(1, i) < 0) half.push_back(i);
  PointSet exemplar(all.positions()(Eigen::all, half).colwise() + offset);
  exemplar.set_normals(all.normals()(Eigen::all, half));
  const auto turn = [](double deg) {
    return Similarity{Eigen::AngleAxisd(deg * M_PI / 180, Eigen::Vector3d::UnitZ()).toRotationMatrix(),
                      Eigen::Vector3d::Zero(), 1};
  };
  const Synthesis syn = refine_transforms(
      exemplar, random_surface_points(plain, n, 11), {turn(90), turn(180)},
      [](const Eigen::Vector3d& p) { return p.x() < 0 ? 1 : 0; }, alpha);
  std::printf("registration offset (%.4f, %.4f, %.4f)\n", syn.registration_offset.x(), syn.registration_offset.y(),
              syn.registration_offset.z());
  EXPECT_LT((syn.registration_offset.head<2>() - offset.head<2>()).norm(), 0.2 * alpha);
  EXPECT_LT(std::abs(syn.registration_offset.z()), 1e-9);  // a turn about z sees nothing of d along z
  const std::vector<double> distance = distances_to_shifted(syn, gear, offset, alpha, -2);
  ASSERT_GT(distance.size(), 1000u);
  EXPECT_LT(ninetieth_percentile(distance), 0.5);  // 90% within half an alpha
}

// The offset is the exemplar's, not the labelling's: a crate seen from a low side (its +x and +y faces) registers
// 1.5 cm off the box, pulled by its raised relief. The labelling takes only the identity and the half turn, whose
// image (the -x and -y faces) meets the exemplar nowhere; the quarter turns, which carry one seen face onto the
// other, are candidates no region took. They fix the offset, and the half turn's image lands on the shifted crate.
TEST(SynthesizeRefinement, FitsTheOffsetWithTheTurnsNoRegionTook) {
  const PointSet crate = make_crate(), plain = make_crate_template();
  const Index n = 20000;
  const double alpha = std::sqrt(0.64 * surface_area(crate.positions(), crate.faces()) / double(n));
  const Eigen::Vector3d offset(-0.011, -0.010, 0);
  const PointSet all = random_surface_points(crate, 2 * n, 7);
  std::vector<Index> seen;  // the +x and +y faces
  for (Index i = 0; i < all.size(); ++i)
    if (all.positions()(0, i) > 0.28 || all.positions()(1, i) > 0.28) seen.push_back(i);
  PointSet exemplar(all.positions()(Eigen::all, seen).colwise() + offset);
  exemplar.set_normals(all.normals()(Eigen::all, seen));
  const auto turn = [](double deg) {
    return Similarity{Eigen::AngleAxisd(deg * M_PI / 180, Eigen::Vector3d::UnitZ()).toRotationMatrix(),
                      Eigen::Vector3d::Zero(), 1};
  };
  const Synthesis syn = refine_transforms(
      exemplar, random_surface_points(plain, n, 11), {turn(0), turn(180), turn(90), turn(270)},
      [](const Eigen::Vector3d& p) { return p.x() + p.y() < 0 ? 1 : 0; }, alpha);
  std::printf("registration offset (%.4f, %.4f, %.4f)\n", syn.registration_offset.x(), syn.registration_offset.y(),
              syn.registration_offset.z());
  EXPECT_LT((syn.registration_offset.head<2>() - offset.head<2>()).norm(), 0.2 * alpha);
  const std::vector<double> distance = distances_to_shifted(syn, crate, offset, alpha, 1);  // the half turn's
  ASSERT_GT(distance.size(), 1000u);
  EXPECT_LT(ninetieth_percentile(distance), 0.5);
}

// A target sample is copied where no patch point lies over it, even where source samples land near it: an exemplar in
// stripes 5 alpha wide and 5 alpha apart (a lid scanned at a grazing angle) leaves the strips between them empty, and
// reaching alone (within 4 alpha of a landed source sample) let them through.
TEST(SynthesizeGaps, CopiesTheTargetBetweenAnExemplarsStripes) {
  const PointSet square = make_plane(1.0, 40);
  const Index n = 8000;
  const double alpha = std::sqrt(0.64 * surface_area(square.positions(), square.faces()) / double(n));
  const PointSet all = random_surface_points(square, n, 7), target = random_surface_points(square, n, 11);
  const PointSet exemplar =
      samples_where(all, [&](const Eigen::Vector3d& p) { return std::fmod(p(0) + 0.5, 10 * alpha) < 5 * alpha; });
  const Synthesis syn = refine_one_transform(exemplar, target, Similarity{}, alpha);
  KdTree output;
  output.build(syn.points.positions());
  Index bare = 0;  // target samples with no output point within 2 alpha
  for (Index t = 0; t < target.size(); ++t) {
    std::int32_t j;
    double d2;
    output.knn(target.positions().col(t), 1, &j, &d2);
    bare += d2 > std::pow(2 * alpha, 2);
  }
  std::printf("%td gap copies, %td of %td target samples bare\n", syn.gap_copies, bare, target.size());
  EXPECT_GT(syn.gap_copies, 0);
  EXPECT_EQ(bare, 0);
}

// A panel sunk 8 alpha behind a frame that lies on the template (a real pillar's relief behind its bounding box) is
// over the template: its image needs no copy of the plain template in front of it. The same panel facing the other
// way (a thin plate's far face) is not, and the template is copied there. Returns the copies in front of the panel,
// whose region holds 0.36 of the 8000 target samples.
Index copies_in_front_of_a_sunk_panel(double panel_facing) {
  const PointSet square = make_plane(1.0, 40);
  const Index n = 8000;
  const double alpha = std::sqrt(0.64 * surface_area(square.positions(), square.faces()) / double(n));
  PointSet exemplar = random_surface_points(square, n, 7);
  Eigen::Matrix3Xd p = exemplar.positions(), normals = exemplar.normals();
  for (Index i = 0; i < p.cols(); ++i)
    if (p.col(i).head<2>().cwiseAbs().maxCoeff() < 0.3) {
      p(2, i) -= 8 * alpha;
      normals.col(i) *= panel_facing;
    }
  exemplar = PointSet(std::move(p));
  exemplar.set_normals(std::move(normals));
  const Synthesis syn = refine_one_transform(exemplar, random_surface_points(square, n, 11), Similarity{}, alpha);
  Index in_panel = 0;
  for (Index i = 0; i < syn.points.size(); ++i)
    in_panel +=
        syn.origin[size_t(i)] == Origin::kTarget && syn.points.positions().col(i).head<2>().cwiseAbs().maxCoeff() < 0.3;
  std::printf("%td gap copies, %td of them in front of the panel\n", syn.gap_copies, in_panel);
  return in_panel;
}

TEST(SynthesizeGaps, NoCopyInFrontOfAPanelSunkBehindTheTemplate) {
  EXPECT_LT(copies_in_front_of_a_sunk_panel(1.0), 0.05 * 0.36 * 8000);  // before: 2000 of the 2880
  EXPECT_GT(copies_in_front_of_a_sunk_panel(-1.0), 0.8 * 0.36 * 8000);
}

// The one-headed body seen from +x (x > -0.12: the head, at -y, whole), the rest labelled with a half turn about its
// axis, as voting leaves it on the plain template: that image puts the head at +y, where the body is plain. The
// exemplar's mirror image about x = 0 replaces it where it lands: 90% of the synthesised points on that side lie
// within an alpha of the body (0.98 measured; 0.68 with `mirror: false`).
TEST(SynthesizeMirror, ReplacesAHalfTurnsImageByTheExemplarsMirrorImage) {
  const PointSet body = one_headed_body(true), plain = one_headed_body(false);
  const Index n = 16000;
  const double alpha = std::sqrt(0.64 * surface_area(body.positions(), body.faces()) / double(n));
  const PointSet all = random_surface_points(body, 2 * n, 7);
  const PointSet exemplar = samples_where(all, [&](const Eigen::Vector3d& p) { return p(0) > -0.12; });
  const PointSet target = random_surface_points(plain, n, 11);
  const Similarity half_turn{Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ()).toRotationMatrix(),
                             Eigen::Vector3d::Zero(), 1};
  const auto label_of = [](const Eigen::Vector3d& p) { return p.x() > -0.12 ? 0 : 1; };
  const TurningPart axis{Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ()};
  KdTree model;
  const PointSet dense = random_surface_points(body, 400000, 5);
  model.build(dense.positions());
  const auto share_on_body = [&](const Synthesis& syn) {
    return share_near(model, syn.points.positions(), alpha, [&](Index i) {
      return syn.origin[size_t(i)] == Origin::kSynthesized && syn.points.positions()(0, i) <= -0.15;
    });
  };
  const Synthesis with = refine_transforms(exemplar, target, {Similarity{}, half_turn}, label_of, alpha, {}, &axis);
  SynthesisOptions off;
  off.mirror = false;
  const Synthesis without = refine_transforms(exemplar, target, {Similarity{}, half_turn}, label_of, alpha, off, &axis);
  std::printf(
      "far side's synthesised points within an alpha of the body: %.3f with the mirror (%lld added, %lld "
      "replaced), %.3f without\n",
      share_on_body(with), static_cast<long long>(with.mirror_fill), static_cast<long long>(with.mirror_replaced),
      share_on_body(without));
  ASSERT_TRUE(with.mirror.has_value());
  EXPECT_GT(std::abs(with.mirror->normal.x()), std::cos(M_PI / 180));
  EXPECT_GT(with.mirror_fill, 1000);
  EXPECT_GT(share_on_body(with), 0.9);
  EXPECT_FALSE(without.mirror.has_value());
}

// A round body with four ribs along it, a quarter turn apart (at 45, 135, 225 and 315 degrees; 0.06 high, 15 degrees
// wide); without them, its plain template.
PointSet four_ribbed_body(bool ribs) {
  return make_prism(
      [ribs](double phi) {
        const double off = std::remainder(phi - M_PI / 4, M_PI / 2);  // from the nearest rib
        return 0.3 + (ribs ? 0.06 * std::exp(-std::pow(off / 0.13, 2)) : 0.0);
      },
      0.0, 0.8, 256);
}

// A scan of one half (y < 0) repeats every quarter turn, and voting leaves the phase of the other half's turn free: it
// came labelled 121 degrees, 31 off the quarter turn, which moves the ribs 0.16 (21 alpha) at their radius, beyond the
// phase search (15 alpha). The exemplar's repeats fix the phase however far it is: the image turns to 90 degrees and
// its ribs land on the body's. Turned to the repeats only within the phase search, the image was refined by 35
// degrees and 0.15 of its rib points lay within an alpha of the body (the barrel with four medallions seen from the
// front, issue 10: an image left at 117 degrees put a medallion beside one, F 0.967 against template blending's 0.968;
// 0.970 turned).
TEST(SynthesizeRefinement, TurnsAnImageToTheExemplarsQuarterTurnRepeatsHoweverFarItsPhase) {
  const PointSet body = four_ribbed_body(true), plain = four_ribbed_body(false);
  const Index n = 16000;
  const double alpha = std::sqrt(0.64 * surface_area(body.positions(), body.faces()) / double(n));
  const PointSet all = random_surface_points(body, 2 * n, 7);
  const PointSet exemplar = samples_where(all, [&](const Eigen::Vector3d& p) { return p(1) < 0; });
  const Similarity turn{Eigen::AngleAxisd(121 * M_PI / 180, Eigen::Vector3d::UnitZ()).toRotationMatrix(),
                        Eigen::Vector3d::Zero(), 1};
  const Synthesis syn = refine_transforms(
      exemplar, random_surface_points(plain, n, 11), {Similarity{}, turn},
      [](const Eigen::Vector3d& p) { return p.y() < 0 ? 0 : 1; }, alpha);
  KdTree model, plain_model;
  const PointSet dense = random_surface_points(body, 400000, 5), dense_plain = random_surface_points(plain, 400000, 5);
  model.build(dense.positions());
  plain_model.build(dense_plain.positions());
  const auto is_rib_of_label_1 = [&](Index i) {
    if (syn.origin[size_t(i)] != Origin::kSynthesized || syn.label[size_t(i)] != 1) return false;
    std::int32_t j;
    double d2;
    plain_model.knn(syn.points.positions().col(i), 1, &j, &d2);
    return d2 > std::pow(2 * alpha, 2);
  };
  const double on_ribs = share_near(model, syn.points.positions(), alpha, is_rib_of_label_1);
  std::printf("turn refined by %.1f degrees; %.3f of its rib points within an alpha of the body\n",
              syn.refinement_deg[1], on_ribs);
  ASSERT_EQ(syn.repeats.size(), 1u);
  EXPECT_EQ(syn.repeats[0].order[0], 4);
  EXPECT_NEAR(syn.refinement_deg[1], 31.0, 1.0);
  EXPECT_GT(on_ribs, 0.9);
}

// A round body with one spout (at -y, standing 0.2 = 22 alpha off it) seen from -y, whole, the rest labelled with a
// turn about its axis by `degrees`, as voting leaves it on the plain body, the mirror off. The scan repeats about no
// axis, so the spout is its own. Returns the share of the far side's synthesised points (y >= 0.15) within 2 alpha of
// the body, and prints it.
double far_side_on_body_after_a_turn(double degrees) {
  const auto body = [](double spout) {
    return make_prism(
        [spout](double phi) {
          const double off = std::remainder(phi + M_PI / 2, 2 * M_PI);  // from the spout's direction, -y
          return 0.3 + spout * std::exp(-std::pow(off / 0.2, 2));
        },
        0.0, 0.8, 256);
  };
  const PointSet spouted = body(0.2), plain = body(0.0);
  const Index n = 16000;
  const double alpha = std::sqrt(0.64 * surface_area(spouted.positions(), spouted.faces()) / double(n));
  const PointSet all = random_surface_points(spouted, 2 * n, 7);
  const PointSet exemplar = samples_where(all, [&](const Eigen::Vector3d& p) { return p(1) < 0.12; });
  const Similarity turn{Eigen::AngleAxisd(degrees * M_PI / 180, Eigen::Vector3d::UnitZ()).toRotationMatrix(),
                        Eigen::Vector3d::Zero(), 1};
  SynthesisOptions no_mirror;
  no_mirror.mirror = false;
  const Synthesis syn = refine_transforms(
      exemplar, random_surface_points(plain, n, 11), {Similarity{}, turn},
      [](const Eigen::Vector3d& p) { return p.y() < 0.12 ? 0 : 1; }, alpha, no_mirror);
  EXPECT_TRUE(syn.repeats.empty());
  KdTree model;
  const PointSet dense = random_surface_points(spouted, 400000, 5);
  model.build(dense.positions());
  const double on_body = share_near(model, syn.points.positions(), 2 * alpha, [&](Index i) {
    return syn.origin[size_t(i)] == Origin::kSynthesized && syn.points.positions()(1, i) >= 0.15;
  });
  std::printf("turn of %.0f degrees: far side's synthesised points within 2 alpha of the body %.3f\n", degrees,
              on_body);
  return on_body;
}

// The half turn carries the body but not the spout's samples more than 8 alpha off the template, which it would put at
// +y. Its foot, under 8 alpha, is carried, as by any quarter or half turn (eq. 9's guess: a vase's knob in front has
// one behind): a stump. Measured 0.795 (0.551 with every sample carried).
TEST(SynthesizeRelief, AHalfTurnDoesNotCarryAReliefThatDoesNotRepeat) {
  EXPECT_GT(far_side_on_body_after_a_turn(180), 0.7);
}

// A turn of 135 degrees carries neither the spout nor its foot (the samples linked to it down to 1 alpha out): seen
// from straight below, a teapot's spout and handle roots were laid round its body in arcs by such turns. Measured
// 0.997 (0.793 with the foot carried).
TEST(SynthesizeRelief, ATurnThatIsNoQuarterTurnCarriesNotEvenTheFootOfAReliefThatDoesNotRepeat) {
  EXPECT_GT(far_side_on_body_after_a_turn(135), 0.95);
}

}  // namespace
}  // namespace scanfill
