#include "core/coordinates/bbw.h"

#include "core/detail/parallel_for.h"
#include "core/detail/format.h"
#include "core/detail/simd.h"
#include "core/common/error.h"
#include "core/solvers/fem_operators.h"
#include "core/solvers/min_quad_with_fixed.h"
#include "core/detail/timing.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <string>
#include <unordered_set>
#include <utility>

namespace bary
{
namespace
{

using SparseMatrix = Eigen::SparseMatrix<double>;
using Clock = std::chrono::steady_clock;

void validate_options(const BBWOptions& o)
{
  auto fail = [](const std::string& what) { throw Error(ErrorCode::InvalidArgument, what); };
  if (o.mode != BBWMode::Fast && o.mode != BBWMode::Coupled)
    fail("BBWOptions::mode is not a BBWMode value");
  if (!(o.tolerance > 0.0 && o.tolerance < 1.0))
    fail("BBWOptions::tolerance must be in (0, 1), got " + detail::format_number(o.tolerance));
  if (o.max_iterations < 1)
    fail("BBWOptions::max_iterations must be >= 1, got " + std::to_string(o.max_iterations));
  if (!(o.partition_tolerance > 0.0 && o.partition_tolerance < 1.0))
    fail("BBWOptions::partition_tolerance must be in (0, 1), got " + detail::format_number(o.partition_tolerance));
  if (o.max_outer_iterations < 1)
    fail("BBWOptions::max_outer_iterations must be >= 1, got " +
      std::to_string(o.max_outer_iterations));
  if (!(o.penalty > 0.0 && std::isfinite(o.penalty)))
    fail("BBWOptions::penalty must be finite and > 0, got " + detail::format_number(o.penalty));
  if (o.threads < 0)
    fail("BBWOptions::threads must be >= 0 (0 = OpenMP's default), got " +
      std::to_string(o.threads));
  if (o.mass_lumping != BBWMassLumping::Barycentric && o.mass_lumping != BBWMassLumping::Voronoi)
    fail("BBWOptions::mass_lumping is not a BBWMassLumping value");
}

/// The bound-constrained QP options of a BBW solve.
BoxQPOptions qp_options(const BBWOptions& o, const ProgressReporter& reporter)
{
  BoxQPOptions q;
  q.tolerance = o.tolerance;
  q.max_iterations = o.max_iterations;
  q.backend = o.backend;
  q.keep_going = [&reporter]() { return !reporter.cancelled(); };
  return q;
}

/// Runs fn(j) for j = 0 .. m-1 on @p threads OpenMP threads; rethrows the first exception.
template<typename Fn>
void for_each_handle(Index m, int threads, const Fn& fn)
{
  ProgressReporter silent({}, m);
  detail::parallel_for(m, 1, threads, silent, "bounded biharmonic weights",
    [&fn](Index begin, Index end) {
      for (Index j = begin; j < end; ++j)
        fn(j);
    });
}

/// Columns [k0, k0 + w) of Y += Q X by rows (Y, X row-major with m columns): for each column c
/// of Q in order, each of its entries (i, c) adds Q_ic X(c, k) to Y(i, k). The same multiplies
/// and adds in the same order however it is compiled (no fused multiply-add: the AVX2 version
/// is BARY_TARGET_AVX2_EXACT), so both versions give the same bits.
BARY_ALWAYS_INLINE void add_product_rows(const SparseMatrix& Q, const double* X, double* Y, Index m,
  Index k0, Index w)
{
  const int* outer = Q.outerIndexPtr();
  const int* inner = Q.innerIndexPtr();
  const double* value = Q.valuePtr();
  for (Index c = 0; c < Q.outerSize(); ++c)
  {
    const double* x = X + c * m + k0;
    for (int q = outer[c]; q < outer[c + 1]; ++q)
    {
      double* y = Y + static_cast<Index>(inner[q]) * m + k0;
      const double v = value[q];
      for (Index k = 0; k < w; ++k)
        y[k] += v * x[k];
    }
  }
}
#if BARY_HAVE_AVX2_DISPATCH
BARY_TARGET_AVX2_EXACT BARY_NOINLINE void add_product_rows_avx2(
  const SparseMatrix& Q, const double* X, double* Y, Index m, Index k0, Index w)
{
  add_product_rows(Q, X, Y, m, k0, w);
}
#endif
BARY_NOINLINE void add_product_rows_portable(
  const SparseMatrix& Q, const double* X, double* Y, Index m, Index k0, Index w)
{
  add_product_rows(Q, X, Y, m, k0, w);
}

/// Y = Q X for every column of X at once, in one pass over Q per thread (instead of one per
/// column): X and Y handled by rows (@p X_rows, @p Y_rows: row-major copies, reused between
/// calls). Each entry sums its terms in the order of Q's columns, as Eigen's product of Q with
/// one column does, so the results are those of Q * X.col(j) bit for bit; the columns are split
/// into one block per thread (the same sums whatever the thread count).
void multiply_all_columns(const SparseMatrix& Q, const Eigen::MatrixXd& X, int threads,
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>& X_rows,
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>& Y_rows, Eigen::MatrixXd& Y)
{
  const Index n = Q.rows(), m = X.cols();
  X_rows = X;
  Y_rows.setZero(n, m);
  const Index tasks = std::max<Index>(1, std::min<Index>(m, detail::thread_count(threads)));
  const Index block = (m + tasks - 1) / tasks;
  [[maybe_unused]] const bool avx2 = detail::simd_level() == detail::SimdLevel::AVX2;
  for_each_handle(tasks, threads, [&](Index b) {
    const Index k0 = b * block, w = std::min(m, k0 + block) - k0;
    if (w <= 0)
      return;
#if BARY_HAVE_AVX2_DISPATCH
    if (avx2)
      add_product_rows_avx2(Q, X_rows.data(), Y_rows.data(), m, k0, w);
    else
#endif
      add_product_rows_portable(Q, X_rows.data(), Y_rows.data(), m, k0, w);
  });
  Y = Y_rows;
}

/// BBWResult::statistics (see its comment) from its fields, for a mesh of @p vertices and
/// @p cells with @p handles handles.
void fill_statistics(BBWResult& result, Index vertices, Index cells, Index handles)
{
  long long iterations = 0, factorizations = 0;
  int most = 0;
  for (std::size_t j = 0; j < result.iterations.size(); ++j)
  {
    iterations += result.iterations[j];
    factorizations += result.factorizations[j];
    most = std::max(most, result.iterations[j]);
  }
  Statistics& st = result.statistics;
  st.clear();
  st.emplace_back("mesh_vertices", static_cast<double>(vertices));
  st.emplace_back("mesh_cells", static_cast<double>(cells));
  st.emplace_back("handles", static_cast<double>(handles));
  st.emplace_back("fixed_vertices", static_cast<double>(result.fixed_vertices));
  st.emplace_back("coupled", result.mode == BBWMode::Coupled ? 1.0 : 0.0);
  st.emplace_back("fast_iterations", static_cast<double>(iterations));
  st.emplace_back("fast_factorizations", static_cast<double>(factorizations));
  st.emplace_back("max_fast_iterations_per_handle", static_cast<double>(most));
  if (result.mode == BBWMode::Coupled)
  {
    st.emplace_back("outer_iterations", result.outer_iterations);
    st.emplace_back("coupled_iterations", result.coupled_iterations);
    st.emplace_back("coupled_factorizations", result.coupled_factorizations);
    st.emplace_back("coupled_kkt_residual", result.coupled_kkt_residual);
    if (!result.iterations.empty()) // compare_with_fast
    {
      st.emplace_back("fast_difference_mean", result.fast_difference_mean);
      st.emplace_back("fast_difference_max", result.fast_difference_max);
    }
  }
  st.emplace_back("max_kkt_residual", result.max_kkt_residual);
  st.emplace_back("max_bound_violation", result.max_bound_violation);
  st.emplace_back("partition_error", result.partition_error);
  st.emplace_back(
    "partition_error_before_normalization", result.partition_error_before_normalization);
  st.emplace_back("converged", result.converged ? 1.0 : 0.0);
  st.emplace_back("solve_seconds", result.seconds);
}

/// What the coupled solver did.
struct CoupledOutcome
{
  Eigen::MatrixXd W;
  int iterations = 0, cg_iterations = 0, factorizations = 0, modifications = 0;
  Index violators = 0;
  double kkt_residual = 0, partition_error = 0;
  bool converged = false;
};

/// The coupled problem (Eq. 8 subject to Eq. 3-6) by a primal-dual active-set method on all
/// handles at once: the iterate X (#V by #handles), the active sets, one factorization of Q on
/// each handle's free set and the multiplier mu of the partition of unity (Eq. 5). See
/// BBWMode::Coupled for the method; run() reads as its steps 1-5.
class CoupledSolver
{
public:
  /// Starts from @p start, the unconstrained biharmonic weights (see
  /// start_from_independent_solves). @p qp, @p o, @p box and @p reporter must outlive the
  /// solver.
  CoupledSolver(const BoxConstrainedQP& qp, const BBWBoundaryConditions& bc,
    const Eigen::MatrixXd& start, const BBWOptions& o, const BoxQPOptions& box,
    ProgressReporter& reporter);

