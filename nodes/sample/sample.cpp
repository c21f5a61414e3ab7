#include "nodes/sample/sample.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/parallel_sort.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>

#include "nodes/core/errors.h"
#include "nodes/core/kdtree.h"
#include "nodes/sample/sample_options.h"

namespace scanfill {
namespace {

constexpr Index kBlock = 4096;  // fixed block size: work split never depends on the thread count

// Mean NN distance of WSE output is sqrt(kSpacingFactor * A / N); measured on planes and spheres (sample_test).
constexpr double kSpacingFactor = 0.64;

// Clouds with more than kThinAbove points per requested sample are thinned to about kThinTo per sample first.
constexpr double kThinAbove = 40, kThinTo = 16;

std::uint64_t splitmix(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

struct Candidates {
  Eigen::Matrix3Xd positions;
  Eigen::Matrix3Xd normals;  // 3 by 0 when unknown
  VectorXi32 face;           // mesh candidates
  Eigen::Matrix3Xd bary;
  VectorXi64 source;  // cloud candidates: index in the input
  VectorXi64 column;  // cloud candidates: column of the point set sampled (for its colours and intensity)
};

// A mesh's triangles as a distribution of random surface points: cumulative areas and face normals.
struct SurfaceTable {
  std::vector<double> cumulative;
  Eigen::Matrix3Xd face_normal;
  double total = 0;
};

SurfaceTable surface_table(const PointSet& mesh) {
  const auto& P = mesh.positions();
  const auto& F = mesh.faces();
  const Index nf = F.cols();
  SurfaceTable t{std::vector<double>(static_cast<size_t>(nf)), Eigen::Matrix3Xd(3, nf), 0};
  for (Index f = 0; f < nf; ++f) {
    const Eigen::Vector3d c = (P.col(F(1, f)) - P.col(F(0, f))).cross(P.col(F(2, f)) - P.col(F(0, f)));
    const double a = 0.5 * c.norm();
    t.face_normal.col(f) = a > 0 ? Eigen::Vector3d(c.normalized()) : Eigen::Vector3d::Zero();
    t.total += a;
    t.cumulative[size_t(f)] = t.total;
  }
  if (!(t.total > 0)) throw InputError("mesh has zero surface area; nothing to sample");
  return t;
}

// The random surface points [r.begin(), r.end()): emit(i, face, barycentrics, position, normal) for each. One
// generator per range, seeded from (seed, range start / kBlock): callers split [0, m) into ranges by a
// simple_partitioner over blocked_range(0, m, kBlock), which halves down to kBlock whatever the thread count and the
// work stealing, so the points depend on m alone; the default (auto) partitioner stops halving where stealing says,
// which made large runs (the copy surface of a 10^7-point scan) differ from run to run.
template <class Emit>
void draw_surface_points(const PointSet& mesh, const SurfaceTable& t, std::uint64_t seed,
                         const tbb::blocked_range<Index>& r, Emit&& emit) {
  const auto& P = mesh.positions();
  const auto& F = mesh.faces();
  const Index nf = F.cols();
  std::mt19937_64 rng(splitmix(seed ^ splitmix(std::uint64_t(r.begin() / kBlock))));
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  for (Index i = r.begin(); i != r.end(); ++i) {
    const double pick = u01(rng) * t.total;
    Index f = std::upper_bound(t.cumulative.begin(), t.cumulative.end(), pick) - t.cumulative.begin();
    f = std::min(f, nf - 1);
    const double s = std::sqrt(u01(rng)), v = u01(rng);
    const Eigen::Vector3d b(1 - s, s * (1 - v), s * v);
    const Eigen::Vector3d p = b(0) * P.col(F(0, f)) + b(1) * P.col(F(1, f)) + b(2) * P.col(F(2, f));
    Eigen::Vector3d n = t.face_normal.col(f);
    if (mesh.has_normals()) {
      const Eigen::Vector3d vn =
          b(0) * mesh.normals().col(F(0, f)) + b(1) * mesh.normals().col(F(1, f)) + b(2) * mesh.normals().col(F(2, f));
      if (vn.norm() > 1e-12) n = vn.normalized();
    }
    emit(i, std::int32_t(f), b, p, n);
  }
}

Candidates mesh_candidates(const PointSet& mesh, Index m, std::uint64_t seed) {
  const SurfaceTable table = surface_table(mesh);
  Candidates c;
  c.positions.resize(3, m);
  c.normals.resize(3, m);
  c.face.resize(m);
  c.bary.resize(3, m);
  const auto fill = [&](const tbb::blocked_range<Index>& r) {
    draw_surface_points(
        mesh, table, seed, r,
        [&](Index i, std::int32_t f, const Eigen::Vector3d& b, const Eigen::Vector3d& p, const Eigen::Vector3d& n) {
          c.face(i) = f;
          c.bary.col(i) = b;
          c.positions.col(i) = p;
          c.normals.col(i) = n;
        });
  };
  tbb::parallel_for(tbb::blocked_range<Index>(0, m, kBlock), fill, tbb::simple_partitioner());
  // Random candidates in Morton order: neighbour queries in index order then stay in cache (3-5x faster at 10^5).
  const std::vector<Index> order = morton_order(c.positions);
  Candidates sorted;
  sorted.positions.resize(3, m);
  sorted.normals.resize(3, m);
  sorted.face.resize(m);
  sorted.bary.resize(3, m);
  tbb::parallel_for(Index(0), m, [&](Index i) {
    const Index o = order[size_t(i)];
    sorted.positions.col(i) = c.positions.col(o);
    sorted.normals.col(i) = c.normals.col(o);
    sorted.face(i) = c.face(o);
    sorted.bary.col(i) = c.bary.col(o);
  });
  return sorted;
}

// Area of a cloud: each point covers pi r^2 / k, r its distance to the k-th neighbour (k = 12, exact on a grid).
// Summed over every stride-th point (at most ~2^17 of them) and scaled: enough for a count, cheap on 10^7 points.
double cloud_area(const Eigen::Matrix3Xd& P, const KdTree& tree) {
  constexpr int k = 12;
  const Index stride = std::max<Index>(1, P.cols() >> 17);
  const Index n = (P.cols() + stride - 1) / stride;
  const double sum = tbb::parallel_deterministic_reduce(
      tbb::blocked_range<Index>(0, n, kBlock), 0.0,
      [&](const tbb::blocked_range<Index>& r, double acc) {
        std::int32_t idx[k + 1];
        double d2[k + 1];
        for (Index s = r.begin(); s != r.end(); ++s) {
          const int found = tree.knn(P.col(s * stride), k + 1, idx, d2);
          acc += M_PI * d2[found - 1] / double(found - 1);
        }
        return acc;
      },
      std::plus<double>());
  return sum * double(P.cols()) / double(n);
}

// The grid cell (and normal octant, when `normals` is given) of point i at position p, for a grid of spacing h anchored
// at lo; d2 its squared distance to the cell centre, in cells.
std::int64_t grid_cell(const Eigen::Vector3d& p, const Eigen::Matrix3Xd* normals, Index i, const Eigen::Vector3d& lo,
                       double h, double& d2) {
  constexpr std::int64_t kCells = std::int64_t(1) << 20;
  std::int64_t key = 0;
  d2 = 0;
  for (int a = 0; a < 3; ++a) {
    const double x = (p[a] - lo[a]) / h;
    const std::int64_t c = std::min<std::int64_t>(kCells - 1, std::int64_t(x));
    d2 += (x - double(c) - 0.5) * (x - double(c) - 0.5);
    key = key << 20 | c;
  }
  if (normals) key = key << 3 | ((*normals)(0, i) < 0) | ((*normals)(1, i) < 0) << 1 | ((*normals)(2, i) < 0) << 2;
  return key;
}

// Indices (ascending, so Morton order is kept) of one point per cell of a grid of spacing h, the one nearest the cell
// centre; with normals, per cell and normal octant, so the two sides of a part thinner than h both survive.
std::vector<Index> thin_cloud(const Eigen::Matrix3Xd& P, const Eigen::Matrix3Xd& normals, double h) {
  const Index n = P.cols();
  const Eigen::Vector3d lo = P.rowwise().minCoeff();
  const bool with_normals = normals.cols() == n;
  struct Entry {
    std::int64_t key;
    double d2;
    Index index;
  };
  std::vector<Entry> entries(static_cast<size_t>(n));
  tbb::parallel_for(tbb::blocked_range<Index>(0, n, kBlock), [&](const tbb::blocked_range<Index>& r) {
    for (Index i = r.begin(); i != r.end(); ++i) {
      double d2 = 0;
      const std::int64_t key = grid_cell(P.col(i), with_normals ? &normals : nullptr, i, lo, h, d2);
      entries[size_t(i)] = {key, d2, i};
    }
  });
  tbb::parallel_sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) {
    return a.key != b.key ? a.key < b.key : a.d2 != b.d2 ? a.d2 < b.d2 : a.index < b.index;  // a total order
  });
  std::vector<Index> kept;
  for (size_t e = 0; e < entries.size(); ++e)
    if (e == 0 || entries[e].key != entries[e - 1].key) kept.push_back(entries[e].index);
  std::sort(kept.begin(), kept.end());
  return kept;
}

// A cloud without its exact duplicates (same position): the first of each kept, in input order, with its normal and
// its index in the input as source_index. `merged` counts the others. Returns an empty set when there are none, so
// ordinary inputs take the same path as before. (1000 copies of one point used to give 100 copies of it as samples.)
PointSet merge_duplicates(const PointSet& cloud, Index& merged) {
  const Eigen::Matrix3Xd& P = cloud.positions();
  const Index n = P.cols();
  std::vector<Index> order(static_cast<size_t>(n));
  std::iota(order.begin(), order.end(), Index(0));
  tbb::parallel_sort(order.begin(), order.end(), [&](Index a, Index b) {
    for (int c = 0; c < 3; ++c)
      if (P(c, a) != P(c, b)) return P(c, a) < P(c, b);
    return a < b;  // a total order: the lowest index of equal positions comes first
  });
  std::vector<std::uint8_t> duplicate(static_cast<size_t>(n), 0);
  merged = 0;
  for (size_t i = 1; i < order.size(); ++i)
    if (P.col(order[i]) == P.col(order[i - 1])) {
      duplicate[size_t(order[i])] = 1;
      ++merged;
    }
  if (merged == 0) return {};
  const Index kept = n - merged;
  std::vector<std::int32_t> first;
  first.reserve(size_t(kept));
  for (Index i = 0; i < n; ++i)
    if (!duplicate[size_t(i)]) first.push_back(std::int32_t(i));
  PointSet out = subset(cloud, first);  // normals, colours, intensity with their points
  VectorXi64 source(kept);
  for (Index j = 0; j < kept; ++j)
    source(j) = cloud.has_source_index() ? cloud.source_index()(first[size_t(j)]) : first[size_t(j)];
  out.set_source_index(std::move(source));
  out.set_viewpoint(cloud.viewpoint());
  return out;
}

// The longest of a triangle's three edges.
double longest_edge_of(const Eigen::Matrix3Xd& P, const Eigen::Matrix<std::int32_t, 3, 1>& corners) {
  double longest = 0;
  for (int k = 0; k < 3; ++k) longest = std::max(longest, (P.col(corners(k)) - P.col(corners((k + 1) % 3))).norm());
  return longest;
}

// One triangle of a mesh as a mesh of its own.
PointSet triangle_alone(const Eigen::Matrix3Xd& P, const Eigen::Matrix<std::int32_t, 3, 1>& corners) {
  Eigen::Matrix3Xd Q(3, 3);
  for (int k = 0; k < 3; ++k) Q.col(k) = P.col(corners(k));
  PointSet out(std::move(Q));
  out.set_faces(Matrix3Xi(Eigen::Matrix<std::int32_t, 3, 1>(0, 1, 2)));
  return out;
}

// The triangles `splits` leaves whole, on the mesh's own (shared) vertices that they use.
PointSet unsplit_triangles(const Eigen::Matrix3Xd& P, const Matrix3Xi& F, const std::vector<int>& splits) {
  std::vector<std::int32_t> index(size_t(P.cols()), -1);
  std::vector<Index> used;
  std::vector<Eigen::Matrix<std::int32_t, 3, 1>> faces;
  for (Index f = 0; f < F.cols(); ++f) {
    if (splits[size_t(f)] != 0) continue;
    for (int k = 0; k < 3; ++k)
      if (index[size_t(F(k, f))] < 0) {
        index[size_t(F(k, f))] = std::int32_t(used.size());
        used.push_back(F(k, f));
      }
    faces.emplace_back(index[size_t(F(0, f))], index[size_t(F(1, f))], index[size_t(F(2, f))]);
  }
  Matrix3Xi G(3, Index(faces.size()));
  for (size_t f = 0; f < faces.size(); ++f) G.col(Index(f)) = faces[f];
  PointSet out(P(Eigen::all, used));
  out.set_faces(std::move(G));
  return out;
}

// Meshes side by side as one (their vertices not merged).
PointSet joined_meshes(const std::vector<PointSet>& parts) {
  Index vertices = 0, faces = 0;
  for (const PointSet& m : parts) {
    vertices += m.size();
    faces += m.faces().cols();
  }
  Eigen::Matrix3Xd P(3, vertices);
  Matrix3Xi F(3, faces);
  Index v = 0, f = 0;
  for (const PointSet& m : parts) {
    P.middleCols(v, m.size()) = m.positions();
    F.middleCols(f, m.faces().cols()) = m.faces().array() + std::int32_t(v);
    v += m.size();
    f += m.faces().cols();
  }
  PointSet out(std::move(P));
  out.set_faces(std::move(F));
  return out;
}

// One 1-to-4 split: each edge's midpoint made once (keyed by its two vertices), each triangle into its three corners'
// triangles and the middle one, wound as it was.
PointSet split_in_four(const PointSet& mesh) {
  const Eigen::Matrix3Xd& P = mesh.positions();
  const Matrix3Xi& F = mesh.faces();
  std::vector<std::pair<std::uint64_t, Index>> edges;
  edges.reserve(size_t(3 * F.cols()));
  const auto key = [](Index a, Index b) {
    return (std::uint64_t(std::min(a, b)) << 32) | std::uint64_t(std::max(a, b));
  };
  for (Index f = 0; f < F.cols(); ++f)
    for (int k = 0; k < 3; ++k) edges.emplace_back(key(F(k, f), F((k + 1) % 3, f)), 0);
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end(), [](const auto& a, const auto& b) { return a.first == b.first; }),
              edges.end());
  Eigen::Matrix3Xd Q(3, P.cols() + Index(edges.size()));
  Q.leftCols(P.cols()) = P;
  for (size_t e = 0; e < edges.size(); ++e) {
    edges[e].second = P.cols() + Index(e);
    Q.col(edges[e].second) = 0.5 * (P.col(Index(edges[e].first >> 32)) + P.col(Index(edges[e].first & 0xffffffffu)));
  }
  const auto midpoint = [&](Index a, Index b) {
    return std::int32_t(std::lower_bound(edges.begin(), edges.end(), std::make_pair(key(a, b), Index(0)))->second);
  };
  using Triangle = Eigen::Matrix<std::int32_t, 3, 1>;
  Matrix3Xi G(3, 4 * F.cols());
  for (Index f = 0; f < F.cols(); ++f) {
    const std::int32_t a = F(0, f), b = F(1, f), c = F(2, f);
    const std::int32_t ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
    G.col(4 * f) = Triangle(a, ab, ca);
    G.col(4 * f + 1) = Triangle(ab, b, bc);
    G.col(4 * f + 2) = Triangle(ca, bc, c);
    G.col(4 * f + 3) = Triangle(ab, bc, ca);
  }
  PointSet out(std::move(Q));
  out.set_faces(std::move(G));
  return out;
}

}  // namespace

