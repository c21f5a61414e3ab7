// The free space a single-view scan shows (free_space.h): a lid over a cup seen from above lies in it; the cup's own
// unseen surface never does.
#include "nodes/correspond/free_space.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <numeric>

#include "nodes/procedural/shapes.h"
#include "nodes/sample/sample.h"
#include "nodes/scan/virtual_scan.h"
#include "sweep_camera.h"

namespace scanfill {
namespace {

constexpr double kSpacing = 0.01;

// The procedural cup (the vase with an inner wall, a rim and a floor): the virtual scanner keeps the faces turned to
// it, and sees the cup's inside through its mouth, as a real one does.
struct Cup {
  PointSet mesh = make_cup();
  BoundingBox box = bounding_box(mesh.positions());
};

// The scan of `vase` from along `view`, at the sweep's distance, thinned to the samples' spacing.
PointSet scan_of(const Cup& vase, const Eigen::Vector3d& view) {
  const ScanResult scan = virtual_scan(vase.mesh, test::sweep_camera(vase.mesh, view));
  PointSet samples = sample(scan.points, {.spacing = kSpacing, .seed = 1}).samples;
  samples.set_viewpoint(scan.points.viewpoint());
  return samples;
}

// A lid on the vase's mouth, as a plain closed cylinder drawn about it has: a disk at its top, 0.6 of the mouth's
// radius wide.
PointSet lid_of(const Cup& vase) {
  double mouth = 0;
  const Eigen::Vector3d centre = (vase.box.min + vase.box.max) / 2;
  for (Index i = 0; i < vase.mesh.size(); ++i) {
    const Eigen::Vector3d p = vase.mesh.positions().col(i);
    if (p.z() > vase.box.max.z() - 0.01) mouth = std::max(mouth, (p - centre).head<2>().norm());
  }
  std::vector<Eigen::Vector3d> disk;
  for (double x = -0.6 * mouth; x <= 0.6 * mouth; x += kSpacing)
    for (double y = -0.6 * mouth; y <= 0.6 * mouth; y += kSpacing)
      if (std::hypot(x, y) <= 0.6 * mouth) disk.emplace_back(centre.x() + x, centre.y() + y, vase.box.max.z());
  Eigen::Matrix3Xd P(3, Index(disk.size()));
  for (size_t k = 0; k < disk.size(); ++k) P.col(Index(k)) = disk[k];
  PointSet lid(std::move(P));
  lid.set_normals(Eigen::Vector3d::UnitZ().replicate(1, lid.size()));
  return lid;
}

double share_of(const std::vector<std::uint8_t>& flags) {
  return double(std::accumulate(flags.begin(), flags.end(), 0)) / double(std::max<size_t>(flags.size(), 1));
}

TEST(SeenThrough, ALidOverACupSeenFromAboveIsSeenThroughAndTheCupsUnseenSideNever) {
  const Cup vase;
  const PointSet lid = lid_of(vase);
  const Eigen::Vector3d above(0.3, -0.2, 1.0);
  const PointSet scan = scan_of(vase, above);
  ASSERT_TRUE(scan.viewpoint());

  EXPECT_GT(share_of(seen_through(scan, Similarity{}, *scan.viewpoint(), lid, kSpacing)), 0.9);
  // From the side the mouth is not looked into: nothing is seen beyond the lid.
  const PointSet side = scan_of(vase, Eigen::Vector3d(1.0, 0.2, 0.05));
  EXPECT_LT(share_of(seen_through(side, Similarity{}, *side.viewpoint(), lid, kSpacing)), 0.02);
  // The cup's surface the view from above did not see (its outside, below and behind): never seen through, judged by
  // depth alone (without normals, every sample faces the eye).
  for (const Eigen::Vector3d& other : {Eigen::Vector3d(-0.3, 0.2, -1.0), Eigen::Vector3d(-1.0, 0.3, 0.1)}) {
    const PointSet unseen(scan_of(vase, other).positions());
    const std::vector<std::uint8_t> judged = seen_through(scan, Similarity{}, *scan.viewpoint(), unseen, kSpacing);
    EXPECT_EQ(std::accumulate(judged.begin(), judged.end(), 0), 0) << other.transpose();
  }
}

TEST(SeenThrough, TheScanAndItsEyeAreCarriedIntoTheTargetsFrame) {
  const Cup vase;
  const PointSet lid = lid_of(vase);
  const PointSet scan = scan_of(vase, Eigen::Vector3d(0.3, -0.2, 1.0));
  const std::vector<std::uint8_t> there = seen_through(scan, Similarity{}, *scan.viewpoint(), lid, kSpacing);
  // The same scan in another frame (turned, moved and scaled), carried back by the registration.
  const Similarity away{Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix(),
                        Eigen::Vector3d(0.4, -1.0, 2.0), 1.3};
  const PointSet moved = transformed(scan, away);
  EXPECT_EQ(seen_through(moved, away.inverse(), away.apply(*scan.viewpoint()), lid, kSpacing), there);
}

TEST(SeenThrough, AnEyeNoSensorHadJudgesNothing) {
  const Cup vase;
  const PointSet lid = lid_of(vase);
  const PointSet scan = scan_of(vase, Eigen::Vector3d(0.3, -0.2, 1.0));
  // A viewpoint within 10% of the template's box (a PCD's default origin on a model drawn about it), here just over the
  // mouth, from where the scan would lie on one side and see through the lid.
  PointSet whole = merged(sample(vase.mesh, {.spacing = kSpacing, .seed = 1}).samples, lid);
  const Eigen::Vector3d over_the_mouth = Eigen::Vector3d(0, 0, vase.box.max.z() + 0.05);
  EXPECT_EQ(share_of(seen_through(scan, Similarity{}, over_the_mouth, whole, kSpacing)), 0.0);
  EXPECT_EQ(share_of(seen_through(PointSet(), Similarity{}, *scan.viewpoint(), lid, kSpacing)), 0.0);
}

}  // namespace
}  // namespace scanfill