  /// Active-set iterations until no violator is left and the KKT residual and the partition
  /// error are within their tolerances (or max_outer_iterations), then the clamped weights
  /// and their certificate.
  CoupledOutcome run();

private:
  using States = Eigen::Matrix<BoxQPState, Eigen::Dynamic, Eigen::Dynamic>;

  /// Active sets of the iterate: fixed rows Fixed, weights <= 0 Lower, >= 1 Upper, else Free.
  void initialize_states();
  /// The start: each handle solved alone on the active sets of the unconstrained weights
  /// (mu = 0, the Fast mode's first iteration), clamped onto [0, 1], rows normalized (a row of
  /// zeros becomes uniform), and the active sets of that; the factorizations are kept.
  void start_from_independent_solves();
  /// max_i sum_j |Q_ij| (1 if 0): it bounds |Q w| for 0 <= w <= 1, the scale of the gradients.
  static double gradient_scale(const SparseMatrix& Q);
  /// FNV-1a hash of the active sets (the safeguard's record of the sets already solved).
  std::uint64_t state_hash() const;

  /// Step 1: active weights onto their bounds, free weights to 0; each handle's free set F_j,
  /// each vertex's count of free weights and sum of upper bounds.
  void collect_free_sets();
  /// Step 1: per handle, the factorization of Q(F_j, F_j) updated and
  /// a_j = Q(F_j, F_j)^-1 (-Q(F_j, N_j) x_j(N_j) - mu(F_j)), the free weights for the current mu
  /// (the last iteration's; 0 at the start).
  void solve_free_sets();
  /// fn(i, j, a) for every free weight (vertex i, handle j), a its value in a_j, handle by
  /// handle in the factor's row order.
  template<typename Fn>
  void for_each_free_weight(const Fn& fn) const
  {
    for (Index j = 0; j < m_; ++j)
    {
      const auto ju = static_cast<std::size_t>(j);
      if (free_[ju].empty())
        continue;
      const std::vector<int>& rows = factors_[ju].rows();
      for (std::size_t k = 0; k < rows.size(); ++k)
        fn(rows[k], j, a_[ju](static_cast<Index>(k)));
    }
  }
  /// Step 2: V, the unknown vertices with a free weight, and each vertex's position in it.
  void collect_multiplier_vertices();
  /// Step 2: sum_j E_j a_j - (1 - bound sums) on V, the partition residual (Eq. 5) of the
  /// free weights a_j: with a_j(mu) = a_j(0) - Q(F_j, F_j)^-1 E_j^T mu it is the residual
  /// rhs - S mu of the multiplier's system, rhs = sum_j E_j a_j(0) - (1 - bound sums).
  Eigen::VectorXd multiplier_rhs() const;
  /// Step 2: S mu = rhs on V by conjugate gradients preconditioned with Q(V, V) / #handles,
  /// started from the current mu (whose residual multiplier_rhs() gives), until
  /// max |residual| <= @p cg_tolerance (or at most cg_cap_ iterations); each step of mu moves
  /// the a_j by the solves apply_S made for it, so the a_j are the free weights for the final mu
  /// without solving again. mu is 0 off V afterwards.
  void solve_multiplier(double cg_tolerance);
  /// S z = sum_j E_j^T Q(F_j, F_j)^-1 E_j z on V, the handles' solves in parallel, summed in
  /// handle order (so the result does not depend on the thread count).
  void apply_S(const Eigen::VectorXd& z, Eigen::VectorXd& result);
  /// The preconditioner z = Q(V, V) r / #handles: exactly S^-1 r when every handle is free on V.
  void precondition(const Eigen::VectorXd& r, Eigen::VectorXd& z);
  /// Y = Q X, one handle per column, all handles in one pass over Q (multiply_all_columns).
  void compute_gradients();
  /// Step 3: mu where no weight is free: the middle of the interval that makes the multipliers
  /// lambda = Y + mu of the active bounds correctly signed (its best compromise when the
  /// interval is empty).
  void multiplier_where_no_weight_is_free();
  /// Step 4: the KKT measures of the iterate (stationarity, sign, complementarity; partition
  /// error) into out_, and the violators; returns the largest violation.
  double find_violators();
  /// Progress: the decrease of log(violation) towards log(tolerance), in thousandths.
  void report_progress(double violation);
  /// Step 5: every violator flips (a block step), or only the last one (the safeguard's single
  /// step, as in BoxConstrainedQP) after block_attempts block steps without a new best count
  /// of violators or when the block step returns to an active set already solved.
  void change_active_sets();
  /// Weight (i, j) changes sets: free to the bound it crossed, bounded to free.
  void flip(Index i, Index j);
  /// A vertex must keep a free weight unless its bounds sum to 1 (else the partition of unity
  /// has no solution on the active set): free its largest weight.
  void repair();
  /// Clamps the weights onto [0, 1] (moves free weights by at most the primal threshold when
  /// converged), certifies the clamped point (KKT residual, partition error) and sums the
  /// factorization counts.
  void clamp_and_certify();

  const SparseMatrix& Q_;
  const BBWOptions& o_;
  const BoxQPOptions& box_;
  ProgressReporter& reporter_;
  const Index n_, m_;
  const int threads_;
  std::vector<char> known_; ///< #V: 1 on the fixed rows
  Eigen::MatrixXd X_;       ///< #V by #handles: the iterate
  Eigen::MatrixXd QX_;      ///< #V by #handles: Q X_ at the free sets' solve
  /// Row-major copies of X_ and of Q X_ for multiply_all_columns (kept between calls).
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> X_rows_, Y_rows_;
  States state_;            ///< #V by #handles: the active sets
  // The scale of the gradient's terms: max_i sum_j |Q_ij| bounds |Q| |w| for 0 <= w <= 1.
  const double sy_;
  // Free weights are pinned once they leave [0, 1] by tx: half the KKT tolerance, and little
  // enough that clamping the weights within tx of a bound keeps the partition error of every
  // vertex within half its tolerance.
  const double tx_;
  const double ty_; ///< multipliers of the wrong sign beyond ty_ are violators
  // Floor of the conjugate gradients' stopping test (the max-norm of the partition residual).
  const double cg_floor_;
  const int cg_cap_;