PointSet subdivided_mesh(const PointSet& mesh, double longest_edge, Index most_faces) {
  if (!mesh.has_faces()) throw InputError("subdivided_mesh: a mesh is needed, not a cloud");
  const Eigen::Matrix3Xd& P = mesh.positions();
  const Matrix3Xi& F = mesh.faces();
  std::vector<int> splits(size_t(F.cols()));
  for (Index f = 0; f < F.cols(); ++f)
    splits[size_t(f)] = int(std::ceil(std::log2(std::max(1.0, longest_edge_of(P, F.col(f)) / longest_edge))));
  const auto faces_made = [&] {
    Index n = 0;
    for (const int s : splits) n += Index(1) << (2 * s);
    return n;
  };
  while (faces_made() > most_faces && *std::max_element(splits.begin(), splits.end()) > 0)
    for (int& s : splits) s = std::max(0, s - 1);
  if (std::all_of(splits.begin(), splits.end(), [](int s) { return s == 0; })) {
    PointSet same(P);
    same.set_faces(F);
    return same;
  }
  std::vector<PointSet> parts(1, unsplit_triangles(P, F, splits));
  for (Index f = 0; f < F.cols(); ++f) {
    if (splits[size_t(f)] == 0) continue;
    PointSet part = triangle_alone(P, F.col(f));
    for (int k = 0; k < splits[size_t(f)]; ++k) part = split_in_four(part);
    parts.push_back(std::move(part));
  }
  return joined_meshes(parts);
}

