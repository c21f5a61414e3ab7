#include "nodes/correspond/deformation_solve.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "nodes/correspond/block_cholesky.h"

namespace scanfill {
namespace {

using Block = BlockCholesky::Block;
using Vector12 = Eigen::Matrix<double, 12, 1>;

// The parameter of A(c, a) (a < 3) or of t_c (a = 3) among a node's 12 (deformation_node.h).
constexpr int slot(int c, int a) {
  return a < 3 ? 3 * c + a : 9 + c;
}

Eigen::Vector4d homogeneous(const Eigen::Vector3d& e) {
  return {e.x(), e.y(), e.z(), 1.0};
}

const Eigen::Vector4d kTranslation(0, 0, 0, 1);  // homogeneous offset of a term that moves with t alone

// h += f P (x) (a b^T): the Gauss-Newton block of two nodes whose motions enter a term as A a and A b (P the term's
// 3 x 3 weight).
void add_kronecker(Block& h, const Eigen::Matrix3d& p, const Eigen::Vector4d& a, const Eigen::Vector4d& b, double f) {
  const Eigen::Matrix4d ab = f * a * b.transpose();
  for (int c = 0; c < 3; ++c)
    for (int d = 0; d < 3; ++d) {
      const double pcd = p(c, d);
      if (pcd == 0) continue;
      for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) h(slot(c, i), slot(d, j)) += pcd * ab(i, j);
    }
}

// g += f y (x) a: the gradient of a term with weighted residual y through a node that enters it as A a.
void add_kronecker(Vector12& g, const Eigen::Vector3d& y, const Eigen::Vector4d& a, double f) {
  for (int c = 0; c < 3; ++c)
    for (int i = 0; i < 4; ++i) g(slot(c, i)) += f * y(c) * a(i);
}

const double* node_params(const std::vector<double>& x, std::int32_t j) {
  return &x[size_t(j) * 12];
}

// A data term's 3 x 3 weight M^T M.
Eigen::Matrix3d data_weight(const DeformationDataTerm& t) {
  return 0.25 * Eigen::Matrix3d::Identity() + t.plane * t.plane * t.n * t.n.transpose();
}

// Huber's rho and rho' at the squared norm s (Ceres' HuberLoss).
std::pair<double, double> huber(double s, double scale) {
  if (s <= scale * scale) return {s, 1.0};
  const double r = std::sqrt(s);
  return {2 * scale * r - scale * scale, scale / r};
}

// The rotation term's residuals and 6 x 12 Jacobian at node parameters x.
void rotation_residual(const double* x, double w, Eigen::Matrix<double, 6, 1>& r, Eigen::Matrix<double, 6, 12>* J) {
  const Eigen::Vector3d c0(x[0], x[3], x[6]), c1(x[1], x[4], x[7]), c2(x[2], x[5], x[8]);
  r << c0.dot(c1), c0.dot(c2), c1.dot(c2), c0.dot(c0) - 1, c1.dot(c1) - 1, c2.dot(c2) - 1;
  r *= w;
  if (!J) return;
  J->setZero();
  for (int row = 0; row < 3; ++row) {  // d/dA(row, m) of the column products
    const double a0 = x[3 * row], a1 = x[3 * row + 1], a2 = x[3 * row + 2];
    const int s0 = 3 * row, s1 = 3 * row + 1, s2 = 3 * row + 2;
    (*J)(0, s0) = a1, (*J)(0, s1) = a0;
    (*J)(1, s0) = a2, (*J)(1, s2) = a0;
    (*J)(2, s1) = a2, (*J)(2, s2) = a1;
    (*J)(3, s0) = 2 * a0, (*J)(4, s1) = 2 * a1, (*J)(5, s2) = 2 * a2;
  }
  *J *= w;
}

// The smooth term's residual: node j's prediction of node k minus where k goes.
Eigen::Vector3d smooth_residual(const DeformationProblem& pr, const std::vector<double>& x, std::int32_t j,
                                std::int32_t k) {
  const Eigen::Vector3d gj = pr.nodes.col(j), gk = pr.nodes.col(k);
  const double* xk = node_params(x, k);
  return pr.edge_scale * (deform_by(node_params(x, j), gk, gj) - gk - Eigen::Vector3d(xk[9], xk[10], xk[11]));
}

// A data term's scaled offset s (v - q).
Eigen::Vector3d data_residual(const DeformationProblem& pr, const std::vector<double>& x,
                              const DeformationDataTerm& t) {
  Eigen::Vector3d v = Eigen::Vector3d::Zero();
  for (int i = 0; i < kNodesPerPoint; ++i)
    v += t.weight[size_t(i)] * deform_by(node_params(x, t.node[size_t(i)]), t.p, pr.nodes.col(t.node[size_t(i)]));
  return t.scale * (v - t.q);
}

// Per data term: its scaled offset and IRLS weight rho'; and the whole cost. Sums run in a fixed order.
struct Linearisation {
  std::vector<Eigen::Vector3d> offset;
  std::vector<double> irls;
  double cost = 0;
};

void linearise(const DeformationProblem& pr, const std::vector<double>& x, Linearisation& lin) {
  const size_t nd = pr.data.size(), nn = size_t(pr.nodes.cols()), ne = pr.edges.size();
  lin.offset.resize(nd);
  lin.irls.resize(nd);
  std::vector<double> cost(nd + nn + ne);
  tbb::parallel_for(size_t(0), nd, [&](size_t t) {
    const DeformationDataTerm& term = pr.data[t];
    const Eigen::Vector3d d = data_residual(pr, x, term);
    const double s = d.dot(data_weight(term) * d);
    const auto [rho, drho] = term.robust ? huber(s, pr.huber) : std::pair{s, 1.0};
    lin.offset[t] = d;
    lin.irls[t] = drho;
    cost[t] = 0.5 * rho;
  });
  tbb::parallel_for(size_t(0), nn, [&](size_t j) {
    Eigen::Matrix<double, 6, 1> r;
    rotation_residual(node_params(x, std::int32_t(j)), pr.rotation_scale, r, nullptr);
    cost[nd + j] = 0.5 * r.squaredNorm();
  });
  tbb::parallel_for(size_t(0), ne, [&](size_t e) {
    cost[nd + nn + e] = 0.5 * smooth_residual(pr, x, pr.edges[e].first, pr.edges[e].second).squaredNorm();
  });
  lin.cost = 0;
  for (const double c : cost) lin.cost += c;
}

// The normal matrix's block pattern: per node row its column nodes (sorted), and the data terms and edges that touch
// the row's node.
struct Pattern {
  std::vector<std::int64_t> row_start;  // row j's blocks: [row_start[j], row_start[j + 1])
  std::vector<std::int32_t> column;
  std::vector<std::int64_t> term_start;
  std::vector<std::int32_t> term;  // data term * kNodesPerPoint + the node's place in it
  std::vector<std::int64_t> edge_start;
  std::vector<std::int32_t> edge;  // edge * 2 + 0 where the row is the edge's j, + 1 where it is its k

