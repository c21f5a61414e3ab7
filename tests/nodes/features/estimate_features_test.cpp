#include "nodes/features/estimate_features.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "nodes/core/errors.h"
#include "nodes/procedural/shapes.h"
#include "nodes/sample/sample.h"

namespace scanfill {
namespace {

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

PointSet samples_of(const PointSet& mesh, Index count) {
  return sample(mesh, {.count = count}).samples;
}

TEST(Features, SphereCurvatureIsOneOverRadiusAndNormalsPointOut) {
  const double r = 0.5;
  const FeaturesResult f = estimate_features(samples_of(make_sphere(r, 128), 8000), {});
  const PointSet& p = f.points;
  std::vector<double> k1, k2;
  Index outward = 0;
  for (Index i = 0; i < p.size(); ++i) {
    k1.push_back(p.curvatures()(0, i));
    k2.push_back(p.curvatures()(1, i));
    outward += p.normals().col(i).dot(p.positions().col(i).normalized()) > 0.9;
  }
  EXPECT_NEAR(median(k1), 1 / r, 0.05 / r);
  EXPECT_NEAR(median(k2), 1 / r, 0.05 / r);
  EXPECT_EQ(outward, p.size());
  // Every direction on a sphere is umbilic: all come from the cross field, and are unit tangent vectors.
  EXPECT_GT(f.unreliable_directions, p.size() / 2);
  for (Index i = 0; i < p.size(); ++i) {
    EXPECT_NEAR(p.directions().col(i).norm(), 1.0, 1e-9);
    EXPECT_LT(std::abs(p.directions().col(i).dot(p.normals().col(i))), 1e-9);
  }
}

TEST(Features, SphereCloudWithoutNormalsIsOrientedOutwardByPropagation) {
  const double r = 0.5;
  const PointSet cloud(samples_of(make_sphere(r, 128), 6000).positions());  // positions only
  const FeaturesResult f = estimate_features(cloud, {});
  EXPECT_EQ(f.orientation_used, NormalOrientation::kPropagate);
  Index outward = 0;
  std::vector<double> k1;
  for (Index i = 0; i < cloud.size(); ++i) {
    outward += f.points.normals().col(i).dot(cloud.positions().col(i)) > 0;
    k1.push_back(f.points.curvatures()(0, i));
  }
  EXPECT_EQ(outward, cloud.size());
  EXPECT_NEAR(median(k1), 1 / r, 0.05 / r);
}

TEST(Features, CylinderHasOneOverRAndZeroWithCircumferentialDirection) {
  const double r = 0.3;
  const FeaturesResult f = estimate_features(samples_of(make_cylinder(r, 1.0, 128), 8000), {});
  const PointSet& p = f.points;
  std::vector<double> k1, k2, axial, outward;
  for (Index i = 0; i < p.size(); ++i) {
    if (std::abs(p.positions()(2, i)) > 0.4) continue;  // away from the open ends
    k1.push_back(p.curvatures()(0, i));
    k2.push_back(std::abs(p.curvatures()(1, i)));
    axial.push_back(std::abs(p.directions()(2, i)));  // k1 direction: circumferential, so no z component
    const Eigen::Vector3d radial(p.positions()(0, i), p.positions()(1, i), 0);
    outward.push_back(p.normals().col(i).dot(radial.normalized()));
  }
  EXPECT_NEAR(median(k1), 1 / r, 0.05 / r);
  EXPECT_LT(median(k2), 0.05 / r);
  EXPECT_LT(median(axial), 0.05);
  EXPECT_GT(*std::min_element(outward.begin(), outward.end()), 0.9);
}

TEST(Features, PlaneHasZeroCurvatureAndOneNormal) {
  const FeaturesResult f = estimate_features(samples_of(make_plane(1.0, 16), 3000), {});
  EXPECT_LT(f.points.curvatures().cwiseAbs().maxCoeff(), 1e-6);
  EXPECT_GT(f.points.normals().row(2).minCoeff(), 1 - 1e-9);
}

// A lid seen at a grazing angle at a low resolution: scan rows 10 cm apart, 2 mm between points along each, so that
// every point's neighbours lie on its own row and PCA cannot tell the normal's turn about the row. The scanner's own
// A wider neighbourhood's PCA normal stands there, or, on a row alone, the scanner's own; the PCA normal of the k
// neighbours alone faced anywhere square to the row.
TEST(Features, ScanRowsWhoseNeighboursLieOnALineKeepTheInputsNormals) {
  const int rows = 8, per_row = 150;
  Eigen::Matrix3Xd p(3, rows * per_row);
  for (int r = 0; r < rows; ++r)
    for (int i = 0; i < per_row; ++i) p.col(r * per_row + i) = Eigen::Vector3d(0.002 * i, 0.1 * r, 0.6);
  PointSet scan(p);
  scan.set_normals(Eigen::Matrix3Xd(Eigen::Vector3d::UnitZ().replicate(1, p.cols())));
  const FeaturesResult f = estimate_features(scan, {});
  EXPECT_GT(f.points.normals().row(2).minCoeff(), std::cos(1.0 * M_PI / 180));
  // Without the scanner's normals (a bare XYZ cloud), a wider neighbourhood reaches the next rows.
  const FeaturesResult bare = estimate_features(PointSet(p), {});
  EXPECT_GT(bare.points.normals().row(2).cwiseAbs().minCoeff(), std::cos(1.0 * M_PI / 180));
  // One row alone, which no neighbourhood widens off its line: the scanner's normals stand.
  PointSet row(Eigen::Matrix3Xd(p.leftCols(per_row)));
  row.set_normals(Eigen::Matrix3Xd(Eigen::Vector3d::UnitZ().replicate(1, per_row)));
  EXPECT_GT(estimate_features(row, {}).points.normals().row(2).minCoeff(), std::cos(1.0 * M_PI / 180));
}

TEST(Features, ViewpointOrientationFacesTheSensor) {
  PointSet cloud(samples_of(make_plane(1.0, 16), 2000).positions());
  cloud.set_viewpoint(Eigen::Vector3d(0.2, 0.1, -3.0));
  const FeaturesResult f = estimate_features(cloud, {});
  EXPECT_EQ(f.orientation_used, NormalOrientation::kViewpoint);
  EXPECT_LT(f.points.normals().row(2).maxCoeff(), -1 + 1e-9);
  FeaturesOptions o;
  o.viewpoint = Eigen::Vector3d(0, 0, 5);  // the option overrides the file's viewpoint
  EXPECT_GT(estimate_features(cloud, o).points.normals().row(2).minCoeff(), 1 - 1e-9);
}

TEST(Features, SameOutputOnOneAndTwoThreads) {
  const PointSet s = samples_of(make_vase(), 6000);
  FeaturesResult one, two;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = estimate_features(s, {});
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
    two = estimate_features(s, {});
  }
  EXPECT_EQ(one.points.normals(), two.points.normals());
  EXPECT_EQ(one.points.curvatures(), two.points.curvatures());
  EXPECT_EQ(one.points.directions(), two.points.directions());
}

// Propagation over the kNN graph's minimum spanning forest: two spheres far apart are two trees, each oriented
// outward on its own, and the normals are the same bytes whatever the thread count (the edges are sorted in parallel).
TEST(Features, TwoSeparateCloudsAreEachOrientedOutwardOnAnyThreadCount) {
  const Eigen::Matrix3Xd sphere = samples_of(make_sphere(0.5, 128), 3000).positions();
  const Eigen::Vector3d shift(5, 0, 0);
  Eigen::Matrix3Xd both(3, 2 * sphere.cols());
  both << sphere, sphere.colwise() + shift;
  const PointSet cloud(both);
  FeaturesResult one, two;
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 1);
    one = estimate_features(cloud, {});
  }
  {
    tbb::global_control c(tbb::global_control::max_allowed_parallelism, 2);
    two = estimate_features(cloud, {});
  }
  ASSERT_EQ(one.orientation_used, NormalOrientation::kPropagate);
  EXPECT_EQ(one.points.normals(), two.points.normals());
  Index outward = 0;
  for (Index i = 0; i < cloud.size(); ++i) {
    const Eigen::Vector3d centre = i < sphere.cols() ? Eigen::Vector3d::Zero() : shift;
    outward += one.points.normals().col(i).dot(cloud.positions().col(i) - centre) > 0;
  }
  EXPECT_EQ(outward, cloud.size());
}