PointSet random_surface_points(const PointSet& mesh, Index n, std::uint64_t seed) {
  if (!mesh.has_faces()) throw InputError("random surface points need a mesh");
  Candidates c = mesh_candidates(mesh, n, seed);
  PointSet out(std::move(c.positions));
  out.set_normals(std::move(c.normals));
  out.set_face_provenance(std::move(c.face), std::move(c.bary));
  return out;
}

PointSet random_surface_points_where(const PointSet& mesh, Index n, std::uint64_t seed,
                                     const std::function<bool(const Eigen::Vector3d&, std::int32_t)>& keep) {
  if (!mesh.has_faces()) throw InputError("random surface points need a mesh");
  if (n <= 0) return PointSet();
  const SurfaceTable table = surface_table(mesh);
  const tbb::blocked_range<Index> all(0, n, kBlock);
  // One pass: every point widens the bounding box (of all n, which sets the Morton grid as in random_surface_points),
  // the kept ones are stored; their Morton keys come after, from the whole box.
  struct Kept {
    std::uint64_t key;
    Index index;
    Eigen::Vector3d p, n;
  };
  struct Part {
    BoundingBox box{Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()),
                    Eigen::Vector3d::Constant(-std::numeric_limits<double>::infinity())};
    std::vector<Kept> kept;
  };
  tbb::enumerable_thread_specific<Part> parts;
  tbb::parallel_for(
      all,
      [&](const tbb::blocked_range<Index>& r) {
        Part& mine = parts.local();
        draw_surface_points(
            mesh, table, seed, r,
            [&](Index i, std::int32_t f, const Eigen::Vector3d&, const Eigen::Vector3d& p, const Eigen::Vector3d& nrm) {
              mine.box.min = mine.box.min.cwiseMin(p);
              mine.box.max = mine.box.max.cwiseMax(p);
              if (keep(p, f)) mine.kept.push_back({0, i, p, nrm});
            });
      },
      tbb::simple_partitioner());
  BoundingBox box = parts.begin()->box;
  for (const Part& part : parts) box = {box.min.cwiseMin(part.box.min), box.max.cwiseMax(part.box.max)};
  std::vector<Kept> all_kept;
  for (const Part& part : parts) all_kept.insert(all_kept.end(), part.kept.begin(), part.kept.end());
  for (Kept& k : all_kept) k.key = morton_key(k.p, box);
  // The order of random_surface_points: by Morton key, ties by index.
  std::sort(all_kept.begin(), all_kept.end(),
            [](const Kept& a, const Kept& b) { return a.key != b.key ? a.key < b.key : a.index < b.index; });
  Eigen::Matrix3Xd P(3, Index(all_kept.size())), N(3, Index(all_kept.size()));
  for (size_t k = 0; k < all_kept.size(); ++k) {
    P.col(Index(k)) = all_kept[k].p;
    N.col(Index(k)) = all_kept[k].n;
  }
  PointSet out(std::move(P));
  out.set_normals(std::move(N));
  return out;
}

