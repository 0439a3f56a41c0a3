#pragma once
/// @file min_quad_with_fixed.h
/// Quadratic minimization with fixed values (Dirichlet conditions):
///
///   min_x  1/2 x^T A x + x^T B   subject to  x(known) = Y,
///
/// solved through the optimality condition on the unknowns u (the complement of known),
///
///   A_uu x_u = -(B_u + A_uk Y),
///
/// with A_uu factored once by SparseCholesky (the precompute/solve split of libigl's
/// min_quad_with_fixed, without its linear equality constraints). Used for harmonic
/// coordinates (A = stiffness matrix, B = 0, Y = boundary values) and the unconstrained steps of
/// bounded biharmonic weights.

#include "core/solvers/sparse_cholesky.h"
#include "core/common/types.h"

namespace bary
{

/// Precompute once for a matrix and a set of known rows, then solve for many right-hand sides
/// and boundary values (all columns at once). Copies share the factorization; const methods are
/// thread-safe.
class MinQuadWithFixed
{
public:
  /// Factor A_uu.
  /// @param A n by n, symmetric positive semidefinite and positive definite on the unknowns
  ///   (A_uu SPD); both triangles stored. E.g. stiffness_matrix(V, T) with at least one known
  ///   vertex per connected component. Only the rows of the unknowns are read (A_uu, A_uk;
  ///   A_ku is taken to be A_uk^T).
  /// @param known indices of the fixed rows, each in [0, n), no repeats, any order; may be
  ///   empty (then A itself must be SPD). The values Y passed to solve() follow this order.
  /// @param backend the SparseCholesky backend for A_uu (default Automatic).
  /// @throws Error(SizeMismatch) if A is not square; Error(EmptyInput) if it is 0 by 0;
  ///   Error(InvalidArgument) for a known index out of range or repeated (named), or if A_uu is
  ///   not symmetric / "not positive definite" (see SparseCholesky::compute; the message names
  ///   rows by their index in A);
  ///   Error(NonFinite) for a NaN / infinite entry of A.
  void precompute(const Eigen::SparseMatrix<double>& A, const Eigen::VectorXi& known,
    SparseCholesky::Backend backend = SparseCholesky::Backend::Automatic);

  /// Minimizer for k problems at once (column c uses B.col(c) and Y.col(c)).
  /// @param B n by k linear term; an empty B (0 columns) means B = 0.
  /// @param Y #known by k fixed values (with no known rows it may be 0 by anything).
  /// @return n by k; rows known(i) equal Y.row(i) exactly.
  /// k is B.cols() when B is not empty, Y.cols() otherwise.
  /// @throws Error(InvalidArgument) before precompute(); Error(SizeMismatch) for shapes that do
  ///   not fit; Error(NonFinite) for NaN / infinity in B or Y.
  Eigen::MatrixXd solve(const Eigen::MatrixXd& B, const Eigen::MatrixXd& Y) const;

  /// Indices of the free rows, ascending (n - #known of them).
  const Eigen::VectorXi& unknown() const noexcept { return unknown_; }
  /// Indices of the fixed rows, as given to precompute().
  const Eigen::VectorXi& known() const noexcept { return known_; }
  /// n (0 before precompute()).
  Index rows() const noexcept { return n_; }
  /// True once precompute() has succeeded.
  bool precomputed() const noexcept { return precomputed_; }
  /// The factorization of A_uu (not computed when every row is known).
  const SparseCholesky& solver() const noexcept { return solver_; }

private:
  Index n_ = 0;
  bool precomputed_ = false;
  Eigen::VectorXi known_, unknown_;
  Eigen::SparseMatrix<double> A_uk_; ///< #unknown by #known
  SparseCholesky solver_;
};

/// One-call form: precompute and solve once. Same arguments and errors as
/// MinQuadWithFixed::precompute() and MinQuadWithFixed::solve().
Eigen::MatrixXd min_quad_with_fixed(const Eigen::SparseMatrix<double>& A,
  const Eigen::MatrixXd& B, const Eigen::VectorXi& known, const Eigen::MatrixXd& Y,
  SparseCholesky::Backend backend = SparseCholesky::Backend::Automatic);

} // namespace bary
