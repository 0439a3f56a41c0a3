#include "core/solvers/box_constrained_qp.h"

#include "core/detail/format.h"
#include "core/common/error.h"
#include "core/detail/timing.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>
#include <unordered_set>
#include <utility>
#include <vector>

namespace bary
{
namespace
{

using SparseMatrix = Eigen::SparseMatrix<double>;
using Clock = std::chrono::steady_clock;
using StateVector = Eigen::Matrix<BoxQPState, Eigen::Dynamic, 1>;

std::uint64_t next_id()
{
  static std::atomic<std::uint64_t> counter{ 0 };
  return ++counter;
}

/// FNV-1a hash of an active set (a collision only costs one unnecessary single step).
std::uint64_t state_hash(const StateVector& state)
{
  std::uint64_t h = 14695981039346656037ull;
  for (Index i = 0; i < state.size(); ++i)
  {
    h ^= static_cast<std::uint64_t>(static_cast<unsigned char>(state(i)));
    h *= 1099511628211ull;
  }
  return h;
}

} // namespace

StateVector active_set_from_guess(
  const Eigen::VectorXd& x0, const Eigen::VectorXd& l, const Eigen::VectorXd& u)
{
  if (x0.size() != l.size() || x0.size() != u.size())
    throw Error(ErrorCode::SizeMismatch,
      "the guess has " + std::to_string(x0.size()) + " entries but the bounds have " +
        std::to_string(l.size()) + " and " + std::to_string(u.size()));
  StateVector state(x0.size());
  for (Index i = 0; i < x0.size(); ++i)
  {
    if (l(i) == u(i))
      state(i) = BoxQPState::Fixed;
    else if (x0(i) <= l(i))
      state(i) = BoxQPState::Lower;
    else if (x0(i) >= u(i))
      state(i) = BoxQPState::Upper;
    else
      state(i) = BoxQPState::Free;
  }
  return state;
}

BoxConstrainedQP::BoxConstrainedQP(const SparseMatrix& A)
{
  precompute(A);
}

void BoxConstrainedQP::precompute(const SparseMatrix& A)
{
  A_ = SparseMatrix();
  id_ = 0;
  if (A.rows() != A.cols())
    throw Error(ErrorCode::SizeMismatch,
      "the quadratic term A must be square, got " + std::to_string(A.rows()) + " by " +
        std::to_string(A.cols()));
  const Index n = A.rows();
  if (n == 0)
    throw Error(ErrorCode::EmptyInput, "the quadratic term A is empty (0 by 0)");
  Eigen::VectorXd diagonal = Eigen::VectorXd::Zero(n);
  for (Index j = 0; j < A.outerSize(); ++j)
    for (SparseMatrix::InnerIterator it(A, j); it; ++it)
    {
      if (!std::isfinite(it.value()))
        throw Error(ErrorCode::NonFinite,
          "the quadratic term A has a non-finite entry at (" + std::to_string(it.row()) + ", " +
            std::to_string(it.col()) + ")");
      if (it.row() == it.col())
        diagonal(it.row()) += it.value();
    }
  for (Index i = 0; i < n; ++i)
    if (!(diagonal(i) > 0.0))
      throw Error(ErrorCode::InvalidArgument,
        "the quadratic term A is not positive definite: its diagonal entry (" +
          std::to_string(i) + ", " + std::to_string(i) + ") is " + detail::format_number(diagonal(i)) +
          ", not > 0; a convex QP needs A symmetric positive definite");
  SparseMatrix stored = A;
  stored.makeCompressed();
  const SparseMatrix asymmetry = stored - SparseMatrix(stored.transpose());
  for (Index j = 0; j < asymmetry.outerSize(); ++j)
    for (SparseMatrix::InnerIterator it(asymmetry, j); it; ++it)
      if (std::abs(it.value()) > 1e-10 * std::sqrt(diagonal(it.row()) * diagonal(it.col())))
        throw Error(ErrorCode::InvalidArgument,
          "the quadratic term A is not symmetric: entries (" + std::to_string(it.row()) + ", " +
            std::to_string(it.col()) + ") and (" + std::to_string(it.col()) + ", " +
            std::to_string(it.row()) + ") differ by " + detail::format_number(it.value()) +
            "; store both triangles of a symmetric matrix");
  // One fill-reducing ordering of A (AMD); the factorizations of the free blocks use its
  // restriction to the free set instead of ordering every block anew.
  ordering_ = fill_reducing_ordering(stored, FillReducingOrdering::Amd);
  A_ = std::move(stored);
  id_ = next_id();
}

BoxQPResult BoxConstrainedQP::solve(const Eigen::VectorXd& b, const Eigen::VectorXd& l,
  const Eigen::VectorXd& u, const BoxQPOptions& options, BoxQPWarmStart* warm) const
{
  const auto start = Clock::now();
  if (id_ == 0)
    throw Error(ErrorCode::InvalidArgument, "BoxConstrainedQP::solve called before precompute()");
  const Index n = A_.rows();
  auto check_size = [n](const Eigen::VectorXd& v, const char* name) {
    if (v.size() != n)
      throw Error(ErrorCode::SizeMismatch,
        std::string("the ") + name + " has " + std::to_string(v.size()) +
          " entries, expected " + std::to_string(n) + " (one per row of A)");
  };
  check_size(b, "linear term b");
  check_size(l, "lower bound l");
  check_size(u, "upper bound u");
  if (!b.allFinite())
    throw Error(ErrorCode::NonFinite, "the linear term b contains NaN or infinity");
  for (Index i = 0; i < n; ++i)
  {
    if (std::isnan(l(i)) || std::isnan(u(i)))
      throw Error(ErrorCode::NonFinite,
        "the bounds of variable " + std::to_string(i) + " contain NaN; use -inf / +inf for a "
        "missing bound");
    if (l(i) > u(i))
      throw Error(ErrorCode::InvalidArgument,
        "the bounds of variable " + std::to_string(i) + " are empty: l = " + detail::format_number(l(i)) +
          " > u = " + detail::format_number(u(i)) + "; the problem is infeasible");
    if (l(i) == u(i) && !std::isfinite(l(i)))
      throw Error(ErrorCode::InvalidArgument,
        "variable " + std::to_string(i) + " is fixed at an infinite value (l = u = " +
          detail::format_number(l(i)) + ")");
  }
  if (!(options.tolerance > 0.0 && options.tolerance < 1.0))
    throw Error(ErrorCode::InvalidArgument,
      "BoxQPOptions::tolerance must be in (0, 1), got " + detail::format_number(options.tolerance));
  if (options.max_iterations < 1)
    throw Error(ErrorCode::InvalidArgument,
      "BoxQPOptions::max_iterations must be >= 1, got " + std::to_string(options.max_iterations));
  if (!(options.gradient_scale >= 0.0 && std::isfinite(options.gradient_scale)))
    throw Error(ErrorCode::InvalidArgument,
      "BoxQPOptions::gradient_scale must be finite and >= 0, got " + detail::format_number(options.gradient_scale));
  if (options.block_attempts < 0)
    throw Error(ErrorCode::InvalidArgument,
      "BoxQPOptions::block_attempts must be >= 0, got " + std::to_string(options.block_attempts));

  // Initial active set, made consistent with the bounds.
  StateVector state = StateVector::Constant(n, BoxQPState::Free);
  if (warm && warm->state.size() != 0)
  {
    if (warm->state.size() != n)
      throw Error(ErrorCode::SizeMismatch,
        "the warm start's active set has " + std::to_string(warm->state.size()) +
          " entries, expected " + std::to_string(n));
    state = warm->state;
  }
  for (Index i = 0; i < n; ++i)
  {
    BoxQPState& s = state(i);
    if (l(i) == u(i))
      s = BoxQPState::Fixed;
    else if (s == BoxQPState::Fixed || (s == BoxQPState::Lower && !std::isfinite(l(i))) ||
      (s == BoxQPState::Upper && !std::isfinite(u(i))))
      s = BoxQPState::Free;
  }

  FreeSetFactor factor(*this, options);
  if (warm && warm->owner == id_ && warm->factor.computed() &&
    warm->factor.backend() == factor.factor().backend() &&
    warm->factor.rows() == warm->factor_free.size())
    factor.adopt(warm->factor,
      std::vector<int>(warm->factor_free.data(), warm->factor_free.data() + warm->factor_free.size()));

  BoxQPResult result;
  Eigen::VectorXd x = Eigen::VectorXd::Zero(n), y(n), r(n), magnitude(n);
  std::vector<int> free;
  std::vector<int> slot(static_cast<std::size_t>(n), -1); // a free row's place in the factor
  std::vector<Index> violators;
  const double half_tolerance = 0.5 * options.tolerance;

  // Scales of x and of the gradient's terms (see the header).
  auto scale_x = [&]() {
    double s = 1.0;
    for (Index i = 0; i < n; ++i)
      if (std::isfinite(x(i)))
        s = std::max(s, std::abs(x(i)));
    return s;
  };
  // The gradient y = A x + b and the scale s_y of its terms, in one pass over the columns of
  // the nonzero x_j.
  auto gradient_and_scale = [&]() {
    y = b;
    const bool computed = options.gradient_scale <= 0.0;
    if (computed)
      magnitude.setZero();
    for (Index j = 0; j < A_.outerSize(); ++j)
    {
      const double xj = x(j);
      if (xj == 0.0)
        continue;
      const double axj = std::abs(xj);
      if (computed)
        for (SparseMatrix::InnerIterator it(A_, j); it; ++it)
        {
          y(it.row()) += it.value() * xj;
          magnitude(it.row()) += std::abs(it.value()) * axj;
        }
      else
        for (SparseMatrix::InnerIterator it(A_, j); it; ++it)
          y(it.row()) += it.value() * xj;
    }
    if (!computed)
      return options.gradient_scale;
    const double s = std::max(b.cwiseAbs().maxCoeff(), magnitude.maxCoeff());
    return s > 0.0 ? s : 1.0;
  };

  std::unordered_set<std::uint64_t> visited; // hashes of the active sets solved so far
  StateVector solved = state;                  // the active set x was computed with
  Index best_violators = std::numeric_limits<Index>::max();
  int attempts_left = options.block_attempts;
  bool settled = false;
  int polishes_left = 3; // see "Polish" below
  while (result.iterations < options.max_iterations)
  {
    if (options.keep_going && !options.keep_going())
      throw Error(ErrorCode::Cancelled, "the bound-constrained QP solve was cancelled");
    ++result.iterations;
    visited.insert(state_hash(state));
    solved = state; // the active set of this iteration's x

    // 1. Active variables on their bounds, then the equality-constrained solve on the free set.
    free.clear();
    for (Index i = 0; i < n; ++i)
    {
      switch (state(i))
      {
        case BoxQPState::Lower: x(i) = l(i); break;
        case BoxQPState::Upper: x(i) = u(i); break;
        case BoxQPState::Fixed: x(i) = l(i); break;
        case BoxQPState::Free:
          free.push_back(static_cast<int>(i));
          x(i) = 0.0;
          continue;
      }
    }
    if (!free.empty())
    {
      try
      {
        factor.update(free);
      }
      catch (const Error& e)
      {
        if (e.code() != ErrorCode::InvalidArgument)
          throw;
        throw Error(ErrorCode::InvalidArgument,
          "the quadratic term A restricted to the " + std::to_string(free.size()) +
            " free variables of active-set iteration " + std::to_string(result.iterations) +
            " cannot be factored (" + e.what() +
            "); A must be symmetric positive definite on the variables that are not fixed, "
            "otherwise the problem may be unbounded below");
      }
      const std::vector<int>& factor_rows = factor.rows();
      // x_F solves A_FF x_F = -(b_F + A_FN x_N), x_F = 0 meanwhile; rows in the factor's order.
      const Index nf = static_cast<Index>(factor_rows.size());
      // Only the columns of the nonzero x_N contribute (for BBW: the fixed rows and the upper
      // bounds, a few hundred columns), so A_FN x_N is scattered from them rather than
      // gathered along every free row; columns in increasing order add each row's terms in
      // the order of its own column (A symmetric).
      Eigen::VectorXd rhs(nf);
      for (Index k = 0; k < nf; ++k)
      {
        const int i = factor_rows[static_cast<std::size_t>(k)];
        slot[static_cast<std::size_t>(i)] = static_cast<int>(k);
        rhs(k) = b(i);
      }
      for (Index j = 0; j < n; ++j)
      {
        const double xj = x(j); // 0 on the free set
        if (xj == 0.0)
          continue;
        for (SparseMatrix::InnerIterator it(A_, j); it; ++it)
        {
          const int k = slot[static_cast<std::size_t>(it.row())];
          if (k >= 0)
            rhs(k) += it.value() * xj;
        }
      }
      for (Index k = 0; k < nf; ++k)
      {
        slot[static_cast<std::size_t>(factor_rows[static_cast<std::size_t>(k)])] = -1;
        rhs(k) = -rhs(k);
      }
      const Eigen::VectorXd x_free = factor.solve(rhs);
      for (Index k = 0; k < nf; ++k)
        x(factor_rows[static_cast<std::size_t>(k)]) = x_free(k);
    }
    const double sy_iteration = gradient_and_scale();

    // 2. Violators beyond half the tolerance.
    const double tx = half_tolerance * scale_x();
    const double ty = half_tolerance * sy_iteration;
    violators.clear();
    for (Index i = 0; i < n; ++i)
    {
      switch (state(i))
      {
        case BoxQPState::Free:
          if (x(i) < l(i) - tx || x(i) > u(i) + tx)
            violators.push_back(i);
          break;
        case BoxQPState::Lower:
          if (y(i) < -ty)
            violators.push_back(i);
          break;
        case BoxQPState::Upper:
          if (y(i) > ty)
            violators.push_back(i);
          break;
        case BoxQPState::Fixed: break;
      }
    }
    result.violators = static_cast<Index>(violators.size());
    if (violators.empty() && factor.modified_rows() > 0)
    {
      // The solve used a modified factor: make sure rounding did not build up beyond what the
      // KKT test can absorb (stationarity on the free set far below the tolerance), else solve
      // this active set again with a fresh factorization.
      double stationarity = 0.0;
      for (const int i : free)
        stationarity = std::max(stationarity, std::abs(y(i)));
      if (stationarity > 0.25 * ty)
      {
        factor.force_refactor();
        continue;
      }
    }
    if (violators.empty() && polishes_left > 0)
    {
      // Polish: free variables just outside their bounds (within the primal threshold) are
      // clamped for the certificate below, which moves the gradient of their neighbours; where
      // A has large entries (e.g. a Voronoi-lumped bi-Laplacian with small vertex masses) that
      // can push a multiplier past the tolerance. If the clamped point would not certify, put
      // those variables on their bounds and solve once more (at most max_polishes times).
      std::vector<Index> outside;
      for (const int i : free)
        if (x(i) < l(i) || x(i) > u(i))
          outside.push_back(i);
      if (!outside.empty())
      {
        const Eigen::VectorXd unclamped = x;
        for (const Index i : outside)
          x(i) = std::min(u(i), std::max(l(i), x(i)));
        const double sy_clamped = gradient_and_scale();
        double worst = 0.0;
        for (Index i = 0; i < n; ++i)
        {
          if (state(i) == BoxQPState::Fixed)
            continue;
          if (x(i) == l(i))
            worst = std::max(worst, -y(i) / sy_clamped);
          else if (x(i) == u(i))
            worst = std::max(worst, y(i) / sy_clamped);
          else
            worst = std::max(worst, std::abs(y(i)) / sy_clamped);
        }
        x = unclamped;
        gradient_and_scale();
        if (worst > options.tolerance)
        {
          for (const Index i : outside)
            state(i) = x(i) < l(i) ? BoxQPState::Lower : BoxQPState::Upper;
          if (visited.count(state_hash(state)) == 0)
          {
            --polishes_left;
            continue;
          }
          for (const Index i : outside)
            state(i) = BoxQPState::Free;
        }
      }
    }
    if (violators.empty())
    {
      settled = true;
      break;
    }

    // 3. Block step, or the safeguard's single step (Júdice & Pires 1994).
    const Index count = static_cast<Index>(violators.size());
    bool block = true;
    if (count < best_violators)
    {
      best_violators = count;
      attempts_left = options.block_attempts;
    }
    else if (attempts_left > 0)
      --attempts_left;
    else
      block = false;
    auto flip = [&](Index i) {
      BoxQPState& s = state(i);
      if (s == BoxQPState::Free)
        s = x(i) < l(i) ? BoxQPState::Lower : BoxQPState::Upper;
      else
        s = BoxQPState::Free;
    };
    if (block)
    {
      for (const Index i : violators)
        flip(i);
      if (visited.count(state_hash(state)) != 0)
      {
        // The block step returns to an active set seen before (a cycle): undo it and take the
        // single step instead.
        for (const Index i : violators)
          flip(i);
        block = false;
      }
    }
    if (!block)
    {
      flip(violators.back()); // the largest index
      ++result.single_steps;
    }
  }

  // Clamp onto the bounds (moves free variables by at most the primal threshold when settled)
  // and certify the clamped point.
  for (Index i = 0; i < n; ++i)
    x(i) = std::min(u(i), std::max(l(i), x(i)));
  const double sy = gradient_and_scale();
  const double sx = scale_x();
  for (Index i = 0; i < n; ++i)
  {
    if (state(i) == BoxQPState::Fixed)
    {
      ++result.fixed;
      continue;
    }
    if (x(i) == l(i))
    {
      ++result.lower;
      result.dual_infeasibility = std::max(result.dual_infeasibility, -y(i) / sy);
    }
    else if (x(i) == u(i))
    {
      ++result.upper;
      result.dual_infeasibility = std::max(result.dual_infeasibility, y(i) / sy);
    }
    else
    {
      ++result.free;
      result.stationarity = std::max(result.stationarity, std::abs(y(i)) / sy);
      const double gap = std::min(x(i) - l(i), u(i) - x(i));
      if (std::isfinite(gap))
        result.complementarity = std::max(result.complementarity, std::abs(y(i)) * gap / (sx * sy));
    }
    result.max_bound_violation =
      std::max({ result.max_bound_violation, l(i) - x(i), x(i) - u(i) });
  }
  result.kkt_residual =
    std::max({ result.stationarity, result.dual_infeasibility, result.complementarity });
  result.objective = 0.5 * x.dot(y) + 0.5 * b.dot(x);
  result.converged = settled && result.kkt_residual <= options.tolerance;
  // The active set of x: variables that ended on a bound while free are reported in the sets
  // they sit in. (When not settled, `state` already holds the next iteration's active set,
  // which is what a warm start should continue from.)
  for (Index i = 0; i < n; ++i)
    if (solved(i) == BoxQPState::Free && (x(i) == l(i) || x(i) == u(i)))
      solved(i) = x(i) == l(i) ? BoxQPState::Lower : BoxQPState::Upper;
  if (settled)
    state = solved;
  result.x = std::move(x);
  result.gradient = std::move(y);
  result.state = solved;
  if (warm)
  {
    warm->state = std::move(state);
    if (!factor.empty())
    {
      warm->factor = factor.factor();
      warm->factor_free = Eigen::Map<const Eigen::VectorXi>(factor.rows().data(),
        static_cast<Index>(factor.rows().size()));
      warm->owner = id_;
    }
  }
  result.factorizations = factor.factorizations;
  result.modifications = factor.modifications;
  result.modified_rows = factor.modified_rows_total;
  result.factor_seconds = factor.seconds;
  result.seconds = seconds_since(start);
  return result;
}

FreeSetFactor::FreeSetFactor(const BoxConstrainedQP& qp, const BoxQPOptions& options)
  : qp_(&qp)
  , reuse_ordering_(options.reuse_ordering)
  , modify_(options.modify_factorizations)
  , factor_(options.backend)
  , in_factor_(static_cast<std::size_t>(qp.size()), 0)
  , position_(static_cast<std::size_t>(qp.size()), -1)
{
}

void FreeSetFactor::adopt(const SparseCholesky& factor, const std::vector<int>& rows)
{
  for (const int i : rows_)
    in_factor_[static_cast<std::size_t>(i)] = 0;
  factor_ = factor;
  rows_ = rows;
  for (const int i : rows_)
    in_factor_[static_cast<std::size_t>(i)] = 1;
  modified_rows_ = 0;
}

void FreeSetFactor::update(const std::vector<int>& free)
{
  const auto start = Clock::now();
  added_.clear();
  removed_.clear();
  for (const int i : free)
    if (!in_factor_[static_cast<std::size_t>(i)])
      added_.push_back(i);
  if (!rows_.empty())
  {
    // Rows of the factor that left the free set: mark the free set, then scan the rows.
    for (const int i : free)
      position_[static_cast<std::size_t>(i)] = 1;
    for (const int i : rows_)
      if (position_[static_cast<std::size_t>(i)] != 1)
        removed_.push_back(i);
    for (const int i : free)
      position_[static_cast<std::size_t>(i)] = -1;
  }
  const Index changes = static_cast<Index>(added_.size() + removed_.size());
  if (!rows_.empty() && changes == 0 && !force_)
    return;
  const Index nf = static_cast<Index>(free.size());
  const bool modify = !rows_.empty() && !force_ && modify_ && factor_.modifiable() &&
    changes <= std::max<Index>(8, nf / 64) && modified_rows_ + changes <= nf / 4;
  const SparseMatrix& A = qp_->matrix();
  if (modify)
  {
    try
    {
      factor_.modify_principal(A,
        Eigen::Map<const Eigen::VectorXi>(added_.data(), static_cast<Index>(added_.size())),
        Eigen::Map<const Eigen::VectorXi>(removed_.data(), static_cast<Index>(removed_.size())));
    }
    catch (...)
    {
      // The failed modification forgot the factorization.
      for (const int i : rows_)
        in_factor_[static_cast<std::size_t>(i)] = 0;
      rows_.clear();
      throw;
    }
    for (const int i : removed_)
      in_factor_[static_cast<std::size_t>(i)] = 0;
    for (const int i : added_)
      in_factor_[static_cast<std::size_t>(i)] = 1;
    rows_ = factor_.principal_rows();
    modified_rows_ += changes;
    ++modifications;
    modified_rows_total += changes;
  }
  else
  {
    // A(F, F) is a principal submatrix of the validated A: symmetric, finite.
    SparseCholeskySettings settings;
    settings.trusted = true;
    if (reuse_ordering_)
    {
      for (Index k = 0; k < nf; ++k)
        position_[static_cast<std::size_t>(free[static_cast<std::size_t>(k)])] = static_cast<int>(k);
      settings.ordering.resize(nf);
      const Eigen::VectorXi& ordering = qp_->ordering();
      Index k = 0;
      for (Index g = 0; g < ordering.size(); ++g)
      {
        const int p = position_[static_cast<std::size_t>(ordering(g))];
        if (p >= 0)
          settings.ordering(k++) = p;
      }
      for (const int i : free)
        position_[static_cast<std::size_t>(i)] = -1;
    }
    // Forget the old factor first: a failure must not leave it looking current.
    for (const int i : rows_)
      in_factor_[static_cast<std::size_t>(i)] = 0;
    rows_.clear();
    factor_.compute_principal(A, Eigen::Map<const Eigen::VectorXi>(free.data(), nf), settings);
    rows_ = free;
    for (const int i : rows_)
      in_factor_[static_cast<std::size_t>(i)] = 1;
    modified_rows_ = 0;
    force_ = false;
    ++factorizations;
  }
  seconds += seconds_since(start);
}

BoxQPResult box_constrained_qp(const SparseMatrix& A, const Eigen::VectorXd& b,
  const Eigen::VectorXd& l, const Eigen::VectorXd& u, const BoxQPOptions& options,
  const Eigen::VectorXd& x0)
{
  const BoxConstrainedQP qp(A);
  if (x0.size() == 0)
    return qp.solve(b, l, u, options);
  BoxQPWarmStart warm;
  warm.state = active_set_from_guess(x0, l, u);
  return qp.solve(b, l, u, options, &warm);
}

} // namespace bary
