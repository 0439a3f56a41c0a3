// Tests of core/surface/surface_mesh: validation, fans, adjacency, topology counts, closest
// points on the surface.
#include "core/surface/surface_mesh.h"
#include "error_matchers.h"
#include "surface_catalogue.h"

#include <gtest/gtest.h>

#include <set>

using namespace bary;
using bary::test::throws_error;

TEST(SurfaceMesh, TopologyOfGridSphereTorus)
{
  const auto grid = test::flat_grid(6);
  const SurfaceMesh g(grid.V, grid.F);
  EXPECT_EQ(g.boundary_loops, 1);
  EXPECT_EQ(g.euler_characteristic(), 1);
  EXPECT_EQ(g.genus(), 0);
  const auto sphere = test::icosphere(2);
  const SurfaceMesh s(sphere.V, sphere.F);
  EXPECT_EQ(s.boundary_loops, 0);
  EXPECT_EQ(s.euler_characteristic(), 2);
  const auto tor = test::torus(12, 8);
  const SurfaceMesh t(tor.V, tor.F);
  EXPECT_EQ(t.genus(), 1);
  EXPECT_EQ(t.boundary_loops, 0);
}

TEST(SurfaceMesh, OneRingsAreFansOfConsecutiveNeighbours)
{
  for (const auto& surf : { test::flat_grid(5), test::icosphere(2), test::torus(10, 7) })
  {
    const SurfaceMesh m(surf.V, surf.F);
    std::set<std::pair<int, int>> edges;
    for (Index f = 0; f < m.face_count(); ++f)
      for (int k = 0; k < 3; ++k)
        edges.insert(std::minmax(m.F(f, k), m.F(f, (k + 1) % 3)));
    for (Index v = 0; v < m.vertex_count(); ++v)
    {
      const int b = m.ring_offsets[v], e = m.ring_offsets[v + 1];
      const int faces = m.face_offsets[v + 1] - m.face_offsets[v];
      // A closed fan has as many neighbours as triangles, an open one one more.
      EXPECT_EQ(e - b, faces + (m.boundary[v] ? 1 : 0)) << "vertex " << v;
      for (int i = b; i + 1 < e; ++i) // consecutive neighbours share an edge (a triangle with v)
        EXPECT_TRUE(edges.count(std::minmax(m.ring[i], m.ring[i + 1]))) << "vertex " << v;
      if (!m.boundary[v])
      {
        EXPECT_TRUE(edges.count(std::minmax(m.ring[b], m.ring[e - 1])));
      }
    }
  }
}

TEST(SurfaceMesh, FaceNeighboursShareTheOppositeEdge)
{
  const auto surf = test::icosphere(1);
  const SurfaceMesh m(surf.V, surf.F);
  for (Index f = 0; f < m.face_count(); ++f)
    for (int k = 0; k < 3; ++k)
    {
      const int g = m.face_neighbors(f, k);
      ASSERT_GE(g, 0);
      const int a = m.F(f, (k + 1) % 3), b = m.F(f, (k + 2) % 3);
      int shared = 0;
      for (int j = 0; j < 3; ++j)
        shared += (m.F(g, j) == a) + (m.F(g, j) == b);
      EXPECT_EQ(shared, 2);
    }
}