namespace {

// sample()'s phases, defined after it.
struct Edge {
  std::int32_t j;
  std::int32_t w;
};

// Each candidate's neighbours within d_max (CSR: degree offsets into adjacency) with each edge's contribution to the
// weight, and each candidate's weight, their sum.
struct WeightGraph {
  std::vector<std::int64_t> degree;  // m + 1 offsets into adjacency
  std::vector<Edge> adjacency;
  std::vector<std::int64_t> weight;
};

// The candidates (a mesh's random surface points, or a cloud's own points, thinned when far denser than the samples)
// and the area they cover (result.area); sets n_target, the number of samples to keep. `input_tree`: a cloud's
// kd-tree, built here.
Candidates candidates(const PointSet& input, const SampleOptions& options, KdTree& input_tree, SampleResult& result,
                      Index& n_target);

// The weight graph of the candidates: neighbours within d_max (normals within the angle when use_normals), each
// contributing (1 - d/d_max)^exponent in fixed point.
WeightGraph weights(const Candidates& cand, const KdTree& tree, double d_max, double cos_limit, bool use_normals,
                    double exponent, const ProgressFn& progress);

// Parallel weighted sample elimination down to n_target survivors; returns them in ascending candidate order.
std::vector<std::int32_t> eliminate(WeightGraph& g, Index n_target, int& rounds, const ProgressFn& progress);

// The surviving candidates as the sampled point set (result.samples), in Morton order for cache-friendly queries
// downstream, and its measured spacing.
void survivors(const PointSet& input, const Candidates& cand, const std::vector<std::int32_t>& live, bool use_normals,
               SampleResult& result);

}  // namespace

namespace {

// Every run of `chunks` in one cloud of `points` points: positions, normals when the runs have them, source_index.
PointSet whole_cloud(PointChunks& chunks, Index chunk_points, Index points) {
  Eigen::Matrix3Xd P(3, points), N(3, points);
  VectorXi64 source(points);
  bool normals = true;
  Index at = 0;
  PointSet run;
  while (chunks.next(chunk_points, run)) {
    const Index n = run.size();
    P.middleCols(at, n) = run.positions();
    if (run.has_normals()) N.middleCols(at, n) = run.normals();
    normals = normals && run.has_normals();
    source.segment(at, n) = run.source_index();
    at += n;
  }
  PointSet out(std::move(P));
  if (normals) out.set_normals(std::move(N));
  out.set_source_index(std::move(source));
  return out;
}

}  // namespace

