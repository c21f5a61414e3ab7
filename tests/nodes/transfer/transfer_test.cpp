// transfer node: known answers on grid meshes. A point of the exemplar follows its nearest sample's patch exactly:
// moved by exemplar_to_working, the patch's transform and working_to_output, plus the sample's alignment offset along
// its normal; points of thinned samples and the triangles they touch are left out; copies come from the target.
// copy_surface: the target as it is when dense enough, else exactly the wanted number of points on its surface.
#include "nodes/transfer/transfer.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>

#include "nodes/core/errors.h"
#include "runs_of.h"

namespace scanfill {
namespace {

Eigen::Matrix3d rot(double angle, const Eigen::Vector3d& axis) {
  return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
}

// A square of side `size` in z = 0 centred at `centre`, `segments` quads per side (2 triangles each), normals +z.
PointSet grid_mesh(int segments, double size, const Eigen::Vector3d& centre = Eigen::Vector3d::Zero()) {
  const int n = segments + 1;
  Eigen::Matrix3Xd p(3, n * n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      p.col(i * n + j) = centre + size * Eigen::Vector3d(double(j) / segments - 0.5, double(i) / segments - 0.5, 0);
  Matrix3Xi f(3, 2 * segments * segments);
  Index k = 0;
  for (int i = 0; i < segments; ++i)
    for (int j = 0; j < segments; ++j) {
      const int a = i * n + j, b = a + 1, c = a + n, d = c + 1;
      f.col(k++) = Eigen::Vector3i(a, b, d);
      f.col(k++) = Eigen::Vector3i(a, d, c);
    }
  PointSet out(p);
  out.set_normals(Eigen::Matrix3Xd::Zero(3, p.cols()).colwise() + Eigen::Vector3d::UnitZ());
  out.set_faces(f);
  return out;
}

PointSet cloud(const Eigen::Matrix3Xd& p) {
  PointSet out(p);
  out.set_normals(Eigen::Matrix3Xd::Zero(3, p.cols()).colwise() + Eigen::Vector3d::UnitZ());
  return out;
}

// A synthesis of patches, each made of base samples `samples[p]` (positions and normals in the base input's working
// frame) moved by the patch's transform.
Synthesis synthesis_of(const std::vector<Patch>& patches, const std::vector<PointSet>& samples) {
  Synthesis s;
  s.patches = patches;
  Index total = 0;
  for (const auto& b : samples) total += b.size();
  Eigen::Matrix3Xd p(3, total), n(3, total);
  Index k = 0;
  for (size_t q = 0; q < patches.size(); ++q)
    for (Index i = 0; i < samples[q].size(); ++i, ++k) {
      p.col(k) = patches[q].transform.apply(samples[q].positions().col(i));
      n.col(k) = patches[q].transform.apply_normal(samples[q].normals().col(i));
      s.origin.push_back(patches[q].origin);
      s.label.push_back(patches[q].label);
      s.patch.push_back(std::int32_t(q));
      s.base.push_back(std::int32_t(i));
      s.ring.push_back(0);
    }
  s.points = PointSet(p);
  s.points.set_normals(n);
  return s;
}

AlignResult no_alignment(const Synthesis& s) {
  AlignResult a;
  a.offset.assign(size_t(s.points.size()), 0.0);
  a.keep.assign(size_t(s.points.size()), 1);
  return a;
}

PointSet in_working_frame(const PointSet& p, const Similarity& x) {
  Eigen::Matrix3Xd q(3, p.size()), n(3, p.size());
  for (Index i = 0; i < p.size(); ++i) {
    q.col(i) = x.apply(p.positions().col(i));
    n.col(i) = x.apply_normal(p.normals().col(i));
  }
  PointSet out(q);
  out.set_normals(n);
  return out;
}

const Similarity kX{rot(M_PI / 6, Eigen::Vector3d::UnitZ()), Eigen::Vector3d(0.1, 0.2, 0.3), 2.0};  // exemplar->working
const Similarity kQ{rot(0.4, Eigen::Vector3d(1, 0, 1)), Eigen::Vector3d(1, -1, 0.5), 0.7};          // the patch's
const Similarity kW{rot(0.2, Eigen::Vector3d::UnitY()), Eigen::Vector3d(0, 0, 1), 1.5};             // working->output

TEST(Transfer, EveryExemplarPointMovesExactlyByItsPatchsTransform) {
  // Samples = the exemplar's own vertices: each vertex's nearest sample is itself.
  const PointSet E = grid_mesh(10, 1.0), samples = cloud(E.positions());
  const Synthesis s = synthesis_of({{3, Origin::kSynthesized, false, kQ}}, {in_working_frame(samples, kX)});
  AlignResult al = no_alignment(s);
  for (size_t j = 0; j < al.offset.size(); ++j) al.offset[j] = 0.001 * double(j % 7);
  const TransferResult out = transfer({E, samples, samples, samples, kX, s, al, kW});
  ASSERT_EQ(out.points.size(), E.size());
  const Similarity whole = kW.compose(kQ.compose(kX));
  for (Index i = 0; i < E.size(); ++i) {
    // Output order is the exemplar's; the offset moves along the synthesis normal, mapped to the output frame.
    const Eigen::Vector3d n_working = s.points.normals().col(i);
    const Eigen::Vector3d want =
        whole.apply(E.positions().col(i)) + al.offset[size_t(i)] * kW.scale * kW.apply_normal(n_working);
    EXPECT_LT((out.points.positions().col(i) - want).norm(), 1e-12) << "point " << i;
    EXPECT_LT((out.points.normals().col(i) - whole.apply_normal(Eigen::Vector3d::UnitZ())).norm(), 1e-12);
    EXPECT_EQ(out.origin[size_t(i)], Origin::kSynthesized);
    EXPECT_EQ(out.label[size_t(i)], 3);
  }
  // Every triangle comes along, with the same corners.
  EXPECT_EQ(out.points.faces(), E.faces());
  out.points.check();
}

TEST(Transfer, PointsFollowTheirNearestSampleAndThinnedSamplesTakeThemAway) {
  // A dense exemplar (21 x 21 vertices, step 0.05) and sparse samples (11 x 11, step 0.1) shifted off the vertices so
  // that every vertex has one nearest sample.
  const PointSet E = grid_mesh(20, 1.0);
  const PointSet samples = cloud(grid_mesh(10, 1.0, Eigen::Vector3d(0.013, 0.007, 0)).positions());
  const Synthesis s = synthesis_of({{2, Origin::kSynthesized, false, kQ}}, {samples});
  AlignResult al = no_alignment(s);
  for (size_t j = 0; j < al.keep.size(); j += 3) al.keep[j] = 0;
  for (size_t j = 0; j < al.offset.size(); ++j) al.offset[j] = 0.01 * double(j % 5);
  const TransferResult out = transfer({E, samples, samples, samples, Similarity{}, s, al, Similarity{}});
  // Brute force: each vertex's nearest sample, the vertices it keeps, their slots in the output.
  std::vector<std::int32_t> slot(size_t(E.size()), -1);
  Index emitted = 0;
  for (Index v = 0; v < E.size(); ++v) {
    Index best = 0;
    for (Index j = 1; j < samples.size(); ++j)
      if ((samples.positions().col(j) - E.positions().col(v)).squaredNorm() <
          (samples.positions().col(best) - E.positions().col(v)).squaredNorm())
        best = j;
    if (!al.keep[size_t(best)]) continue;
    slot[size_t(v)] = std::int32_t(emitted);
    const Eigen::Vector3d want =
        kQ.apply(E.positions().col(v)) + al.offset[size_t(best)] * kQ.apply_normal(Eigen::Vector3d::UnitZ());
    ASSERT_LT(emitted, out.points.size());
    EXPECT_LT((out.points.positions().col(emitted) - want).norm(), 1e-12) << "vertex " << v;
    ++emitted;
  }
  EXPECT_EQ(out.points.size(), emitted);
  EXPECT_LT(emitted, E.size());  // a third of the samples thinned: their vertices are gone
  // The triangles whose three corners were emitted, and only those.
  std::vector<Eigen::Vector3i> want_faces;
  for (Index f = 0; f < E.faces().cols(); ++f) {
    const Eigen::Vector3i c = E.faces().col(f);
    const Eigen::Vector3i m(slot[size_t(c(0))], slot[size_t(c(1))], slot[size_t(c(2))]);
    if (m.minCoeff() >= 0) want_faces.push_back(m);
  }
  ASSERT_EQ(out.points.faces().cols(), Index(want_faces.size()));
  EXPECT_GT(want_faces.size(), 0u);
  for (Index f = 0; f < out.points.faces().cols(); ++f) EXPECT_EQ(out.points.faces().col(f), want_faces[size_t(f)]);
}

TEST(Transfer, TheExemplarAndACopyOfTheTargetEachKeepTheirOriginAndLabel) {
  // Patch 0: the exemplar itself (completion's scan); patch 1: a copy of the target (self label 5), moved by c.
  const PointSet E = grid_mesh(6, 1.0), e_samples = cloud(E.positions());
  const PointSet target = cloud(grid_mesh(8, 1.0, Eigen::Vector3d(2, 0, 0)).positions());
  const PointSet t_samples = cloud(grid_mesh(4, 1.0, Eigen::Vector3d(2, 0, 0)).positions());
  const Similarity c{rot(0.3, Eigen::Vector3d::UnitZ()), Eigen::Vector3d(0, 1, 0), 1.0};
  const Synthesis s = synthesis_of({{-1, Origin::kExemplar, false, Similarity{}}, {5, Origin::kTarget, true, c}},
                                   {in_working_frame(e_samples, kX), t_samples});
  const TransferResult out = transfer({E, e_samples, target, t_samples, kX, s, no_alignment(s), kW});
  ASSERT_EQ(out.points.size(), E.size() + target.size());
  for (Index i = 0; i < E.size(); ++i) {
    EXPECT_LT((out.points.positions().col(i) - kW.apply(kX.apply(E.positions().col(i)))).norm(), 1e-12);
    EXPECT_EQ(out.origin[size_t(i)], Origin::kExemplar);
    EXPECT_EQ(out.label[size_t(i)], -1);
  }
  for (Index i = 0; i < target.size(); ++i) {
    const Index o = E.size() + i;
    EXPECT_LT((out.points.positions().col(o) - kW.apply(c.apply(target.positions().col(i)))).norm(), 1e-12);
    EXPECT_EQ(out.origin[size_t(o)], Origin::kTarget);
    EXPECT_EQ(out.label[size_t(o)], 5);
  }
  // The exemplar's triangles; the target is a cloud and adds none.
  EXPECT_EQ(out.points.faces(), E.faces());
}

TEST(Transfer, AnAlignmentOfAnotherSynthesisIsRefused) {
  const PointSet E = grid_mesh(4, 1.0), samples = cloud(E.positions());
  const Synthesis s = synthesis_of({{0, Origin::kSynthesized, false, Similarity{}}}, {samples});
  AlignResult al = no_alignment(s);
  al.keep.pop_back();
  EXPECT_THROW(transfer({E, samples, samples, samples, Similarity{}, s, al, Similarity{}}), InvariantError);
}

// A two-patch transfer with thinned samples and offsets, its exemplar a cloud (as tiles are) and a target to copy.
struct TwoPatches {
  PointSet E = cloud(grid_mesh(20, 1.0).positions());
  PointSet samples = cloud(grid_mesh(10, 1.0, Eigen::Vector3d(0.013, 0.007, 0)).positions());
  PointSet target = cloud(grid_mesh(8, 1.0, Eigen::Vector3d(2, 0, 0)).positions());
  PointSet t_samples = cloud(grid_mesh(4, 1.0, Eigen::Vector3d(2, 0, 0)).positions());
  Synthesis s = synthesis_of({{2, Origin::kSynthesized, false, kQ},
                              {-1, Origin::kExemplar, false, Similarity{}},
                              {5, Origin::kTarget, true, kX}},
                             {in_working_frame(samples, kX), in_working_frame(samples, kX), t_samples});
  AlignResult al = thinned(s);
  TransferInputs inputs() const { return {E, samples, target, t_samples, kX, s, al, kW}; }
  static AlignResult thinned(const Synthesis& s) {
    AlignResult a = no_alignment(s);
    for (size_t j = 0; j < a.keep.size(); j += 4) a.keep[j] = 0;
    for (size_t j = 0; j < a.offset.size(); ++j) a.offset[j] = 0.01 * double(j % 5);
    return a;
  }
};

// The exemplar of TwoPatches with a colour and an intensity that name each point (its index).
PointSet coloured(PointSet points) {
  Matrix3Xu8 c(3, points.size());
  Eigen::VectorXf v(points.size());
  for (Index i = 0; i < points.size(); ++i) {
    c.col(i) << std::uint8_t(i & 255), std::uint8_t(i >> 8 & 255), 7;
    v(i) = float(i) + 0.5f;
  }
  points.set_colours(std::move(c));
  points.set_intensity(std::move(v));
  return points;
}

// The points of a result as sortable tuples: position, normal, origin, label, colour and intensity (-1 when absent).
std::vector<std::array<double, 12>> point_set_of(const TransferResult& r) {
  std::vector<std::array<double, 12>> out;
  const PointSet& q = r.points;
  for (Index i = 0; i < q.size(); ++i) {
    const auto p = q.positions().col(i), n = q.normals().col(i);
    const auto c = [&](int k) { return q.has_colours() ? double(q.colours()(k, i)) : -1.0; };
    out.push_back({p.x(), p.y(), p.z(), n.x(), n.y(), n.z(), double(int(r.origin[size_t(i)])),
                   double(r.label[size_t(i)]), c(0), c(1), c(2), q.has_intensity() ? double(q.intensity()(i)) : -1.0});
  }
  std::sort(out.begin(), out.end());
  return out;
}

// Three tiles of consecutive points, then the plan-level points (the copies) alone, give the whole transfer.
void expect_tiles_give_the_whole_transfer(const TwoPatches& t) {
  const TransferResult whole = transfer(t.inputs());
  const TransferPlan plan = plan_transfer(t.inputs());
  EXPECT_TRUE(plan_copies_target(plan));
  EXPECT_EQ(plan_inconsistency(plan), "");
  std::vector<std::array<double, 12>> parts;
  Index exemplar_points = 0;
  for (const auto& range : tile_ranges(t.E.size(), 3)) {
    const PointSet part = tile_points(t.E, range);
    EXPECT_EQ(part.size(), range.second - range.first);
    const TransferResult tile = apply_plan(plan, &part, nullptr);
    exemplar_points += tile.points.size();
    for (const auto& p : point_set_of(tile)) parts.push_back(p);
  }
  const TransferResult copies = transfer_planned(plan, nullptr, &t.target);
  EXPECT_GT(copies.points.size(), 0);  // copies of the kept target samples only
  EXPECT_LT(copies.points.size(), t.target.size());
  EXPECT_EQ(copies.points.has_colours(), t.E.has_colours());  // the plan says, not the copies' own input
  for (const auto& p : point_set_of(copies)) parts.push_back(p);
  std::sort(parts.begin(), parts.end());
  EXPECT_EQ(parts, point_set_of(whole));  // bit for bit, as sets
  EXPECT_EQ(exemplar_points + copies.points.size(), whole.points.size());
  // Both exemplar patches emitted points, and the thinned samples removed some.
  EXPECT_LT(exemplar_points, 2 * t.E.size());
  EXPECT_GT(exemplar_points, t.E.size());
}

TEST(ApplyPlan, TilesOfTheExemplarAndTheCopiesGiveTheWholeTransferExactly) {
  expect_tiles_give_the_whole_transfer(TwoPatches{});
}

TEST(ApplyPlan, TilesCarryTheExemplarsColoursAndIntensityCopiesTheNeutralOnes) {
  TwoPatches t;
  t.E = coloured(t.E);
  expect_tiles_give_the_whole_transfer(t);
  const TransferResult whole = transfer(t.inputs());
  ASSERT_TRUE(whole.points.has_colours());
  ASSERT_TRUE(whole.points.has_intensity());
  for (Index i = 0; i < whole.points.size(); ++i) {
    const Eigen::Matrix<std::uint8_t, 3, 1> c = whole.points.colours().col(i);
    const float v = whole.points.intensity()(i);
    if (whole.origin[size_t(i)] == Origin::kTarget) {
      ASSERT_EQ(c, kCopiedColour) << i;
      ASSERT_EQ(v, kCopiedIntensity) << i;
    } else {  // the exemplar point's own: colour and intensity name the same point
      ASSERT_EQ(c(2), 7) << i;
      ASSERT_EQ(Index(c(0)) | Index(c(1)) << 8, Index(v)) << i;
    }
  }
  // A tile without the colours the plan's exemplar had is refused.
  const TransferPlan plan = plan_transfer(t.inputs());
  const PointSet bare(t.E.positions());
  EXPECT_THROW(apply_plan(plan, &bare, nullptr), InvariantError);
}

// The whole output of stream_plan in chunks of `chunk` input points, gathered in order, and how many runs it came in.
struct Streamed {
  TransferResult out;
  TransferCounts counts;
  Index runs = 0;
};
// With `runs`: the exemplar read from it a run at a time (stream_plan_chunks), else held whole (stream_plan).
Streamed stream_in_chunks(const TransferPlan& plan, const PointSet* exemplar, const PointSet* copies, Index chunk,
                          PointChunks* runs = nullptr) {
  Streamed s;
  std::vector<Eigen::Vector3d> P, N;
  std::vector<Eigen::Matrix<std::uint8_t, 3, 1>> C;
  std::vector<float> I;
  Matrix3Xi faces;
  const TransferSink sink{[&](const TransferCounts& c) { s.counts = c; },
                          [&](const TransferResult& run) {
                            EXPECT_LE(run.points.size(), chunk);
                            ++s.runs;
                            for (Index i = 0; i < run.points.size(); ++i) {
                              P.push_back(run.points.positions().col(i));
                              N.push_back(run.points.normals().col(i));
                              if (run.points.has_colours()) C.push_back(run.points.colours().col(i));
                              if (run.points.has_intensity()) I.push_back(run.points.intensity()(i));
                            }
                            s.out.origin.insert(s.out.origin.end(), run.origin.begin(), run.origin.end());
                            s.out.label.insert(s.out.label.end(), run.label.begin(), run.label.end());
                          },
                          [&](const Matrix3Xi& f) { faces = f; }};
  const TransferCounts counts = runs ? stream_plan_chunks(plan, *runs, exemplar->size(), copies, chunk, sink)
                                     : stream_plan(plan, exemplar, copies, chunk, sink);
  EXPECT_EQ(counts.points, s.counts.points);
  Eigen::Matrix3Xd p(3, Index(P.size())), n(3, Index(N.size()));
  for (size_t i = 0; i < P.size(); ++i) p.col(Index(i)) = P[i], n.col(Index(i)) = N[i];
  s.out.points = PointSet(p);
  s.out.points.set_normals(n);
  if (!C.empty()) {
    Matrix3Xu8 c(3, Index(C.size()));
    for (size_t i = 0; i < C.size(); ++i) c.col(Index(i)) = C[i];
    s.out.points.set_colours(c);
  }
  if (!I.empty()) s.out.points.set_intensity(Eigen::Map<const Eigen::VectorXf>(I.data(), Index(I.size())));
  if (faces.cols() > 0) s.out.points.set_faces(faces);
  return s;
}

// The same points in the same order, bit for bit, with the same attributes and triangles.
void expect_identical(const TransferResult& a, const TransferResult& b) {
  ASSERT_EQ(a.points.size(), b.points.size());
  EXPECT_EQ(a.points.positions(), b.points.positions());
  EXPECT_EQ(a.points.normals(), b.points.normals());
  EXPECT_EQ(a.points.colours(), b.points.colours());
  EXPECT_EQ(a.points.intensity(), b.points.intensity());
  EXPECT_EQ(a.points.faces(), b.points.faces());
  EXPECT_EQ(a.origin, b.origin);
  EXPECT_EQ(a.label, b.label);
}

TEST(StreamPlan, ChunksOfAnySizeGiveTheWholeTransferInItsOrder) {
  // A coloured mesh exemplar (its triangles stream after the points), two exemplar patches and a copied target.
  TwoPatches t;
  t.E = coloured(grid_mesh(20, 1.0));
  const TransferPlan plan = plan_transfer(t.inputs());
  const TransferResult whole = transfer(t.inputs());
  ASSERT_GT(whole.points.faces().cols(), 0);
  const PointSet copies = copied_points(plan, t.target);
  for (const Index chunk : {Index(1), Index(7), Index(64), Index(100000)}) {
    SCOPED_TRACE(chunk);
    const Streamed s = stream_in_chunks(plan, &t.E, &copies, chunk);
    expect_identical(s.out, whole);
    EXPECT_EQ(s.counts.faces, whole.points.faces().cols());
    EXPECT_EQ(s.counts.by_origin[0] + s.counts.by_origin[1] + s.counts.by_origin[2], whole.points.size());
    if (chunk == 7) {
      EXPECT_GT(s.runs, 100);  // many chunks
    }
  }
}

TEST(StreamPlan, AnExemplarReadInRunsGivesTheWholeTransferInItsOrder) {
  // The scan read from its file in chunks (issue 13): two exemplar patches, each a pass over the runs, and copies.
  TwoPatches t;
  const TransferPlan plan = plan_transfer(t.inputs());
  const PointSet copies = copied_points(plan, t.target);
  const TransferResult whole = apply_plan(plan, &t.E, &copies);
  test::RunsOf runs(t.E);
  for (const Index chunk : {Index(1), Index(7), Index(100000)}) {
    SCOPED_TRACE(chunk);
    const Streamed s = stream_in_chunks(plan, &t.E, &copies, chunk, &runs);
    expect_identical(s.out, whole);
    EXPECT_EQ(s.counts.points, whole.points.size());
    EXPECT_EQ(s.counts.by_origin[0] + s.counts.by_origin[1] + s.counts.by_origin[2], whole.points.size());
  }
  // An exemplar with colours needs them in the runs: refused, not carried grey.
  TwoPatches c;
  c.E = coloured(c.E);
  const TransferPlan coloured_plan = plan_transfer(c.inputs());
  test::RunsOf coloured_runs(c.E);
  EXPECT_THROW(stream_plan_chunks(coloured_plan, coloured_runs, c.E.size(), nullptr, 7, {}), InvariantError);
}

TEST(StreamPlan, EveryKthKeepsTheOutputPointsWhoseIndexIsAMultipleOfK) {
  TwoPatches t;
  t.E = coloured(t.E);
  const TransferPlan plan = plan_transfer(t.inputs());
  const PointSet copies = copied_points(plan, t.target);
  const TransferResult whole = apply_plan(plan, &t.E, &copies);
  EveryKth every(3);
  const TransferSink sink{{}, [&](const TransferResult& run) { every.add(run); }, {}};
  stream_plan(plan, &t.E, &copies, 7, sink);
  const TransferResult kept = every.take();
  std::vector<std::int32_t> rows;
  for (Index i = 0; i < whole.points.size(); i += 3) rows.push_back(std::int32_t(i));
  TransferResult want;
  want.points = subset(whole.points, rows);
  for (const auto r : rows)
    want.origin.push_back(whole.origin[size_t(r)]), want.label.push_back(whole.label[size_t(r)]);
  expect_identical(kept, want);
}

TEST(StreamPlan, CopiedPointsAreTheCopySurfacesCopiesWithoutTheRest) {
  // A low-poly target (9 vertices) is copied from random points on its surface at the exemplar's density: copied_points
  // makes them block by block and keeps the copied ones, in the order of the whole copy surface.
  TwoPatches t;
  t.target = grid_mesh(2, 1.0, Eigen::Vector3d(2, 0, 0));
  const TransferPlan plan = plan_transfer(t.inputs());
  const PointSet surface =
      copy_surface(t.target, plan.exemplar_points, plan.exemplar_samples.cols(), plan.target_samples.cols());
  ASSERT_GT(surface.size(), t.target.size());  // random surface points, not the vertices
  const PointSet copies = copied_points(plan, t.target);
  EXPECT_GT(copies.size(), 0);
  EXPECT_LT(copies.size(), surface.size());  // a thinned target sample's points are left out
  expect_identical(apply_plan(plan, nullptr, &copies), apply_plan(plan, nullptr, &surface));
}

TEST(ApplyPlan, PointsOutsideThePlansScanAreFound) {
  const TwoPatches t;
  const TransferPlan plan = plan_transfer(t.inputs());
  EXPECT_EQ(first_point_outside(plan, t.E), -1);
  Eigen::Matrix3Xd p = t.E.positions();
  p.col(7) += Eigen::Vector3d(0, 0, 0.01);
  EXPECT_EQ(first_point_outside(plan, PointSet(p)), 7);
}

TEST(ApplyPlan, InconsistentPlansAreNamed) {
  const TwoPatches t;
  TransferPlan plan = plan_transfer(t.inputs());
  plan.base[3] = std::int32_t(plan.exemplar_samples.cols());
  EXPECT_NE(plan_inconsistency(plan).find("base out of range"), std::string::npos);
  plan = plan_transfer(t.inputs());
  plan.patch[0] = 9;
  EXPECT_NE(plan_inconsistency(plan).find("patch out of range"), std::string::npos);
  plan = plan_transfer(t.inputs());
  plan.shift.pop_back();
  EXPECT_NE(plan_inconsistency(plan), "");
}

TEST(TileRanges, ConsecutiveRunsCoverEveryIndexOnce) {
  const auto r = tile_ranges(10, 4);
  ASSERT_EQ(r.size(), 4u);
  EXPECT_EQ(r[0], std::make_pair(Index(0), Index(3)));
  EXPECT_EQ(r[1], std::make_pair(Index(3), Index(6)));
  EXPECT_EQ(r[2], std::make_pair(Index(6), Index(8)));
  EXPECT_EQ(r[3], std::make_pair(Index(8), Index(10)));
  EXPECT_THROW(tile_ranges(10, 0), InvariantError);
}

TEST(CopySurface, ACloudOrADenseEnoughMeshIsTheTargetItself) {
  const PointSet c = cloud(grid_mesh(4, 1.0).positions());
  EXPECT_EQ(&copy_surface(c, 100000, 10, 10).positions(), &c.positions());  // shared, not copied
  // 41 x 41 = 1681 vertices >= 10 per sample x 100 samples.
  const PointSet dense = grid_mesh(40, 1.0);
  const PointSet same = copy_surface(dense, 1000, 100, 100);
  EXPECT_EQ(&same.positions(), &dense.positions());
  EXPECT_TRUE(same.has_faces());
  // No exemplar samples to measure a density by: as it is.
  const PointSet coarse = grid_mesh(4, 1.0);
  EXPECT_EQ(copy_surface(coarse, 1000, 0, 100).size(), coarse.size());
}

TEST(CopySurface, ACoarseMeshGivesTheExemplarsDensityOnItsSurface) {
  const PointSet coarse = grid_mesh(4, 1.0);  // 25 vertices
  // 10 exemplar points per sample, 50 target samples: 500 points, on the square, without triangles.
  const PointSet p = copy_surface(coarse, 1000, 100, 50);
  ASSERT_EQ(p.size(), 500);
  EXPECT_FALSE(p.has_faces());
  for (Index i = 0; i < p.size(); ++i) {
    EXPECT_NEAR(p.positions()(2, i), 0.0, 1e-12);
    EXPECT_LE(p.positions().col(i).head<2>().cwiseAbs().maxCoeff(), 0.5 + 1e-12);
  }
  EXPECT_EQ(copy_surface(coarse, 1000, 100, 50).positions(), p.positions());  // seeded
  // The density rounds up (10.01 x 50 = 500.5 -> 501) and is never below one point per sample.
  EXPECT_EQ(copy_surface(coarse, 1001, 100, 50).size(), 501);
  EXPECT_EQ(copy_surface(coarse, 10, 100, 50).size(), 50);
}

}  // namespace
}  // namespace scanfill
