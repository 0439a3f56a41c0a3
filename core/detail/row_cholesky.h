#pragma once
/// @file row_cholesky.h
/// A sparse Cholesky factorization solved for row-major blocks of right-hand sides, the kernel
/// of local barycentric coordinates' ADMM (LBCOptions::backend Automatic).
///
/// Why not SparseCholesky (sparse_cholesky.h): its solve() takes column-major blocks and
/// solves column by column (the supernodal backend with dense kernels per supernode); the
/// ADMM solves #free by #C row-major blocks thousands of times, where an update of a whole row
/// of the block per factor entry (a contiguous axpy over the columns) is faster (LBCOptions::
/// backend documents the measurements). LBC can still use SparseCholesky for comparison.

#include "core/common/types.h"

#include <Eigen/SparseCore>

#include <vector>

namespace bary::detail
{

/// A = L L^T of a symmetric positive definite matrix (Eigen's simplicial factor of the AMD-
/// permuted matrix), solved for a row-major block of right-hand sides: each factor entry
/// updates a whole row of the block (a contiguous axpy over the columns), the BLAS-3-like
/// access pattern that suits the ADMM's #free by #C blocks. Columns are split between threads;
/// every column's arithmetic is the same whatever the split, so results do not depend on the
/// thread count.
class RowCholesky
{
public:
  using RowMatrix = DenseWeights;

  /// Factors @p A (both triangles stored; the lower one is read).
  /// @throws Error(InvalidArgument) "the ADMM's linear system is not positive definite ..."
  ///   when A is not positive definite (the message names LBC's system, its only user).
  void factor(const Eigen::SparseMatrix<double>& A);

  Index rows() const noexcept { return n_; }
  /// Entries of L (the diagonal included).
  Index nonzeros() const noexcept { return static_cast<Index>(values_.size()) + n_; }

  /// B <- A^-1 B for the n by k row-major block B, columns split over @p threads threads.
  void solve(RowMatrix& B, int threads) const;

private:
  /// Columns [c0, c1) of B (W = c1 - c0 when W > 0: fixed size, unrolled loops).
  template<int W>
  void solve_columns(RowMatrix& B, Index c0, Index c1) const;

  Index n_ = 0;
  std::vector<int> perm_, colptr_, rows_;
  std::vector<double> values_, diag_, inv_diag_;
};

} // namespace bary::detail
