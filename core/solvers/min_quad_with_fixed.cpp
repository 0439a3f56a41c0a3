#include "core/solvers/min_quad_with_fixed.h"

#include "core/common/error.h"

#include <cmath>
#include <string>
#include <utility>
#include <vector>

namespace bary
{

void MinQuadWithFixed::precompute(const Eigen::SparseMatrix<double>& A,
  const Eigen::VectorXi& known, SparseCholesky::Backend backend)
{
  precomputed_ = false;
  if (A.rows() != A.cols())
    throw Error(ErrorCode::SizeMismatch,
      "the quadratic term A must be square, got " + std::to_string(A.rows()) + " by " +
        std::to_string(A.cols()));
  const Index n = A.rows();
  if (n == 0)
    throw Error(ErrorCode::EmptyInput, "the quadratic term A is empty (0 by 0)");

  // slot(i) = -1 - (position of i in known) for a known row (always < 0), then the position of
  // i among the unknowns (>= 0) for a free row; 0 marks "not known" until the unknowns are
  // numbered.
  std::vector<Index> slot(static_cast<std::size_t>(n), 0);
  for (Index k = 0; k < known.size(); ++k)
  {
    const int i = known(k);
    if (i < 0 || i >= n)
      throw Error(ErrorCode::InvalidArgument,
        "known(" + std::to_string(k) + ") = " + std::to_string(i) + " is outside [0, " +
          std::to_string(n) + ")");
    if (slot[static_cast<std::size_t>(i)] != 0)
      throw Error(ErrorCode::InvalidArgument,
        "row " + std::to_string(i) + " is listed twice in known (at " +
          std::to_string(-1 - slot[static_cast<std::size_t>(i)]) + " and " + std::to_string(k) +
          "); each known row must appear once");
    slot[static_cast<std::size_t>(i)] = -1 - k;
  }
  Eigen::VectorXi unknown(n - known.size());
  for (Index i = 0, u = 0; i < n; ++i)
    if (slot[static_cast<std::size_t>(i)] == 0)
    {
      unknown(u) = static_cast<int>(i);
      slot[static_cast<std::size_t>(i)] = u++;
    }

  std::vector<Eigen::Triplet<double>> uu, uk;
  uu.reserve(static_cast<std::size_t>(A.nonZeros()));
  for (Index j = 0; j < A.outerSize(); ++j)
    for (Eigen::SparseMatrix<double>::InnerIterator it(A, j); it; ++it)
    {
      if (!std::isfinite(it.value()))
        throw Error(ErrorCode::NonFinite,
          "the quadratic term A has a non-finite entry at (" + std::to_string(it.row()) + ", " +
            std::to_string(it.col()) + ")");
      const Index si = slot[static_cast<std::size_t>(it.row())];
      const Index sj = slot[static_cast<std::size_t>(it.col())];
      if (si < 0)
        continue; // known row: not needed (A is symmetric, A_ku = A_uk^T)
      if (sj >= 0)
        uu.emplace_back(si, sj, it.value());
      else
        uk.emplace_back(si, -1 - sj, it.value());
    }
  const Index nu = unknown.size();
  Eigen::SparseMatrix<double> A_uk(nu, known.size());
  A_uk.setFromTriplets(uk.begin(), uk.end());

  SparseCholesky solver(backend);
  if (nu > 0)
  {
    Eigen::SparseMatrix<double> A_uu(nu, nu);
    A_uu.setFromTriplets(uu.begin(), uu.end());
    solver.compute(A_uu, unknown); // errors name rows of A, not of A_uu
  }

  n_ = n;
  known_ = known;
  unknown_ = std::move(unknown);
  A_uk_ = std::move(A_uk);
  solver_ = std::move(solver);
  precomputed_ = true;
}

Eigen::MatrixXd MinQuadWithFixed::solve(const Eigen::MatrixXd& B, const Eigen::MatrixXd& Y) const
{
  if (!precomputed_)
    throw Error(ErrorCode::InvalidArgument, "MinQuadWithFixed::solve called before precompute()");
  const Index nk = known_.size();
  const bool has_B = B.cols() > 0;
  const Index k = has_B ? B.cols() : Y.cols();
  if (has_B && B.rows() != n_)
    throw Error(ErrorCode::SizeMismatch,
      "the linear term B has " + std::to_string(B.rows()) + " rows, expected " +
        std::to_string(n_) + " (one per row of A)");
  if (Y.rows() != nk)
    throw Error(ErrorCode::SizeMismatch,
      "the fixed values Y have " + std::to_string(Y.rows()) + " rows, expected " +
        std::to_string(nk) + " (one per known index)");
  if (nk > 0 && Y.cols() != k)
    throw Error(ErrorCode::SizeMismatch,
      "the fixed values Y have " + std::to_string(Y.cols()) +
        " columns but the linear term B has " + std::to_string(k));
  if (has_B && !B.allFinite())
    throw Error(ErrorCode::NonFinite, "the linear term B contains NaN or infinity");
  if (!Y.allFinite())
    throw Error(ErrorCode::NonFinite, "the fixed values Y contain NaN or infinity");

  Eigen::MatrixXd X(n_, k);
  for (Index i = 0; i < nk; ++i)
    X.row(known_(i)) = Y.row(i);
  const Index nu = unknown_.size();
  if (nu == 0 || k == 0)
    return X;

  // A_uu x_u = -(B_u + A_uk Y).
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(nu, k);
  if (nk > 0)
    rhs.noalias() -= A_uk_ * Y;
  if (has_B)
    for (Index u = 0; u < nu; ++u)
      rhs.row(u) -= B.row(unknown_(u));
  const Eigen::MatrixXd X_u = solver_.solve(rhs);
  for (Index u = 0; u < nu; ++u)
    X.row(unknown_(u)) = X_u.row(u);
  return X;
}

Eigen::MatrixXd min_quad_with_fixed(const Eigen::SparseMatrix<double>& A,
  const Eigen::MatrixXd& B, const Eigen::VectorXi& known, const Eigen::MatrixXd& Y,
  SparseCholesky::Backend backend)
{
  MinQuadWithFixed solver;
  solver.precompute(A, known, backend);
  return solver.solve(B, Y);
}

} // namespace bary
