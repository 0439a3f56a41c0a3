// Tests for core/detail/anderson.h: Anderson acceleration and the deterministic dot product.
#include "core/detail/anderson.h"

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <random>
#include <vector>

namespace
{
using namespace bary;

TEST(ChunkedDot, SumsInFixedChunksWhateverTheThreads)
{
  const Index n = 10000; // three chunks of 4096
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<double> a(static_cast<std::size_t>(n)), b(static_cast<std::size_t>(n));
  for (Index k = 0; k < n; ++k)
  {
    a[static_cast<std::size_t>(k)] = u(rng);
    b[static_cast<std::size_t>(k)] = u(rng);
  }
  const double one = detail::chunked_dot(a.data(), b.data(), n, 1);
  EXPECT_EQ(one, detail::chunked_dot(a.data(), b.data(), n, 2));
  EXPECT_EQ(one, detail::chunked_dot(a.data(), b.data(), n, 3));
  double naive = 0.0;
  for (Index k = 0; k < n; ++k)
    naive += a[static_cast<std::size_t>(k)] * b[static_cast<std::size_t>(k)];
  EXPECT_NEAR(one, naive, 1e-11);
  EXPECT_EQ(detail::chunked_dot(a.data(), b.data(), 0, 2), 0.0);
}

/// Iterations of s <- s + g(s), g(s) = M s + c - s (a linear contraction with fixed point
/// s* = (I - M)^-1 c), until |g| <= 1e-10; with Anderson extrapolation when @p accelerate.
int iterations_to_converge(bool accelerate, Eigen::VectorXd* solution)
{
  const int n = 40;
  Eigen::MatrixXd M(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      M(i, j) = (i == j ? 0.95 : 0.0) + (std::abs(i - j) == 1 ? 0.02 : 0.0);
  const Eigen::VectorXd c = Eigen::VectorXd::LinSpaced(n, -1.0, 1.0);
  Eigen::VectorXd s = Eigen::VectorXd::Zero(n), next(n);
  detail::Anderson anderson(n, 5, 2);
  for (int it = 1; it <= 5000; ++it)
  {
    const Eigen::VectorXd g = M * s + c - s;
    if (g.norm() <= 1e-10)
    {
      *solution = s;
      return it;
    }
    if (accelerate && anderson.extrapolate(s.data(), g.data(), next.data()))
      s = next;
    else
      s += g;
  }
  *solution = s;
  return 5000;
}

TEST(Anderson, AcceleratesALinearFixedPointIteration)
{
  Eigen::VectorXd plain, accelerated;
  const int slow = iterations_to_converge(false, &plain);
  const int fast = iterations_to_converge(true, &accelerated);
  std::printf("[ info ] plain %d iterations, Anderson(5) %d\n", slow, fast);
  EXPECT_LT(fast, slow / 5);
  EXPECT_LE((plain - accelerated).norm(), 1e-8);
}

TEST(Anderson, NoExtrapolationWithoutHistoryOrAfterReset)
{
  detail::Anderson anderson(3, 2, 1);
  const double s[3] = { 1, 2, 3 }, g[3] = { 0.5, 0.5, 0.5 }, s2[3] = { 1.5, 2.5, 3.5 },
               g2[3] = { 0.25, 0.25, 0.25 };
  double out[3] = { -7, -7, -7 };
  EXPECT_FALSE(anderson.extrapolate(s, g, out)); // the first pair: no secant yet
  EXPECT_EQ(out[0], -7.0);
  EXPECT_TRUE(anderson.extrapolate(s2, g2, out)); // one secant: extrapolates
  // along the secant g falls by 0.25 per 0.5 of s: the secant model of g vanishes at s2 + 0.5
  for (int k = 0; k < 3; ++k)
    EXPECT_NEAR(out[k], s2[k] + 0.5, 1e-8) << k;
  anderson.reset();
  EXPECT_FALSE(anderson.extrapolate(s, g, out));
  // a zero difference gives a degenerate least-squares problem: no extrapolation
  EXPECT_FALSE(anderson.extrapolate(s, g, out));
}
} // namespace