std::vector<Index> thin_on_grid(const Eigen::Matrix3Xd& positions, const Eigen::Matrix3Xd& normals, double h) {
  return thin_cloud(positions, normals, h);
}

void GridThinner::add(const PointSet& run) {
  const Index n = run.size(), first = seen_;
  const Eigen::Matrix3Xd& P = run.positions();
  const Eigen::Matrix3Xd* normals = run.has_normals() ? &run.normals() : nullptr;
  normals_ = normals != nullptr;
  run_.resize(size_t(n));
  tbb::parallel_for(tbb::blocked_range<Index>(0, n, kBlock), [&](const tbb::blocked_range<Index>& r) {
    for (Index i = r.begin(); i != r.end(); ++i) {
      Cell& c = run_[size_t(i)];
      c.key = grid_cell(P.col(i), normals, i, lo_, h_, c.d2);
      c.index = first + i;
      c.source = run.has_source_index() ? run.source_index()(i) : first + i;
      c.p = P.col(i);
      c.n = normals ? Eigen::Vector3d((*normals).col(i)) : Eigen::Vector3d::Zero();
    }
  });
  seen_ += n;
  // thin_cloud's total order: by cell, then nearest the centre, then the lower index.
  const auto before = [](const Cell& a, const Cell& b) {
    return a.key != b.key ? a.key < b.key : a.d2 != b.d2 ? a.d2 < b.d2 : a.index < b.index;
  };
  tbb::parallel_sort(run_.begin(), run_.end(), before);
  // The run's best of each cell merged with the best so far, both ordered by cell.
  merged_.clear();
  size_t a = 0, b = 0;
  while (a < cells_.size() || b < run_.size()) {
    if (b < run_.size() && b > 0 && run_[b].key == run_[b - 1].key) {
      ++b;  // not the best of its cell in this run
    } else if (b == run_.size() || (a < cells_.size() && cells_[a].key < run_[b].key)) {
      merged_.push_back(cells_[a++]);
    } else if (a == cells_.size() || run_[b].key < cells_[a].key) {
      merged_.push_back(run_[b++]);
    } else {
      merged_.push_back(before(cells_[a], run_[b]) ? cells_[a] : run_[b]);
      ++a;
      ++b;
    }
  }
  cells_.swap(merged_);
}

PointSet GridThinner::take() {
  std::sort(cells_.begin(), cells_.end(), [](const Cell& a, const Cell& b) { return a.index < b.index; });
  const Index n = Index(cells_.size());
  Eigen::Matrix3Xd P(3, n), N(3, normals_ ? n : 0);
  VectorXi64 source(n);
  for (Index k = 0; k < n; ++k) {
    P.col(k) = cells_[size_t(k)].p;
    if (normals_) N.col(k) = cells_[size_t(k)].n;
    source(k) = cells_[size_t(k)].source;
  }
  cells_.clear();
  seen_ = 0;
  PointSet out(std::move(P));
  if (normals_) out.set_normals(std::move(N));
  out.set_source_index(std::move(source));
  return out;
}

ChunksSummary summarize_chunks(PointChunks& chunks, Index chunk_points, Index kept_points) {
  ChunksSummary s;
  s.stride = std::max<Index>(1, chunks.rows() / std::max<Index>(kept_points, 1));
  s.bounds = {Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()),
              Eigen::Vector3d::Constant(-std::numeric_limits<double>::infinity())};
  std::vector<Eigen::Vector3d> P, N;
  std::vector<std::int64_t> source;
  PointSet run;
  chunks.rewind();
  while (chunks.next(chunk_points, run)) {
    s.points += run.size();
    if (run.size() == 0) continue;
    s.bounds.min = s.bounds.min.cwiseMin(run.positions().rowwise().minCoeff());
    s.bounds.max = s.bounds.max.cwiseMax(run.positions().rowwise().maxCoeff());
    for (Index i = 0; i < run.size(); ++i)
      if (run.source_index()(i) % s.stride == 0) {
        P.push_back(run.positions().col(i));
        if (run.has_normals()) N.push_back(run.normals().col(i));
        source.push_back(run.source_index()(i));
      }
  }
  const Index n = Index(P.size());
  Eigen::Matrix3Xd positions(3, n), normals(3, Index(N.size()) == n ? n : 0);
  for (Index k = 0; k < n; ++k) positions.col(k) = P[size_t(k)];
  for (Index k = 0; k < normals.cols(); ++k) normals.col(k) = N[size_t(k)];
  s.every_kth = PointSet(std::move(positions));
  if (normals.cols() > 0) s.every_kth.set_normals(std::move(normals));
  s.every_kth.set_source_index(Eigen::Map<const VectorXi64>(source.data(), n));
  return s;
}

SampleResult sample_chunks(PointChunks& chunks, const ChunksSummary& summary, const SampleOptions& options,
                           Index chunk_points, const ProgressFn& progress) {
  check_options(options);
  if (summary.every_kth.size() < 3)
    throw InputError("sampling needs at least 3 points, the input has " + std::to_string(summary.points));
  KdTree tree;
  tree.build(summary.every_kth.positions());
  const double area = cloud_area(summary.every_kth.positions(), tree);
  const Index n_target = options.spacing > 0 ? count_for_spacing(area, options.spacing) : options.count;
  chunks.rewind();
  PointSet run;
  if (double(summary.points) <= kThinAbove * double(n_target)) {
    // Few enough to hold: the whole cloud, as sample() takes it.
    return sample(whole_cloud(chunks, chunk_points, summary.points), options, progress);
  }
  const double h = std::sqrt(1.5 * area / (kThinTo * double(n_target)));
  GridThinner thinner(summary.bounds.min, h);
  while (chunks.next(chunk_points, run)) thinner.add(run);
  report(progress, 0.1);
  return sample(thinner.take(), options, progress);
}

