// Tests for core/coordinates/bbw_handles.h: mixed handles in one BBW solve (points, bones, a
// closed or open cage, regions) against independent references (today's cage handles, today's
// skeleton handles, a point handle), their constraints (Eq. 3-6), the errors, and the
// shape-preservation brush given per vertex.
#include "core/coordinates/bbw_handles.h"
#include "core/common/error.h"
#include "core/coordinates/weight_method.h"
#include "core/solvers/fem_operators.h"
#include "error_matchers.h"
#include "grid_meshes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

namespace
{
using namespace bary;
using bary::test::throws_error;

using Square = bary::test::SquareGrid;
Square square(int n)
{
  return bary::test::unit_square_grid(n);
}

WeightsResult solve_mixed(const Square& g, const Skeleton& s, bool coupled,
  const std::vector<std::vector<int>>* regions = nullptr, const Eigen::VectorXd* brush = nullptr)
{
  WeightsSettings settings;
  settings.method = MethodId::BBW;
  settings.bbw_fast = !coupled;
  WeightsInput in;
  in.skeleton = &s;
  in.domain_V = &g.V;
  in.domain_T = &g.T;
  in.points = &g.V;
  in.region_vertices = regions;
  in.shape_preservation = brush;
  return compute_weights(in, settings);
}

double statistic(const WeightsResult& r, const std::string& name)
{
  for (const auto& [key, value] : r.statistics)
    if (key == name)
      return value;
  return std::nan("");
}

TEST(MixedHandles, AClosedCageAmongMixedHandlesEqualsTodaysCageHandles)
{
  // The square's boundary as a closed cage of 4 vertices: as mixed handles (cage faces over
  // joints) the weights equal the cage-handle path's (the cage's boundary values, Eq. 4,
  // from cage_boundary_values on the same given mesh).
  const Square g = square(13);
  Cage cage;
  cage.V.resize(4, 2);
  cage.V << 0, 0, 1, 0, 1, 1, 0, 1;
  WeightsSettings settings;
  settings.method = MethodId::BBW;
  WeightsInput in;
  in.cage = &cage;
  in.domain_V = &g.V;
  in.domain_T = &g.T;
  in.points = &g.V;
  const WeightsResult reference = compute_weights(in, settings);
  Skeleton s;
  s.C = cage.V;
  s.CF.resize(4, 2);
  s.CF << 0, 1, 1, 2, 2, 3, 3, 0;
  const WeightsResult mixed = solve_mixed(g, s, true);
  ASSERT_EQ(mixed.W.cols(), 4);
  EXPECT_LE((mixed.W - reference.W).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(MixedHandles, PointsAndBonesAloneAreTodaysSkeletonHandles)
{
  const Square g = square(11);
  Skeleton s;
  s.C.resize(4, 2);
  s.C << 0.2, 0.2, 0.5, 0.5, 0.8, 0.5, 0.3, 0.9;
  s.P.resize(1);
  s.P << 3;
  s.BE.resize(2, 2);
  s.BE << 0, 1, 1, 2;
  const BBWHandles a = mixed_bbw_handles(g.V, s);
  const BBWHandles b = handles_from_skeleton(g.V, s.C, s.P, s.BE);
  EXPECT_EQ(a.point_vertex, b.point_vertex);
  EXPECT_EQ(a.bone_vertices, b.bone_vertices);
  EXPECT_EQ(a.extra_handles, 0);
  EXPECT_EQ(a.fixed_vertices.size(), 0);
}

TEST(MixedHandles, ARegionOfOneVertexIsAPointHandle)
{
  // A vertex region {v}, and a polygon region around v holding no other vertex, give the
  // weights of a point handle at v.
  const Square g = square(11);
  const int v = g.id(7, 6);
  Skeleton points;
  points.C.resize(2, 2);
  points.C << 0.2, 0.3, 0.7, 0.6;
  points.P.resize(2);
  points.P << 0, 1;
  const WeightsResult reference = solve_mixed(g, points, true);

  Skeleton one;
  one.C = points.C.topRows(1);
  one.P.resize(1);
  one.P << 0;
  const std::vector<std::vector<int>> regions{ { v } };
  const WeightsResult by_vertices = solve_mixed(g, one, true, &regions);
  ASSERT_EQ(by_vertices.W.cols(), 2);
  EXPECT_LE((by_vertices.W - reference.W).cwiseAbs().maxCoeff(), 1e-12);

  Skeleton polygon = one;
  const double e = 0.3 * g.h();
  polygon.C.conservativeResize(5, 2);
  polygon.C.bottomRows(4) << 0.7 - e, 0.6 - e, 0.7 + e, 0.6 - e, 0.7 + e, 0.6 + e, 0.7 - e, 0.6 + e;
  polygon.regions.push_back((Eigen::MatrixXi(4, 2) << 1, 2, 2, 3, 3, 4, 4, 1).finished());
  const WeightsResult by_polygon = solve_mixed(g, polygon, true);
  EXPECT_LE((by_polygon.W - reference.W).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(MixedHandles, PointBoneOpenCageAndRegionInOneCoupledSolve)
{
  // Fig. 1's mix on the unit square: a point handle, a bone, an open cage of two edges on the
  // right side, a square region; every constraint checked against its own formula.
  const Square g = square(21); // h = 0.05
  Skeleton s;
  s.C.resize(10, 2);
  s.C << 0.2, 0.8,                       // 0: point handle
    0.5, 0.15, 0.8, 0.15,                // 1-2: bone
    1.0, 0.3, 1.0, 0.6, 1.0, 0.9,        // 3-5: open cage
    0.35, 0.4, 0.55, 0.4, 0.55, 0.6, 0.35, 0.6; // 6-9: region
  s.P.resize(1);
  s.P << 0;
  s.BE.resize(1, 2);
  s.BE << 1, 2;
  s.CF.resize(2, 2);
  s.CF << 3, 4, 4, 5;
  s.regions.push_back((Eigen::MatrixXi(4, 2) << 6, 7, 7, 8, 8, 9, 9, 6).finished());
  ASSERT_EQ(s.handle_count(), 6);
  const WeightsResult r = solve_mixed(g, s, true);
  ASSERT_EQ(r.W.cols(), 6); // point, bone, cage joints 3, 4, 5, region
  auto unit = [&](int vertex, int column) {
    Eigen::RowVectorXd e = Eigen::RowVectorXd::Zero(6);
    e(column) = 1;
    return (r.W.row(vertex) - e).cwiseAbs().maxCoeff();
  };
  EXPECT_LE(unit(g.id(4, 16), 0), 1e-14);
  for (int i = 10; i <= 16; ++i)
    EXPECT_LE(unit(g.id(i, 3), 1), 1e-14) << "bone vertex x = " << i * g.h();
  int region_vertices = 0;
  for (int j = 8; j <= 12; ++j)
    for (int i = 7; i <= 11; ++i, ++region_vertices)
      EXPECT_LE(unit(g.id(i, j), 5), 1e-14) << "region vertex " << i << ", " << j;
  EXPECT_EQ(region_vertices, 25);
  for (int j = 6; j <= 18; ++j)
  {
    // Eq. 4 on the cage edges x = 1, y in [0.3, 0.9]: the hat functions of joints 3, 4, 5.
    const double y = j * g.h();
    Eigen::RowVectorXd expected = Eigen::RowVectorXd::Zero(6);
    if (y <= 0.6)
    {
      expected(2) = (0.6 - y) / 0.3;
      expected(3) = 1 - expected(2);
    }
    else
    {
      expected(3) = (0.9 - y) / 0.3;
      expected(4) = 1 - expected(3);
    }
    EXPECT_LE((r.W.row(g.id(20, j)) - expected).cwiseAbs().maxCoeff(), 1e-12) << "y = " << y;
  }
  EXPECT_GE(r.W.minCoeff(), 0.0);
  EXPECT_LE(r.W.maxCoeff(), 1.0);
  EXPECT_LE(statistic(r, "partition_error_before_normalization"), 1e-9);
  EXPECT_LE((r.W.rowwise().sum().array() - 1.0).abs().maxCoeff(), 1e-12);
  // The open cage's weights vanish where it does not reach (the left side) and are positive
  // next to it: its influence is local, as a handle's.
  EXPECT_LE(r.W.block(g.id(0, 10), 2, 1, 3).maxCoeff(), 1e-3);
  EXPECT_GT(r.W(g.id(19, 12), 3), 0.5);
}

TEST(MixedHandles, TriangleCageFacesIn3DAreLinear)
{
  // One face of the unit cube as a partial 3D cage (two triangles) and a point handle in the
  // opposite corner: on the face, the weights are the triangles' barycentric coordinates.
  const int n = 5;
  Eigen::MatrixXd V(n * n * n, 3);
  auto id = [&](int i, int j, int k) { return (k * n + j) * n + i; };
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        V.row(id(i, j, k)) << double(i) / (n - 1), double(j) / (n - 1), double(k) / (n - 1);
  Eigen::MatrixXi T(6 * (n - 1) * (n - 1) * (n - 1), 4);
  int t = 0;
  for (int k = 0; k + 1 < n; ++k)
    for (int j = 0; j + 1 < n; ++j)
      for (int i = 0; i + 1 < n; ++i)
      {
        int c[8];
        for (int b = 0; b < 8; ++b)
          c[b] = id(i + (b & 1), j + ((b >> 1) & 1), k + ((b >> 2) & 1));
        // Six tetrahedra around the diagonal c0 - c7.
        const int paths[6][2] = { { 1, 3 }, { 3, 2 }, { 2, 6 }, { 6, 4 }, { 4, 5 }, { 5, 1 } };
        for (const auto& p : paths)
          T.row(t++) << c[0], c[p[0]], c[p[1]], c[7];
      }
  Skeleton s;
  s.C.resize(5, 3);
  s.C << 1, 1, 1, 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0; // point handle; the face z = 0
  s.P.resize(1);
  s.P << 0;
  s.CF.resize(2, 3);
  s.CF << 1, 2, 3, 1, 3, 4;
  const BBWResult r = bounded_biharmonic_weights(V, T, mixed_bbw_handles(V, s));
  ASSERT_EQ(r.W.cols(), 5);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
    {
      const double x = double(i) / (n - 1), y = double(j) / (n - 1);
      // Triangle (0,0)-(1,0)-(1,1) below the diagonal, (0,0)-(1,1)-(0,1) above it.
      Eigen::RowVectorXd expected = Eigen::RowVectorXd::Zero(5);
      if (y <= x)
        expected.segment(1, 3) << 1 - x, x - y, y;
      else
        expected << 0, 1 - y, 0, x, y - x;
      EXPECT_LE((r.W.row(id(i, j, 0)) - expected).cwiseAbs().maxCoeff(), 1e-12) << x << ", " << y;
    }
  EXPECT_LE((r.W.row(id(n - 1, n - 1, n - 1)) - Eigen::RowVectorXd::Unit(5, 0)).norm(), 1e-14);
}

TEST(MixedHandles, Errors)
{
  const Square g = square(11);
  Skeleton base;
  base.C.resize(6, 2);
  base.C << 0.2, 0.2, 0.5, 0.2, 0.8, 0.2, 0.2, 0.8, 0.5, 0.8, 0.8, 0.8;
  // A bone that runs along a cage edge: the same mesh vertices fixed by both.
  Skeleton overlap = base;
  overlap.BE.resize(1, 2);
  overlap.BE << 0, 2;
  overlap.CF.resize(1, 2);
  overlap.CF << 3, 4;
  overlap.C.row(3) << 0.3, 0.2;
  overlap.C.row(4) << 0.7, 0.2;
  EXPECT_TRUE(throws_error([&] { mixed_bbw_handles(g.V, overlap); }, ErrorCode::InvalidArgument,
    { "bone 0", "cage vertex handle", "disjoint" }));
  // A joint that is both a point handle and a cage vertex (validate_skeleton).
  Skeleton shared = base;
  shared.P.resize(1);
  shared.P << 0;
  shared.CF.resize(1, 2);
  shared.CF << 0, 1;
  EXPECT_TRUE(throws_error([&] { mixed_bbw_handles(g.V, shared); }, ErrorCode::InvalidArgument,
    { "joint 0", "point handle", "cage vertex" }));
  // Two regions over the same vertex; a vertex region and a point handle's vertex.
  Skeleton point = base;
  point.P.resize(1);
  point.P << 0;
  EXPECT_TRUE(throws_error(
    [&] { mixed_bbw_handles(g.V, point, { { g.id(5, 5) }, { g.id(5, 5), g.id(5, 6) } }); },
    ErrorCode::InvalidArgument, { "mesh vertex " + std::to_string(g.id(5, 5)), "vertex region 0", "vertex region 1" }));
  EXPECT_TRUE(throws_error([&] { mixed_bbw_handles(g.V, point, { { g.id(2, 2) } }); },
    ErrorCode::InvalidArgument, { "point handle 0", "vertex region 0" }));
  // Empty handles: no handle at all, an empty vertex region, an empty polygon region, a region
  // between the mesh vertices, indices outside the mesh.
  EXPECT_TRUE(throws_error([&] { mixed_bbw_handles(g.V, Skeleton()); }, ErrorCode::EmptyInput));
  EXPECT_TRUE(throws_error([&] { mixed_bbw_handles(g.V, point, { {} }); }, ErrorCode::EmptyInput,
    { "vertex region 0" }));
  Skeleton empty_region = point;
  empty_region.regions.emplace_back(0, 2);
  EXPECT_TRUE(throws_error([&] { mixed_bbw_handles(g.V, empty_region); }, ErrorCode::EmptyInput,
    { "region 0" }));
  Skeleton small = point;
  small.C.row(1) << 0.52, 0.52;
  small.C.row(2) << 0.58, 0.52;
  small.C.row(3) << 0.55, 0.58;
  small.regions.push_back((Eigen::MatrixXi(3, 2) << 1, 2, 2, 3, 3, 1).finished());
  EXPECT_TRUE(throws_error([&] { mixed_bbw_handles(g.V, small); }, ErrorCode::InvalidArgument,
    { "region 0 holds no mesh vertex" }));
  EXPECT_TRUE(throws_error([&] { mixed_bbw_handles(g.V, point, { { 121 } }); },
    ErrorCode::InvalidArgument, { "vertex region 0", "121" }));
  // An open cage entirely outside the domain fixes nothing.
  Skeleton outside = point;
  outside.C.row(4) << 1.5, 0.2;
  outside.C.row(5) << 1.5, 0.8;
  outside.CF.resize(1, 2);
  outside.CF << 4, 5;
  EXPECT_TRUE(throws_error([&] { mixed_bbw_handles(g.V, outside); }, ErrorCode::InvalidArgument,
    { "cage vertex handle 0 (joint 4)", "no mesh vertex" }));
  // Shapes: triangles as 2D cage faces, a region of segments in 3D, a degenerate face.
  Skeleton triangles = point;
  triangles.CF.resize(1, 3);
  triangles.CF << 3, 4, 5;
  EXPECT_TRUE(throws_error([&] { validate_skeleton(triangles); }, ErrorCode::SizeMismatch,
    { "cage faces" }));
  Skeleton degenerate = point;
  degenerate.CF.resize(1, 2);
  degenerate.CF << 4, 4;
  EXPECT_TRUE(throws_error([&] { validate_skeleton(degenerate); }, ErrorCode::InvalidArgument,
    { "cage face 0", "degenerate" }));
  // Region vertex lists and a per-vertex brush need a given mesh, not one to be meshed.
  EXPECT_TRUE(throws_error(
    [&] {
      Cage boundary;
      boundary.V.resize(4, 2);
      boundary.V << 0, 0, 1, 0, 1, 1, 0, 1;
      WeightsSettings settings;
      settings.method = MethodId::BBW;
      const std::vector<std::vector<int>> regions{ { 0 } };
      WeightsInput in;
      in.skeleton = &point;
      in.domain_boundary = &boundary;
      in.points = &g.V;
      in.region_vertices = &regions;
      compute_weights(in, settings);
    },
    ErrorCode::InvalidArgument, { "given domain mesh" }));
}

TEST(ShapePreservationBrush, PerVertexToPerElementIsTheExactIntegral)
{
  // For a brush linear in x, y the per-element values times the areas sum to its integral over
  // the square: rho = x + 2 y integrates to 1.5.
  const Square g = square(9);
  const Eigen::VectorXd rho = g.V.col(0) + 2.0 * g.V.col(1);
  const Eigen::VectorXd element = shape_preservation_per_element(g.T, rho, g.V.rows());
  ASSERT_EQ(element.size(), g.T.rows());
  EXPECT_NEAR(element.dot(simplex_volumes(g.V, g.T)), 1.5, 1e-13);
  EXPECT_TRUE(throws_error([&] { shape_preservation_per_element(g.T, rho.head(5), g.V.rows()); },
    ErrorCode::SizeMismatch, { "5 values", "81" }));
  Eigen::VectorXd bad = rho;
  bad(7) = std::nan("");
  EXPECT_TRUE(throws_error([&] { shape_preservation_per_element(g.T, bad, g.V.rows()); },
    ErrorCode::NonFinite, { "vertex 7" }));
  bad(7) = -0.5;
  EXPECT_TRUE(throws_error([&] { shape_preservation_per_element(g.T, bad, g.V.rows()); },
    ErrorCode::InvalidArgument, { "negative", "vertex 7" }));
}

TEST(ShapePreservationBrush, APaintedDiskHasNearlyConstantWeights)
{
  // §3.3 / Fig. 5: a brush painted per vertex on a disk between three point handles (soft:
  // 1 inside radius 0.15, falling linearly to 0 at 0.2) makes every weight nearly constant
  // there. Measured: the mean |grad w| over the disk's triangles, with and without the brush.
  const Square g = square(31);
  Skeleton s;
  s.C.resize(3, 2);
  s.C << 0.1, 0.5, 0.9, 0.5, 0.5, 0.1;
  s.P.resize(3);
  s.P << 0, 1, 2;
  const double strength = 1e4;
  Eigen::VectorXd rho(g.V.rows());
  for (Eigen::Index i = 0; i < g.V.rows(); ++i)
  {
    const double r = (g.V.row(i) - Eigen::RowVector2d(0.5, 0.55)).norm();
    rho(i) = strength * std::clamp((0.2 - r) / 0.05, 0.0, 1.0);
  }
  const WeightsResult plain = solve_mixed(g, s, false);
  const WeightsResult painted = solve_mixed(g, s, false, nullptr, &rho);
  const Eigen::SparseMatrix<double> G = gradient_operator(g.V, g.T);
  auto mean_gradient = [&](const DenseWeights& W) {
    double sum = 0;
    int count = 0;
    for (Eigen::Index t = 0; t < g.T.rows(); ++t)
    {
      bool inside = true;
      for (int k = 0; k < 3; ++k)
        inside = inside && rho(g.T(t, k)) >= strength;
      if (!inside)
        continue;
      for (Eigen::Index j = 0; j < W.cols(); ++j)
      {
        const Eigen::VectorXd grad = G * W.col(j);
        sum += grad.segment(2 * t, 2).norm();
        ++count;
      }
    }
    return sum / count;
  };
  const double before = mean_gradient(plain.W), after = mean_gradient(painted.W);
  std::cout << "[ info ] mean |grad w| in the painted disk: " << before << " -> " << after
            << " (ratio " << after / before << ")\n";
  EXPECT_LT(after, 0.05 * before);
  EXPECT_GE(painted.W.minCoeff(), 0.0);
  EXPECT_LE((painted.W.rowwise().sum().array() - 1.0).abs().maxCoeff(), 1e-12);
  // A zero brush is no brush.
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(g.V.rows());
  EXPECT_LE((solve_mixed(g, s, false, nullptr, &zero).W - plain.W).cwiseAbs().maxCoeff(), 1e-13);
  // A brush of the wrong size is refused with the sizes named.
  const Eigen::VectorXd short_brush = rho.head(10);
  EXPECT_TRUE(throws_error([&] { solve_mixed(g, s, false, nullptr, &short_brush); },
    ErrorCode::SizeMismatch, { "10 values" }));
}

} // namespace