  std::int64_t block(std::int32_t j, std::int32_t k) const {
    const auto first = column.begin() + row_start[size_t(j)], last = column.begin() + row_start[size_t(j) + 1];
    return std::lower_bound(first, last, k) - column.begin();
  }
};

// Flattens per-row lists into start offsets and values.
template <class T>
void flatten(const std::vector<std::vector<T>>& rows, std::vector<std::int64_t>& start, std::vector<T>& values) {
  start.assign(rows.size() + 1, 0);
  for (size_t j = 0; j < rows.size(); ++j) start[j + 1] = start[j] + std::int64_t(rows[j].size());
  values.clear();
  values.reserve(size_t(start.back()));
  for (const auto& row : rows) values.insert(values.end(), row.begin(), row.end());
}

Pattern block_pattern(const DeformationProblem& pr) {
  const size_t nn = size_t(pr.nodes.cols());
  std::vector<std::vector<std::int32_t>> columns(nn), terms(nn), edges(nn);
  for (size_t j = 0; j < nn; ++j) columns[j].push_back(std::int32_t(j));
  for (size_t t = 0; t < pr.data.size(); ++t)
    for (int a = 0; a < kNodesPerPoint; ++a) {
      const auto j = size_t(pr.data[t].node[size_t(a)]);
      terms[j].push_back(std::int32_t(t * kNodesPerPoint + size_t(a)));
      for (const auto k : pr.data[t].node) columns[j].push_back(k);
    }
  for (size_t e = 0; e < pr.edges.size(); ++e) {
    const auto [j, k] = pr.edges[e];
    edges[size_t(j)].push_back(std::int32_t(2 * e));
    edges[size_t(k)].push_back(std::int32_t(2 * e + 1));
    columns[size_t(j)].push_back(k);
    columns[size_t(k)].push_back(j);
  }
  for (auto& c : columns) {
    std::sort(c.begin(), c.end());
    c.erase(std::unique(c.begin(), c.end()), c.end());
  }
  Pattern p;
  flatten(columns, p.row_start, p.column);
  flatten(terms, p.term_start, p.term);
  flatten(edges, p.edge_start, p.edge);
  return p;
}

// Row j of J^T J and J^T r: the blocks from its rotation term, its edges and its data terms, in that order.
void assemble_row(const DeformationProblem& pr, const Pattern& pat, const std::vector<double>& x,
                  const Linearisation& lin, std::int32_t j, Block* blocks, Vector12& g) {
  for (auto b = pat.row_start[size_t(j)]; b < pat.row_start[size_t(j) + 1]; ++b) blocks[b].setZero();
  g.setZero();
  Eigen::Matrix<double, 6, 1> rr;
  Eigen::Matrix<double, 6, 12> rj;
  rotation_residual(node_params(x, j), pr.rotation_scale, rr, &rj);
  blocks[pat.block(j, j)].noalias() += rj.transpose() * rj;
  g.noalias() += rj.transpose() * rr;
  const Eigen::Matrix3d identity = Eigen::Matrix3d::Identity();
  const double s2 = pr.edge_scale * pr.edge_scale;
  for (auto i = pat.edge_start[size_t(j)]; i < pat.edge_start[size_t(j) + 1]; ++i) {
    const auto [a, b] = pr.edges[size_t(pat.edge[size_t(i)] / 2)];
    const Eigen::Vector4d d = homogeneous(pr.nodes.col(b) - pr.nodes.col(a));
    const Eigen::Vector4d& mine = pat.edge[size_t(i)] % 2 == 0 ? d : kTranslation;
    const double sign = pat.edge[size_t(i)] % 2 == 0 ? 1.0 : -1.0;
    add_kronecker(blocks[pat.block(j, a)], identity, mine, d, sign * s2);
    add_kronecker(blocks[pat.block(j, b)], identity, mine, kTranslation, -sign * s2);
    add_kronecker(g, smooth_residual(pr, x, a, b), mine, sign * pr.edge_scale);
  }
  for (auto i = pat.term_start[size_t(j)]; i < pat.term_start[size_t(j) + 1]; ++i) {
    const auto t = size_t(pat.term[size_t(i)]) / kNodesPerPoint;
    const auto a = size_t(pat.term[size_t(i)]) % kNodesPerPoint;
    const DeformationDataTerm& term = pr.data[t];
    const Eigen::Matrix3d P = data_weight(term);
    const double f = lin.irls[t] * term.scale * term.weight[a];
    const Eigen::Vector4d ea = homogeneous(term.p - pr.nodes.col(j));
    for (size_t b = 0; b < kNodesPerPoint; ++b) {
      const Eigen::Vector4d eb = homogeneous(term.p - pr.nodes.col(term.node[b]));
      add_kronecker(blocks[pat.block(j, term.node[b])], P, ea, eb, f * term.scale * term.weight[b]);
    }
    add_kronecker(g, P * lin.offset[t], ea, f);
  }
}

// diag(J^T J), clamped to [1e-6, 1e32] as Ceres' Levenberg-Marquardt does: the damping's scale.
Eigen::VectorXd damping_scale(const Pattern& pat, const std::vector<Block>& blocks) {
  const auto nn = Eigen::Index(pat.row_start.size()) - 1;
  Eigen::VectorXd d(12 * nn);
  for (Eigen::Index j = 0; j < nn; ++j)
    d.segment<12>(12 * j) =
        blocks[size_t(pat.block(std::int32_t(j), std::int32_t(j)))].diagonal().cwiseMax(1e-6).cwiseMin(1e32);
  return d;
}

// J^T J's blocks and the gradient J^T r at x.
void assemble(const DeformationProblem& pr, const Pattern& pat, const std::vector<double>& x, const Linearisation& lin,
              std::vector<Block>& blocks, Eigen::VectorXd& gradient) {
  blocks.resize(pat.column.size());
  gradient.resize(12 * pr.nodes.cols());
  tbb::parallel_for(std::int32_t(0), std::int32_t(pr.nodes.cols()), [&](std::int32_t j) {
    Vector12 g;
    assemble_row(pr, pat, x, lin, j, blocks.data(), g);
    gradient.segment<12>(12 * Eigen::Index(j)) = g;
  });
}

}  // namespace

