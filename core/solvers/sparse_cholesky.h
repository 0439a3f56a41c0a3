#pragma once
/// @file sparse_cholesky.h
/// Sparse Cholesky factorization of a symmetric positive definite matrix: CHOLMOD's supernodal
/// LL^T (Chen, Davis, Hager & Rajamanickam, "Algorithm 887: CHOLMOD", ACM TOMS 35(3), 2008)
/// when BaryLab was built with CHOLMOD, Eigen's SimplicialLDLT otherwise, or (Backend::Supernodal)
/// BaryLab's own supernodal LL^T, whose dense blocks use AVX2 + FMA kernels or Eigen's.
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
///
/// Backend::Supernodal: AMD ordering (Eigen's) or a given one; symbolic analysis: elimination
/// tree (Liu), postorder, column counts (Gilbert, Ng & Peyton 1994, as in Davis's CSparse),
/// fundamental supernodes merged by CHOLMOD's relaxed amalgamation rule, row structures.
/// Numeric factorization: left-looking supernodal (Ng & Peyton 1993, the algorithm of CHOLMOD's
/// numeric phase): per supernode, the updates of its descendants are dense products L_d L_d^T
/// scattered through a relative map, then the diagonal block is factored and the rows below it
/// solved. The dense kernels are chosen at run time (core/detail/simd.h): where the CPU has AVX2
/// and FMA, register panels of 8 rows by 4 columns accumulated with FMA for the products and a
/// left-looking LL^T of the supernode's whole panel by blocks of 4 columns on the same panels;
/// elsewhere (or with BARYLAB_SIMD=portable) Eigen's blocked GEMM, LLT and TRSM, compiled for the
/// build's instruction set (SSE2 on x86-64 without -march). The two paths agree to rounding,
/// not bit for bit (FMA). Where the CPU also has AVX-512 (F and VL; detail::avx512_enabled(),
/// BARYLAB_SIMD=avx2 turns it off) the products use panels of 16 rows by up to 8 columns of
/// 512-bit vectors: every entry is still the same FMAs in the same order, so the factor is the
/// AVX2 one bit for bit (tested). Either way the products run single-threaded whatever the OpenMP
/// settings, so the factor does not depend on the thread count. One right-hand side is solved
/// by an AVX2 kernel too (each panel read once forward, once backward). It can factor a
/// principal submatrix of a matrix without forming it (compute_principal). Measured on the free
/// blocks of bounded biharmonic weights on libigl's hand (3,000-5,000 unknowns, bi-Laplacian
/// stencil, 6.6e7 flops on average), AMD EPYC at 2.1 GHz: numeric factorization 3.2 ms on
/// average (20.6-20.9 GFlop/s, 37% of the core's 56 GFlop/s AVX2 FMA peak; the rest is assembling
/// the columns and scattering the updates) with the AVX2 kernels, 7.1 ms (9.3 GFlop/s) with
/// Eigen's; the symbolic analysis 1.55 ms more. Eigen's SimplicialLDLT took 15-45 ms and CHOLMOD's numeric
/// factorization with the reference BLAS 20-40 ms on them (an earlier measurement). On handle
/// 0's final free block (3,705 unknowns, 5.0e5 entries, 5.6e7 flops; bench_bbw BBWHandBlock), a
/// whole fresh factorization, symbolic analysis included, took 4.30 / 4.53 ms with the 256-bit
/// products and 4.05 / 4.59 ms with the 512-bit ones (best of 7, two alternations, AMD EPYC of
/// the Zen 5 family): about a third of it is the symbolic analysis and a fifth the assembly and
/// scattering, so wider products gain 0-6% there.

#include "core/common/types.h"

#include <memory>
#include <vector>

namespace bary
{

struct SparseCholeskySettings;

/// Factor once, solve many right-hand sides.
///
/// Copies are cheap and share the factorization (which compute() never modifies: it builds a
/// new one; modify_principal() copies it first when it is shared). solve() is thread-safe; with
/// the CHOLMOD backend, and after modify_principal(), concurrent solves on the same
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
    Eigen,     ///< Eigen's SimplicialLDLT with AMD ordering: always available, slower on large
               ///< or 3D problems whose factors have dense blocks
    Supernodal ///< BaryLab's supernodal LL^T on its AVX2 + FMA or Eigen's dense kernels (see
               ///< the file comment): always available; the fastest without an optimized BLAS
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
  /// The same with @p settings (a given fill-reducing ordering; skipping the input checks).
  /// @throws as above, and Error(InvalidArgument) when settings.ordering is not a permutation of
  ///   0 .. n-1 (or Error(SizeMismatch) when it has neither 0 nor n entries).
  void compute(const Eigen::SparseMatrix<double>& A, const Eigen::VectorXi& row_ids,
    const SparseCholeskySettings& settings);
  /// Factor the principal submatrix M = A(rows, rows) (M's row i is A's row rows(i); distinct
  /// indices of A in any order), then solve() works with M's rows. The Supernodal backend reads
  /// M from A without forming it when settings.trusted (A then stores both triangles of a
  /// symmetric matrix); the others form M. settings.ordering refers to M's rows. Error messages
  /// name A's rows.
  /// @throws as compute(), and Error(InvalidArgument) for an index of rows outside A or repeated.
  void compute_principal(const Eigen::SparseMatrix<double>& A, const Eigen::VectorXi& rows,
    const SparseCholeskySettings& settings);