TEST(SurfaceMesh, RefusesBadSurfacesNamingTheProblem)
{
  const auto grid = test::flat_grid(2);
  Eigen::MatrixXd V = grid.V;
  Eigen::MatrixXi F = grid.F;
  EXPECT_TRUE(throws_error([&] { SurfaceMesh(Eigen::MatrixXd(0, 3), F); }, ErrorCode::EmptyInput, { "no vertices" }));
  EXPECT_TRUE(throws_error([&] { SurfaceMesh(V, Eigen::MatrixXi(0, 3)); }, ErrorCode::EmptyInput, { "no triangles" }));
  EXPECT_TRUE(throws_error([&] { SurfaceMesh(V.leftCols(2), F); }, ErrorCode::SizeMismatch, { "3 coordinates" }));
  Eigen::MatrixXd Vn = V;
  Vn(4, 1) = std::nan("");
  EXPECT_TRUE(throws_error([&] { SurfaceMesh(Vn, F); }, ErrorCode::NonFinite, { "vertex 4" }));
  Eigen::MatrixXi Fo = F;
  Fo(3, 2) = 99;
  EXPECT_TRUE(throws_error([&] { SurfaceMesh(V, Fo); }, ErrorCode::InvalidArgument, { "triangle 3", "vertex 99" }));
  Eigen::MatrixXi Fd = F;
  Fd(0, 1) = Fd(0, 0);
  EXPECT_TRUE(throws_error([&] { SurfaceMesh(V, Fd); }, ErrorCode::InvalidArgument, { "triangle 0", "degenerate" }));
  // Unused vertex.
  Eigen::MatrixXd Vu(V.rows() + 1, 3);
  Vu << V, Eigen::RowVector3d(5, 5, 5);
  EXPECT_TRUE(throws_error([&] { SurfaceMesh(Vu, F); }, ErrorCode::InvalidArgument, { "vertex 9", "no triangle" }));
  // Non-manifold edge: a third triangle on the interior edge (0, 4).
  Eigen::MatrixXd Vm(V.rows() + 1, 3);
  Vm << V, Eigen::RowVector3d(0, 0, 1);
  Eigen::MatrixXi Fm(F.rows() + 1, 3);
  Fm << F, Eigen::RowVector3i(0, 4, 9);
  EXPECT_TRUE(throws_error([&] { SurfaceMesh(Vm, Fm); }, ErrorCode::InvalidArgument, { "(0, 4)", "3 triangles", "non-manifold" }));
  // Two pieces.
  Eigen::MatrixXd V2(2 * V.rows(), 3);
  V2 << V, V.rowwise() + Eigen::RowVector3d(5, 0, 0);
  Eigen::MatrixXi F2(2 * F.rows(), 3);
  F2 << F, F.array() + static_cast<int>(V.rows());
  EXPECT_TRUE(throws_error([&] { SurfaceMesh(V2, F2); }, ErrorCode::InvalidArgument, { "2 connected pieces" }));
  // Two sheets touching at a vertex (a bow tie).
  Eigen::MatrixXd Vb(5, 3);
  Vb << 0, 0, 0, 1, 0, 0, 1, 1, 0, -1, 0, 0, -1, -1, 0;
  Eigen::MatrixXi Fb(2, 3);
  Fb << 0, 1, 2, 0, 3, 4;
  EXPECT_TRUE(throws_error([&] { SurfaceMesh(Vb, Fb); }, ErrorCode::InvalidArgument, { "vertex 0", "one fan" }));
}

TEST(SurfaceMesh, ClosestPointsAgainstBruteForce)
{
  const auto surf = test::icosphere(2);
  const SurfaceMesh m(surf.V, surf.F);
  Eigen::MatrixXd P = Eigen::MatrixXd::Random(200, 3) * 1.5;
  std::vector<double> distance;
  const auto points = closest_surface_points(m, P, &distance);
  const Eigen::MatrixXd X = surface_point_positions(m.F, m.V, points);
  for (Index i = 0; i < P.rows(); ++i)
  {
    EXPECT_NEAR((X.row(i) - P.row(i)).norm(), distance[i], 1e-12);
    // No vertex is closer than the closest point (vertices are points of the surface).
    for (Index v = 0; v < m.vertex_count(); ++v)
      ASSERT_LE(distance[i], (m.V.row(v) - P.row(i)).norm() + 1e-12);
  }
  EXPECT_TRUE(throws_error([&] { closest_surface_points(m, P.leftCols(2)); }, ErrorCode::SizeMismatch, { "3 coordinates" }));
}