Index count_for_spacing(double area, double spacing) {
  return std::max<Index>(1, Index(std::llround(kSpacingFactor * area / (spacing * spacing))));
}

SampleResult sample(const PointSet& given, const SampleOptions& options, const ProgressFn& progress) {
  given.check();
  SampleResult result;
  const bool mesh = given.has_faces();
  if (given.size() < 3)
    throw InputError("sampling needs at least 3 points, the input has " + std::to_string(given.size()));
  // A cloud's duplicate points are merged first (a mesh's vertices do not matter: its triangles are sampled).
  Index merged = 0;
  const PointSet distinct = mesh ? PointSet() : merge_duplicates(given, merged);
  const PointSet& input = merged > 0 ? distinct : given;
  if (merged > 0) {
    result.warnings.push_back(std::to_string(merged) + " of the cloud's " + std::to_string(given.size()) +
                              " points repeat another point's position and were merged before sampling");
    if (input.size() < 3)
      throw InputError("sampling needs at least 3 distinct points, the cloud has " + std::to_string(input.size()) +
                       " (" + std::to_string(merged) + " duplicates merged)");
  }

  // Candidates and the area they cover.
  KdTree input_tree;
  Index n_target = 0;
  const Candidates cand = candidates(input, options, input_tree, result, n_target);
  report(progress, 0.1);
  const Index m = cand.positions.cols();
  result.candidates = m;
  result.r_max = std::sqrt(result.area / (2.0 * std::sqrt(3.0) * double(n_target)));
  const double d_max = 2.0 * result.r_max;
  const double cos_limit = std::cos(options.normal_angle_deg * M_PI / 180.0);
  const bool use_normals = cand.normals.cols() == m && options.normal_angle_deg < 180.0;
  // A cloud's candidates are its points (unless thinned): then its tree is reused.
  const bool own_tree = mesh || cand.positions.cols() != input.size();
  KdTree candidate_tree;
  if (own_tree) candidate_tree.build(cand.positions);
  if (own_tree && !mesh) input_tree = KdTree();  // a thinned cloud's tree of every point is no longer needed
  WeightGraph g = weights(cand, own_tree ? candidate_tree : input_tree, d_max, cos_limit, use_normals,
                          options.weight_exponent, progress);
  report(progress, 0.3);
  const std::vector<std::int32_t> live = eliminate(g, n_target, result.rounds, progress);
  survivors(input, cand, live, use_normals, result);
  report(progress, 1.0);
  return result;
}

