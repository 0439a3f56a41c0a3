#include "core/detail/anderson.h"

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>

namespace bary::detail
{
namespace
{
// Sums are taken over fixed chunks (independent of the thread count) and the chunk sums are
// added in order, so every reduction gives the same bits whatever the number of threads.
constexpr Index kChunk = 4096;
} // namespace

double chunked_dot(const double* a, const double* b, Index n, int threads)
{
  const Index chunks = (n + kChunk - 1) / kChunk;
  std::vector<double> partial(static_cast<std::size_t>(chunks), 0.0);
#pragma omp parallel for num_threads(threads) schedule(static)
  for (Index c = 0; c < chunks; ++c)
  {
    const Index begin = c * kChunk, end = std::min(n, begin + kChunk);
    double sum = 0.0;
    for (Index k = begin; k < end; ++k)
      sum += a[k] * b[k];
    partial[static_cast<std::size_t>(c)] = sum;
  }
  double sum = 0.0;
  for (double p : partial)
    sum += p;
  return sum;
}

Anderson::Anderson(Index size, int history, int threads)
  : n_(size)
  , m_(history)
  , threads_(threads)
  , dS_(static_cast<std::size_t>(size * history))
  , dG_(static_cast<std::size_t>(size * history))
  , prev_s_(static_cast<std::size_t>(size))
  , prev_g_(static_cast<std::size_t>(size))
  , gram_(Eigen::MatrixXd::Zero(history, history))
{
}

void Anderson::reset()
{
  count_ = 0;
  head_ = 0;
  has_prev_ = false;
}

bool Anderson::extrapolate(const double* s, const double* g, double* out)
{
  const Index n = n_;
  if (has_prev_)
  {
    double* ds = dS_.data() + static_cast<Index>(head_) * n;
    double* dg = dG_.data() + static_cast<Index>(head_) * n;
    const double* ps = prev_s_.data();
    const double* pg = prev_g_.data();
#pragma omp parallel for num_threads(threads_) schedule(static)
    for (Index k = 0; k < n; ++k)
    {
      ds[k] = s[k] - ps[k];
      dg[k] = g[k] - pg[k];
    }
    const int written = head_;
    head_ = (head_ + 1) % m_;
    count_ = std::min(count_ + 1, m_);
    for (int j = 0; j < count_; ++j)
    {
      const int slot = slot_of(j);
      const double v = chunked_dot(dg, dG_.data() + static_cast<Index>(slot) * n, n, threads_);
      gram_(written, slot) = v;
      gram_(slot, written) = v;
    }
  }
  std::copy(s, s + n, prev_s_.data());
  std::copy(g, g + n, prev_g_.data());
  has_prev_ = true;
  if (count_ == 0)
    return false;

  // theta = argmin |g - dG theta|
  const int c = count_;
  Eigen::MatrixXd A(c, c);
  Eigen::VectorXd rhs(c);
  std::vector<int> slots(static_cast<std::size_t>(c));
  for (int j = 0; j < c; ++j)
    slots[static_cast<std::size_t>(j)] = slot_of(j);
  for (int a = 0; a < c; ++a)
  {
    for (int b = 0; b < c; ++b)
      A(a, b) = gram_(slots[static_cast<std::size_t>(a)], slots[static_cast<std::size_t>(b)]);
    rhs(a) = chunked_dot(
      dG_.data() + static_cast<Index>(slots[static_cast<std::size_t>(a)]) * n, g, n, threads_);
  }
  const double scale = A.diagonal().maxCoeff();
  if (!(scale > 0.0) || !std::isfinite(scale))
    return false;
  A.diagonal().array() += 1e-10 * scale;
  const Eigen::VectorXd theta = A.ldlt().solve(rhs);
  if (!theta.allFinite())
    return false;
#pragma omp parallel for num_threads(threads_) schedule(static)
  for (Index k = 0; k < n; ++k)
  {
    double v = s[k] + g[k];
    for (int j = 0; j < c; ++j)
    {
      const Index off = static_cast<Index>(slots[static_cast<std::size_t>(j)]) * n + k;
      v -= theta(j) * (dS_[static_cast<std::size_t>(off)] + dG_[static_cast<std::size_t>(off)]);
    }
    out[k] = v;
  }
  return true;
}

} // namespace bary::detail
