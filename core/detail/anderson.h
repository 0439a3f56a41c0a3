#pragma once
/// @file anderson.h
/// Anderson acceleration of a fixed-point iteration, as local barycentric coordinates' ADMM
/// uses it (LBCOptions::anderson).

#include "core/common/types.h"

#include <Eigen/Core>

#include <vector>

namespace bary::detail
{

/// sum_k a[k] b[k] over fixed chunks of 4096 entries (independent of the thread count), the
/// chunk sums added in order: the same bits whatever @p threads.
double chunked_dot(const double* a, const double* b, Index n, int threads);

/// Type-II Anderson acceleration (Walker & Ni 2011) of a fixed-point map s -> s + g(s) over the
/// last `history` secant pairs, with Tikhonov-regularised normal equations. Results do not
/// depend on the thread count.
class Anderson
{
public:
  /// @param size the length of s; @param history the number of secant pairs kept (>= 1);
  /// @param threads OpenMP threads of the vector operations (>= 1).
  Anderson(Index size, int history, int threads);

  /// Forgets the history.
  void reset();

  /// Records the accepted pair (s, g) and writes the extrapolated point to @p out.
  /// Returns false (and leaves out untouched) when there is no history yet or the least-squares
  /// problem is degenerate.
  bool extrapolate(const double* s, const double* g, double* out);

private:
  /// Slot of the j-th most recent difference (j = 0: newest).
  int slot_of(int j) const { return ((head_ - 1 - j) % m_ + 2 * m_) % m_; }

  Index n_;
  int m_, threads_;
  std::vector<double> dS_, dG_, prev_s_, prev_g_;
  Eigen::MatrixXd gram_;
  int count_ = 0, head_ = 0;
  bool has_prev_ = false;
};

} // namespace bary::detail
