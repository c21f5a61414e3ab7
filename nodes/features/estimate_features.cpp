#include "nodes/features/estimate_features.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/parallel_sort.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <complex>
#include <numeric>
#include <tuple>

#include "nodes/core/disjoint_sets.h"
#include "nodes/core/errors.h"
#include "nodes/core/kdtree.h"
#include "nodes/features/features_options.h"

namespace scanfill {
namespace {

using Complex = std::complex<double>;
constexpr Index kGrain = 2048;

// Deterministic parallel sum over [0, n) of f(i).
template <class F>
double parallel_sum(Index n, F&& f) {
  return tbb::parallel_deterministic_reduce(
      tbb::blocked_range<Index>(0, n, kGrain), 0.0,
      [&](const tbb::blocked_range<Index>& r, double acc) {
        for (Index i = r.begin(); i != r.end(); ++i) acc += f(i);
        return acc;
      },
      std::plus<double>());
}

// A tangent frame (u, v) for normal n, a deterministic function of n.
void tangent_frame(const Eigen::Vector3d& n, Eigen::Vector3d& u, Eigen::Vector3d& v) {
  u = n.unitOrthogonal();
  v = n.cross(u);
}

// An edge i < j of the kNN graph and its orientation cost 1 - |n_i . n_j|, the same for either sign of either normal.
struct OrientEdge {
  double cost;
  std::int32_t i, j;
  bool operator<(const OrientEdge& o) const { return std::tie(cost, i, j) < std::tie(o.cost, o.i, o.j); }
};

// The kNN graph's edges by increasing cost, ties by their ends: one order whatever the thread count.
std::vector<OrientEdge> edges_by_cost(const Eigen::Matrix3Xd& N, const std::vector<std::int32_t>& knn, int k) {
  const Index n = N.cols();
  const size_t per_point = size_t(k - 1);
  std::vector<OrientEdge> edges(size_t(n) * per_point);
  tbb::parallel_for(tbb::blocked_range<Index>(0, n, kGrain), [&](const tbb::blocked_range<Index>& r) {
    for (Index i = r.begin(); i != r.end(); ++i)
      for (int a = 1; a < k; ++a) {
        const std::int32_t j = knn[size_t(i * k + a)];
        const double cost = 1.0 - std::abs(N.col(i).dot(N.col(j)));
        edges[size_t(i) * per_point + size_t(a - 1)] = {cost, std::min(std::int32_t(i), j),
                                                        std::max(std::int32_t(i), j)};
      }
  });
  tbb::parallel_sort(edges.begin(), edges.end());
  return edges;
}

// A forest as adjacency lists in CSR.
struct Forest {
  std::vector<std::int64_t> offset;
  std::vector<std::int32_t> adjacent;
};

// The minimum spanning forest of the kNN graph (Kruskal), for orientation costs 1 - |n_i . n_j|.
Forest spanning_forest(const Eigen::Matrix3Xd& N, const std::vector<std::int32_t>& knn, int k) {
  const Index n = N.cols();
  std::vector<std::pair<std::int32_t, std::int32_t>> kept;
  DisjointSets sets(n);
  for (const OrientEdge& e : edges_by_cost(N, knn, k))
    if (sets.join(e.i, e.j)) kept.emplace_back(e.i, e.j);
  Forest f{std::vector<std::int64_t>(size_t(n) + 1, 0), std::vector<std::int32_t>(2 * kept.size())};
  for (const auto& [i, j] : kept) {
    ++f.offset[size_t(i) + 1];
    ++f.offset[size_t(j) + 1];
  }
  std::partial_sum(f.offset.begin(), f.offset.end(), f.offset.begin());
  std::vector<std::int64_t> fill(f.offset.begin(), f.offset.end() - 1);
  for (const auto& [i, j] : kept) {
    f.adjacent[size_t(fill[size_t(i)]++)] = j;
    f.adjacent[size_t(fill[size_t(j)]++)] = i;
  }
  return f;
}

// Orients normals by propagation over a minimum spanning tree of the symmetrised kNN graph (Hoppe et al.): each
// tree's highest point's normal points up, each other normal agrees with its parent's, and then each tree's normals
// are flipped together when they point towards the centroid on balance.
void orient_by_propagation(const Eigen::Matrix3Xd& P, Eigen::Matrix3Xd& N, const std::vector<std::int32_t>& knn,
                           int k) {
  const Index n = P.cols();
  const Forest forest = spanning_forest(N, knn, k);
  const Eigen::Vector3d centroid = P.rowwise().mean();
  std::vector<std::uint8_t> visited(size_t(n), 0);
  std::vector<std::int32_t> component;
  std::vector<std::int32_t> by_z(static_cast<size_t>(n));
  std::iota(by_z.begin(), by_z.end(), 0);
  std::stable_sort(by_z.begin(), by_z.end(), [&](auto a, auto b) { return P(2, a) > P(2, b); });
  for (const std::int32_t seed : by_z) {
    if (visited[size_t(seed)]) continue;
    if (N(2, seed) < 0) N.col(seed) *= -1;
    component.assign(1, seed);
    visited[size_t(seed)] = 1;
    for (size_t next = 0; next < component.size(); ++next) {  // breadth first: parents before children
      const std::int32_t i = component[next];
      for (std::int64_t e = forest.offset[size_t(i)]; e < forest.offset[size_t(i) + 1]; ++e) {
        const std::int32_t j = forest.adjacent[size_t(e)];
        if (visited[size_t(j)]) continue;
        visited[size_t(j)] = 1;
        if (N.col(j).dot(N.col(i)) < 0) N.col(j) *= -1;
        component.push_back(j);
      }
    }
    double outward = 0;
    for (const auto i : component) outward += N.col(i).dot(P.col(i) - centroid);
    if (outward < 0)
      for (const auto i : component) N.col(i) *= -1;
  }
}

// Hermitian sparse matrix in CSR with complex entries, for the cross-field solve.
struct ComplexCsr {
  std::vector<std::int64_t> offset;
  std::vector<std::int32_t> column;
  std::vector<Complex> value;
  std::vector<double> diagonal;
  Index rows() const { return Index(diagonal.size()); }
  void multiply(const std::vector<Complex>& x, std::vector<Complex>& y) const {
    tbb::parallel_for(tbb::blocked_range<Index>(0, rows(), kGrain), [&](const tbb::blocked_range<Index>& r) {
      for (Index i = r.begin(); i != r.end(); ++i) {
        Complex s = diagonal[size_t(i)] * x[size_t(i)];
        for (std::int64_t e = offset[size_t(i)]; e < offset[size_t(i) + 1]; ++e)
          s += value[size_t(e)] * x[size_t(column[size_t(e)])];
        y[size_t(i)] = s;
      }
    });
  }
};

// Drops the slots of constants (column -1) and merges the two entries that a mutual kNN pair leaves in each row
// (most kNN edges are mutual), halving the work of every product.
void compact_rows(ComplexCsr& A) {
  const Index rows = A.rows();
  std::vector<std::int64_t> count(size_t(rows) + 1, 0);
  tbb::parallel_for(tbb::blocked_range<Index>(0, rows, 256), [&](const tbb::blocked_range<Index>& r) {
    std::vector<std::pair<std::int32_t, Complex>> row;
    for (Index i = r.begin(); i != r.end(); ++i) {
      row.clear();
      for (std::int64_t e = A.offset[size_t(i)]; e < A.offset[size_t(i) + 1]; ++e)
        if (A.column[size_t(e)] >= 0) row.push_back({A.column[size_t(e)], A.value[size_t(e)]});
      std::sort(row.begin(), row.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
      std::int64_t out = A.offset[size_t(i)];
      for (size_t k = 0; k < row.size(); ++k) {
        if (k > 0 && row[k].first == row[k - 1].first) {
          A.value[size_t(out - 1)] += row[k].second;
          continue;
        }
        A.column[size_t(out)] = row[k].first;
        A.value[size_t(out)] = row[k].second;
        ++out;
      }
      count[size_t(i) + 1] = out - A.offset[size_t(i)];
    }
  });
  std::partial_sum(count.begin(), count.end(), count.begin());
  std::vector<std::int32_t> column(size_t(count.back()));
  std::vector<Complex> value(size_t(count.back()));
  tbb::parallel_for(tbb::blocked_range<Index>(0, rows, 1024), [&](const tbb::blocked_range<Index>& r) {
    for (Index i = r.begin(); i != r.end(); ++i) {
      const auto n = count[size_t(i) + 1] - count[size_t(i)];
      std::copy_n(A.column.begin() + A.offset[size_t(i)], n, column.begin() + count[size_t(i)]);
      std::copy_n(A.value.begin() + A.offset[size_t(i)], n, value.begin() + count[size_t(i)]);
    }
  });
  A.offset = std::move(count);
  A.column = std::move(column);
  A.value = std::move(value);
}

// Jacobi-preconditioned CG for the Hermitian positive definite system A x = b.
void conjugate_gradient(const ComplexCsr& A, const std::vector<Complex>& b, std::vector<Complex>& x, int max_iter,
                        double tol, FeaturesResult& result) {
  const Index n = A.rows();
  std::vector<Complex> r(static_cast<size_t>(n)), z(static_cast<size_t>(n)), p(static_cast<size_t>(n)),
      q(static_cast<size_t>(n));
  A.multiply(x, q);
  for (Index i = 0; i < n; ++i) r[size_t(i)] = b[size_t(i)] - q[size_t(i)];
  const double b_norm = std::sqrt(parallel_sum(n, [&](Index i) { return std::norm(b[size_t(i)]); }));
  if (b_norm == 0) {
    std::fill(x.begin(), x.end(), Complex(0));
    return;
  }
  for (Index i = 0; i < n; ++i) z[size_t(i)] = r[size_t(i)] / A.diagonal[size_t(i)];
  p = z;
  double rz = parallel_sum(n, [&](Index i) { return std::real(std::conj(r[size_t(i)]) * z[size_t(i)]); });
  result.converged = false;
  for (int it = 0; it < max_iter; ++it) {
    const double r_norm = std::sqrt(parallel_sum(n, [&](Index i) { return std::norm(r[size_t(i)]); }));
    result.residual = r_norm / b_norm;
    result.iterations = it;
    if (result.residual < tol) {
      result.converged = true;
      return;
    }
    A.multiply(p, q);
    const double pq = parallel_sum(n, [&](Index i) { return std::real(std::conj(p[size_t(i)]) * q[size_t(i)]); });
    if (!(pq > 0)) break;
    const double alpha = rz / pq;
    tbb::parallel_for(tbb::blocked_range<Index>(0, n, kGrain), [&](const tbb::blocked_range<Index>& rg) {
      for (Index i = rg.begin(); i != rg.end(); ++i) {
        x[size_t(i)] += alpha * p[size_t(i)];
        r[size_t(i)] -= alpha * q[size_t(i)];
        z[size_t(i)] = r[size_t(i)] / A.diagonal[size_t(i)];
      }
    });
    const double rz_new = parallel_sum(n, [&](Index i) { return std::real(std::conj(r[size_t(i)]) * z[size_t(i)]); });
    const double beta = rz_new / rz;
    rz = rz_new;
    tbb::parallel_for(tbb::blocked_range<Index>(0, n, kGrain), [&](const tbb::blocked_range<Index>& rg) {
      for (Index i = rg.begin(); i != rg.end(); ++i) p[size_t(i)] = z[size_t(i)] + beta * p[size_t(i)];
    });
    result.iterations = it + 1;
  }
  result.residual = std::sqrt(parallel_sum(n, [&](Index i) { return std::norm(r[size_t(i)]); })) / b_norm;
  result.converged = result.residual < tol;
}

// exp(4 i rho_ij): j's frame vector u_j carried to i's tangent plane (by projection, which agrees with the minimal
// rotation to second order in the angle between the normals), as a unit complex number in i's frame, to the 4th power.
Complex connection4(const Eigen::Vector3d& ni, const Eigen::Vector3d& ui, const Eigen::Vector3d& vi,
                    const Eigen::Vector3d& uj) {
  const Eigen::Vector3d t = uj - uj.dot(ni) * ni;
  Complex c(t.dot(ui), t.dot(vi));
  const double len = std::abs(c);
  if (!(len > 1e-12)) return Complex(1.0, 0.0);
  c /= len;
  c *= c;
  return c * c;
}

// Per point: its k nearest neighbours (self first), the distance to the farthest, and the PCA normal (unoriented).
struct Neighbourhoods {
  std::vector<std::int32_t> knn;  // n * k
  std::vector<double> radius;
  Eigen::Matrix3Xd normals;
};

// Neighbours this nearly on a line (the covariance's middle eigenvalue under this share of its largest) leave the PCA
// normal undetermined about the line: a single scan row, as a grazing view of a lid gives (the ribbed box's lid from
// the front in a 160 by 160 scan: rows 11 cm apart, 3 mm between points along each). There the PCA of kWiden times as
// many neighbours, which reach the next rows, stands; else the input's own normal, where it has one.
constexpr double kCollinear = 0.01;
constexpr int kWiden = 8;

struct PcaNormal {
  Eigen::Vector3d normal;
  bool on_a_line;
};

PcaNormal pca_normal(const Eigen::Matrix3Xd& P, const std::int32_t* nb, int count) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (int a = 0; a < count; ++a) mean += P.col(nb[a]);
  mean /= count;
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (int a = 0; a < count; ++a) {
    const Eigen::Vector3d d = P.col(nb[a]) - mean;
    cov.noalias() += d * d.transpose();
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
  eig.computeDirect(cov);
  return {eig.eigenvectors().col(0), eig.eigenvalues()(1) < kCollinear * eig.eigenvalues()(2)};
}

bool has_own_normal(const PointSet& input, Index i) {
  return input.has_normals() && input.normals().col(i).squaredNorm() > 0.25;
}

// Per-thread buffers of the wider neighbourhood.
struct WideNeighbours {
  std::vector<std::int32_t> nb;
  std::vector<double> d2;
};

// The normal at point i, whose k neighbours lie on a line (`on_line`, their PCA normal): the wider neighbourhood's
// PCA, which agrees with its neighbours' (a normal of another kind beside them bends the curvature fit), else the
// input's own normal.
Eigen::Vector3d normal_off_the_line(const PointSet& input, const KdTree& tree, Index i, const Eigen::Vector3d& on_line,
                                    WideNeighbours& wide) {
  const int count = int(wide.nb.size());
  tree.knn(input.positions().col(i), count, wide.nb.data(), wide.d2.data());
  const PcaNormal w = pca_normal(input.positions(), wide.nb.data(), count);
  if (!w.on_a_line) return w.normal;
  return has_own_normal(input, i) ? Eigen::Vector3d(input.normals().col(i).normalized()) : on_line;
}

Neighbourhoods pca_normals(const PointSet& input, const KdTree& tree, int k) {
  const Eigen::Matrix3Xd& P = input.positions();
  const Index n = P.cols();
  Neighbourhoods out;
  std::vector<std::int32_t>& knn = out.knn;
  std::vector<double>& radius = out.radius;
  Eigen::Matrix3Xd& N = out.normals;
  knn.resize(size_t(n * k));
  radius.resize(static_cast<size_t>(n));
  N.resize(3, n);
  const size_t wide_count = size_t(std::min<Index>(n, Index(kWiden) * k));
  tbb::parallel_for(tbb::blocked_range<Index>(0, n, kGrain), [&](const tbb::blocked_range<Index>& r) {
    std::vector<double> d2(static_cast<size_t>(k));
    WideNeighbours wide{std::vector<std::int32_t>(wide_count), std::vector<double>(wide_count)};
    for (Index i = r.begin(); i != r.end(); ++i) {
      std::int32_t* nb = &knn[size_t(i * k)];
      tree.knn(P.col(i), k, nb, d2.data());
      radius[size_t(i)] = std::sqrt(d2[size_t(k - 1)]);
      const PcaNormal pca = pca_normal(P, nb, k);
      N.col(i) = pca.on_a_line ? normal_off_the_line(input, tree, i, pca.normal, wide) : pca.normal;
    }
  });
  return out;
}

// Flips the normals N to agree with the input's normals, a viewpoint, or each other (propagation), as `options` ask
// ('auto' picks in that order what the input has). Returns the orientation used.
NormalOrientation orient_normals(const PointSet& input, const Neighbourhoods& hood, int k,
                                 const FeaturesOptions& options, Eigen::Matrix3Xd& N) {
  const Index n = input.size();
  const Eigen::Matrix3Xd& P = input.positions();
  const std::vector<std::int32_t>& knn = hood.knn;
  NormalOrientation mode = options.orientation;
  const std::optional<Eigen::Vector3d> viewpoint = options.viewpoint ? options.viewpoint : input.viewpoint();
  if (mode == NormalOrientation::kAuto)
    mode = input.has_normals() ? NormalOrientation::kInput
           : viewpoint         ? NormalOrientation::kViewpoint
                               : NormalOrientation::kPropagate;
  if (mode == NormalOrientation::kInput && !input.has_normals())
    throw InputError("normal orientation 'input' asked, but the input has no normals");
  if (mode == NormalOrientation::kViewpoint && !viewpoint)
    throw InputError("normal orientation 'viewpoint' asked, but no viewpoint is known (set features.viewpoint)");
  if (mode == NormalOrientation::kPropagate) {
    orient_by_propagation(P, N, knn, k);
  } else {
    tbb::parallel_for(tbb::blocked_range<Index>(0, n, kGrain), [&](const tbb::blocked_range<Index>& r) {
      for (Index i = r.begin(); i != r.end(); ++i) {
        const Eigen::Vector3d ref = mode == NormalOrientation::kInput ? Eigen::Vector3d(input.normals().col(i))
                                                                      : Eigen::Vector3d(*viewpoint - P.col(i));
        if (N.col(i).dot(ref) < 0) N.col(i) *= -1;
      }
    });
  }
  return mode;
}

// One tangent frame (U, V) per point, shared by the curvature fit and the cross field.
void tangent_frames(const Eigen::Matrix3Xd& N, Eigen::Matrix3Xd& U, Eigen::Matrix3Xd& V) {
  const Index n = N.cols();
  U.resize(3, n);
  V.resize(3, n);
  tbb::parallel_for(tbb::blocked_range<Index>(0, n, kGrain), [&](const tbb::blocked_range<Index>& r) {
    for (Index i = r.begin(); i != r.end(); ++i) {
      Eigen::Vector3d u, v;
      tangent_frame(N.col(i), u, v);
      U.col(i) = u;
      V.col(i) = v;
    }
  });
}

// The shape operator fit per point, dn = S dp in the tangent plane: signed principal curvatures K (|k1| >= |k2|),
// the k1 direction D, whether that direction is unreliable (flat or umbilic), and exp(4 i theta) of it (`raw`).
struct ShapeOperatorFit {
  Eigen::Matrix2Xd K;
  Eigen::Matrix3Xd D;
  std::vector<std::uint8_t> unreliable;
  std::vector<Complex> raw;  // exp(4 i theta) of the raw k1 direction in the tangent frame
};

ShapeOperatorFit fit_shape_operator(const Eigen::Matrix3Xd& P, const Eigen::Matrix3Xd& N, const Eigen::Matrix3Xd& U,
                                    const Eigen::Matrix3Xd& V, const Neighbourhoods& hood, int k,
                                    const FeaturesOptions& options) {
  const Index n = P.cols();
  const std::vector<std::int32_t>& knn = hood.knn;
  const std::vector<double>& radius = hood.radius;
  ShapeOperatorFit fit;
  Eigen::Matrix2Xd& K = fit.K;
  Eigen::Matrix3Xd& D = fit.D;
  std::vector<std::uint8_t>& unreliable = fit.unreliable;
  std::vector<Complex>& raw = fit.raw;
  K.resize(2, n);
  D.resize(3, n);
  unreliable.assign(size_t(n), 0);
  raw.resize(static_cast<size_t>(n));
  tbb::parallel_for(tbb::blocked_range<Index>(0, n, kGrain), [&](const tbb::blocked_range<Index>& r) {
    for (Index i = r.begin(); i != r.end(); ++i) {
      const Eigen::Vector3d ni = N.col(i), u = U.col(i), v = V.col(i);
      Eigen::Matrix3d AtA = Eigen::Matrix3d::Zero();
      Eigen::Vector3d Atb = Eigen::Vector3d::Zero();
      const std::int32_t* nb = &knn[size_t(i * k)];
      for (int a = 1; a < k; ++a) {
        const Eigen::Vector3d dp = P.col(nb[a]) - P.col(i);
        Eigen::Vector3d nj = N.col(nb[a]);
        if (nj.dot(ni) < 0) nj = -nj;
        const Eigen::Vector3d dn = nj - ni;
        const double x = dp.dot(u), y = dp.dot(v), du = dn.dot(u), dv = dn.dot(v);
        // rows [x y 0] . (e f g) = du and [0 x y] . (e f g) = dv
        const Eigen::Vector3d r1(x, y, 0), r2(0, x, y);
        AtA.noalias() += r1 * r1.transpose() + r2 * r2.transpose();
        Atb += r1 * du + r2 * dv;
      }
      Eigen::Vector3d s = Eigen::Vector3d::Zero();
      Eigen::LDLT<Eigen::Matrix3d> ldlt(AtA);
      // Singular fits are skipped relative to the neighbourhood's size (AtA grows as h^2, its determinant as h^6): an
      // absolute bound made every point of a model scaled to 1e-5 flat (k1 = k2 = 0).
      const double scale = AtA.trace();
      if (ldlt.info() == Eigen::Success && ldlt.isPositive() &&
          std::abs(AtA.determinant()) > 1e-20 * scale * scale * scale)
        s = ldlt.solve(Atb);
      if (!s.allFinite()) s.setZero();
      Eigen::Matrix2d S;
      S << s(0), s(1), s(1), s(2);
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(S);
      int big = std::abs(eig.eigenvalues()(1)) >= std::abs(eig.eigenvalues()(0)) ? 1 : 0;
      const double k1 = eig.eigenvalues()(big), k2 = eig.eigenvalues()(1 - big);
      const Eigen::Vector2d e = eig.eigenvectors().col(big);
      K.col(i) << k1, k2;
      D.col(i) = (e(0) * u + e(1) * v).normalized();
      const double theta = std::atan2(e(1), e(0));
      raw[size_t(i)] = std::polar(1.0, 4 * theta);
      const double h = radius[size_t(i)];
      unreliable[size_t(i)] =
          std::abs(k1) * h < options.flat_threshold || std::abs(k2) > options.umbilic_ratio * std::abs(k1);
    }
  });
  return fit;
}

// Replaces the unreliable directions of `fit.D` by a smooth 4-fold cross field (Hertzmann and Zorin 2000): one complex
// unknown per unreliable point and its neighbours, solved by conjugate gradients; counts them in `result`.
void smooth_cross_field(const Eigen::Matrix3Xd& N, const Eigen::Matrix3Xd& U, const Eigen::Matrix3Xd& V,
                        const Neighbourhoods& hood, int k, const FeaturesOptions& options, ShapeOperatorFit& fit,
                        FeaturesResult& result) {
  const Index n = N.cols();
  const std::vector<std::int32_t>& knn = hood.knn;
  const std::vector<std::uint8_t>& unreliable = fit.unreliable;
  const std::vector<Complex>& raw = fit.raw;
  Eigen::Matrix3Xd& D = fit.D;
  for (Index i = 0; i < n; ++i) result.unreliable_directions += unreliable[size_t(i)];
  if (options.smooth_directions && result.unreliable_directions > 0) {
    // Unknowns: unreliable points and their reliable neighbours (soft-constrained); the rest enter as constants.
    std::vector<std::int32_t> unknown_id(size_t(n), -1);
    for (Index i = 0; i < n; ++i)
      if (unreliable[size_t(i)])
        for (int a = 0; a < k; ++a) unknown_id[size_t(knn[size_t(i * k + a)])] = 0;
    std::vector<std::int32_t> unknowns;
    for (Index i = 0; i < n; ++i)
      if (unknown_id[size_t(i)] == 0) {
        unknown_id[size_t(i)] = std::int32_t(unknowns.size());
        unknowns.push_back(std::int32_t(i));
      }
    const Index m = Index(unknowns.size());
    // Each directed kNN edge (i, j) adds |z_i - c_ij z_j|^2 with c_ij = exp(4 i rho_ij): A_ii += 1, A_jj += 1,
    // A_ij -= c_ij, A_ji -= conj(c_ij). Rows gather, per unknown, its out-edges and the in-edges pointing to it.
    std::vector<std::int64_t> in_offset(size_t(m) + 1, 0);  // CSR of in-edges: the points whose kNN name the row
    for (Index i = 0; i < n; ++i)
      for (int a = 1; a < k; ++a)
        if (const auto j = unknown_id[size_t(knn[size_t(i * k + a)])]; j >= 0) ++in_offset[size_t(j) + 1];
    std::partial_sum(in_offset.begin(), in_offset.end(), in_offset.begin());
    std::vector<std::int32_t> in_source(size_t(in_offset.back()));
    {
      std::vector<std::int64_t> fill(in_offset.begin(), in_offset.end() - 1);
      for (Index i = 0; i < n; ++i)
        for (int a = 1; a < k; ++a)
          if (const auto j = unknown_id[size_t(knn[size_t(i * k + a)])]; j >= 0)
            in_source[size_t(fill[size_t(j)]++)] = std::int32_t(i);
    }
    std::vector<std::int64_t> offset(size_t(m) + 1, 0);
    for (Index r = 0; r < m; ++r)
      offset[size_t(r) + 1] = offset[size_t(r)] + (k - 1) + (in_offset[size_t(r) + 1] - in_offset[size_t(r)]);
    ComplexCsr A;
    A.offset = offset;
    A.column.resize(size_t(offset.back()));
    A.value.resize(size_t(offset.back()));
    A.diagonal.assign(size_t(m), 0.0);
    std::vector<Complex> b(static_cast<size_t>(m)), x(static_cast<size_t>(m));
    tbb::parallel_for(tbb::blocked_range<Index>(0, m, 256), [&](const tbb::blocked_range<Index>& rg) {
      for (Index row = rg.begin(); row != rg.end(); ++row) {
        const std::int32_t i = unknowns[size_t(row)];
        const Eigen::Vector3d ni = N.col(i), ui = U.col(i), vi = V.col(i);
        double diag = 0;
        Complex rhs = 0;
        std::int64_t e = offset[size_t(row)];
        auto add = [&](std::int32_t j, Complex c) {  // term |z_i - c z_j|^2 seen from row i
          diag += 1.0;
          if (unknown_id[size_t(j)] >= 0) {
            A.column[size_t(e)] = unknown_id[size_t(j)];
            A.value[size_t(e)] = -c;
          } else {
            A.column[size_t(e)] = -1;  // a constant: moves to the right-hand side, its slot is dropped below
            rhs += c * raw[size_t(j)];
          }
          ++e;
        };
        for (int a = 1; a < k; ++a) {
          const std::int32_t j = knn[size_t(i * k + a)];
          add(j, connection4(ni, ui, vi, U.col(j)));
        }
        for (std::int64_t s = in_offset[size_t(row)]; s < in_offset[size_t(row) + 1]; ++s) {
          const std::int32_t j = in_source[size_t(s)];  // edge (j, i): its term |z_j - c_ji z_i|^2 seen from row i
          add(j, std::conj(connection4(N.col(j), U.col(j), V.col(j), ui)));
        }
        const double lambda = unreliable[size_t(i)] ? options.regularization : options.reliable_weight;
        A.diagonal[size_t(row)] = diag + lambda;
        b[size_t(row)] = rhs + lambda * raw[size_t(i)];
        x[size_t(row)] = raw[size_t(i)];
      }
    });
    compact_rows(A);
    conjugate_gradient(A, b, x, options.max_iterations, options.tolerance, result);
    if (!result.converged)
      result.warnings.push_back("cross-field smoothing stopped after " + std::to_string(result.iterations) +
                                " iterations at relative residual " + std::to_string(result.residual));
    tbb::parallel_for(tbb::blocked_range<Index>(0, m, kGrain), [&](const tbb::blocked_range<Index>& rg) {
      for (Index row = rg.begin(); row != rg.end(); ++row) {
        const std::int32_t i = unknowns[size_t(row)];
        if (!unreliable[size_t(i)] || std::abs(x[size_t(row)]) < 1e-12) continue;
        const double theta = std::arg(x[size_t(row)]) / 4;
        D.col(i) = std::cos(theta) * U.col(i) + std::sin(theta) * V.col(i);
      }
    });
  }
}

}  // namespace

FeaturesResult estimate_features(const PointSet& input, const FeaturesOptions& options, const ProgressFn& progress) {
  check_options(options);  // the config checks these too; a direct caller gets the same checks
  input.check();
  const Index n = input.size();
  const int k = options.k;
  if (n < k + 1)
    throw InputError("features need at least k + 1 = " + std::to_string(k + 1) + " points, the input has " +
                     std::to_string(n));
  FeaturesResult result;
  const Eigen::Matrix3Xd& P = input.positions();
  KdTree tree;
  tree.build(P);
  Neighbourhoods hood = pca_normals(input, tree, k);
  report(progress, 0.3);
  Eigen::Matrix3Xd N = std::move(hood.normals);
  result.orientation_used = orient_normals(input, hood, k, options, N);
  report(progress, 0.45);
  Eigen::Matrix3Xd U, V;
  tangent_frames(N, U, V);
  ShapeOperatorFit fit = fit_shape_operator(P, N, U, V, hood, k, options);
  report(progress, 0.7);
  smooth_cross_field(N, U, V, hood, k, options, fit, result);
  report(progress, 1.0);

  result.points = input;
  result.points.set_normals(std::move(N));
  result.points.set_curvatures(std::move(fit.K));
  result.points.set_directions(std::move(fit.D));
  result.points.check();
  return result;
}

}  // namespace scanfill
