#pragma once
/// @file box_constrained_qp.h
/// Convex quadratic programs with bound constraints,
///
///   min_x  1/2 x^T A x + b^T x   subject to  l <= x <= u,
///
/// A sparse symmetric positive definite (on the variables that are not fixed), l_i = u_i fixing
/// x_i (eliminated), infinite bounds allowed. The inner solver of bounded biharmonic weights
/// (core/coordinates/bbw.h): Jacobson et al. 2011 solve Eq. (8) subject to Eq. (6) per handle with MOSEK;
/// this is the replacement.
///
/// Method: the primal-dual active-set method of Hintermüller, Ito & Kunisch ("The primal-dual
/// active set strategy as a semismooth Newton method", SIAM J. Optim. 13(3), 2002), which for
/// bound constraints is the block principal pivoting method of Júdice & Pires ("A block
/// principal pivoting algorithm for large-scale strictly monotone linear complementarity
/// problems", Comput. Oper. Res. 21(5), 1994), with Júdice & Pires's safeguard against cycling.
/// Each iteration
///  1. fixes the variables of the current active set at their bounds and solves the
///     equality-constrained problem on the free set: A_FF x_F = -(b_F + A_FN x_N), with the
///     factorization of A_FF kept by a FreeSetFactor (below): a new sparse Cholesky
///     factorization, or the last one modified by row additions / deletions when few variables
///     changed sets (reused as is when the free set equals the one a warm start carries);
///  2. computes the gradient y = A x + b (the multipliers: y_i >= 0 on the lower-active set,
///     y_i <= 0 on the upper-active set, 0 on the free set at the optimum);
///  3. lists the violators: free variables outside their bounds, active variables whose
///     multiplier has the wrong sign (each beyond half the tolerance, see below);
///  4. stops if there are none; otherwise moves every violator to the other set (a block step:
///     free -> the bound it crossed, active -> free). The safeguard: when the number of
///     violators has not dropped below its best value for `block_attempts` consecutive
///     iterations, or when the block step would return to an active set already solved (a
///     cycle), only the violator with the largest index is moved (Murty's single pivot) until the
///     count drops below the best value. For a symmetric positive definite A (a P-matrix) this
///     makes the method finite (Júdice & Pires 1994; the single pivots are Murty's finite
///     least-index principal pivoting).
///
/// Iteration counts: for M-matrices (e.g. a stiffness matrix) block steps converge
/// monotonically in a few iterations (Hintermüller et al.). For bi-Laplacians (BBW's Q, not an
/// M-matrix) the active set's front oscillates and regions far from the handles, where the
/// solution is nearly flat, are pinned at a bound by an early block step and released slowly:
/// 20-60 iterations per handle on the BBW problems of the libigl knight (1,822 vertices) and hand
/// (7,234), nearly independent of the starting active set (on the knight, starting from the
/// solution's active set grown or shrunk by one ring took 18-60 iterations). The cause is the
/// tolerance: BBW weights have long tails of tiny values (on the hand, 80% of a weight's
/// support is below 1e-3 and down to 1e-11), which the KKT test at 1e-10 must resolve, and the
/// violations shrink by about a decade per 7 iterations (the hand's handle 0: 4-6 iterations at
/// tolerance 1e-4, 10 at 1e-6, 31-40 at 1e-8, 41-48 at 1e-10). In experiments on the knight,
/// projected Newton (Bertsekas 1982), a line-searched semismooth Newton method on the natural
/// residual, partial block steps and Moreau-Yosida path following all needed as many or more
/// factorizations (or stalled); on the hand, releasing the 1-3 rings around released variables
/// too, hysteresis for variables that flipped in the last iteration, projected Gauss-Seidel
/// smoothing between the solves, continuation in the tolerance and starting sets from
/// thresholded unconstrained weights did not reduce the iterations either. A primal-dual
/// interior-point method (Mehrotra's predictor-corrector; testing/benchmarks/bbw_study
/// interior) costs more: on the hand each of its iterations factors every unknown (12 ms against
/// 4.8 ms for a free block), it needs 13-28 iterations per handle to reach mu / s_y = 1e-10 ..
/// 1e-18, and started from its point this solver still takes 606-184 of its 654 iterations (the
/// problem is nearly degenerate in the tails: values and multipliers both below the tolerance);
/// 6.7-8.9 s in all against 3.2 s. Hence the work per iteration is what was made cheap (below).
///
/// Convergence test, on the returned point (after the final clamp described below), with
/// s_x = max(1, max |x_i|) and s_y = max(max_i sum_j |A_ij| |x_j|, max_i |b_i|) (the magnitude of
/// the terms that make up the gradient, so the measures are relative and unit-free):
///  - stationarity = max |y_i| / s_y over the variables strictly between their bounds;
///  - dual_infeasibility = max over variables on a bound of the wrong-signed part of y_i, / s_y;
///  - complementarity = max_i |y_i| min(x_i - l_i, u_i - x_i) / (s_x s_y) over the same
///    interior variables (the gap times the multiplier estimate; 0 on a bound by construction);
///  - kkt_residual = the largest of the three; converged when it is <= tolerance and the
///    last active-set iteration found no violator.
/// Bounds hold exactly: free variables that the last solve left outside their bounds by less
/// than the primal threshold (tolerance/2 * s_x) are clamped onto them, and the KKT measures
/// are evaluated after the clamp, so "converged" certifies the clamped point. When an iteration
/// finds no violator but the clamped point would not certify (the clamp moved the gradient of
/// neighbouring variables past the tolerance, as on a Voronoi-lumped bi-Laplacian with small
/// vertex masses), those clamped variables are put on their bounds and the active set is solved
/// again ("polish", at most 3 times per solve).
///
/// Cost: per iteration one update of the factorization of A restricted to the free set (for BBW,
/// the support of the weight: 3,000-5,000 of the hand's 7,234 vertices), one solve and one pass
/// over A's columns of the nonzero x_j (gradient and its scale together). The update
/// (FreeSetFactor) is either
///  - a fresh factorization of A_FF ordered by the restriction of one AMD ordering of A
///    (computed by precompute(); options.reuse_ordering), which skips the ordering's cost (as
///    much as the numeric factorization with a fresh AMD, measured) at the price of ~20-60% more
///    fill, and with the Supernodal backend reads A_FF from A without forming it; on the hand's
///    blocks 4.8 ms on average (symbolic analysis 1.55 ms, numeric 3.2 ms with the AVX2
///    kernels of sparse_cholesky.h; AMD EPYC), against 25-60 ms for Eigen's SimplicialLDLT with
///    its AMD (an earlier measurement); or
///  - when at most max(8, |F| / 64) variables changed sets (and |F| / 4 since the last fresh
///    factorization), CHOLMOD's row deletions and additions on the last factorization
///    (options.modify_factorizations, Supernodal backend): 0.15 ms per changed variable on the
///    hand on average. Late iterations change few variables (on the hand, a third of the
///    iterations change <= 30), so 258 of its 634 iterations are modifications. (With the
///    threshold at |F| / 128 the fresh factorizations and modifications cost the same in
///    total: 2.88 s against 2.86 s on the hand.)
///    When an iteration with a modified factorization finds no violator but the free variables'
///    gradient exceeds a quarter of the threshold (rounding accumulated), the active set is
///    solved again with a fresh factorization before "converged" is decided.
/// Both choices depend on counts only, so the iterates are deterministic. Memory: one factor at a
/// time.
///
/// Non-convergence within max_iterations is reported (converged = false), never silent;
/// the callers decide (BBW turns it into Error(NotConverged) by default).

