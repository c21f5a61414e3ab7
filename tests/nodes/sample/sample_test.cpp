#include "nodes/sample/sample.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <random>

#include "nodes/core/errors.h"
#include "nodes/core/kdtree.h"
#include "nodes/procedural/shapes.h"
#include "runs_of.h"

namespace scanfill {
namespace {

// Nearest-neighbour distance of every point.
std::vector<double> nn_distances(const Eigen::Matrix3Xd& p) {
  KdTree tree;
  tree.build(p);
  std::vector<double> d(static_cast<size_t>(p.cols()));
  for (Index i = 0; i < p.cols(); ++i) {
    std::int32_t idx[2];
    double d2[2];
    tree.knn(p.col(i), 2, idx, d2);
    d[size_t(i)] = std::sqrt(d2[1]);
  }
  return d;
}

double mean(const std::vector<double>& v) {
  return std::accumulate(v.begin(), v.end(), 0.0) / double(v.size());
}
double min(const std::vector<double>& v) {
  return *std::min_element(v.begin(), v.end());
}

TEST(Sample, PoissonDiskPropertyOnAPlane) {
  const PointSet plane = make_plane(1.0, 20);
  SampleOptions o;
  o.count = 4000;
  const SampleResult r = sample(plane, o);
  ASSERT_EQ(r.samples.size(), 4000);
  const auto d = nn_distances(r.samples.positions());
  EXPECT_GE(min(d), 0.6 * mean(d)) << "min " << min(d) << " mean " << mean(d);
  // The same number of uniformly random points has a minimum near 0: the property is not automatic.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.5, 0.5);
  Eigen::Matrix3Xd random(3, 4000);
  for (Index i = 0; i < 4000; ++i) random.col(i) << u(rng), u(rng), 0;
  const auto dr = nn_distances(random);
  EXPECT_LT(min(dr), 0.1 * mean(dr));
}

TEST(Sample, PoissonDiskPropertyOnACloudAndProvenance) {
  const PointSet dense = make_sphere(1.0, 256);  // 33k vertices used as a cloud
  const PointSet cloud(dense.positions());
  SampleOptions o;
  o.count = 3000;
  const SampleResult r = sample(cloud, o);
  ASSERT_EQ(r.samples.size(), 3000);
  ASSERT_TRUE(r.samples.has_source_index());
  for (Index i = 0; i < r.samples.size(); ++i)
    ASSERT_EQ(r.samples.positions().col(i), cloud.positions().col(r.samples.source_index()(i)));
  // The lat-long vertices crowd at the poles; the samples must not.
  const auto d = nn_distances(r.samples.positions());
  EXPECT_GE(min(d), 0.6 * mean(d)) << "min " << min(d) << " mean " << mean(d);
}

// The hexagon a vase is drawn in, split until its edges are at most 2 cm: its walls' long triangles 6 times, its caps'
// 5 times, so that its points spread as its area does; its area and winding kept (the area vectors of a closed surface
// sum to zero), and no more splits than the cap allows.
TEST(Sample, SubdividedMeshKeepsItsSurfaceWithEdgesAtMostTheLengthAsked) {
  const PointSet hexagon = make_lowpoly_cylinder(0.33, 0, 1.0, 6);
  const auto area = [](const PointSet& m) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    double total = 0;
    for (Index f = 0; f < m.faces().cols(); ++f) {
      const Eigen::Vector3d a = m.positions().col(m.faces()(0, f)), b = m.positions().col(m.faces()(1, f)),
                            c = m.positions().col(m.faces()(2, f));
      sum += (b - a).cross(c - a);
      total += 0.5 * (b - a).cross(c - a).norm();
    }
    return std::make_pair(total, sum.norm());
  };
  const PointSet fine = subdivided_mesh(hexagon, 0.02, Index(1) << 21);
  EXPECT_EQ(fine.faces().cols(), 12 * 4096 + 12 * 1024);
  EXPECT_NEAR(area(fine).first, area(hexagon).first, 1e-9);
  EXPECT_LT(area(fine).second, 1e-9) << "closed and wound as it was";
  for (Index f = 0; f < fine.faces().cols(); ++f)
    for (int k = 0; k < 3; ++k)
      ASSERT_LE((fine.positions().col(fine.faces()(k, f)) - fine.positions().col(fine.faces()((k + 1) % 3, f))).norm(),
                0.02);
  EXPECT_EQ(subdivided_mesh(hexagon, 0.02, 1000).faces().cols(), 12 * 64 + 12 * 16) << "the cap holds";
  const PointSet whole = subdivided_mesh(hexagon, 2.0, 1000);
  EXPECT_EQ(whole.faces(), hexagon.faces()) << "short enough already: the mesh itself, on its shared vertices";
  EXPECT_EQ(whole.size(), hexagon.size());
  EXPECT_THROW(subdivided_mesh(PointSet(hexagon.positions()), 0.02, 1000), InputError);
}

TEST(Sample, MeshSamplesCarryFaceAndBarycentrics) {
  const PointSet mesh = make_cylinder(0.3, 1.0, 64);
  const SampleResult r = sample(mesh, {.count = 1000});
  ASSERT_TRUE(r.samples.has_face_provenance());
  for (Index i = 0; i < r.samples.size(); ++i) {
    const auto f = r.samples.source_face()(i);
    const Eigen::Vector3d b = r.samples.barycentrics().col(i);
    EXPECT_NEAR(b.sum(), 1.0, 1e-12);
    const Eigen::Vector3d p = b(0) * mesh.positions().col(mesh.faces()(0, f)) +
                              b(1) * mesh.positions().col(mesh.faces()(1, f)) +
                              b(2) * mesh.positions().col(mesh.faces()(2, f));
    EXPECT_LT((p - r.samples.positions().col(i)).norm(), 1e-12);
  }
}

TEST(Sample, SpacingGivesThatMeanNearestNeighbourDistance) {
  for (const PointSet& shape : {make_plane(1.0, 16), make_sphere(0.5, 96)}) {
    const double alpha = 0.02;
    const SampleResult r = sample(shape, {.spacing = alpha});
    EXPECT_NEAR(r.spacing, alpha, 0.05 * alpha) << r.samples.size() << " samples, area " << r.area << ", factor "
                                                << r.spacing * r.spacing * double(r.samples.size()) / r.area;
  }
}

TEST(Sample, BothSidesOfAThinSheetSurvive) {
  // Two facing sheets 0.002 apart, far closer than the sample spacing (~0.02), with opposite normals.
  PointSet top = make_plane(1.0, 8), bottom = make_plane(1.0, 8);
  Eigen::Matrix3Xd p(3, top.size() * 2);
  p << top.positions(), bottom.positions();
  p.block(2, top.size(), 1, top.size()).setConstant(-0.002);
  Matrix3Xi f(3, top.faces().cols() * 2);
  Matrix3Xi flipped = bottom.faces();
  flipped.row(1).swap(flipped.row(2));  // the lower sheet faces down
  f << top.faces(), (flipped.array() + std::int32_t(top.size())).matrix();
  PointSet sheet(p);
  sheet.set_faces(f);
  const SampleResult r = sample(sheet, {.count = 2000});
  const Index upper = (r.samples.positions().row(2).array() > -0.001).count();
  EXPECT_NEAR(double(upper) / 2000.0, 0.5, 0.05);
}

TEST(Sample, AVeryDenseCloudIsThinnedFirstAndStillGivesPoissonDiskSamples) {
  // 300k points on a sphere sampled to 2500 (120 points per sample, like a 10^6-point scan sampled at a template's
  // spacing): the cloud is thinned before elimination (16 candidates per sample, not 120), the samples keep the
  // Poisson-disk property, the requested spacing, provenance, and the two sides of a thin sheet.
  const PointSet sphere = random_surface_points(make_sphere(0.5, 96), 300000, 3);
  const double area = 4 * M_PI * 0.25, alpha = std::sqrt(0.64 * area / 2500);
  const SampleResult r = sample(sphere, {.spacing = alpha});
  EXPECT_LT(r.candidates, 40 * r.samples.size());
  EXPECT_GT(r.candidates, 8 * r.samples.size());
  EXPECT_NEAR(r.spacing, alpha, 0.05 * alpha);
  const auto d = nn_distances(r.samples.positions());
  EXPECT_GE(min(d), 0.6 * mean(d)) << "min " << min(d) << " mean " << mean(d);
  for (Index i = 0; i < r.samples.size(); ++i)
    ASSERT_EQ(r.samples.positions().col(i), sphere.positions().col(r.samples.source_index()(i)));

  // A dense two-sided sheet (0.002 apart, spacing ~0.02) as a cloud with normals: both sides survive the thinning.
  PointSet top = random_surface_points(make_plane(1.0, 8), 100000, 4);
  Eigen::Matrix3Xd p(3, 2 * top.size()), n(3, 2 * top.size());
  p << top.positions(), top.positions();
  p.block(2, top.size(), 1, top.size()).setConstant(-0.002);
  n.leftCols(top.size()).colwise() = Eigen::Vector3d::UnitZ();
  n.rightCols(top.size()).colwise() = -Eigen::Vector3d::UnitZ();
  PointSet sheet(p);
  sheet.set_normals(n);
  const SampleResult two = sample(sheet, {.count = 2000});
  EXPECT_LT(two.candidates, 40 * 2000);
  const Index upper = (two.samples.positions().row(2).array() > -0.001).count();
  EXPECT_NEAR(double(upper) / 2000.0, 0.5, 0.05);
}

TEST(SampleChunks, GridThinningRunByRunKeepsTheWholeCloudsPoints) {
  // Issue 13: the sampler thins a cloud too large to hold a run at a time; any runs give the whole cloud's thinning.
  const PointSet sphere = random_surface_points(make_sphere(0.5, 48), 5000, 5);
  const double h = 0.08;
  const std::vector<Index> whole = thin_on_grid(sphere.positions(), sphere.normals(), h);
  ASSERT_LT(whole.size(), 5000u / 3);  // several points per cell
  test::RunsOf runs(sphere);
  for (const Index chunk : {Index(1), Index(7), sphere.size()}) {
    SCOPED_TRACE(chunk);
    GridThinner thinner(sphere.positions().rowwise().minCoeff(), h);
    PointSet run;
    runs.rewind();
    while (runs.next(chunk, run)) thinner.add(run);
    const PointSet kept = thinner.take();
    ASSERT_EQ(kept.size(), Index(whole.size()));
    for (Index k = 0; k < kept.size(); ++k) {
      const Index i = whole[size_t(k)];
      ASSERT_EQ(kept.source_index()(k), i);
      ASSERT_EQ(kept.positions().col(k), sphere.positions().col(i));
      ASSERT_EQ(kept.normals().col(k), sphere.normals().col(i));
    }
  }
}

TEST(SampleChunks, ADenseCloudReadInRunsGivesPoissonDiskSamplesOfItsOwnPoints) {
  // 200 points per sample: thinned run by run, then sampled as a held cloud. The samples are points of the cloud
  // (source_index: the row), as many as asked, and keep the Poisson-disk property.
  const PointSet sphere = random_surface_points(make_sphere(0.5, 48), 100000, 6);
  test::RunsOf runs(sphere);
  const ChunksSummary summary = summarize_chunks(runs, 4096, 20000);
  EXPECT_EQ(summary.points, sphere.size());
  EXPECT_EQ(summary.bounds.min, Eigen::Vector3d(sphere.positions().rowwise().minCoeff()));
  EXPECT_EQ(summary.every_kth.size(), 20000);
  const SampleResult r = sample_chunks(runs, summary, {.count = 500}, 4096);
  EXPECT_EQ(r.samples.size(), 500);
  EXPECT_LT(r.candidates, 40 * 500);
  for (Index i = 0; i < r.samples.size(); ++i)
    ASSERT_EQ(r.samples.positions().col(i), sphere.positions().col(r.samples.source_index()(i)));
  const auto d = nn_distances(r.samples.positions());
  EXPECT_GE(min(d), 0.6 * mean(d)) << "min " << min(d) << " mean " << mean(d);
}

TEST(Sample, SameSeedSameSamplesOnOneAndTwoThreads) {
  const PointSet mesh = make_vase();
  SampleResult one, two;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = sample(mesh, {.count = 5000, .seed = 7});
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
    two = sample(mesh, {.count = 5000, .seed = 7});
  }
  EXPECT_EQ(one.samples.positions(), two.samples.positions());
  EXPECT_EQ(one.samples.source_face(), two.samples.source_face());
  const SampleResult other = sample(mesh, {.count = 5000, .seed = 8});
  EXPECT_NE(one.samples.positions(), other.samples.positions());
}

TEST(Sample, RefusesWhatTheInputCannotGive) {
  const PointSet cloud(make_plane(1.0, 9).positions());  // 100 points
  EXPECT_THROW(sample(cloud, {.count = 101}), InputError);
  try {
    sample(cloud, {.spacing = 1e-4});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("use a larger spacing"), std::string::npos) << e.what();
  }
  EXPECT_THROW(sample(PointSet(Eigen::Matrix3Xd::Zero(3, 2)), {}), InputError);
  PointSet flat(Eigen::Matrix3Xd::Zero(3, 3));
  flat.set_faces(Matrix3Xi(Eigen::Vector3i(0, 1, 2)));
  EXPECT_THROW(sample(flat, {}), InputError);
}

TEST(Sample, ChecksItsOwnOptionsNamingTheKey) {
  // The config's range checks run at the node's entry too, so a direct caller cannot bypass them.
  const PointSet plane = make_plane(1.0, 8);
  try {
    sample(plane, {.count = 0, .oversampling = 1.0});
    FAIL();
  } catch (const ConfigError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("sample.count: expected an integer >= 1"), std::string::npos) << what;
    EXPECT_NE(what.find("sample.oversampling: expected a number in [2, 100]"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace scanfill
