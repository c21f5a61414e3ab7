// kd-tree (nodes/core/kdtree.h): k-nearest, radius and nearest-of-each queries against brute force on seeded random
// points; ties, duplicates, empty and one-point sets; the kNN graph, the Morton order and the mean spacing alpha on a
// grid whose answer is known.
#include "nodes/core/kdtree.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>
#include <set>

#include "nodes/core/errors.h"

namespace scanfill {
namespace {

Eigen::Matrix3Xd random_points(Index n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  Eigen::Matrix3Xd p(3, n);
  for (Index i = 0; i < n; ++i) p.col(i) = Eigen::Vector3d(u(rng), u(rng), u(rng));
  return p;
}

// Every point's squared distance to q, with its index, nearest first (ties by index).
std::vector<std::pair<double, std::int32_t>> brute_force(const Eigen::Matrix3Xd& p, const Eigen::Vector3d& q) {
  std::vector<std::pair<double, std::int32_t>> all;
  for (Index i = 0; i < p.cols(); ++i) all.push_back({(p.col(i) - q).squaredNorm(), std::int32_t(i)});
  std::sort(all.begin(), all.end());
  return all;
}

// A regular grid of n^3 points with spacing h.
Eigen::Matrix3Xd grid(int n, double h) {
  Eigen::Matrix3Xd p(3, n * n * n);
  Index c = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) p.col(c++) = h * Eigen::Vector3d(i, j, k);
  return p;
}

TEST(KdTree, KNearestMatchesBruteForceOnRandomPoints) {
  const Eigen::Matrix3Xd p = random_points(2000, 1), queries = random_points(200, 2);
  KdTree tree;
  tree.build(p);
  EXPECT_EQ(tree.size(), 2000);
  for (const int k : {1, 7, 32}) {
    std::vector<std::int32_t> idx(static_cast<size_t>(k));
    std::vector<double> d2(static_cast<size_t>(k));
    for (Index q = 0; q < queries.cols(); ++q) {
      ASSERT_EQ(tree.knn(queries.col(q), k, idx.data(), d2.data()), k);
      const auto truth = brute_force(p, queries.col(q));
      for (int a = 0; a < k; ++a) {
        // Random points have no ties: the same indices in the same order, and the exact squared distances.
        EXPECT_EQ(idx[size_t(a)], truth[size_t(a)].second) << "k " << k << " rank " << a;
        EXPECT_NEAR(d2[size_t(a)], truth[size_t(a)].first, 1e-12);
      }
    }
  }
}

TEST(KdTree, AQueryAtAPointFindsItselfFirstAtDistanceZero) {
  const Eigen::Matrix3Xd p = random_points(500, 3);
  KdTree tree;
  tree.build(p);
  for (Index i = 0; i < p.cols(); i += 7) {
    std::int32_t idx[2];
    double d2[2];
    ASSERT_EQ(tree.knn(p.col(i), 2, idx, d2), 2);
    EXPECT_EQ(idx[0], i);
    EXPECT_EQ(d2[0], 0.0);
    EXPECT_GT(d2[1], 0.0);
  }
}

TEST(KdTree, AskingForMoreThanThereAreReturnsThemAll) {
  const Eigen::Matrix3Xd p = random_points(5, 4);
  KdTree tree;
  tree.build(p);
  std::vector<std::int32_t> idx(10);
  std::vector<double> d2(10);
  ASSERT_EQ(tree.knn(Eigen::Vector3d::Zero(), 10, idx.data(), d2.data()), 5);
  const auto truth = brute_force(p, Eigen::Vector3d::Zero());
  for (int a = 0; a < 5; ++a) EXPECT_EQ(idx[size_t(a)], truth[size_t(a)].second);
}

TEST(KdTree, TiesAreAllAtTheSameDistanceAndDistinct) {
  // The centre of a unit cube of the grid is equidistant (3/4) from its 8 corners; the 4 nearest are 4 of them.
  const Eigen::Matrix3Xd p = grid(4, 1.0);
  KdTree tree;
  tree.build(p);
  const Eigen::Vector3d centre(1.5, 1.5, 1.5);
  std::int32_t idx[9];
  double d2[9];
  ASSERT_EQ(tree.knn(centre, 4, idx, d2), 4);
  std::set<std::int32_t> distinct(idx, idx + 4);
  EXPECT_EQ(distinct.size(), 4u);
  for (int a = 0; a < 4; ++a) {
    EXPECT_DOUBLE_EQ(d2[a], 0.75);
    EXPECT_DOUBLE_EQ((p.col(idx[a]) - centre).squaredNorm(), 0.75);
  }
  // All 8 corners, then the next shell (distance^2 = 0.25 + 0.25 + 2.25 = 2.75).
  ASSERT_EQ(tree.knn(centre, 9, idx, d2), 9);
  EXPECT_EQ(std::set<std::int32_t>(idx, idx + 8).size(), 8u);
  for (int a = 0; a < 8; ++a) EXPECT_DOUBLE_EQ(d2[a], 0.75);
  EXPECT_DOUBLE_EQ(d2[8], 2.75);
}

TEST(KdTree, RadiusMatchesBruteForceAndIsStrict) {
  const Eigen::Matrix3Xd p = random_points(2000, 5), queries = random_points(100, 6);
  KdTree tree;
  tree.build(p);
  std::vector<Neighbor> out;
  for (Index q = 0; q < queries.cols(); ++q) {
    const double r = 0.1 + 0.3 * double(q) / double(queries.cols());
    tree.radius(queries.col(q), r, out);
    std::set<std::int32_t> got;
    for (const Neighbor& nb : out) {
      got.insert(nb.index);
      EXPECT_NEAR(nb.distance2, (p.col(nb.index) - queries.col(q)).squaredNorm(), 1e-12);
    }
    EXPECT_EQ(got.size(), out.size());  // no index twice
    std::set<std::int32_t> truth;
    for (Index i = 0; i < p.cols(); ++i)
      if ((p.col(i) - queries.col(q)).squaredNorm() < r * r) truth.insert(std::int32_t(i));
    EXPECT_EQ(got, truth) << "query " << q;
  }
  // On the unit grid, radius 1 from a grid point excludes its 6 neighbours at exactly 1: only the point itself.
  const Eigen::Matrix3Xd g = grid(3, 1.0);
  KdTree gt;
  gt.build(g);
  gt.radius(Eigen::Vector3d(1, 1, 1), 1.0, out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(g.col(out[0].index), Eigen::Vector3d(1, 1, 1));
  gt.radius(Eigen::Vector3d(1, 1, 1), 1.0 + 1e-9, out);
  EXPECT_EQ(out.size(), 7u);
}

TEST(KdTree, RadiusClearsTheOutputFirst) {
  const Eigen::Matrix3Xd p = random_points(100, 7);
  KdTree tree;
  tree.build(p);
  std::vector<Neighbor> out(5, Neighbor{-1, -1.0});
  tree.radius(Eigen::Vector3d(10, 10, 10), 0.5, out);
  EXPECT_TRUE(out.empty());
}

TEST(KdTree, DuplicatesAreAllFoundAtDistanceZero) {
  Eigen::Matrix3Xd p = random_points(50, 8);
  p.col(10) = p.col(3);
  p.col(20) = p.col(3);
  KdTree tree;
  tree.build(p);
  std::int32_t idx[4];
  double d2[4];
  ASSERT_EQ(tree.knn(p.col(3), 4, idx, d2), 4);
  EXPECT_EQ(std::set<std::int32_t>(idx, idx + 3), (std::set<std::int32_t>{3, 10, 20}));
  for (int a = 0; a < 3; ++a) EXPECT_EQ(d2[a], 0.0);
  EXPECT_GT(d2[3], 0.0);
  std::vector<Neighbor> out;
  tree.radius(p.col(3), 1e-9, out);
  EXPECT_EQ(out.size(), 3u);
  // In the kNN graph a point's duplicates are its nearest others, at distance 0, and the point itself is never listed.
  std::vector<double> gd2;
  const auto graph = knn_graph(tree, p, 3, &gd2);
  for (const Index i : {3, 10, 20}) {
    std::set<std::int32_t> first_two(graph.begin() + i * 3, graph.begin() + i * 3 + 2);
    std::set<std::int32_t> others{3, 10, 20};
    others.erase(std::int32_t(i));
    EXPECT_EQ(first_two, others) << "point " << i;
    EXPECT_EQ(gd2[size_t(i) * 3], 0.0);
    EXPECT_EQ(gd2[size_t(i) * 3 + 1], 0.0);
    EXPECT_GT(gd2[size_t(i) * 3 + 2], 0.0);
  }
}

TEST(KdTree, AnEmptySetFindsNothing) {
  const Eigen::Matrix3Xd p(3, 0);
  KdTree tree;
  tree.build(p);
  EXPECT_EQ(tree.size(), 0);
  std::int32_t idx[3] = {-7, -7, -7};
  double d2[3];
  EXPECT_EQ(tree.knn(Eigen::Vector3d::Zero(), 3, idx, d2), 0);
  std::vector<Neighbor> out(2);
  tree.radius(Eigen::Vector3d::Zero(), 1.0, out);
  EXPECT_TRUE(out.empty());
  EXPECT_TRUE(knn_graph(tree, p, 4).empty());
  EXPECT_TRUE(morton_order(p).empty());
}

TEST(KdTree, OnePointIsEveryQuerysNearest) {
  Eigen::Matrix3Xd p(3, 1);
  p.col(0) = Eigen::Vector3d(1, 2, 3);
  KdTree tree;
  tree.build(p);
  std::int32_t idx[2];
  double d2[2];
  ASSERT_EQ(tree.knn(Eigen::Vector3d::Zero(), 2, idx, d2), 1);
  EXPECT_EQ(idx[0], 0);
  EXPECT_DOUBLE_EQ(d2[0], 14.0);
  // Its kNN graph has no other point: every slot is -1.
  const auto graph = knn_graph(tree, p, 3);
  EXPECT_EQ(graph, (std::vector<std::int32_t>{-1, -1, -1}));
  EXPECT_THROW(mean_nearest_neighbor_distance(p, tree), InputError);
}

TEST(KdTree, QueriesBeforeBuildAndOversizedGraphsThrow) {
  KdTree tree;
  EXPECT_EQ(tree.size(), 0);
  std::int32_t idx;
  double d2;
  EXPECT_THROW(tree.knn(Eigen::Vector3d::Zero(), 1, &idx, &d2), InvariantError);
  std::vector<Neighbor> out;
  EXPECT_THROW(tree.radius(Eigen::Vector3d::Zero(), 1.0, out), InvariantError);
  const Eigen::Matrix3Xd p = random_points(100, 9);
  tree.build(p);
  EXPECT_THROW(knn_graph(tree, p, 65), InvariantError);
  EXPECT_THROW(knn_graph(tree, p, -1), InvariantError);
  EXPECT_EQ(knn_graph(tree, p, 0).size(), 0u);
}

TEST(KdTree, NearestEachMatchesBruteForce) {
  const Eigen::Matrix3Xd p = random_points(1000, 10), queries = random_points(300, 11);
  KdTree tree;
  tree.build(p);
  std::vector<std::int32_t> index;
  std::vector<double> distance2;
  nearest_each(tree, queries, index, distance2);
  ASSERT_EQ(index.size(), 300u);
  ASSERT_EQ(distance2.size(), 300u);
  for (Index q = 0; q < queries.cols(); ++q) {
    const auto truth = brute_force(p, queries.col(q));
    EXPECT_EQ(index[size_t(q)], truth[0].second);
    EXPECT_NEAR(distance2[size_t(q)], truth[0].first, 1e-12);
  }
}

TEST(KdTree, KnnGraphMatchesBruteForce) {
  const Eigen::Matrix3Xd p = random_points(800, 12);
  KdTree tree;
  tree.build(p);
  const int k = 6;
  std::vector<double> d2;
  const auto graph = knn_graph(tree, p, k, &d2);
  ASSERT_EQ(graph.size(), 800u * k);
  for (Index i = 0; i < p.cols(); ++i) {
    const auto truth = brute_force(p, p.col(i));  // truth[0] is i itself
    ASSERT_EQ(truth[0].second, i);
    for (int a = 0; a < k; ++a) {
      EXPECT_EQ(graph[size_t(i) * k + size_t(a)], truth[size_t(a) + 1].second);
      EXPECT_NEAR(d2[size_t(i) * k + size_t(a)], truth[size_t(a) + 1].first, 1e-12);
    }
  }
}

TEST(KdTree, MeanSpacingOfAGridIsItsStep) {
  // Every point of a regular grid has its nearest other point exactly h away.
  const Eigen::Matrix3Xd g = grid(6, 0.05);
  KdTree tree;
  tree.build(g);
  EXPECT_NEAR(mean_nearest_neighbor_distance(g, tree), 0.05, 1e-12);
  // Two points: both see each other.
  Eigen::Matrix3Xd two(3, 2);
  two << 0, 3, 0, 4, 0, 0;
  KdTree t2;
  t2.build(two);
  EXPECT_DOUBLE_EQ(mean_nearest_neighbor_distance(two, t2), 5.0);
  // A duplicated point has spacing 0: of 4 points, the two duplicates count 0 and the other two 1 each.
  Eigen::Matrix3Xd dup(3, 4);
  dup << 0, 0, 10, 11, 0, 0, 0, 0, 0, 0, 0, 0;
  KdTree t3;
  t3.build(dup);
  EXPECT_DOUBLE_EQ(mean_nearest_neighbor_distance(dup, t3), 0.5);
}

TEST(KdTree, MortonOrderIsAPermutationAlongTheZCurve) {
  const Eigen::Matrix3Xd p = random_points(3000, 13);
  const std::vector<Index> order = morton_order(p);
  ASSERT_EQ(order.size(), 3000u);
  std::vector<Index> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  std::vector<Index> iota(3000);
  std::iota(iota.begin(), iota.end(), 0);
  EXPECT_EQ(sorted, iota);
  // On a 2 x 2 x 2 grid the Z curve visits x fastest, then y, then z.
  Eigen::Matrix3Xd cube(3, 8);
  const int shuffled[8] = {5, 2, 7, 0, 3, 6, 1, 4};  // position of corner c in the input
  for (int c = 0; c < 8; ++c) cube.col(shuffled[c]) = Eigen::Vector3d(c & 1, c >> 1 & 1, c >> 2 & 1);
  const std::vector<Index> z = morton_order(cube);
  for (int c = 0; c < 8; ++c) EXPECT_EQ(z[size_t(c)], shuffled[c]) << "corner " << c;
  // Neighbours along the curve are close: the mean step is far below that of the input's random order.
  double along = 0, random = 0;
  for (size_t i = 1; i < order.size(); ++i) {
    along += (p.col(order[i]) - p.col(order[i - 1])).norm();
    random += (p.col(Index(i)) - p.col(Index(i) - 1)).norm();
  }
  EXPECT_LT(along, 0.2 * random);
}

}  // namespace
}  // namespace scanfill