#include "core/solvers/sparse_cholesky.h"
#include "core/common/types.h"

#include <cstdint>
#include <functional>

namespace bary
{

/// Options of the bound-constrained QP solver.
struct BoxQPOptions
{
  /// Relative KKT tolerance (see the file comment), in (0, 1). Default 1e-10.
  double tolerance = 1e-10;
  /// Cap on active-set iterations (each one factorization), >= 1. Reaching it returns
  /// converged = false. Default 1000.
  int max_iterations = 1000;
  /// Júdice-Pires safeguard: block steps allowed in a row without reducing the number of
  /// violators below its best value before single-index steps are taken, >= 0. 0 takes single
  /// steps whenever the count does not improve. Default 30: block steps on bi-Laplacians often
  /// go 10 or more iterations without a new best while still converging, and single steps (one
  /// factorization per changed variable) are slow; exact cycles are caught by the cycle test.
  int block_attempts = 30;
  /// When > 0, replaces the gradient scale s_y of the KKT measures (see the file comment), for a
  /// caller that knows the natural magnitude of the gradient better than |A| |x| does (e.g. when
  /// A holds a large penalty term whose contribution nearly cancels). Default 0: computed.
  double gradient_scale = 0.0;
  /// Backend of the factorizations. Default Automatic (CHOLMOD when available).
  SparseCholesky::Backend backend = SparseCholesky::Backend::Automatic;
  /// Order every free block by the restriction of one AMD ordering of A (computed by
  /// precompute()) instead of a fresh ordering per factorization: saves the ordering's cost
  /// (about as much as the numeric factorization of a free block of a bi-Laplacian) at the
  /// price of ~20-60% more fill. Default true.
  bool reuse_ordering = true;
  /// When few variables enter or leave the free set, change the factorization by row additions
  /// and deletions (SparseCholesky::modify_principal) instead of factoring anew. Needs the
  /// Supernodal backend and CHOLMOD; ignored otherwise. Default true.
  bool modify_factorizations = true;
  /// Called once per iteration; returning false stops the solver with Error(Cancelled).
  /// Empty: never cancelled.
  std::function<bool()> keep_going;
};

/// Variable states in an active set.
enum class BoxQPState : signed char
{
  Lower = -1, ///< held at its lower bound
  Free = 0,   ///< solved for
  Upper = 1,  ///< held at its upper bound
  Fixed = 2   ///< l_i == u_i: eliminated
};

/// Outcome of one solve.
struct BoxQPResult
{
  Eigen::VectorXd x;        ///< n, the minimizer; l <= x <= u holds exactly
  Eigen::VectorXd gradient; ///< n, A x + b: the multiplier of x_i's active bound (>= 0 at a
                            ///< lower bound, <= 0 at an upper bound), ~0 for free variables
  Eigen::Matrix<BoxQPState, Eigen::Dynamic, 1> state; ///< n, the active set of x
  int iterations = 0;           ///< active-set iterations (= linear solves)
  int factorizations = 0;       ///< of which needed a new factorization (warm start reuses)
  int modifications = 0;        ///< of which changed the factorization by row modifications
  Index modified_rows = 0;      ///< rows added or deleted by those modifications
  int single_steps = 0;         ///< iterations that took the safeguard's single-index step
  Index free = 0, lower = 0, upper = 0, fixed = 0; ///< sizes of the final sets
  Index violators = 0;          ///< violators at the last iteration (0 when converged)
  double stationarity = 0;      ///< see the file comment
  double dual_infeasibility = 0; ///< see the file comment
  double complementarity = 0;   ///< see the file comment
  double kkt_residual = 0;      ///< max of the three above
  double max_bound_violation = 0; ///< max(l - x, x - u, 0): always exactly 0
  double objective = 0;         ///< 1/2 x^T A x + b^T x
  bool converged = false;       ///< kkt_residual <= tolerance and no violator left
  double factor_seconds = 0;    ///< time in assembling and factoring the free blocks
  double seconds = 0;           ///< total time of the solve
};

/// Start and reuse information carried from one solve to the next (same BoxConstrainedQP,
/// same fixed variables): pass the same object to successive solve() calls.
struct BoxQPWarmStart
{
  /// In: the active set to start from (n entries, or empty = every non-fixed variable free);
  /// entries for fixed variables and for infinite bounds are corrected. Out: the final active
  /// set when converged, else the one the next iteration would have solved (so a solve with a
  /// larger max_iterations continues where this one stopped). Build one from a guess of x with
  /// active_set_from_guess().
  Eigen::Matrix<BoxQPState, Eigen::Dynamic, 1> state;
  /// The last factorization and its free set (internal): reused by the next solve if its first
  /// free set is the same. Belongs to the BoxConstrainedQP identified by owner.
  SparseCholesky factor;
  Eigen::VectorXi factor_free;
  std::uint64_t owner = 0;
};

/// Active set suggested by a guess @p x0 of the solution: Lower where x0_i <= l_i, Upper where
/// x0_i >= u_i, Fixed where l_i == u_i, Free elsewhere.
/// @throws Error(SizeMismatch) when the sizes differ.
Eigen::Matrix<BoxQPState, Eigen::Dynamic, 1> active_set_from_guess(
  const Eigen::VectorXd& x0, const Eigen::VectorXd& l, const Eigen::VectorXd& u);

/// The solver for one matrix A and many (b, l, u). precompute() validates and stores A; solve()
/// is const and thread-safe (each call owns its factorizations).
class BoxConstrainedQP
{
public:
  BoxConstrainedQP() = default;
  /// Same as default construction followed by precompute(A).
  explicit BoxConstrainedQP(const Eigen::SparseMatrix<double>& A);

