#include "core/detail/row_cholesky.h"

#include "core/common/error.h"
#include "core/detail/simd.h"

#include <Eigen/OrderingMethods>
#include <Eigen/SparseCholesky>

#ifdef _OPENMP
#include <omp.h>
#endif

#include <algorithm>

namespace bary::detail
{

void RowCholesky::factor(const Eigen::SparseMatrix<double>& A)
{
  const Index n = A.rows();
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> pinv;
  Eigen::AMDOrdering<int> amd;
  amd(A, pinv);
  perm_.assign(pinv.indices().data(), pinv.indices().data() + n);
  std::vector<int> inverse(static_cast<std::size_t>(n));
  for (Index i = 0; i < n; ++i)
    inverse[static_cast<std::size_t>(perm_[static_cast<std::size_t>(i)])] = static_cast<int>(i);
  // Ap(i, j) = A(perm[i], perm[j]), lower triangle.
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(static_cast<std::size_t>(A.nonZeros()));
  for (Index j = 0; j < A.outerSize(); ++j)
    for (Eigen::SparseMatrix<double>::InnerIterator it(A, j); it; ++it)
    {
      const int r = inverse[static_cast<std::size_t>(it.row())];
      const int c = inverse[static_cast<std::size_t>(it.col())];
      if (r >= c)
        triplets.emplace_back(r, c, it.value());
    }
  Eigen::SparseMatrix<double> Ap(n, n);
  Ap.setFromTriplets(triplets.begin(), triplets.end());
  Eigen::SimplicialLLT<Eigen::SparseMatrix<double>, Eigen::Lower, Eigen::NaturalOrdering<int>> llt;
  llt.compute(Ap);
  if (llt.info() != Eigen::Success)
    throw Error(ErrorCode::InvalidArgument,
      "the ADMM's linear system is not positive definite (every vertex must belong to an "
      "element)");
  const Eigen::SparseMatrix<double> L = llt.matrixL();
  diag_.assign(static_cast<std::size_t>(n), 0.0);
  colptr_.assign(static_cast<std::size_t>(n) + 1, 0);
  rows_.clear();
  values_.clear();
  rows_.reserve(static_cast<std::size_t>(L.nonZeros()));
  values_.reserve(static_cast<std::size_t>(L.nonZeros()));
  for (Index j = 0; j < n; ++j)
  {
    for (Eigen::SparseMatrix<double>::InnerIterator it(L, j); it; ++it)
      if (it.row() == j)
        diag_[static_cast<std::size_t>(j)] = it.value();
      else if (it.row() > j)
      {
        rows_.push_back(static_cast<int>(it.row()));
        values_.push_back(it.value());
      }
    colptr_[static_cast<std::size_t>(j) + 1] = static_cast<int>(rows_.size());
  }
  inv_diag_.resize(static_cast<std::size_t>(n));
  for (Index j = 0; j < n; ++j)
  {
    if (!(diag_[static_cast<std::size_t>(j)] > 0.0))
      throw Error(ErrorCode::InvalidArgument,
        "the ADMM's linear system is not positive definite");
    inv_diag_[static_cast<std::size_t>(j)] = 1.0 / diag_[static_cast<std::size_t>(j)];
  }
  n_ = n;
}

namespace
{
/// The two triangular solves on the permuted block Y (n rows of w doubles) in plain loops (one
/// axpy over a row per factor entry), which the compiler vectorises for its target: SSE2 in
/// the portable build, four doubles in solve_avx2 (the same operations: the same bits).
template <int W>
BARY_ALWAYS_INLINE void triangular_solves(Index n, Index wd, const int* colptr, const int* rows,
  const double* values, const double* inv_diag, double* Y)
{
  const Index w = W > 0 ? W : wd;
  // L y = b (column-oriented: scatter; rows never overlap)
  for (Index j = 0; j < n; ++j)
  {
    double* __restrict yj = Y + j * w;
    const double d = inv_diag[j];
    for (Index i = 0; i < w; ++i)
      yj[i] *= d;
    for (int p = colptr[j]; p < colptr[j + 1]; ++p)
    {
      double* __restrict yr = Y + static_cast<Index>(rows[p]) * w;
      const double v = values[p];
      for (Index i = 0; i < w; ++i)
        yr[i] -= v * yj[i];
    }
  }
  // L^T x = y (row-oriented: gather)
  for (Index j = n - 1; j >= 0; --j)
  {
    double* __restrict yj = Y + j * w;
    for (int p = colptr[j]; p < colptr[j + 1]; ++p)
    {
      const double* __restrict yr = Y + static_cast<Index>(rows[p]) * w;
      const double v = values[p];
      for (Index i = 0; i < w; ++i)
        yj[i] -= v * yr[i];
    }
    const double d = inv_diag[j];
    for (Index i = 0; i < w; ++i)
      yj[i] *= d;
  }
}

template <int W>
BARY_NOINLINE void solve_portable(Index n, Index w, const int* colptr, const int* rows,
  const double* values, const double* inv_diag, double* Y)
{
  triangular_solves<W>(n, w, colptr, rows, values, inv_diag, Y);
}

#if BARY_HAVE_AVX2_DISPATCH
template <int W>
BARY_TARGET_AVX2_EXACT BARY_NOINLINE void solve_avx2(Index n, Index w, const int* colptr,
  const int* rows, const double* values, const double* inv_diag, double* Y)
{
  triangular_solves<W>(n, w, colptr, rows, values, inv_diag, Y);
}
#endif
} // namespace

template <int W>
void RowCholesky::solve_columns(RowMatrix& B, Index c0, Index c1) const
{
  const Index n = n_, k = B.cols();
  const Index w = W > 0 ? W : c1 - c0;
  std::vector<double> y(static_cast<std::size_t>(n * w));
  double* Y = y.data();
  for (Index i = 0; i < n; ++i)
  {
    const double* b = B.data() + static_cast<Index>(perm_[static_cast<std::size_t>(i)]) * k + c0;
    std::copy(b, b + w, Y + i * w);
  }
#if BARY_HAVE_AVX2_DISPATCH
  if (simd_level() == SimdLevel::AVX2)
    solve_avx2<W>(n, w, colptr_.data(), rows_.data(), values_.data(), inv_diag_.data(), Y);
  else
#endif
    solve_portable<W>(n, w, colptr_.data(), rows_.data(), values_.data(), inv_diag_.data(), Y);
  for (Index i = 0; i < n; ++i)
    std::copy(Y + i * w, Y + (i + 1) * w,
      B.data() + static_cast<Index>(perm_[static_cast<std::size_t>(i)]) * k + c0);
}

void RowCholesky::solve(RowMatrix& B, int threads) const
{
  const Index k = B.cols();
  if (k == 0 || n_ == 0)
    return;
  const int parts = static_cast<int>(std::min<Index>(threads, k));
#pragma omp parallel num_threads(parts)
  {
    const int part = omp_get_thread_num(), count = omp_get_num_threads();
    const Index c0 = k * part / count, c1 = k * (part + 1) / count;
    switch (c1 - c0)
    {
      case 3: solve_columns<3>(B, c0, c1); break;
      case 4: solve_columns<4>(B, c0, c1); break;
      case 6: solve_columns<6>(B, c0, c1); break;
      case 8: solve_columns<8>(B, c0, c1); break;
      default: solve_columns<0>(B, c0, c1); break;
    }
  }
}

} // namespace bary::detail
