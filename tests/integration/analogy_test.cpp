// Integration test of the vote -> modes -> support -> label chain (issue 3): the four stages run one after another
// with default options on procedural shapes whose analogy is known (a shape moved, scaled, copied twice, with a part
// the source lacks; a symmetric cylinder; an L of two boxes), and the labelling is checked, not each stage. Each
// stage's own known-answer tests are in tests/nodes/<stage>/.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <map>
#include <set>

#include "nodes/features/estimate_features.h"
#include "nodes/label/label.h"
#include "nodes/modes/modes.h"
#include "nodes/procedural/shapes.h"
#include "nodes/sample/sample.h"
#include "nodes/support/support.h"
#include "nodes/vote/vote.h"

namespace scanfill {
namespace {

struct Analogy {
  PointSet source, target;
  double spacing = 0;
  std::vector<SupportedTransform> transforms;
  LabelResult labels;
};

// The whole chain with default options; both shapes sampled at the same spacing.
// As the engine does: alpha is the target samples' measured mean spacing.
Analogy run(const PointSet& source_mesh, const PointSet& target_mesh, double spacing, bool allow_scale = true) {
  Analogy a;
  const SampleResult target_samples = sample(target_mesh, {.spacing = spacing});
  a.spacing = spacing = target_samples.spacing;
  a.source = estimate_features(sample(source_mesh, {.spacing = spacing}).samples, {}).points;
  a.target = estimate_features(target_samples.samples, {}).points;
  VoteOptions vo;
  vo.allow_scale = allow_scale;
  const VoteResult votes = vote(a.source, a.target, spacing, vo);
  const ModesResult modes = find_modes(votes, {});
  SupportOptions so;
  so.allow_scale = allow_scale;
  a.transforms = grow_supports(a.source, a.target, modes.modes, spacing, mode_accuracy(votes, {}), so).transforms;
  a.labels = label_target(a.source, a.target, a.transforms, spacing, {});
  if (std::getenv("SCANFILL_DEBUG"))
    std::printf("source %ld target %ld votes %ld modes %zu transforms %zu energy %g -> %g\n", long(a.source.size()),
                long(a.target.size()), long(votes.embedding.cols()), modes.modes.size(), a.transforms.size(),
                a.labels.energy_before, a.labels.energy_after);
  return a;
}

// Fraction of target samples with label l.
double coverage(const Analogy& a, int l) {
  return double(std::count(a.labels.labels.begin(), a.labels.labels.end(), l)) / double(a.labels.labels.size());
}

int dominant(const Analogy& a) {
  std::vector<Index> count(a.transforms.size() + 1, 0);
  for (int l : a.labels.labels) ++count[size_t(l)];
  return int(std::max_element(count.begin(), count.end()) - count.begin());
}

TEST(Analogy, OneRigidMotionIsRecovered) {
  Similarity g;  // T = g(S); the label's Q maps T back to S, so Q = g^-1
  g.rotation = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  g.translation = Eigen::Vector3d(0.3, -0.2, 0.5);
  const PointSet blob = make_blob();
  const Analogy a = run(blob, transformed(blob, g), 0.02, false);
  ASSERT_FALSE(a.transforms.empty());
  const int l = dominant(a);
  ASSERT_NE(l, a.labels.self_label);
  EXPECT_GE(coverage(a, l), 0.95);
  const Similarity& q = a.transforms[size_t(l)].transform;
  const double angle = rotation_angle(q.rotation * g.rotation) * 180 / M_PI;
  EXPECT_LT(angle, 1.0);
  // Translation of Q against g^-1's, compared where it matters: on the shape.
  const Eigen::Vector3d expected = -(g.rotation.transpose() * g.translation);
  EXPECT_LT((q.translation - expected).norm(), 0.5 * a.spacing) << q.translation.transpose();
}

TEST(Analogy, ScaleIsRecovered) {
  Similarity g;
  g.scale = 1.5;
  g.translation = Eigen::Vector3d(0.1, 0.2, -0.1);
  const PointSet blob = make_blob();
  const Analogy a = run(blob, transformed(blob, g), 0.02);
  const int l = dominant(a);
  ASSERT_NE(l, a.labels.self_label);
  EXPECT_GE(coverage(a, l), 0.9);
  EXPECT_NEAR(a.transforms[size_t(l)].transform.scale, 1 / 1.5, 0.03 / 1.5);
}

// Which copy each target sample lies on: the first `faces` faces of the target mesh, or the rest.
std::vector<int> part_of(const Analogy& a, Index faces_of_first) {
  std::vector<int> part;
  for (Index i = 0; i < a.target.size(); ++i) part.push_back(a.target.source_face()(i) < faces_of_first ? 0 : 1);
  return part;
}

TEST(Analogy, TwoCopiesGetTwoLabels) {
  const PointSet blob = make_blob();
  Similarity g1, g2;
  g1.translation = Eigen::Vector3d(-0.8, 0, 0);
  g2.rotation = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  g2.translation = Eigen::Vector3d(0.8, 0, 0);
  const Analogy a = run(blob, merged(transformed(blob, g1), transformed(blob, g2)), 0.025, false);
  const std::vector<int> part = part_of(a, blob.faces().cols());
  std::set<int> used(a.labels.labels.begin(), a.labels.labels.end());
  EXPECT_EQ(used.size(), 2u);
  for (int p = 0; p < 2; ++p) {
    std::map<int, Index> count;
    Index total = 0;
    for (Index i = 0; i < a.target.size(); ++i)
      if (part[size_t(i)] == p) {
        ++count[a.labels.labels[size_t(i)]];
        ++total;
      }
    const auto best =
        std::max_element(count.begin(), count.end(), [](auto& x, auto& y) { return x.second < y.second; });
    EXPECT_NE(best->first, a.labels.self_label);
    EXPECT_GE(double(best->second) / double(total), 0.9) << "copy " << p;
  }
}

TEST(Analogy, APartAbsentFromTheSourceIsSelfReferenced) {
  const PointSet blob = make_blob();
  const PointSet slab = make_box(Eigen::Vector3d(0.8, 0.8, 0.1));
  Similarity shift;
  shift.translation = Eigen::Vector3d(1.3, 0, 0);
  const Analogy a = run(blob, merged(blob, transformed(slab, shift)), 0.02, false);
  const std::vector<int> part = part_of(a, blob.faces().cols());
  Index self_on_plate = 0, plate = 0, self_on_blob = 0, on_blob = 0;
  for (Index i = 0; i < a.target.size(); ++i) {
    const bool self = a.labels.labels[size_t(i)] == a.labels.self_label;
    (part[size_t(i)] ? plate : on_blob) += 1;
    (part[size_t(i)] ? self_on_plate : self_on_blob) += self;
  }
  EXPECT_GE(double(self_on_plate) / double(plate), 0.9);
  EXPECT_LE(double(self_on_blob) / double(on_blob), 0.1);
}

TEST(Analogy, SymmetricCylinderIsNotFragmented) {
  const PointSet cylinder = make_cylinder(0.3, 1.0, 128);
  const Analogy a = run(cylinder, cylinder, 0.02, false);
  std::map<int, Index> count;
  for (int l : a.labels.labels) ++count[l];
  int tiny = 0;
  for (const auto& [l, c] : count) tiny += double(c) < 0.01 * double(a.labels.labels.size());
  EXPECT_LE(tiny, 2);
  EXPECT_LE(count.size(), 4u);
  EXPECT_LT(coverage(a, a.labels.self_label), 0.1);
}

TEST(Analogy, LOfTwoBoxesGetsOneLabelPerBox) {
  const PointSet box = make_box(Eigen::Vector3d(1.0, 0.4, 0.4));
  Similarity up;  // the second box stands upright on the first one's end: an L
  up.rotation = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY()).toRotationMatrix();
  up.translation = Eigen::Vector3d(0.3, 0, 0.7);
  const Analogy a = run(box, merged(box, transformed(box, up)), 0.025, false);
  const std::vector<int> part = part_of(a, box.faces().cols());
  std::array<std::map<int, Index>, 2> count;
  std::array<Index, 2> total{0, 0};
  for (Index i = 0; i < a.target.size(); ++i) {
    ++count[size_t(part[size_t(i)])][a.labels.labels[size_t(i)]];
    ++total[size_t(part[size_t(i)])];
  }
  std::array<int, 2> best{};
  for (int p = 0; p < 2; ++p) {
    const auto it = std::max_element(count[size_t(p)].begin(), count[size_t(p)].end(),
                                     [](auto& x, auto& y) { return x.second < y.second; });
    best[size_t(p)] = it->first;
    EXPECT_NE(it->first, a.labels.self_label);
    EXPECT_GE(double(it->second) / double(total[size_t(p)]), 0.95) << "box " << p;
  }
  EXPECT_NE(best[0], best[1]);
  EXPECT_EQ(std::set<int>(a.labels.labels.begin(), a.labels.labels.end()).size(), 2u);
}

}  // namespace
}  // namespace scanfill