  /// Validates and stores @p A (n by n, both triangles stored).
  /// @throws Error(SizeMismatch) if A is not square; Error(EmptyInput) if it is 0 by 0;
  ///   Error(NonFinite) for a NaN or infinite entry; Error(InvalidArgument) if A is not
  ///   symmetric (|A_ij - A_ji| > 1e-10 sqrt(|A_ii A_jj|), named) or a diagonal entry is <= 0
  ///   (then A is not positive definite: named).
  void precompute(const Eigen::SparseMatrix<double>& A);

  /// Minimizes 1/2 x^T A x + b^T x over l <= x <= u.
  /// @param b, l, u n-vectors; l_i may be -infinity, u_i +infinity; l_i == u_i fixes x_i.
  /// @param warm optional start / reuse state (see BoxQPWarmStart); updated on return.
  /// @throws Error(InvalidArgument) before precompute(), for l_i > u_i (named; the problem is
  ///   infeasible) or when A restricted to a free set is not positive definite (A is not SPD,
  ///   or the problem is unbounded below: a free variable with two infinite bounds in a
  ///   direction of zero curvature); Error(SizeMismatch) for vectors of the wrong length;
  ///   Error(NonFinite) for NaN in b, l or u, or infinite b; Error(Cancelled) when
  ///   options.keep_going returns false.
  BoxQPResult solve(const Eigen::VectorXd& b, const Eigen::VectorXd& l, const Eigen::VectorXd& u,
    const BoxQPOptions& options = {}, BoxQPWarmStart* warm = nullptr) const;