namespace {

// A cloud's points as candidates: all of them, or the rows `kept`.
Candidates cloud_candidates(const PointSet& input) {
  Candidates cand;
  cand.positions = input.positions();
  cand.normals = input.normals();
  cand.column = VectorXi64::LinSpaced(input.size(), 0, input.size() - 1);
  cand.source = input.has_source_index() ? input.source_index() : cand.column;
  return cand;
}

Candidates cloud_candidates(const PointSet& input, const std::vector<Index>& kept) {
  const Index n = Index(kept.size());
  Candidates cand;
  cand.positions.resize(3, n);
  if (input.has_normals()) cand.normals.resize(3, n);
  cand.source.resize(n);
  cand.column.resize(n);
  for (Index k = 0; k < n; ++k) {
    const Index i = kept[size_t(k)];
    cand.positions.col(k) = input.positions().col(i);
    if (input.has_normals()) cand.normals.col(k) = input.normals().col(i);
    cand.source[k] = input.has_source_index() ? input.source_index()(i) : i;
    cand.column[k] = i;
  }
  return cand;
}

Candidates candidates(const PointSet& input, const SampleOptions& options, KdTree& input_tree, SampleResult& result,
                      Index& n_target) {
  check_options(options);  // sample's first phase: the config checks these too, a direct caller gets the same checks
  const bool mesh = input.has_faces();
  Candidates cand;
  n_target = options.count;
  if (mesh) {
    result.area = surface_area(input.positions(), input.faces());
    if (!(result.area > 0)) throw InputError("mesh has zero surface area; nothing to sample");
    if (options.spacing > 0) n_target = count_for_spacing(result.area, options.spacing);
    const Index m = std::max<Index>(n_target + 1, Index(std::ceil(options.oversampling * double(n_target))));
    cand = mesh_candidates(input, m, options.seed);
  } else {
    input_tree.build(input.positions());
    result.area = cloud_area(input.positions(), input_tree);
    if (options.spacing > 0) n_target = count_for_spacing(result.area, options.spacing);
    if (n_target > input.size() && options.spacing > 0 && options.all_points_when_sparse) {
      result.warnings.push_back("the cloud's " + std::to_string(input.size()) +
                                " points are sparser than the spacing " + std::to_string(options.spacing) +
                                " asks for (" + std::to_string(n_target) + " samples): every point is used");
      n_target = input.size();
    }
    if (n_target > input.size()) {
      if (options.spacing > 0)
        throw InputError("sample spacing " + std::to_string(options.spacing) + " asks for " + std::to_string(n_target) +
                         " samples but the cloud has only " + std::to_string(input.size()) +
                         " points: use a larger spacing");
      throw InputError("cannot draw " + std::to_string(n_target) + " samples from a cloud of " +
                       std::to_string(input.size()) + " points: use a smaller count");
    }
    // A cloud far denser than the samples asked for (a 10^6-point scan sampled to 10^4) would give every candidate
    // hundreds of neighbours within d_max (about 3.6 per point per sample): gigabytes of lists. Above kThinAbove points
    // per sample it is first thinned on a grid sized for about kThinTo candidates per sample (a surface crosses about
    // 1.5 A / h^2 cells of side h); sparse regions keep every point. The candidates are then the kept points alone,
    // never a copy of the whole cloud.
    std::vector<Index> kept;
    if (double(input.size()) > kThinAbove * double(n_target)) {
      const double h = std::sqrt(1.5 * result.area / (kThinTo * double(n_target)));
      kept = thin_cloud(input.positions(), input.normals(), h);
      if (Index(kept.size()) <= n_target) kept.clear();
    }
    cand = kept.empty() ? cloud_candidates(input) : cloud_candidates(input, kept);
  }
  return cand;
}

WeightGraph weights(const Candidates& cand, const KdTree& tree, double d_max, double cos_limit, bool use_normals,
                    double exponent, const ProgressFn& progress) {
  const Index m = cand.positions.cols();
  // Weights are fixed-point integers (2^-30 units per edge, summed in 64 bits): sums and the atomic subtractions of the
  // parallel rounds are then exact and order-independent, so the result is the same on any number of threads.
  constexpr double kScale = double(std::int32_t(1) << 30);
  const int int_exponent = int(exponent);
  const bool integral = double(int_exponent) == exponent;
  auto contribution = [&](double d2) -> std::int32_t {
    const double x = std::max(0.0, 1.0 - std::sqrt(d2) / d_max);
    double w = 1.0;
    if (integral) {
      double base = x;
      for (int e = int_exponent; e > 0; e >>= 1, base *= base)
        if (e & 1) w *= base;
    } else {
      w = std::pow(x, exponent);
    }
    return std::int32_t(w * kScale + 0.5);
  };

  // Neighbour lists within d_max with each edge's contribution (CSR), built per fixed block and concatenated. The
  // kd-tree visits neighbours in the same order on any thread count, and nanoflann's squared distance is the same
  // bits for (i, j) and (j, i), so the lists and weights are deterministic and symmetric.
  const Index n_blocks = (m + kBlock - 1) / kBlock;
  std::vector<std::vector<Edge>> block_adj(static_cast<size_t>(n_blocks));
  WeightGraph g;
  std::vector<std::int64_t>& degree = g.degree;
  std::vector<std::int64_t>& weight = g.weight;
  degree.assign(size_t(m) + 1, 0);
  weight.assign(static_cast<size_t>(m), 0);
  std::atomic<Index> blocks_done{0};
  tbb::parallel_for(tbb::blocked_range<Index>(0, n_blocks, 1), [&](const tbb::blocked_range<Index>& br) {
    std::vector<Neighbor> hits;
    for (Index b = br.begin(); b != br.end(); ++b) {
      report(progress, 0.1 + 0.2 * double(blocks_done++) / double(n_blocks));
      auto& adj = block_adj[size_t(b)];
      for (Index i = b * kBlock; i < std::min(m, (b + 1) * kBlock); ++i) {
        tree.radius(cand.positions.col(i), d_max, hits);
        std::int64_t w = 0;
        for (const Neighbor& h : hits) {
          if (h.index == i) continue;
          if (use_normals && cand.normals.col(i).dot(cand.normals.col(h.index)) < cos_limit) continue;
          const std::int32_t c = contribution(h.distance2);
          adj.push_back({h.index, c});
          ++degree[size_t(i) + 1];
          w += c;
        }
        weight[size_t(i)] = w;
      }
    }
  });
  std::partial_sum(degree.begin(), degree.end(), degree.begin());
  std::vector<Edge>& adjacency = g.adjacency;
  adjacency.resize(size_t(degree.back()));
  tbb::parallel_for(Index(0), n_blocks, [&](Index b) {
    std::copy(block_adj[size_t(b)].begin(), block_adj[size_t(b)].end(),
              adjacency.begin() + degree[size_t(std::min(m, b * kBlock))]);
    std::vector<Edge>().swap(block_adj[size_t(b)]);
  });
  return g;
}

std::vector<std::int32_t> eliminate(WeightGraph& g, Index n_target, int& rounds, const ProgressFn& progress) {
  const Index m = Index(g.weight.size());
  // Parallel elimination rounds over the list of live candidates (compacted after each round).
  std::vector<std::uint8_t> alive(static_cast<size_t>(m), 1);
  // A live heavier neighbour found in an earlier round: weights only fall, so it usually still blocks, in O(1).
  std::vector<std::int32_t> blocker(static_cast<size_t>(m), -1);
  std::vector<std::int32_t> live(static_cast<size_t>(m));
  std::iota(live.begin(), live.end(), 0);
  std::vector<std::uint8_t> is_max;
  std::vector<std::int64_t> scratch;
  std::vector<Index> maxima;
  const Index excess0 = m - n_target;
  std::vector<std::int64_t>& weight = g.weight;
  const std::vector<std::int64_t>& degree = g.degree;
  const std::vector<Edge>& adjacency = g.adjacency;
  auto heavier = [&](Index a, Index b) {  // strict order on (weight, index)
    return weight[size_t(a)] > weight[size_t(b)] || (weight[size_t(a)] == weight[size_t(b)] && a < b);
  };
  while (Index(live.size()) > n_target) {
    const Index excess = Index(live.size()) - n_target;
    const size_t L = live.size();
    // Threshold: the excess-th largest live weight.
    scratch.resize(L);
    for (size_t k = 0; k < L; ++k) scratch[k] = weight[size_t(live[k])];
    std::nth_element(scratch.begin(), scratch.begin() + (excess - 1), scratch.end(), std::greater<std::int64_t>());
    const std::int64_t tau = scratch[size_t(excess - 1)];
    is_max.assign(L, 0);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, L, kBlock), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t k = r.begin(); k != r.end(); ++k) {
        const Index i = live[k];
        if (weight[size_t(i)] < tau) continue;
        if (weight[size_t(i)] == 0) {
          is_max[k] = 1;  // isolated candidates (tau == 0): chosen by index below
          continue;
        }
        if (const auto b = blocker[size_t(i)]; b >= 0 && alive[size_t(b)] && heavier(b, i)) continue;
        bool local_max = true;
        for (std::int64_t e = degree[size_t(i)]; e < degree[size_t(i) + 1] && local_max; ++e) {
          const Index j = adjacency[size_t(e)].j;
          if (alive[size_t(j)] && heavier(j, i)) {
            local_max = false;
            blocker[size_t(i)] = std::int32_t(j);
          }
        }
        is_max[k] = local_max;
      }
    });
    maxima.clear();
    for (size_t k = 0; k < L; ++k)
      if (is_max[k]) maxima.push_back(live[k]);
    if (Index(maxima.size()) > excess) {
      std::sort(maxima.begin(), maxima.end(), heavier);
      maxima.resize(static_cast<size_t>(excess));
    }
    if (maxima.empty()) throw InvariantError("sample elimination made no progress");
    for (Index i : maxima) alive[size_t(i)] = 0;
    // Push: each removed candidate subtracts its contribution from its live neighbours (integer atomics: exact).
    tbb::parallel_for(tbb::blocked_range<size_t>(0, maxima.size(), 64), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t k = r.begin(); k != r.end(); ++k) {
        const Index i = maxima[k];
        for (std::int64_t e = degree[size_t(i)]; e < degree[size_t(i) + 1]; ++e) {
          const Edge& edge = adjacency[size_t(e)];
          if (alive[size_t(edge.j)])
            std::atomic_ref<std::int64_t>(weight[size_t(edge.j)]).fetch_sub(edge.w, std::memory_order_relaxed);
        }
      }
    });
    live.erase(std::remove_if(live.begin(), live.end(), [&](std::int32_t i) { return !alive[size_t(i)]; }), live.end());
    ++rounds;
    report(progress,
           0.3 + 0.6 * double(excess0 - (Index(live.size()) - n_target)) / double(std::max<Index>(excess0, 1)));
  }

  return live;
}