double deformation_cost(const DeformationProblem& problem, const std::vector<double>& params) {
  Linearisation lin;
  linearise(problem, params, lin);
  return lin.cost;
}

SolverSummary solve_deformation(const DeformationProblem& pr, std::vector<double>& x, int max_iterations) {
  const Pattern pat = block_pattern(pr);
  BlockCholesky cholesky(pat.row_start, pat.column);
  Linearisation lin, trial;
  linearise(pr, x, lin);
  SolverSummary summary{"NO_CONVERGENCE", 1, lin.cost, lin.cost};
  std::vector<Block> blocks;
  Eigen::VectorXd gradient, damping;
  const auto linearise_at_x = [&] {
    assemble(pr, pat, x, lin, blocks, gradient);
    damping = damping_scale(pat, blocks);
  };
  linearise_at_x();
  double radius = 1e4, decrease = 2;
  const auto converged = [&] {
    summary.termination = "CONVERGENCE";
    return summary;
  };
  const auto shrink = [&] { radius /= decrease, decrease *= 2; };  // after an unsuccessful step
  for (int step = 0; step < max_iterations; ++step, ++summary.iterations) {
    if (gradient.lpNorm<Eigen::Infinity>() <= 1e-10) return converged();
    const Eigen::VectorXd delta =
        cholesky.factorize(blocks, damping / radius) ? Eigen::VectorXd(-cholesky.solve(gradient)) : Eigen::VectorXd();
    if (delta.size() == 0 || !delta.allFinite()) {
      shrink();
      continue;
    }
    const Eigen::Map<Eigen::VectorXd> xv(x.data(), Eigen::Index(x.size()));
    if (delta.norm() <= 1e-8 * (xv.norm() + 1e-8)) return converged();
    // Model decrease -(g.d + d.H d / 2), with (H + D / radius) d = -g.
    const double model = 0.5 * (-gradient.dot(delta) + delta.dot(damping.cwiseProduct(delta)) / radius);
    std::vector<double> candidate(x);
    Eigen::Map<Eigen::VectorXd>(candidate.data(), Eigen::Index(candidate.size())) += delta;
    linearise(pr, candidate, trial);
    const double ratio = model > 0 ? (lin.cost - trial.cost) / model : -1;
    if (ratio <= 1e-3) {
      shrink();
      continue;
    }
    const double change = (lin.cost - trial.cost) / std::max(lin.cost, 1e-300);
    x.swap(candidate);
    std::swap(lin, trial);
    summary.final_cost = lin.cost;
    radius = std::min(1e16, radius / std::max(1.0 / 3.0, 1 - std::pow(2 * ratio - 1, 3)));
    decrease = 2;
    if (change <= 1e-6) {
      ++summary.iterations;
      return converged();
    }
    linearise_at_x();
  }
  return summary;
}

}  // namespace scanfill
