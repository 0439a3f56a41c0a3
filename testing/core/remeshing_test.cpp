// Tests of core/surface/remeshing: semiregular remeshing by weighted averages (Panozzo et al.
// 2013, §4.1, Fig. 7): exact subdivision on a plane, smoothing that keeps a regular grid,
// vertices on a sphere, errors.
#include "core/surface/remeshing.h"
#include "error_matchers.h"
#include "surface_catalogue.h"

#include <gtest/gtest.h>

using namespace bary;
using bary::test::throws_error;

namespace
{

/// The 3 x 3 grid of points of [-0.8, 0.8]^2 and its 2 x 2 quads.
void coarse_square(Eigen::MatrixXd& P, Eigen::MatrixXi& Q)
{
  P.resize(9, 3);
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i)
      P.row(3 * j + i) << -0.8 + 0.8 * i, -0.8 + 0.8 * j, 0.0;
  Q.resize(4, 4);
  int q = 0;
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i)
      Q.row(q++) << 3 * j + i, 3 * j + i + 1, 3 * (j + 1) + i + 1, 3 * (j + 1) + i;
}

} // namespace

TEST(Remeshing, PlaneSubdivisionIsExactAndSmoothingKeepsARegularGrid)
{
  const auto g = test::flat_grid(12);
  const SurfaceMesh m(g.V, g.F);
  const WeightedAverages wa(m, m.V);
  Eigen::MatrixXd P;
  Eigen::MatrixXi Q;
  coarse_square(P, Q);
  for (const int smoothing : { 0, 5 })
  {
    RemeshOptions o;
    o.levels = 2;
    o.smoothing_steps = smoothing;
    const QuadRemesh r = semiregular_remesh(wa, closest_surface_points(m, P), Q, o);
    EXPECT_EQ(r.quads.rows(), 4 * 16);
    EXPECT_EQ(r.points.size(), 81u); // a 9 x 9 grid
    EXPECT_EQ(r.failures, 0);
    const Eigen::MatrixXd X = surface_point_positions(m.F, m.V, r.points);
    // Every vertex is a node of the 9 x 9 grid of spacing 0.2 (each exactly once).
    std::vector<int> seen(81, 0);
    for (Index v = 0; v < X.rows(); ++v)
    {
      const double i = (X(v, 0) + 0.8) / 0.2, j = (X(v, 1) + 0.8) / 0.2;
      EXPECT_NEAR(i, std::round(i), 1e-10);
      EXPECT_NEAR(j, std::round(j), 1e-10);
      ++seen[static_cast<int>(std::round(j)) * 9 + static_cast<int>(std::round(i))];
    }
    EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), 81);
  }
}

TEST(Remeshing, SphereVerticesLieOnTheSurface)
{
  const auto s = test::icosphere(4);
  const SurfaceMesh m(s.V, s.F);
  const WeightedAverages wa(m, test::lift8(m.V));
  // A quad patch around the north pole: 3 x 3 points on the sphere.
  Eigen::MatrixXd P(9, 3);
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i)
      P.row(3 * j + i) = Eigen::RowVector3d(-0.4 + 0.4 * i, -0.4 + 0.4 * j, 1.0).normalized();
  Eigen::MatrixXi Q(4, 4);
  Q << 0, 1, 4, 3, 1, 2, 5, 4, 3, 4, 7, 6, 4, 5, 8, 7;
  const QuadRemesh r = semiregular_remesh(wa, closest_surface_points(m, P), Q);
  EXPECT_EQ(r.failures, 0);
  EXPECT_EQ(r.quads.rows(), 64);
  const Eigen::MatrixXd X = surface_point_positions(m.F, m.V, r.points);
  for (Index v = 0; v < X.rows(); ++v)
    EXPECT_NEAR(X.row(v).norm(), 1.0, 0.01); // on the icosphere (its flat triangles)
  // The boundary stays put: the corners are the coarse corners.
  const Eigen::MatrixXd C = surface_point_positions(m.F, m.V, closest_surface_points(m, P));
  for (const int corner : { 0, 2, 6, 8 })
    EXPECT_LT((X.row(corner) - C.row(corner)).norm(), 1e-12);
}

TEST(Remeshing, Errors)
{
  const auto g = test::flat_grid(4);
  const SurfaceMesh m(g.V, g.F);
  const WeightedAverages wa(m, m.V);
  Eigen::MatrixXd P;
  Eigen::MatrixXi Q;
  coarse_square(P, Q);
  const auto points = closest_surface_points(m, P);
  EXPECT_TRUE(throws_error([&] { semiregular_remesh(wa, points, Q.leftCols(3)); }, ErrorCode::SizeMismatch, { "4 indices" }));
  Eigen::MatrixXi bad = Q;
  bad(1, 2) = 42;
  EXPECT_TRUE(throws_error([&] { semiregular_remesh(wa, points, bad); }, ErrorCode::InvalidArgument, { "quad 1", "vertex 42" }));
  RemeshOptions o;
  o.levels = 9;
  EXPECT_TRUE(throws_error([&] { semiregular_remesh(wa, points, Q, o); }, ErrorCode::InvalidArgument, { "[0, 8]" }));
  EXPECT_TRUE(throws_error([&] { semiregular_remesh(wa, points, Eigen::MatrixXi(0, 4)); }, ErrorCode::EmptyInput, { "no quads" }));
}
