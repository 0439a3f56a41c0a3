#pragma once
/// @file surface_catalogue.h
/// Triangle surfaces made in the tests of the surface family: a flat grid, an icosphere, a
/// torus; and a smooth lift of a surface into R^8 (a non-trivial embedding with a known map).

#include <Eigen/Core>

#include <cmath>
#include <map>
#include <utility>
#include <vector>

namespace bary::test
{

struct Surface
{
  Eigen::MatrixXd V;
  Eigen::MatrixXi F;
};

/// n by n squares of [-1, 1]^2 at z = 0, each split into two triangles (alternating diagonals).
inline Surface flat_grid(int n)
{
  Surface s;
  s.V.resize((n + 1) * (n + 1), 3);
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      s.V.row(j * (n + 1) + i) << -1.0 + 2.0 * i / n, -1.0 + 2.0 * j / n, 0.0;
  s.F.resize(2 * n * n, 3);
  int f = 0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
    {
      const int a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
      if ((i + j) % 2 == 0)
      {
        s.F.row(f++) << a, b, d;
        s.F.row(f++) << a, d, c;
      }
      else
      {
        s.F.row(f++) << a, b, c;
        s.F.row(f++) << b, d, c;
      }
    }
  return s;
}

/// Unit icosphere: the icosahedron with each triangle split into four, @p levels times.
inline Surface icosphere(int levels)
{
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Eigen::Vector3d> v = { { -1, t, 0 }, { 1, t, 0 }, { -1, -t, 0 }, { 1, -t, 0 },
    { 0, -1, t }, { 0, 1, t }, { 0, -1, -t }, { 0, 1, -t }, { t, 0, -1 }, { t, 0, 1 },
    { -t, 0, -1 }, { -t, 0, 1 } };
  for (auto& p : v)
    p.normalize();
  std::vector<Eigen::Vector3i> f = { { 0, 11, 5 }, { 0, 5, 1 }, { 0, 1, 7 }, { 0, 7, 10 },
    { 0, 10, 11 }, { 1, 5, 9 }, { 5, 11, 4 }, { 11, 10, 2 }, { 10, 7, 6 }, { 7, 1, 8 },
    { 3, 9, 4 }, { 3, 4, 2 }, { 3, 2, 6 }, { 3, 6, 8 }, { 3, 8, 9 }, { 4, 9, 5 }, { 2, 4, 11 },
    { 6, 2, 10 }, { 8, 6, 7 }, { 9, 8, 1 } };
  for (int l = 0; l < levels; ++l)
  {
    std::map<std::pair<int, int>, int> mid;
    auto middle = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      const auto it = mid.find(key);
      if (it != mid.end())
        return it->second;
      v.push_back((v[a] + v[b]).normalized());
      return mid[key] = static_cast<int>(v.size()) - 1;
    };
    std::vector<Eigen::Vector3i> g;
    for (const auto& tri : f)
    {
      const int a = middle(tri(0), tri(1)), b = middle(tri(1), tri(2)), c = middle(tri(2), tri(0));
      g.push_back({ tri(0), a, c });
      g.push_back({ tri(1), b, a });
      g.push_back({ tri(2), c, b });
      g.push_back({ a, b, c });
    }
    f.swap(g);
  }
  Surface s;
  s.V.resize(static_cast<Eigen::Index>(v.size()), 3);
  for (std::size_t i = 0; i < v.size(); ++i)
    s.V.row(static_cast<Eigen::Index>(i)) = v[i].transpose();
  s.F.resize(static_cast<Eigen::Index>(f.size()), 3);
  for (std::size_t i = 0; i < f.size(); ++i)
    s.F.row(static_cast<Eigen::Index>(i)) = f[i].transpose();
  return s;
}

/// Torus with radii R, r, n by m quads split into triangles.
inline Surface torus(int n, int m, double R = 1.0, double r = 0.4)
{
  const double pi = std::acos(-1.0);
  Surface s;
  s.V.resize(n * m, 3);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j)
    {
      const double u = 2 * pi * i / n, w = 2 * pi * j / m;
      s.V.row(i * m + j) << (R + r * std::cos(w)) * std::cos(u), (R + r * std::cos(w)) * std::sin(u),
        r * std::sin(w);
    }
  s.F.resize(2 * n * m, 3);
  int f = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j)
    {
      const int a = i * m + j, b = ((i + 1) % n) * m + j, c = i * m + (j + 1) % m,
                d = ((i + 1) % n) * m + (j + 1) % m;
      s.F.row(f++) << a, b, d;
      s.F.row(f++) << a, d, c;
    }
  return s;
}

/// A smooth injective lift of R^3 into R^8: (x, y, z, x^2/2, y^2/2, z^2/2, xy/2, yz/2) applied to
/// every vertex, for Phong projections in more than three dimensions with a known geometry.
inline Eigen::MatrixXd lift8(const Eigen::MatrixXd& V)
{
  Eigen::MatrixXd E(V.rows(), 8);
  for (Eigen::Index i = 0; i < V.rows(); ++i)
  {
    const double x = V(i, 0), y = V(i, 1), z = V(i, 2);
    E.row(i) << x, y, z, x * x / 2, y * y / 2, z * z / 2, x * y / 2, y * z / 2;
  }
  return E;
}

} // namespace bary::test