  /// n (0 before precompute()).
  Index size() const noexcept { return A_.rows(); }
  const Eigen::SparseMatrix<double>& matrix() const noexcept { return A_; }
  /// The AMD ordering of A computed by precompute(): ordering()(k) is eliminated k-th.
  const Eigen::VectorXi& ordering() const noexcept { return ordering_; }

private:
  Eigen::SparseMatrix<double> A_;
  Eigen::VectorXi ordering_; ///< AMD ordering of A: ordering_(k) is eliminated k-th
  std::uint64_t id_ = 0;     ///< identifies this matrix to warm starts
};

/// The factorization of A restricted to a free set that changes from one active-set iteration
/// to the next: a fresh factorization of A(F, F) (ordered by the restriction of the
/// BoxConstrainedQP's AMD ordering when options.reuse_ordering), or, when few variables entered
/// or left F, a modification of the last one by row additions / deletions
/// (SparseCholesky::modify_principal; options.modify_factorizations, Supernodal backend with
/// CHOLMOD): at most max(8, |F| / 64) rows at a time and |F| / 4 rows since the last fresh
/// factorization. Used by BoxConstrainedQP::solve and by the coupled mode of bounded biharmonic
/// weights, which keeps one per handle. Not thread-safe; solve() is const and may run
/// concurrently with other objects' calls.
class FreeSetFactor
{
public:
  /// @p qp must outlive this object (its matrix and ordering are used by reference).
  FreeSetFactor(const BoxConstrainedQP& qp, const BoxQPOptions& options);

  /// Makes this the factorization of A(free, free), @p free ascending and non-empty (nothing
  /// happens when it is already, unless force_refactor() was called).
  /// @throws the errors of SparseCholesky::compute_principal / modify_principal.
  void update(const std::vector<int>& free);
  /// The next update() factors anew (e.g. when rounding from many modifications shows).
  void force_refactor() noexcept { force_ = true; }
  /// Rows modified since the last fresh factorization (0 right after one).
  Index modified_rows() const noexcept { return modified_rows_; }
  /// A's row of each row of the factorization: the order of solve()'s vectors.
  const std::vector<int>& rows() const noexcept { return rows_; }
  bool empty() const noexcept { return rows_.empty(); }
  /// Solves A(F, F) z = rhs, rhs and z in the order of rows().
  Eigen::VectorXd solve(const Eigen::VectorXd& rhs) const { return factor_.solve(rhs); }
  /// Starts from a factorization of A(rows, rows) made by another FreeSetFactor of the same
  /// BoxConstrainedQP (warm starts).
  void adopt(const SparseCholesky& factor, const std::vector<int>& rows);
  const SparseCholesky& factor() const noexcept { return factor_; }

  int factorizations = 0;     ///< fresh factorizations so far
  int modifications = 0;     ///< modifications so far
  Index modified_rows_total = 0; ///< rows added or deleted by them
  double seconds = 0;         ///< time in update()

private:
  const BoxConstrainedQP* qp_;
  bool reuse_ordering_, modify_;
  SparseCholesky factor_;
  std::vector<int> rows_;
  std::vector<char> in_factor_;
  std::vector<int> position_, added_, removed_;
  Index modified_rows_ = 0;
  bool force_ = false;
};

/// One-call form: BoxConstrainedQP(A).solve(b, l, u, options), starting from the active set
/// suggested by @p x0 when it is given (non-empty). Same errors as precompute() and solve().
BoxQPResult box_constrained_qp(const Eigen::SparseMatrix<double>& A, const Eigen::VectorXd& b,
  const Eigen::VectorXd& l, const Eigen::VectorXd& u, const BoxQPOptions& options = {},
  const Eigen::VectorXd& x0 = Eigen::VectorXd());

} // namespace bary