  /// After compute_principal() with the Supernodal backend and trusted settings: change the
  /// factored submatrix to A(rows', rows'), rows' = its rows minus @p remove plus @p add (rows of
  /// the same @p A), by CHOLMOD's row deletions and additions (cholmod_rowdel / cholmod_rowadd on
  /// a simplicial LDL^T that the first call converts the supernodal factor to) instead of a new
  /// factorization: each changed row costs about 1/100 of a refactorization of the BBW blocks.
  /// Afterwards M's rows are the remaining ones in their previous order followed by @p add
  /// (principal_rows()), and solve() works with that numbering. Copies made before keep their
  /// factorization. Rounding accumulates with the number of modifications (~1e-13 relative after
  /// hundreds on the BBW blocks); callers that need full accuracy refactor now and then.
  /// @throws Error(InvalidArgument) when the factorization is not modifiable (modifiable()), for
  ///   a row outside A, a removed row that is not in M or an added row that is; Error(SizeMismatch)
  ///   for a matrix of another size; Error(InvalidArgument) "not positive definite" when a pivot
  ///   becomes non-positive.
  void modify_principal(const Eigen::SparseMatrix<double>& A, const Eigen::VectorXi& add,
    const Eigen::VectorXi& remove);
  /// True when modify_principal() can be called: a compute_principal() factorization by the
  /// Supernodal backend with trusted settings, BaryLab built with CHOLMOD.
  bool modifiable() const noexcept;
  /// After compute_principal(): A's row of each row of the factored matrix (empty otherwise).
  const std::vector<int>& principal_rows() const noexcept;

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
  /// Entries stored in the factor (Supernodal: including the explicit zeros of its relaxed
  /// supernodes) and flops of the numeric factorization (sum of the squared column counts;
  /// CHOLMOD's count for Cholmod and Supernodal). 0 before compute().
  double factor_entries() const noexcept;
  double factor_flops() const noexcept;

  /// True when BaryLab was compiled with CHOLMOD (CMake found it; BARYLAB_USE_CHOLMOD=ON).
  static bool cholmod_available() noexcept;

private:
  struct Impl;
  Backend backend_;
  std::shared_ptr<Impl> impl_;
};

/// Optional settings of SparseCholesky::compute().
struct SparseCholeskySettings
{
  /// Fill-reducing ordering to use instead of the backend's own (AMD, or METIS when CHOLMOD
  /// prefers it): ordering(k) is the row of A eliminated k-th. Empty (default): the backend's.
  /// Saves the ordering's cost when the caller factors many related matrices, e.g. principal
  /// submatrices of one matrix with the restriction of one ordering of it.
  Eigen::VectorXi ordering;
  /// Skip the checks for non-finite entries and asymmetry (their cost is that of a few passes
  /// over A): for callers that factor submatrices of a matrix they validated. The diagonal and
  /// the definiteness test are checked regardless. Default false.
  bool trusted = false;
};

/// Fill-reducing orderings of a symmetric sparsity pattern.
enum class FillReducingOrdering
{
  Amd,              ///< approximate minimum degree (Eigen's AMD)
  Metis,            ///< METIS nested dissection through CHOLMOD (AMD without CHOLMOD)
  NestedDissection  ///< CHOLMOD's nested dissection (METIS bisection + constrained minimum
                    ///< degree; AMD without CHOLMOD): the least fill on 3D meshes, the slowest
};

/// A fill-reducing ordering of the pattern of @p A (square, both triangles stored; values are
/// ignored): result(k) is the row to eliminate k-th.
/// @throws Error(SizeMismatch) if A is not square; Error(Internal) if CHOLMOD fails.
Eigen::VectorXi fill_reducing_ordering(
  const Eigen::SparseMatrix<double>& A, FillReducingOrdering method = FillReducingOrdering::Amd);

/// Short stable name of a backend: "automatic", "cholmod", "eigen" or "supernodal".
const char* to_string(SparseCholesky::Backend backend) noexcept;

} // namespace bary
