#pragma once
/// @file grid_meshes.h
/// The unit square as a side x side grid of vertices (vertex (i, j) at (i, j) / (side - 1),
/// index j side + i), each cell split along alternating diagonals: the structured mesh the BBW
/// tests solve on (bbw_test.cpp, bbw_handles_test.cpp).
#include <Eigen/Core>

namespace bary::test
{
struct SquareGrid
{
  Eigen::MatrixXd V;
  Eigen::MatrixXi T;
  int side = 0;
  int id(int i, int j) const { return j * side + i; }
  double h() const { return 1.0 / (side - 1); }
};

inline SquareGrid unit_square_grid(int side)
{
  SquareGrid g;
  g.side = side;
  g.V.resize(side * side, 2);
  for (int j = 0; j < side; ++j)
    for (int i = 0; i < side; ++i)
      g.V.row(g.id(i, j)) << double(i) / (side - 1), double(j) / (side - 1);
  g.T.resize(2 * (side - 1) * (side - 1), 3);
  int t = 0;
  for (int j = 0; j + 1 < side; ++j)
    for (int i = 0; i + 1 < side; ++i)
    {
      const int a = g.id(i, j), b = g.id(i + 1, j), c = g.id(i + 1, j + 1), d = g.id(i, j + 1);
      if ((i + j) % 2 == 0)
      {
        g.T.row(t++) << a, b, c;
        g.T.row(t++) << a, c, d;
      }
      else
      {
        g.T.row(t++) << a, b, d;
        g.T.row(t++) << b, c, d;
      }
    }
  return g;
}
} // namespace bary::test
