#include "nodes/correspond/block_cholesky.h"

#include <tbb/parallel_for.h>

#include <Eigen/Cholesky>
#include <Eigen/OrderingMethods>
#include <Eigen/SparseCore>
#include <algorithm>

namespace scanfill {
namespace {

using Vector12 = Eigen::Matrix<double, 12, 1>;

// The position of `value` in the sorted range [first, first + count), or -1.
template <class T>
std::int64_t find_sorted(const T* first, std::int64_t count, T value) {
  const T* it = std::lower_bound(first, first + count, value);
  return it != first + count && *it == value ? it - first : -1;
}

// Approximate minimum degree order of the block graph: order[k] is the block eliminated k-th.
std::vector<std::int32_t> minimum_degree_order(const std::vector<std::int64_t>& row_start,
                                               const std::vector<std::int32_t>& column) {
  const auto n = Eigen::Index(row_start.size()) - 1;
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(column.size());
  for (Eigen::Index j = 0; j < n; ++j)
    for (auto b = row_start[size_t(j)]; b < row_start[size_t(j) + 1]; ++b)
      entries.emplace_back(column[size_t(b)], int(j), 1.0);
  Eigen::SparseMatrix<double> graph(n, n);
  graph.setFromTriplets(entries.begin(), entries.end());
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> perm;
  Eigen::AMDOrdering<int>()(graph, perm);
  return {perm.indices().data(), perm.indices().data() + n};
}

}  // namespace

BlockCholesky::BlockCholesky(const std::vector<std::int64_t>& row_start, const std::vector<std::int32_t>& column) {
  const auto n = std::int32_t(row_start.size()) - 1;
  order_ = minimum_degree_order(row_start, column);
  position_.assign(size_t(n), 0);
  for (std::int32_t k = 0; k < n; ++k) position_[size_t(order_[size_t(k)])] = k;
  // Column k of L: the later neighbours of order_[k], and what its children in the elimination tree pass up.
  std::vector<std::vector<std::int32_t>> rows(static_cast<size_t>(n)), children(static_cast<size_t>(n));
  for (std::int32_t k = 0; k < n; ++k) {
    auto& s = rows[size_t(k)];
    const auto j = size_t(order_[size_t(k)]);
    for (auto b = row_start[j]; b < row_start[j + 1]; ++b)
      if (position_[size_t(column[size_t(b)])] > k) s.push_back(position_[size_t(column[size_t(b)])]);
    for (const auto c : children[size_t(k)])
      for (const auto i : rows[size_t(c)])
        if (i > k) s.push_back(i);
    std::sort(s.begin(), s.end());
    s.erase(std::unique(s.begin(), s.end()), s.end());
    if (!s.empty()) children[size_t(s.front())].push_back(k);
  }
  column_start_.assign(size_t(n) + 1, 0);
  for (std::int32_t k = 0; k < n; ++k)
    column_start_[size_t(k) + 1] = column_start_[size_t(k)] + std::int64_t(rows[size_t(k)].size());
  for (const auto& s : rows) row_.insert(row_.end(), s.begin(), s.end());
  // Where each block starts from in the pattern (row order_[i], column order_[k]).
  const auto pattern_block = [&](std::int32_t i, std::int32_t k) {
    const auto r = size_t(order_[size_t(i)]);
    const auto at = find_sorted(column.data() + row_start[r], row_start[r + 1] - row_start[r], order_[size_t(k)]);
    return at < 0 ? std::int64_t(-1) : row_start[r] + at;
  };
  source_.resize(row_.size());
  for (std::int32_t k = 0; k < n; ++k)
    for (auto p = column_start_[size_t(k)]; p < column_start_[size_t(k) + 1]; ++p)
      source_[size_t(p)] = pattern_block(row_[size_t(p)], k);
  diagonal_source_.resize(size_t(n));
  for (std::int32_t k = 0; k < n; ++k) diagonal_source_[size_t(k)] = pattern_block(k, k);
  lower_.resize(row_.size());
  diagonal_.resize(size_t(n));
}

std::int64_t BlockCholesky::factor_block(std::int32_t k, std::int32_t i) const {
  const auto first = column_start_[size_t(k)];
  return first + find_sorted(row_.data() + first, column_start_[size_t(k) + 1] - first, i);
}

bool BlockCholesky::factorize(const std::vector<Block>& blocks, const Eigen::VectorXd& diagonal_add) {
  const auto n = std::int32_t(diagonal_.size());
  for (std::int32_t k = 0; k < n; ++k) {
    diagonal_[size_t(k)] = blocks[size_t(diagonal_source_[size_t(k)])];
    diagonal_[size_t(k)].diagonal() += diagonal_add.segment<12>(12 * Eigen::Index(order_[size_t(k)]));
  }
  for (size_t p = 0; p < lower_.size(); ++p) lower_[p] = source_[p] >= 0 ? blocks[size_t(source_[p])] : Block::Zero();
  for (std::int32_t k = 0; k < n; ++k) {
    const Eigen::LLT<Block> llt(diagonal_[size_t(k)]);
    if (llt.info() != Eigen::Success) return false;
    diagonal_[size_t(k)] = llt.matrixL();
    const auto first = column_start_[size_t(k)], last = column_start_[size_t(k) + 1];
    for (auto p = first; p < last; ++p)  // L_ik = A_ik L_kk^-T
      diagonal_[size_t(k)].triangularView<Eigen::Lower>().transpose().solveInPlace<Eigen::OnTheRight>(
          lower_[size_t(p)]);
    // Each later column b of this one's pattern takes its updates from one task: A_ab -= L_ak L_bk^T, a >= b.
    tbb::parallel_for(first, last, [&](std::int64_t b) {
      const auto target = row_[size_t(b)];
      diagonal_[size_t(target)].noalias() -= lower_[size_t(b)] * lower_[size_t(b)].transpose();
      for (auto a = b + 1; a < last; ++a)
        lower_[size_t(factor_block(target, row_[size_t(a)]))].noalias() -=
            lower_[size_t(a)] * lower_[size_t(b)].transpose();
    });
  }
  return true;
}

Eigen::VectorXd BlockCholesky::solve(const Eigen::VectorXd& rhs) const {
  const auto n = std::int32_t(diagonal_.size());
  std::vector<Vector12> y(static_cast<size_t>(n));
  for (std::int32_t k = 0; k < n; ++k) y[size_t(k)] = rhs.segment<12>(12 * Eigen::Index(order_[size_t(k)]));
  for (std::int32_t k = 0; k < n; ++k) {  // L y = b
    diagonal_[size_t(k)].triangularView<Eigen::Lower>().solveInPlace(y[size_t(k)]);
    for (auto p = column_start_[size_t(k)]; p < column_start_[size_t(k) + 1]; ++p)
      y[size_t(row_[size_t(p)])].noalias() -= lower_[size_t(p)] * y[size_t(k)];
  }
  for (std::int32_t k = n - 1; k >= 0; --k) {  // L^T x = y
    for (auto p = column_start_[size_t(k)]; p < column_start_[size_t(k) + 1]; ++p)
      y[size_t(k)].noalias() -= lower_[size_t(p)].transpose() * y[size_t(row_[size_t(p)])];
    diagonal_[size_t(k)].triangularView<Eigen::Lower>().transpose().solveInPlace(y[size_t(k)]);
  }
  Eigen::VectorXd x(rhs.size());
  for (std::int32_t k = 0; k < n; ++k) x.segment<12>(12 * Eigen::Index(order_[size_t(k)])) = y[size_t(k)];
  return x;
}

}  // namespace scanfill