  std::vector<FreeSetFactor> factors_;
  std::vector<std::vector<int>> free_;    ///< F_j, ascending
  std::vector<Eigen::VectorXd> a_;        ///< a_j, in the order of factors_[j].rows()
  std::vector<Eigen::VectorXd> solved_;   ///< apply_S's per-handle solves
  Eigen::VectorXd mu_, full_, bound_sum_;
  std::vector<int> free_count_, vpos_, V_;
  Eigen::MatrixXd Y_; ///< #V by #handles: Q X

  std::unordered_set<std::uint64_t> visited_;
  Index best_violators_ = std::numeric_limits<Index>::max();
  int attempts_left_;
  double first_violation_ = -1.0;
  long long reported_ = 0;
  std::vector<std::pair<Index, Index>> violators_; // (vertex, handle)
  CoupledOutcome out_;
};

CoupledSolver::CoupledSolver(const BoxConstrainedQP& qp, const BBWBoundaryConditions& bc,
  const Eigen::MatrixXd& start, const BBWOptions& o, const BoxQPOptions& box,
  ProgressReporter& reporter)
  : Q_(qp.matrix())
  , o_(o)
  , box_(box)
  , reporter_(reporter)
  , n_(Q_.rows())
  , m_(start.cols())
  , threads_(detail::thread_count(o.threads))
  , known_(static_cast<std::size_t>(n_), 0)
  , X_(start)
  , state_(n_, m_)
  , sy_(gradient_scale(Q_))
  , tx_(std::min(0.5 * o.tolerance, 0.5 * o.partition_tolerance / static_cast<double>(m_)))
  , ty_(0.5 * o.tolerance * sy_)
  , cg_floor_(0.1 * o.partition_tolerance)
  , cg_cap_(static_cast<int>(std::min<Index>(5000, 10 * n_ + 10)))
  , free_(static_cast<std::size_t>(m_))
  , a_(static_cast<std::size_t>(m_))
  , solved_(static_cast<std::size_t>(m_))
  , mu_(Eigen::VectorXd::Zero(n_))
  , full_(n_)
  , bound_sum_(n_)
  , free_count_(static_cast<std::size_t>(n_))
  , vpos_(static_cast<std::size_t>(n_), -1)
  , Y_(n_, m_)
  , attempts_left_(box.block_attempts)
{
  for (Index k = 0; k < bc.vertices.size(); ++k)
    known_[static_cast<std::size_t>(bc.vertices(k))] = 1;
  initialize_states();
  factors_.reserve(static_cast<std::size_t>(m_));
  for (Index j = 0; j < m_; ++j)
    factors_.emplace_back(qp, box_);
}

void CoupledSolver::initialize_states()
{
  for (Index j = 0; j < m_; ++j)
    for (Index i = 0; i < n_; ++i)
    {
      BoxQPState& st = state_(i, j);
      if (known_[static_cast<std::size_t>(i)])
        st = BoxQPState::Fixed;
      else if (X_(i, j) <= 0.0)
        st = BoxQPState::Lower;
      else if (X_(i, j) >= 1.0)
        st = BoxQPState::Upper;
      else
        st = BoxQPState::Free;
    }
}

void CoupledSolver::start_from_independent_solves()
{
  collect_free_sets();
  solve_free_sets(); // mu = 0 still
  for_each_free_weight([&](int i, Index j, double a) { X_(i, j) = std::clamp(a, 0.0, 1.0); });
  for (Index i = 0; i < n_; ++i)
  {
    if (known_[static_cast<std::size_t>(i)])
      continue;
    const double sum = X_.row(i).sum();
    if (sum > 0.0)
      X_.row(i) /= sum;
    else
      X_.row(i).setConstant(1.0 / static_cast<double>(m_));
  }
  initialize_states();
}

double CoupledSolver::gradient_scale(const SparseMatrix& Q)
{
  double sy = 0.0;
  for (Index i = 0; i < Q.rows(); ++i)
  {
    double row = 0.0;
    for (SparseMatrix::InnerIterator it(Q, i); it; ++it)
      row += std::abs(it.value());
    sy = std::max(sy, row);
  }
  return sy > 0.0 ? sy : 1.0;
}

std::uint64_t CoupledSolver::state_hash() const
{
  std::uint64_t h = 14695981039346656037ull;
  for (Index k = 0; k < state_.size(); ++k)
  {
    h ^= static_cast<std::uint64_t>(static_cast<unsigned char>(state_.data()[k]));
    h *= 1099511628211ull;
  }
  return h;
}

CoupledOutcome CoupledSolver::run()
{
  start_from_independent_solves();
  double last_violation = 1.0;
  bool tight = false, refactored_at_end = false;
  while (out_.iterations < o_.max_outer_iterations)
  {
    if (reporter_.cancelled())
      reporter_.throw_if_cancelled("bounded biharmonic weights (coupled)");
    ++out_.iterations;
    visited_.insert(state_hash());

    // 1. Active weights on their bounds; per handle, the factorization of Q on its free set and
    //    a_j, the free weights for the last mu (on V, the vertices with a free weight).
    collect_free_sets();
    collect_multiplier_vertices();
    solve_free_sets();

    // 2. mu on V from S mu = sum_j a_j(0) - (1 - bound sums), to a tolerance that follows the
    //    violations (tight once they are gone), started from the last mu; a_j follows mu.
    const double cg_tolerance = tight ? cg_floor_ : std::max(cg_floor_, 0.1 * last_violation);
    solve_multiplier(cg_tolerance);

    // 3. The free weights a_j, the gradients Y = Q X and the multipliers lambda = Y + mu of the
    //    bounds.
    for_each_free_weight([&](int i, Index j, double a) { X_(i, j) = a; });
    compute_gradients();
    multiplier_where_no_weight_is_free();

    // 4. KKT measures and violators.
    const double violation = find_violators();
    report_progress(violation);
    if (violators_.empty())
    {
      if (cg_tolerance > cg_floor_ && !tight)
      {
        tight = true; // confirm with mu solved to the partition tolerance
        continue;
      }
      if (out_.partition_error <= o_.partition_tolerance && out_.kkt_residual <= o_.tolerance)
      {
        out_.converged = true;
        break;
      }
      // Rounding from factor modifications (or conjugate gradients at their cap): once, solve
      // the same active set with fresh factorizations.
      if (!refactored_at_end)
      {
        refactored_at_end = true;
        for (FreeSetFactor& f : factors_)
          f.force_refactor();
        continue;
      }
      break;
    }
    last_violation = violation;
    tight = false;

    // 5. Block step, or the safeguard's single step (as in BoxConstrainedQP).
    change_active_sets();
  }
  clamp_and_certify();
  out_.W = std::move(X_);
  return std::move(out_);
}

void CoupledSolver::collect_free_sets()
{
  for (Index i = 0; i < n_; ++i)
  {
    free_count_[static_cast<std::size_t>(i)] = 0;
    bound_sum_(i) = 0.0;
  }
  for (Index j = 0; j < m_; ++j)
  {
    std::vector<int>& f = free_[static_cast<std::size_t>(j)];
    f.clear();
    for (Index i = 0; i < n_; ++i)
      switch (state_(i, j))
      {
        case BoxQPState::Free:
          f.push_back(static_cast<int>(i));
          ++free_count_[static_cast<std::size_t>(i)];
          X_(i, j) = 0.0;
          break;
        case BoxQPState::Lower: X_(i, j) = 0.0; break;
        case BoxQPState::Upper:
          X_(i, j) = 1.0;
          bound_sum_(i) += 1.0;
          break;
        case BoxQPState::Fixed: break;
      }
  }
}

void CoupledSolver::solve_free_sets()
{
  // Q(F_j, :) x_j for every handle from one product Q X (Q is exactly symmetric: row i of the
  // product sums column i's entries in their order, as a pass along column i would).
  multiply_all_columns(Q_, X_, threads_, X_rows_, Y_rows_, QX_);
  for_each_handle(m_, threads_, [&](Index j) {
    const auto ju = static_cast<std::size_t>(j);
    if (free_[ju].empty())
      return;
    factors_[ju].update(free_[ju]);
    const std::vector<int>& rows = factors_[ju].rows();
    Eigen::VectorXd rhs(static_cast<Index>(rows.size()));
    for (std::size_t k = 0; k < rows.size(); ++k)
      rhs(static_cast<Index>(k)) = -QX_(rows[k], j) - mu_(rows[k]);
    a_[ju] = factors_[ju].solve(rhs);
  });
}

void CoupledSolver::collect_multiplier_vertices()
{
  V_.clear();
  for (Index i = 0; i < n_; ++i)
  {
    vpos_[static_cast<std::size_t>(i)] = -1;
    if (!known_[static_cast<std::size_t>(i)] && free_count_[static_cast<std::size_t>(i)] > 0)
    {
      vpos_[static_cast<std::size_t>(i)] = static_cast<int>(V_.size());
      V_.push_back(static_cast<int>(i));
    }
  }
}

Eigen::VectorXd CoupledSolver::multiplier_rhs() const
{
  const Index nv = static_cast<Index>(V_.size());
  Eigen::VectorXd rhs(nv);
  for (Index v = 0; v < nv; ++v)
    rhs(v) = bound_sum_(V_[static_cast<std::size_t>(v)]) - 1.0;
  for_each_free_weight([&](int i, Index, double a) { rhs(vpos_[static_cast<std::size_t>(i)]) += a; });
  return rhs;
}

void CoupledSolver::solve_multiplier(double cg_tolerance)
{
  const Index nv = static_cast<Index>(V_.size());
  Eigen::VectorXd z(nv), p(nv), Sp(nv), x(nv);
  if (nv > 0)
  {
    for (Index v = 0; v < nv; ++v)
      x(v) = mu_(V_[static_cast<std::size_t>(v)]);
    // The partition residual of the a_j (solved for the last mu) is rhs - S mu.
    Eigen::VectorXd r = multiplier_rhs();
    precondition(r, z);
    p = z;
    double rz = r.dot(z);
    for (int k = 0; k < cg_cap_ && r.cwiseAbs().maxCoeff() > cg_tolerance; ++k)
    {
      apply_S(p, Sp);
      const double curvature = p.dot(Sp);
      if (!(curvature > 0.0))
        break;
      const double alpha = rz / curvature;
      x += alpha * p;
      r -= alpha * Sp;
      // a_j = Q(F_j, F_j)^-1 (b_j - mu(F_j)) follows x: apply_S's solves are those of p.
      for (Index j = 0; j < m_; ++j)
      {
        const auto ju = static_cast<std::size_t>(j);
        if (!factors_[ju].empty() && !free_[ju].empty())
          a_[ju] -= alpha * solved_[ju];
      }
      precondition(r, z);
      const double rz_next = r.dot(z);
      p = z + (rz_next / rz) * p;
      rz = rz_next;
      ++out_.cg_iterations;
    }
  }
  mu_.setZero();
  for (Index v = 0; v < nv; ++v)
    mu_(V_[static_cast<std::size_t>(v)]) = x(v);
}

void CoupledSolver::apply_S(const Eigen::VectorXd& z, Eigen::VectorXd& result)
{
  for_each_handle(m_, threads_, [&](Index j) {
    const auto ju = static_cast<std::size_t>(j);
    if (factors_[ju].empty() || free_[ju].empty())
      return;
    const std::vector<int>& rows = factors_[ju].rows();
    Eigen::VectorXd g(static_cast<Index>(rows.size()));
    for (std::size_t k = 0; k < rows.size(); ++k)
      g(static_cast<Index>(k)) = z(vpos_[static_cast<std::size_t>(rows[k])]);
    solved_[ju] = factors_[ju].solve(g);
  });
  result.setZero(static_cast<Index>(V_.size()));
  for (Index j = 0; j < m_; ++j)
  {
    const auto ju = static_cast<std::size_t>(j);
    if (factors_[ju].empty() || free_[ju].empty())
      continue;
    const std::vector<int>& rows = factors_[ju].rows();
    for (std::size_t k = 0; k < rows.size(); ++k)
      result(vpos_[static_cast<std::size_t>(rows[k])]) += solved_[ju](static_cast<Index>(k));
  }
}

void CoupledSolver::precondition(const Eigen::VectorXd& r, Eigen::VectorXd& z)
{
  full_.setZero();
  for (std::size_t v = 0; v < V_.size(); ++v)
    full_(V_[v]) = r(static_cast<Index>(v));
  const Eigen::VectorXd product = Q_ * full_;
  z.resize(static_cast<Index>(V_.size()));
  for (std::size_t v = 0; v < V_.size(); ++v)
    z(static_cast<Index>(v)) = product(V_[v]) / static_cast<double>(m_);
}

void CoupledSolver::compute_gradients()
{
  multiply_all_columns(Q_, X_, threads_, X_rows_, Y_rows_, Y_);
}

void CoupledSolver::multiplier_where_no_weight_is_free()
{
  for (Index i = 0; i < n_; ++i)
  {
    if (known_[static_cast<std::size_t>(i)] || free_count_[static_cast<std::size_t>(i)] > 0)
      continue;
    double lo = -std::numeric_limits<double>::infinity(), hi = std::numeric_limits<double>::infinity();
    for (Index j = 0; j < m_; ++j)
      if (state_(i, j) == BoxQPState::Lower)
        lo = std::max(lo, -Y_(i, j));
      else if (state_(i, j) == BoxQPState::Upper)
        hi = std::min(hi, -Y_(i, j));
    mu_(i) = std::isfinite(lo) && std::isfinite(hi) ? 0.5 * (lo + hi) : std::isfinite(lo) ? lo : hi;
  }
}

double CoupledSolver::find_violators()
{
  double stationarity = 0.0, dual = 0.0, complementarity = 0.0, partition = 0.0;
  violators_.clear();
  double violation = 0.0;
  for (Index i = 0; i < n_; ++i)
  {
    if (known_[static_cast<std::size_t>(i)])
      continue;
    partition = std::max(partition, std::abs(X_.row(i).sum() - 1.0));
    for (Index j = 0; j < m_; ++j)
    {
      const double w = X_(i, j), lambda = Y_(i, j) + mu_(i);
      switch (state_(i, j))
      {
        case BoxQPState::Free:
          stationarity = std::max(stationarity, std::abs(lambda) / sy_);
          complementarity = std::max(complementarity, std::abs(lambda) * std::max(0.0, std::min(w, 1.0 - w)) / sy_);
          if (w < -tx_ || w > 1.0 + tx_)
          {
            violators_.emplace_back(i, j);
            violation = std::max(violation, std::max(-w, w - 1.0));
          }
          break;
        case BoxQPState::Lower:
          dual = std::max(dual, -lambda / sy_);
          if (lambda < -ty_)
          {
            violators_.emplace_back(i, j);
            violation = std::max(violation, -lambda / sy_);
          }
          break;
        case BoxQPState::Upper:
          dual = std::max(dual, lambda / sy_);
          if (lambda > ty_)
          {
            violators_.emplace_back(i, j);
            violation = std::max(violation, lambda / sy_);
          }
          break;
        case BoxQPState::Fixed: break;
      }
    }
  }
  out_.violators = static_cast<Index>(violators_.size());
  out_.kkt_residual = std::max({ stationarity, dual, complementarity });
  out_.partition_error = partition;
  return violation;
}

void CoupledSolver::report_progress(double violation)
{
  if (first_violation_ < 0.0)
    first_violation_ = std::max(violation, 10.0 * o_.tolerance);
  const double fraction = std::clamp(std::log(first_violation_ / std::max(violation, 1e-300)) /
      std::log(first_violation_ / o_.tolerance), 0.0, 1.0);
  const long long now = static_cast<long long>(999.0 * fraction);
  if (!reporter_.step(std::max(0LL, now - reported_)))
    reporter_.throw_if_cancelled("bounded biharmonic weights (coupled)");
  reported_ = std::max(reported_, now);
}

void CoupledSolver::change_active_sets()
{
  const Index count = static_cast<Index>(violators_.size());
  bool block = true;
  if (count < best_violators_)
  {
    best_violators_ = count;
    attempts_left_ = box_.block_attempts;
  }
  else if (attempts_left_ > 0)
    --attempts_left_;
  else
    block = false;
  if (block)
  {
    const States before = state_;
    for (const auto& [i, j] : violators_)
      flip(i, j);
    repair();
    if (visited_.count(state_hash()) != 0)
    {
      state_ = before;
      block = false;
    }
  }
  if (!block)
  {
    // The violator with the largest index (handle-major).
    auto last = violators_.front();
    for (const auto& v : violators_)
      if (v.second > last.second || (v.second == last.second && v.first > last.first))
        last = v;
    flip(last.first, last.second);
    repair();
  }
}

void CoupledSolver::flip(Index i, Index j)
{
  BoxQPState& st = state_(i, j);
  if (st == BoxQPState::Free)
    st = X_(i, j) < 0.0 ? BoxQPState::Lower : BoxQPState::Upper;
  else
    st = BoxQPState::Free;
}

void CoupledSolver::repair()
{
  for (Index i = 0; i < n_; ++i)
  {
    if (known_[static_cast<std::size_t>(i)])
      continue;
    Index largest = 0;
    double sum = 0.0;
    bool any_free = false;
    for (Index j = 0; j < m_; ++j)
    {
      any_free = any_free || state_(i, j) == BoxQPState::Free;
      sum += state_(i, j) == BoxQPState::Upper ? 1.0 : 0.0;
      if (X_(i, j) > X_(i, largest))
        largest = j;
    }
    if (!any_free && sum != 1.0)
      state_(i, largest) = BoxQPState::Free;
  }
}

void CoupledSolver::clamp_and_certify()
{
  for (Index j = 0; j < m_; ++j)
    for (Index i = 0; i < n_; ++i)
      if (!known_[static_cast<std::size_t>(i)])
        X_(i, j) = std::clamp(X_(i, j), 0.0, 1.0);
  compute_gradients();
  double stationarity = 0.0, dual = 0.0, complementarity = 0.0, partition = 0.0;
  for (Index i = 0; i < n_; ++i)
  {
    if (known_[static_cast<std::size_t>(i)])
      continue;
    partition = std::max(partition, std::abs(X_.row(i).sum() - 1.0));
    for (Index j = 0; j < m_; ++j)
    {
      const double w = X_(i, j), lambda = Y_(i, j) + mu_(i);
      if (w == 0.0)
        dual = std::max(dual, -lambda / sy_);
      else if (w == 1.0)
        dual = std::max(dual, lambda / sy_);
      else
      {
        stationarity = std::max(stationarity, std::abs(lambda) / sy_);
        complementarity = std::max(complementarity, std::abs(lambda) * std::min(w, 1.0 - w) / sy_);
      }
    }
  }
  out_.kkt_residual = std::max({ stationarity, dual, complementarity });
  out_.partition_error = partition;
  out_.converged = out_.converged && out_.kkt_residual <= o_.tolerance;
  for (const FreeSetFactor& f : factors_)
  {
    out_.factorizations += f.factorizations;
    out_.modifications += f.modifications;
  }
}

/// The coupled problem (Eq. 8 subject to Eq. 3-6) by a primal-dual active-set method on all
/// handles at once, started from the active sets of @p start (the unconstrained biharmonic
/// weights). See BBWMode::Coupled for the method.
CoupledOutcome solve_coupled(const BoxConstrainedQP& qp, const BBWBoundaryConditions& bc,
  const Eigen::MatrixXd& start, const BBWOptions& o, const BoxQPOptions& box,
  ProgressReporter& reporter)
{
  return CoupledSolver(qp, bc, start, o, box, reporter).run();
}

[[noreturn]] void throw_not_converged(const std::string& what)
{
  throw Error(ErrorCode::NotConverged, "bounded biharmonic weights: " + what,
    "raise BBWOptions::max_iterations / max_outer_iterations, loosen the tolerances, or set "
    "BBWOptions::require_convergence = false to get the unconverged weights");
}

} // namespace

namespace
{

/// The unbounded biharmonic weights (BBWOptions::bounded = false): X0, the minimizer of Eq. 8
/// subject to Eq. 3-4 only, is the answer in both modes (see BBWOptions::bounded); @p result
/// gets it, its stationarity residual and the partition / bound measures.
BBWResult unbounded_result(BBWResult& result, const Eigen::MatrixXd& X0,
  const BBWBoundaryConditions& bc, const Eigen::SparseMatrix<double>& Q, const BBWOptions& o,
  Index cells, Clock::time_point start)
{
  const Index n = X0.rows(), m = X0.cols();
  Eigen::MatrixXd W = X0;
  result.iterations.assign(static_cast<std::size_t>(m), 0);
  result.factorizations.assign(static_cast<std::size_t>(m), 1);
  result.modifications.assign(static_cast<std::size_t>(m), 0);
  // Relative stationarity residual max |(Q W)_ij| over the unknown rows / max_i sum_j |Q_ij|.
  Eigen::MatrixXd R = Q * W;
  for (Index k = 0; k < bc.vertices.size(); ++k)
    R.row(bc.vertices(k)).setZero();
  double scale = 0.0;
  for (Index i = 0; i < Q.outerSize(); ++i)
  {
    double row = 0.0;
    for (Eigen::SparseMatrix<double>::InnerIterator it(Q, i); it; ++it)
      row += std::abs(it.value());
    scale = std::max(scale, row);
  }
  const double kkt = R.size() > 0 ? R.cwiseAbs().maxCoeff() / (scale > 0.0 ? scale : 1.0) : 0.0;
  result.kkt_residual.assign(static_cast<std::size_t>(m), kkt);
  result.max_kkt_residual = kkt;
  result.coupled_kkt_residual = o.mode == BBWMode::Coupled ? kkt : 0.0;
  result.converged = true;
  const Eigen::VectorXd sums = W.rowwise().sum();
  result.partition_error_before_normalization = (sums.array() - 1.0).abs().maxCoeff();
  if (o.normalize)
  {
    // The sums are 1 up to rounding (Q 1 = 0); dividing keeps the fixed rows as they are.
    W = sums.cwiseInverse().asDiagonal() * W;
    for (Index k = 0; k < bc.vertices.size(); ++k)
      W.row(bc.vertices(k)) = bc.values.row(k);
  }
  result.partition_error = (W.rowwise().sum().array() - 1.0).abs().maxCoeff();
  result.max_bound_violation = std::max({ 0.0, -W.minCoeff(), W.maxCoeff() - 1.0 });
  result.W = W;
  result.seconds = seconds_since(start);
  fill_statistics(result, n, cells, m);
  return result;
}

} // namespace

BBWBoundaryConditions bbw_boundary_conditions(const BBWHandles& handles, Index vertex_count)
{
  if (handles.extra_handles < 0)
    throw Error(ErrorCode::InvalidArgument,
      "BBWHandles::extra_handles must be >= 0, got " + std::to_string(handles.extra_handles));
  const Index np = handles.point_vertex.size();
  const Index nb = static_cast<Index>(handles.bone_vertices.size());
  const Index m = handles.handle_count();
  if (m == 0)
    throw Error(ErrorCode::EmptyInput,
      "no handles: give point handles, bones, or explicit rows (extra_handles > 0)");
  auto check_vertex = [vertex_count](int v, const std::string& owner) {
    if (v < 0 || v >= vertex_count)
      throw Error(ErrorCode::InvalidArgument,
        owner + " refers to vertex " + std::to_string(v) + ", outside [0, " +
          std::to_string(vertex_count) + ")");
  };

  // Handles of every point / bone vertex.
  std::vector<std::vector<Index>> members(static_cast<std::size_t>(vertex_count));
  auto add = [&](int v, Index h) {
    auto& list = members[static_cast<std::size_t>(v)];
    if (std::find(list.begin(), list.end(), h) == list.end())
      list.push_back(h);
  };
  for (Index p = 0; p < np; ++p)
  {
    check_vertex(handles.point_vertex(p), "point handle " + std::to_string(p));
    add(handles.point_vertex(p), p);
  }
  for (Index b = 0; b < nb; ++b)
  {
    const auto& bone = handles.bone_vertices[static_cast<std::size_t>(b)];
    if (bone.empty())
      throw Error(ErrorCode::InvalidArgument,
        "bone " + std::to_string(b) + " has no mesh vertex; sample it into the mesh (e.g. with "
        "handles_from_skeleton on a mesh that contains points along the bone)");
    for (const int v : bone)
    {
      check_vertex(v, "bone " + std::to_string(b));
      add(v, np + b);
    }
  }

  const Index nf = handles.fixed_vertices.size();
  if (handles.fixed_values.rows() != nf || (nf > 0 && handles.fixed_values.cols() != m))
    throw Error(ErrorCode::SizeMismatch,
      "BBWHandles::fixed_values is " + std::to_string(handles.fixed_values.rows()) + " by " +
        std::to_string(handles.fixed_values.cols()) + ", expected #fixed_vertices (" +
        std::to_string(nf) + ") by the number of handles (" + std::to_string(m) + " = " +
        std::to_string(np) + " points + " + std::to_string(nb) + " bones + " +
        std::to_string(handles.extra_handles) + " extra)");
  std::vector<Index> explicit_row(static_cast<std::size_t>(vertex_count), -1);
  for (Index f = 0; f < nf; ++f)
  {
    const int v = handles.fixed_vertices(f);
    check_vertex(v, "fixed_vertices(" + std::to_string(f) + ")");
    if (!members[static_cast<std::size_t>(v)].empty())
      throw Error(ErrorCode::InvalidArgument,
        "vertex " + std::to_string(v) + " is both in fixed_vertices and a point/bone vertex of "
        "handle " + std::to_string(members[static_cast<std::size_t>(v)].front()) +
        "; give it one explicit row instead");
    if (explicit_row[static_cast<std::size_t>(v)] >= 0)
      throw Error(ErrorCode::InvalidArgument,
        "vertex " + std::to_string(v) + " is listed twice in fixed_vertices (at " +
          std::to_string(explicit_row[static_cast<std::size_t>(v)]) + " and " +
          std::to_string(f) + ")");
    explicit_row[static_cast<std::size_t>(v)] = f;
    double sum = 0.0;
    for (Index j = 0; j < m; ++j)
    {
      const double w = handles.fixed_values(f, j);
      if (!std::isfinite(w))
        throw Error(ErrorCode::NonFinite,
          "fixed_values(" + std::to_string(f) + ", " + std::to_string(j) + ") is not finite");
      if (w < 0.0 || w > 1.0)
        throw Error(ErrorCode::InvalidArgument,
          "fixed_values(" + std::to_string(f) + ", " + std::to_string(j) + ") = " + detail::format_number(w) +
            " is outside [0, 1] (Eq. 6 bounds every weight)");
      sum += w;
    }
    if (std::abs(sum - 1.0) > 1e-9)
      throw Error(ErrorCode::InvalidArgument,
        "the fixed values of vertex " + std::to_string(v) + " (fixed_values row " +
          std::to_string(f) + ") sum to " + detail::format_number(sum) +
          ", not 1: partition of unity (Eq. 5) needs every fixed row to sum to 1");
  }

  BBWBoundaryConditions bc;
  std::vector<int> known;
  for (Index v = 0; v < vertex_count; ++v)
    if (!members[static_cast<std::size_t>(v)].empty() || explicit_row[static_cast<std::size_t>(v)] >= 0)
      known.push_back(static_cast<int>(v));
  bc.vertices = Eigen::Map<const Eigen::VectorXi>(known.data(), static_cast<Index>(known.size()));
  bc.values = Eigen::MatrixXd::Zero(static_cast<Index>(known.size()), m);
  for (Index k = 0; k < bc.vertices.size(); ++k)
  {
    const int v = bc.vertices(k);
    const auto& list = members[static_cast<std::size_t>(v)];
    if (!list.empty())
      for (const Index h : list)
        bc.values(k, h) = 1.0 / static_cast<double>(list.size());
    else
      bc.values.row(k) = handles.fixed_values.row(explicit_row[static_cast<std::size_t>(v)]);
  }
  for (Index j = 0; j < m; ++j)
    if (!(bc.values.rows() > 0 && bc.values.col(j).maxCoeff() > 0.0))
      throw Error(ErrorCode::InvalidArgument,
        "handle " + std::to_string(j) + " is fixed to a positive value at no vertex; its "
        "weights would vanish. Give every handle at least one vertex where its weight is > 0");
  return bc;
}

BBWHandles handles_from_skeleton(const Eigen::MatrixXd& V, const Eigen::MatrixXd& C,
  const Eigen::VectorXi& P, const Eigen::MatrixXi& BE, double tolerance)
{
  if (C.cols() != V.cols())
    throw Error(ErrorCode::SizeMismatch,
      "the joints are " + std::to_string(C.cols()) + "D but the mesh vertices are " +
        std::to_string(V.cols()) + "D");
  if (BE.rows() > 0 && BE.cols() != 2)
    throw Error(ErrorCode::SizeMismatch,
      "the bones must be #B by 2 (pairs of joint indices), got " + std::to_string(BE.rows()) +
        " by " + std::to_string(BE.cols()));
  if (V.rows() == 0)
    throw Error(ErrorCode::EmptyInput, "the mesh has no vertices");
  if (!(tolerance > 0.0))
  {
    const double diagonal = (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm();
    tolerance = 1e-6 * (diagonal > 0.0 ? diagonal : 1.0);
  }
  auto joint = [&](Index j, const std::string& owner) -> Eigen::VectorXd {
    if (j < 0 || j >= C.rows())
      throw Error(ErrorCode::InvalidArgument,
        owner + " refers to joint " + std::to_string(j) + ", outside [0, " +
          std::to_string(C.rows()) + ")");
    return C.row(j).transpose();
  };

  BBWHandles handles;
  handles.point_vertex.resize(P.size());
  for (Index p = 0; p < P.size(); ++p)
  {
    const Eigen::VectorXd c = joint(P(p), "point handle " + std::to_string(p));
    Index nearest = 0;
    const double distance = std::sqrt((V.rowwise() - c.transpose()).rowwise().squaredNorm().minCoeff(&nearest));
    if (distance > tolerance)
      throw Error(ErrorCode::InvalidArgument,
        "point handle " + std::to_string(p) + " (joint " + std::to_string(P(p)) +
          ") is at distance " + detail::format_number(distance) + " from the nearest mesh vertex, more than the "
          "tolerance " + detail::format_number(tolerance),
        "make the handle a vertex of the mesh");
    handles.point_vertex(p) = static_cast<int>(nearest);
  }
  for (Index b = 0; b < BE.rows(); ++b)
  {
    const std::string owner = "bone " + std::to_string(b);
    const Eigen::VectorXd a = joint(BE(b, 0), owner), e = joint(BE(b, 1), owner);
    const Eigen::VectorXd d = e - a;
    const double length2 = d.squaredNorm();
    std::vector<int> samples;
    for (Index i = 0; i < V.rows(); ++i)
    {
      const Eigen::VectorXd v = V.row(i).transpose() - a;
      const double t = length2 > 0.0 ? std::clamp(v.dot(d) / length2, 0.0, 1.0) : 0.0;
      if ((v - t * d).norm() <= tolerance)
        samples.push_back(static_cast<int>(i));
    }
    if (samples.empty())
      throw Error(ErrorCode::InvalidArgument,
        owner + " (joints " + std::to_string(BE(b, 0)) + " - " + std::to_string(BE(b, 1)) +
          ") has no mesh vertex within " + detail::format_number(tolerance),
        "mesh the domain with the bone sampled (its joints and points along it as vertices)");
    handles.bone_vertices.push_back(std::move(samples));
  }
  return handles;
}

WeightDifference weight_difference(const DenseWeights& a, const DenseWeights& b)
{
  if (a.rows() != b.rows() || a.cols() != b.cols())
    throw Error(ErrorCode::SizeMismatch,
      "cannot compare weights of shapes " + std::to_string(a.rows()) + " by " +
        std::to_string(a.cols()) + " and " + std::to_string(b.rows()) + " by " +
        std::to_string(b.cols()));
  if (a.size() == 0)
    throw Error(ErrorCode::EmptyInput, "cannot compare empty weight matrices");
  const DenseWeights d = (a - b).cwiseAbs();
  return { d.mean(), d.maxCoeff() };
}

BoundedBiharmonicWeights::BoundedBiharmonicWeights(
  const Eigen::MatrixXd& V, const Eigen::MatrixXi& T, const BBWOptions& options)
  : options_(options)
{
  const auto start = Clock::now();
  validate_options(options_);
  const SparseMatrix K = stiffness_matrix(V, T); // validates the mesh
  const SparseMatrix M = mass_matrix(V, T,
    options_.mass_lumping == BBWMassLumping::Voronoi ? MassMatrixType::Voronoi
                                                      : MassMatrixType::Barycentric);
  const Index n = V.rows();
  Eigen::VectorXd inverse_mass(n);
  for (Index i = 0; i < n; ++i)
  {
    const double mi = M.coeff(i, i);
    if (!(mi > 0.0))
      throw Error(ErrorCode::InvalidArgument,
        "vertex " + std::to_string(i) + " belongs to no element; remove unreferenced "
        "vertices from the mesh (their weights are undefined)");
    inverse_mass(i) = 1.0 / mi;
  }
  SparseMatrix Q = K * inverse_mass.asDiagonal() * K;

  const Eigen::VectorXd& rho = options_.shape_preservation;
  if (rho.size() != 0)
  {
    if (rho.size() != T.rows())
      throw Error(ErrorCode::SizeMismatch,
        "BBWOptions::shape_preservation has " + std::to_string(rho.size()) +
          " entries, expected one per element (" + std::to_string(T.rows()) + ")");
    for (Index t = 0; t < rho.size(); ++t)
      if (!std::isfinite(rho(t)) || rho(t) < 0.0)
        throw Error(std::isfinite(rho(t)) ? ErrorCode::InvalidArgument : ErrorCode::NonFinite,
          "BBWOptions::shape_preservation(" + std::to_string(t) + ") = " + detail::format_number(rho(t)) +
            " must be finite and >= 0");
    // Eq. 9: G^T diag(rho_t vol_t, repeated dim times) G, the rho-weighted stiffness matrix.
    const SparseMatrix G = gradient_operator(V, T);
    const Eigen::VectorXd volume = simplex_volumes(V, T);
    const Index dim = V.cols();
    Eigen::VectorXd weight(T.rows() * dim);
    for (Index t = 0; t < T.rows(); ++t)
      weight.segment(t * dim, dim).setConstant(rho(t) * volume(t));
    Q += SparseMatrix(G.transpose() * weight.asDiagonal() * G);
  }
  Q = 0.5 * (Q + SparseMatrix(Q.transpose())); // exactly symmetric
  Q.prune(0.0);
  Q.makeCompressed();
  Q_ = std::move(Q);
  component_ = connected_components(n, T);
  cell_count_ = T.rows();
  operator_seconds_ = seconds_since(start);
}

BBWResult BoundedBiharmonicWeights::compute(
  const BBWHandles& handles, const ProgressCallback& progress) const
{
  const auto start = Clock::now();
  const BBWOptions& o = options_;
  const Index n = Q_.rows();
  const BBWBoundaryConditions bc = bbw_boundary_conditions(handles, n);
  const Index m = handles.handle_count();
  const Index nk = bc.vertices.size();

  // Every connected component needs a fixed vertex, or Q is singular on it.
  {
    std::vector<char> anchored(static_cast<std::size_t>(n), 0);
    for (Index k = 0; k < nk; ++k)
      anchored[static_cast<std::size_t>(component_(bc.vertices(k)))] = 1;
    for (Index i = 0; i < n; ++i)
      if (!anchored[static_cast<std::size_t>(component_(i))])
        throw Error(ErrorCode::InvalidArgument,
          "the connected component of the mesh that contains vertex " + std::to_string(i) +
            " holds no handle, so its weights are undefined; add a handle there or remove it");
  }

  BBWResult result;
  result.mode = o.mode;
  result.fixed_vertices = nk;
  result.operator_seconds = operator_seconds_;
  const bool coupled = o.mode == BBWMode::Coupled;
  // The per-handle QPs: the fast mode's solve, in the coupled mode only for the comparison.
  const bool fast_phase = !coupled || o.compare_with_fast;
  const double fast_end = !fast_phase ? 0.1 : coupled ? 0.4 : 1.0;

  // 1. The unconstrained biharmonic weights (one factorization for all handles): the start of
  //    every handle's active set.
  auto phase_start = Clock::now();
  ProgressReporter setup_reporter(progress, 1, 0.0, 0.1);
  MinQuadWithFixed unconstrained;
  unconstrained.precompute(Q_, bc.vertices, o.backend);
  const Eigen::MatrixXd X0 = unconstrained.solve(Eigen::MatrixXd(), bc.values);
  result.unconstrained_seconds = seconds_since(phase_start);
  if (!setup_reporter.step())
    setup_reporter.throw_if_cancelled("bounded biharmonic weights");
  if (!o.bounded)
    return unbounded_result(result, X0, bc, Q_, o, cell_count_, start);

  // 2. Fast (or the coupled mode's comparison): each handle's bound-constrained QP.
  phase_start = Clock::now();
  const BoxConstrainedQP qp(Q_);
  Eigen::VectorXd lower = Eigen::VectorXd::Zero(n), upper = Eigen::VectorXd::Ones(n);
  Eigen::MatrixXd W(n, m); // column-major: one handle per column
  result.converged = true;
  if (fast_phase)
  {
    result.iterations.assign(static_cast<std::size_t>(m), 0);
    result.factorizations.assign(static_cast<std::size_t>(m), 0);
    result.modifications.assign(static_cast<std::size_t>(m), 0);
    result.kkt_residual.assign(static_cast<std::size_t>(m), 0.0);
    std::vector<char> handle_converged(static_cast<std::size_t>(m), 0);
    {
      ProgressReporter reporter(progress, m, 0.1, fast_end);
      const BoxQPOptions box = qp_options(o, reporter);
      // Handle j's QP: [0, 1] bounds, its fixed rows, started from the active set of its
      // unconstrained weights; written into column j only.
      auto solve_handle = [&](Index j) {
        Eigen::VectorXd l = lower, u = upper;
        for (Index k = 0; k < nk; ++k)
          l(bc.vertices(k)) = u(bc.vertices(k)) = bc.values(k, j);
        BoxQPWarmStart warm;
        warm.state = active_set_from_guess(X0.col(j), l, u);
        const BoxQPResult r = qp.solve(Eigen::VectorXd::Zero(n), l, u, box, &warm);
        const auto jj = static_cast<std::size_t>(j);
        W.col(j) = r.x;
        result.iterations[jj] = r.iterations;
        result.factorizations[jj] = r.factorizations;
        result.modifications[jj] = r.modifications;
        result.kkt_residual[jj] = r.kkt_residual;
        handle_converged[jj] = r.converged;
      };
      // One handle per chunk (detail/parallel_for.h). Every handle is solved by the same
      // sequential code into its own column, so the weights do not depend on the number of
      // threads.
      detail::parallel_for(m, 1, o.threads, reporter, "bounded biharmonic weights",
        [&](Index begin, Index end) {
          for (Index j = begin; j < end; ++j)
            solve_handle(j);
        });
    }
    result.fast_seconds = seconds_since(phase_start);
    for (Index j = 0; j < m; ++j)
    {
      result.max_kkt_residual =
        std::max(result.max_kkt_residual, result.kkt_residual[static_cast<std::size_t>(j)]);
      if (!handle_converged[static_cast<std::size_t>(j)])
      {
        result.converged = false;
        if (o.require_convergence)
          throw_not_converged("the QP of handle " + std::to_string(j) + " did not converge in " +
            std::to_string(result.iterations[static_cast<std::size_t>(j)]) +
            " active-set iterations (KKT residual " +
            detail::format_number(result.kkt_residual[static_cast<std::size_t>(j)]) + ", tolerance " +
            detail::format_number(o.tolerance) + ")");
      }
    }
  }

  auto row_sums = [&](const Eigen::MatrixXd& X) { return Eigen::VectorXd(X.rowwise().sum()); };
  // Rows divided by their sums. A zero row throws, or becomes uniform for the coupled mode's
  // comparison.
  auto normalized = [&](const Eigen::MatrixXd& X, bool zero_rows_uniform = false) {
    Eigen::VectorXd s = row_sums(X);
    Eigen::MatrixXd Y = X;
    for (Index i = 0; i < n; ++i)
      if (!(s(i) > 0.0) && zero_rows_uniform)
      {
        Y.row(i).setConstant(1.0);
        s(i) = static_cast<double>(m);
      }
      else if (!(s(i) > 0.0))
        throw Error(ErrorCode::InvalidArgument,
          "vertex " + std::to_string(i) + " gets weight 0 from every handle when the handles "
          "are solved independently (fast mode), so its weights cannot be normalized",
          "use BBWMode::Coupled, which enforces partition of unity");
    Y = s.cwiseInverse().asDiagonal() * Y;
    for (Index k = 0; k < nk; ++k) // keep fixed rows exact
      Y.row(bc.vertices(k)) = bc.values.row(k);
    return Y;
  };

  // 3. Coupled: the active-set method on the coupled problem (see BBWMode::Coupled).
  if (coupled)
  {
    phase_start = Clock::now();
    ProgressReporter reporter(progress, 1000, fast_end, 1.0);
    const BoxQPOptions box = qp_options(o, reporter);
    Eigen::MatrixXd unconstrained_start = X0;
    for (Index k = 0; k < nk; ++k) // the fixed rows exactly
      unconstrained_start.row(bc.vertices(k)) = bc.values.row(k);
    const CoupledOutcome outcome = solve_coupled(qp, bc, unconstrained_start, o, box, reporter);
    // The fast weights of the comparison (compare_with_fast), normalized.
    const Eigen::MatrixXd W_fast = fast_phase ? normalized(W, true) : Eigen::MatrixXd();
    reporter.finish();
    reporter.throw_if_cancelled("bounded biharmonic weights (coupled)");
    W = outcome.W;
    result.outer_iterations = outcome.iterations;
    result.coupled_iterations = outcome.cg_iterations;
    result.coupled_factorizations = outcome.factorizations;
    result.coupled_modifications = outcome.modifications;
    result.coupled_kkt_residual = outcome.kkt_residual;
    result.max_kkt_residual = outcome.kkt_residual;
    result.coupled_seconds = seconds_since(phase_start);
    if (!outcome.converged)
    {
      result.converged = false;
      if (o.require_convergence)
        throw_not_converged("the coupled solver did not converge in " +
          std::to_string(outcome.iterations) + " active-set iterations (KKT residual " +
          detail::format_number(outcome.kkt_residual) + ", partition error " + detail::format_number(outcome.partition_error) +
          ", " + std::to_string(outcome.violators) + " violators left)");
    }
    result.W = W;
    if (o.normalize)
      W = normalized(W);
    if (fast_phase)
    {
      const WeightDifference d = weight_difference(DenseWeights(W_fast), DenseWeights(W));
      result.fast_difference_mean = d.mean;
      result.fast_difference_max = d.max;
    }
  }

  // 4. Partition of unity before and after normalizing; bounds.
  result.partition_error_before_normalization =
    (row_sums(coupled ? Eigen::MatrixXd(result.W) : W) - Eigen::VectorXd::Ones(n))
      .cwiseAbs()
      .maxCoeff();
  if (o.normalize && !coupled)
    W = normalized(W);
  result.partition_error = (row_sums(W) - Eigen::VectorXd::Ones(n)).cwiseAbs().maxCoeff();
  result.max_bound_violation = std::max({ 0.0, -W.minCoeff(), W.maxCoeff() - 1.0 });
  result.W = W;
  result.seconds = seconds_since(start);
  fill_statistics(result, n, cell_count_, m);
  return result;
}

BBWResult bounded_biharmonic_weights(const Eigen::MatrixXd& V, const Eigen::MatrixXi& T,
  const BBWHandles& handles, const BBWOptions& options, const ProgressCallback& progress)
{
  return BoundedBiharmonicWeights(V, T, options).compute(handles, progress);
}

} // namespace bary
