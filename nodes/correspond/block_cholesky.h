// Sparse Cholesky factorisation of a symmetric positive definite matrix made of 12 x 12 blocks (embedded
// deformation's normal equations: one block row per deformation node). The nodes are ordered by approximate minimum
// degree (Eigen's AMD on the block graph), the factor's block pattern is found once (the elimination tree), and each
// factorisation is right-looking on dense 12 x 12 blocks: a node-sized supernode, so the work runs in fixed-size
// block products rather than scalar updates (about 5x faster than a scalar simplicial LDL^T here). The updates a
// column sends go to distinct later columns, one task each, so the factor is the same bytes on any number of threads.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace scanfill {

class BlockCholesky {
 public:
  using Block = Eigen::Matrix<double, 12, 12, Eigen::RowMajor>;

  // The matrix's block pattern: block row j holds the block columns column[row_start[j] .. row_start[j + 1]), sorted,
  // the diagonal included, the pattern symmetric.
  BlockCholesky(const std::vector<std::int64_t>& row_start, const std::vector<std::int32_t>& column);

  // Factorises the matrix with the pattern's blocks (in the pattern's order) plus diag(diagonal_add); false when it
  // is not positive definite.
  bool factorize(const std::vector<Block>& blocks, const Eigen::VectorXd& diagonal_add);

  // Solves A x = b with the last successful factorisation.
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const;

 private:
  std::int64_t factor_block(std::int32_t k, std::int32_t i) const;  // L's block (i, k), i > k, in the new order

  std::vector<std::int32_t> order_;         // order_[k]: the original block row eliminated k-th
  std::vector<std::int32_t> position_;      // its inverse
  std::vector<std::int64_t> column_start_;  // L's column k: rows row_[column_start_[k] ..), sorted, all > k
  std::vector<std::int32_t> row_;
  std::vector<std::int64_t> source_;           // per L block: the pattern's block it starts from, or -1 (fill)
  std::vector<std::int64_t> diagonal_source_;  // per column k: the pattern's diagonal block of order_[k]
  std::vector<Block> lower_, diagonal_;
};

}  // namespace scanfill