// Issue 11: an absolute determinant bound in the shape-operator fit made every point of a model scaled to 1e-5 flat
// (k1 = k2 = 0). Curvature scales as 1 / size: the same cloud scaled by s has curvatures divided by s.
TEST(Features, CurvatureIsScaleFree) {
  const PointSet unit(samples_of(make_sphere(0.5, 128), 4000).positions());
  for (const double s : {1e-5, 1e-3, 1e4}) {
    const FeaturesResult scaled = estimate_features(PointSet(unit.positions() * s), {});
    std::vector<double> ratio;
    for (Index i = 0; i < unit.size(); ++i) ratio.push_back(scaled.points.curvatures()(0, i) * s);
    EXPECT_NEAR(median(ratio), 2.0, 0.1) << "scale " << s;  // 1 / r, r = 0.5
    Index flat = 0;
    for (Index i = 0; i < unit.size(); ++i) flat += scaled.points.curvatures()(0, i) == 0;
    EXPECT_EQ(flat, 0) << "scale " << s;
  }
}

TEST(Features, RefusesTooFewPointsAndImpossibleOrientation) {
  const PointSet tiny(Eigen::Matrix3Xd::Random(3, 10));
  EXPECT_THROW(estimate_features(tiny, {}), InputError);
  const PointSet cloud(samples_of(make_plane(1.0, 4), 100).positions());
  FeaturesOptions o;
  o.orientation = NormalOrientation::kViewpoint;
  EXPECT_THROW(estimate_features(cloud, o), InputError);
  o.orientation = NormalOrientation::kInput;
  EXPECT_THROW(estimate_features(cloud, o), InputError);
}

}  // namespace
}  // namespace scanfill
