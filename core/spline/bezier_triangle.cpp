#include "core/spline/bezier_triangle.h"

#include <cmath>

namespace bary
{

namespace
{

double factorial(int n)
{
  double f = 1.0;
  for (int i = 2; i <= n; ++i)
    f *= i;
  return f;
}

double multinomial(int d, int i, int j, int k)
{
  return factorial(d) / (factorial(i) * factorial(j) * factorial(k));
}

/// One de Casteljau step: coefficients of degree r (rows) to degree r - 1 with the point w.
Eigen::MatrixXd casteljau_step(const Eigen::MatrixXd& C, int r, const Eigen::Vector3d& w)
{
  Eigen::MatrixXd out(bezier_count(r - 1), C.cols());
  for (int i = 0; i <= r - 1; ++i)
    for (int j = 0; j <= r - 1 - i; ++j)
      out.row(bezier_index(r - 1, i, j)) = w[0] * C.row(bezier_index(r, i + 1, j)) +
        w[1] * C.row(bezier_index(r, i, j + 1)) + w[2] * C.row(bezier_index(r, i, j));
  return out;
}

} // namespace

std::vector<std::array<int, 3>> bezier_multi_indices(int d)
{
  std::vector<std::array<int, 3>> out;
  out.reserve(static_cast<size_t>(bezier_count(d)));
  for (int i = 0; i <= d; ++i)
    for (int j = 0; j <= d - i; ++j)
      out.push_back({ i, j, d - i - j });
  return out;
}

void bernstein_basis(int d, const Eigen::Vector3d& b, double* out)
{
  // Powers of each coordinate, then d!/(i!j!k!) b0^i b1^j b2^k.
  double p0[32], p1[32], p2[32];
  p0[0] = p1[0] = p2[0] = 1.0;
  for (int e = 1; e <= d; ++e)
  {
    p0[e] = p0[e - 1] * b[0];
    p1[e] = p1[e - 1] * b[1];
    p2[e] = p2[e - 1] * b[2];
  }
  const double fd = factorial(d);
  for (int i = 0; i <= d; ++i)
    for (int j = 0; j <= d - i; ++j)
    {
      const int k = d - i - j;
      out[bezier_index(d, i, j)] =
        fd / (factorial(i) * factorial(j) * factorial(k)) * p0[i] * p1[j] * p2[k];
    }
}

Eigen::RowVectorXd bezier_evaluate(const Eigen::MatrixXd& C, int d, const Eigen::Vector3d& b)
{
  Eigen::MatrixXd level = C;
  for (int r = d; r > 0; --r)
    level = casteljau_step(level, r, b);
  return level.row(0);
}

Eigen::MatrixXd bezier_derivative(const Eigen::MatrixXd& C, int d, const Eigen::Vector3d& u)
{
  return d * casteljau_step(C, d, u);
}

Eigen::MatrixXd bezier_elevate(const Eigen::MatrixXd& C, int d)
{
  const int e = d + 1;
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(bezier_count(e), C.cols());
  for (int i = 0; i <= e; ++i)
    for (int j = 0; j <= e - i; ++j)
    {
      const int k = e - i - j;
      auto row = out.row(bezier_index(e, i, j));
      if (i > 0)
        row += (double(i) / e) * C.row(bezier_index(d, i - 1, j));
      if (j > 0)
        row += (double(j) / e) * C.row(bezier_index(d, i, j - 1));
      if (k > 0)
        row += (double(k) / e) * C.row(bezier_index(d, i, j));
    }
  return out;
}

Eigen::VectorXd bezier_product(const Eigen::VectorXd& p, int m, const Eigen::VectorXd& q, int n)
{
  const int s = m + n;
  Eigen::VectorXd out = Eigen::VectorXd::Zero(bezier_count(s));
  for (int i = 0; i <= m; ++i)
    for (int j = 0; j <= m - i; ++j)
    {
      const int k = m - i - j;
      const double a = multinomial(m, i, j, k) * p[bezier_index(m, i, j)];
      if (a == 0.0)
        continue;
      for (int i2 = 0; i2 <= n; ++i2)
        for (int j2 = 0; j2 <= n - i2; ++j2)
        {
          const int k2 = n - i2 - j2;
          out[bezier_index(s, i + i2, j + j2)] +=
            a * multinomial(n, i2, j2, k2) * q[bezier_index(n, i2, j2)];
        }
    }
  for (int i = 0; i <= s; ++i)
    for (int j = 0; j <= s - i; ++j)
      out[bezier_index(s, i, j)] /= multinomial(s, i, j, s - i - j);
  return out;
}

Eigen::MatrixXd bezier_subtriangle(const Eigen::MatrixXd& C, int d, const Eigen::Vector3d& a,
  const Eigen::Vector3d& b, const Eigen::Vector3d& c)
{
  Eigen::MatrixXd out(bezier_count(d), C.cols());
  for (int i = 0; i <= d; ++i)
    for (int j = 0; j <= d - i; ++j)
    {
      // The blossom at a (i times), b (j times), c (k times): de Casteljau with a different
      // point at each level.
      Eigen::MatrixXd level = C;
      int r = d;
      for (int s = 0; s < i; ++s, --r)
        level = casteljau_step(level, r, a);
      for (int s = 0; s < j; ++s, --r)
        level = casteljau_step(level, r, b);
      while (r > 0)
      {
        level = casteljau_step(level, r, c);
        --r;
      }
      out.row(bezier_index(d, i, j)) = level.row(0);
    }
  return out;
}

} // namespace bary