// The samples' colours and intensity: a cloud sample's are its point's; a mesh sample's are its face corners',
// interpolated at its barycentrics (colours rounded).
void carry_appearance(const PointSet& input, const Candidates& cand, const std::vector<Index>& kept,
                      const std::vector<Index>& order, PointSet& out) {
  const Index n = Index(kept.size());
  const bool mesh = input.has_faces();
  Matrix3Xu8 colours(3, input.has_colours() ? n : 0);
  Eigen::VectorXf intensity(input.has_intensity() ? n : 0);
  for (Index k = 0; k < n; ++k) {
    const Index c = kept[size_t(order[size_t(k)])];
    if (!mesh) {
      if (colours.cols()) colours.col(k) = input.colours().col(cand.column(c));
      if (intensity.size()) intensity(k) = input.intensity()(cand.column(c));
      continue;
    }
    const Eigen::Vector3i corner = input.faces().col(cand.face(c)).cast<int>();
    const Eigen::Vector3d b = cand.bary.col(c);
    Eigen::Vector3d rgb = Eigen::Vector3d::Zero();
    double value = 0;
    for (int j = 0; j < 3; ++j) {
      if (colours.cols()) rgb += b(j) * input.colours().col(corner(j)).cast<double>();
      if (intensity.size()) value += b(j) * double(input.intensity()(corner(j)));
    }
    if (colours.cols()) colours.col(k) = rgb.array().round().min(255.0).max(0.0).cast<std::uint8_t>().matrix();
    if (intensity.size()) intensity(k) = float(value);
  }
  if (colours.cols()) out.set_colours(std::move(colours));
  if (intensity.size()) out.set_intensity(std::move(intensity));
}

void survivors(const PointSet& input, const Candidates& cand, const std::vector<std::int32_t>& live, bool use_normals,
               SampleResult& result) {
  const std::vector<Index> kept(live.begin(), live.end());  // ascending candidate order
  const bool mesh = input.has_faces();
  const Index n = Index(kept.size());
  Eigen::Matrix3Xd pos(3, n);
  for (Index k = 0; k < n; ++k) pos.col(k) = cand.positions.col(kept[size_t(k)]);
  const std::vector<Index> order = morton_order(pos);
  PointSet& out = result.samples;
  Eigen::Matrix3Xd P(3, n), N(3, use_normals || mesh ? n : 0), B(3, mesh ? n : 0);
  VectorXi32 F(mesh ? n : 0);
  VectorXi64 S(mesh ? 0 : n);
  for (Index k = 0; k < n; ++k) {
    const Index c = kept[size_t(order[size_t(k)])];
    P.col(k) = cand.positions.col(c);
    if (N.cols()) N.col(k) = cand.normals.col(c);
    if (mesh) {
      F(k) = cand.face(c);
      B.col(k) = cand.bary.col(c);
    } else {
      S(k) = cand.source(c);
    }
  }
  out.set_positions(std::move(P));
  if (N.cols()) out.set_normals(std::move(N));
  if (mesh)
    out.set_face_provenance(std::move(F), std::move(B));
  else
    out.set_source_index(std::move(S));
  out.set_viewpoint(input.viewpoint());
  if (input.has_colours() || input.has_intensity()) carry_appearance(input, cand, kept, order, out);
  out.check();
  KdTree out_tree;
  out_tree.build(out.positions());
  if (n >= 2) result.spacing = mean_nearest_neighbor_distance(out.positions(), out_tree);
}

}  // namespace

}  // namespace scanfill
