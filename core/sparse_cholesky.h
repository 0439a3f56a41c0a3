#pragma once
/// @file sparse_cholesky.h
/// Sparse Cholesky factorization of a symmetric positive definite matrix: CHOLMOD's supernodal
/// LL^T (Chen, Davis, Hager & Rajamanickam, "Algorithm 887: CHOLMOD", ACM TOMS 35(3), 2008)
/// when BaryLab was built with CHOLMOD, Eigen's SimplicialLDLT otherwise.
///
/// The matrix is scaled symmetrically to unit diagonal before it is factored,
/// A~ = S A S with S = diag(A)^-1/2, and solves return x = S A~^-1 S b. The scaling makes the
/// definiteness test below independent of units and of how rows are scaled (graded meshes),
/// and does not change the solution beyond rounding.
///
/// Definiteness test: the factorization fails, or one of its pivots (the diagonal of D in
/// A~ = L D L^T, the squared diagonal of L for CHOLMOD) is <= 16 n eps with n the size: then
/// A is not (numerically) positive definite. For SPD A every pivot of A~ is >= lambda_min(A~)
/// >= 1 / cond(A~) (the unit diagonal makes lambda_max(A~) >= 1), so only matrices with
/// cond(A~) > 1 / (16 n eps) ~ 2.8e14 / n can be refused, and in practice pivots stay far above
/// 1 / cond: measured on 500 x 500 grids (n = 250k), the smallest pivot of a Dirichlet
/// biharmonic matrix is ~1e-4 while that of a singular (pure Neumann) Laplacian is ~1e-11
/// (rounding grows like n eps). Typical cause of a refusal: a Laplacian with no fixed (known)
/// vertex in some connected component, or a vertex no element references.
///
/// @warning Cost: with nested dissection (CHOLMOD picks METIS or AMD, Eigen uses AMD) the
/// factor holds O(n log n) entries and costs O(n^1.5) flops for 2D meshes, O(n^4/3) entries and
/// O(n^2) flops for 3D meshes. CHOLMOD's supernodal speed is that
/// of the BLAS it is linked with: with Debian's reference BLAS a 30^3 Kuhn tet grid (30k
/// unknowns, 5 GFlop) factors in ~1.8 s and a 50^3 one (133k unknowns) in ~32 s; an optimized
/// BLAS (OpenBLAS) is several times faster. Eigen's SimplicialLDLT took 8 s and 215 s on them.

#include "types.h"

#include <memory>

namespace bary
{

/// Factor once, solve many right-hand sides.
///
/// Copies are cheap and share the factorization (which compute() never modifies: it builds a
/// new one). solve() is thread-safe; with the CHOLMOD backend concurrent solves on the same
/// factorization are serialized (CHOLMOD's workspace is not re-entrant).
class SparseCholesky
{
public:
  /// Which factorization to use.
  enum class Backend
  {
    Automatic, ///< Cholmod when available (cholmod_available()), Eigen otherwise. Default.
    Cholmod,   ///< CHOLMOD supernodal LL^T (BLAS-3 on dense supernodes: the fastest on large 3D
               ///< meshes); Error(InvalidArgument) when BaryLab was built without CHOLMOD
    Eigen      ///< Eigen's SimplicialLDLT with AMD ordering: always available, slower on large
               ///< or 3D problems whose factors have dense blocks
  };

  /// Resolves Automatic to the backend that will be used.
  /// @throws Error(InvalidArgument) for Backend::Cholmod when cholmod_available() is false.
  explicit SparseCholesky(Backend backend = Backend::Automatic);

  /// Factor @p A (n by n, symmetric positive definite; both triangles must be stored). Replaces
  /// any previous factorization of this object (copies made before keep theirs).
  /// @param row_ids optional, n entries: the numbers error messages use for rows and columns
  ///   of A (e.g. the original vertex ids when A is a submatrix); empty (default) = 0 .. n-1.
  /// @throws Error(SizeMismatch) if A is not square or row_ids is neither empty nor of size n;
  ///   Error(EmptyInput) if A is 0 by 0;
  ///   Error(NonFinite) for a NaN / infinite entry; Error(InvalidArgument) if A is not
  ///   symmetric (|A_ij - A_ji| > 1e-10 sqrt(A_ii A_jj)) or "not positive definite" (a diagonal
  ///   entry <= 0, or the definiteness test in the file comment fails; the message names the
  ///   smallest pivot and the row it belongs to).
  void compute(const Eigen::SparseMatrix<double>& A, const Eigen::VectorXi& row_ids = {});

  /// Solve A X = B for X. @p B is n by k (k >= 0); returns n by k.
  /// @throws Error(InvalidArgument) if compute() has not succeeded; Error(SizeMismatch) if
  ///   B.rows() != n; Error(NonFinite) if B holds NaN or infinity.
  Eigen::MatrixXd solve(const Eigen::MatrixXd& B) const;

  /// The backend actually used (never Automatic).
  Backend backend() const noexcept { return backend_; }
  /// True once compute() has succeeded.
  bool computed() const noexcept { return impl_ != nullptr; }
  /// n, the size of the factored matrix (0 before compute()).
  Index rows() const noexcept;
  /// Smallest pivot of the scaled matrix A~ (see the file comment): a cheap lower estimate of
  /// 1 / cond(A~) up to the growth of the factorization. 0 before compute().
  double min_pivot() const noexcept;

  /// True when BaryLab was compiled with CHOLMOD (CMake found it; BARYLAB_USE_CHOLMOD=ON).
  static bool cholmod_available() noexcept;

private:
  struct Impl;
  Backend backend_;
  std::shared_ptr<Impl> impl_;
};

/// Short stable name of a backend: "automatic", "cholmod" or "eigen".
const char* to_string(SparseCholesky::Backend backend) noexcept;

} // namespace bary
