// Heat-method geodesic distances (core/solvers/geodesic_heat.h).
//
// References are exact distances computed here without the heat method: the Euclidean distance
// in convex domains, and in the L-shaped polygon the shortest path around its reflex corner
// (straight when the source sees the point, source -> corner -> point otherwise).
//
// Tolerances. The heat method is first order in the mesh size h away from the source (Crane et
// al. 2013, §3.3) and smooths the distance near the source over ~sqrt(t) = h; the measured errors
// (printed by the tests) were:
// - square, source at a corner, 500 -> 2000 -> 8000 target cells: max error 0.039 -> 0.024 ->
//   0.014 (first order: asserted >= 1.4 x smaller per refinement), mean 0.0087 -> 0.0088 -> 0.0050
//   (diameter 1.41);
// - L (6000 cells), the 150 vertices whose path around the reflex corner is > 0.08 longer than
//   the blocked straight segment: mean error 0.017, max 0.021 (diameter 2.83), and the heat
//   distance takes the whole detour (>= 70% of it asserted, 106% measured);
// - cube, 6269 tetrahedra: mean error 0.020, max 0.096 (diameter 1.73).
#include "cage_catalogue.h"
#include "core/meshing/domain_mesh.h"
#include "core/common/error.h"
#include "core/solvers/fem_operators.h"
#include "core/solvers/geodesic_heat.h"
#include "error_matchers.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

namespace bary
{
namespace
{

struct ErrorStats
{
  double mean = 0, max = 0;
};

/// Errors of column 0 of D against exact(v) over vertices farther than `skip` from the source.
template<class Exact>
ErrorStats errors(const DomainMesh& mesh, const Eigen::MatrixXd& D, int source, double skip,
  Exact&& exact)
{
  ErrorStats e;
  int count = 0;
  for (Index v = 0; v < mesh.V.rows(); ++v)
  {
    if ((mesh.V.row(v) - mesh.V.row(source)).norm() < skip)
      continue;
    const double err = std::abs(D(v, 0) - exact(v));
    e.mean += err;
    e.max = std::max(e.max, err);
    ++count;
  }
  e.mean /= std::max(count, 1);
  return e;
}

DomainMesh square_mesh(int cells)
{
  PolygonMeshOptions o;
  o.target_cells = cells;
  return mesh_polygon(test::unit_square(), o);
}

TEST(GeodesicHeat, ConvergesOnTheSquare)
{
  // Source at the corner (0, 0): the exact distance is |x|.
  std::vector<ErrorStats> stats;
  for (int cells : { 500, 2000, 8000 })
  {
    const DomainMesh mesh = square_mesh(cells);
    const Eigen::MatrixXd D = heat_geodesic_distances(mesh.V, mesh.T, Eigen::VectorXi::Constant(1, 0));
    EXPECT_EQ(D(0, 0), 0.0);
    const ErrorStats e =
      errors(mesh, D, 0, 0.0, [&](Index v) { return mesh.V.row(v).norm(); });
    std::printf("square, %d target cells (%ld vertices): mean error %.4f, max %.4f (diameter %.4f)\n",
      cells, static_cast<long>(mesh.V.rows()), e.mean, e.max, std::sqrt(2.0));
    stats.push_back(e);
  }
  // The max error is first order (4x the cells: h / 2); the mean error, dominated by the
  // smoothing near the source and the boundary, decreases more slowly.
  EXPECT_LT(stats[1].max * 1.4, stats[0].max);
  EXPECT_LT(stats[2].max * 1.4, stats[1].max);
  EXPECT_LT(stats[2].mean, stats[0].mean);
  EXPECT_LT(stats[2].mean, 0.005 * std::sqrt(2.0));
  EXPECT_LT(stats[2].max, 0.015 * std::sqrt(2.0));
}

TEST(GeodesicHeat, GoesAroundTheReflexCornerOfAnL)
{
  // L = [0,2]^2 minus [1,2] x [1,2]; reflex corner r = (1,1). From the source (2,0) the points
  // of the upper arm with x < 1 and y > 1 - (x - 1)... are hidden behind the corner: their
  // geodesic distance is |s - r| + |r - p|.
  PolygonMeshOptions o;
  o.target_cells = 6000;
  const DomainMesh mesh = mesh_polygon(test::l_polygon(), o);
  int source = -1;
  for (Index v = 0; v < mesh.V.rows(); ++v)
    if ((mesh.V.row(v) - Eigen::RowVector2d(2, 0)).norm() < 1e-12)
      source = static_cast<int>(v);
  ASSERT_GE(source, 0);
  const Eigen::MatrixXd D =
    heat_geodesic_distances(mesh.V, mesh.T, Eigen::VectorXi::Constant(1, source));
  const Eigen::Vector2d s(2, 0), r(1, 1);
  // p is hidden iff it lies strictly above the line through s and r (y > 2 - x) with y > 1.
  auto hidden = [&](const Eigen::Vector2d& p) { return p.y() > 1.0 && p.y() > 2.0 - p.x() + 1e-9; };
  auto exact = [&](Index v) {
    const Eigen::Vector2d p = mesh.V.row(v).transpose();
    return hidden(p) ? (s - r).norm() + (r - p).norm() : (s - p).norm();
  };
  // Points where the detour around the corner is large (geodesic - straight > 0.08): the heat
  // distance must follow the detour, not the (blocked) straight segment.
  double mean_hidden = 0, max_hidden = 0, worst_fraction = std::numeric_limits<double>::infinity();
  int count = 0;
  for (Index v = 0; v < mesh.V.rows(); ++v)
  {
    const Eigen::Vector2d p = mesh.V.row(v).transpose();
    const double detour = exact(v) - (s - p).norm();
    if (detour < 0.08)
      continue;
    const double err = std::abs(D(v, 0) - exact(v));
    mean_hidden += err;
    max_hidden = std::max(max_hidden, err);
    worst_fraction = std::min(worst_fraction, (D(v, 0) - (s - p).norm()) / detour);
    ++count;
  }
  ASSERT_GT(count, 50);
  mean_hidden /= count;
  const ErrorStats all = errors(mesh, D, source, 0.0, exact);
  const double diameter = std::sqrt(8.0);
  std::printf("L: %d points with a detour > 0.08: mean error %.4f, max %.4f, smallest fraction of "
              "the detour taken %.2f; all points: mean %.4f, max %.4f (diameter %.3f)\n",
    count, mean_hidden, max_hidden, worst_fraction, all.mean, all.max, diameter);
  EXPECT_LT(mean_hidden, 0.01 * diameter);
  EXPECT_LT(max_hidden, 0.02 * diameter);
  EXPECT_LT(all.mean, 0.01 * diameter);
  EXPECT_GT(worst_fraction, 0.7);
}

TEST(GeodesicHeat, CubeTetrahedra)
{
  SurfaceMeshOptions o;
  o.target_cells = 2000;
  const DomainMesh mesh = mesh_closed_surface(test::unit_cube(), o);
  const GeodesicHeat heat(mesh.V, mesh.T);
  EXPECT_GT(heat.time_step(), 0.0);
  EXPECT_NEAR(heat.time_step(), heat.mean_edge_length() * heat.mean_edge_length(), 1e-15);
  Index zero = -1;
  const Eigen::MatrixXd D = heat.distances(Eigen::VectorXi::Constant(1, 0), {}, &zero);
  EXPECT_EQ(zero, 0);
  const ErrorStats e = errors(mesh, D, 0, 0.0, [&](Index v) { return mesh.V.row(v).norm(); });
  std::printf("cube, %ld tetrahedra: mean error %.4f, max %.4f (diameter %.4f)\n",
    static_cast<long>(mesh.T.rows()), e.mean, e.max, std::sqrt(3.0));
  EXPECT_LT(e.mean, 0.03 * std::sqrt(3.0));
  EXPECT_LT(e.max, 0.1 * std::sqrt(3.0));
}

TEST(GeodesicHeat, ManySourcesEqualOneAtATimeAndDoNotDependOnThreads)
{
  const DomainMesh mesh = square_mesh(1500);
  const Eigen::VectorXi sources = (Eigen::VectorXi(4) << 0, 1, 2, 3).finished();
  GeodesicHeatOptions one;
  one.threads = 1;
  GeodesicHeatOptions two;
  two.threads = 2;
  const GeodesicHeat h1(mesh.V, mesh.T, one), h2(mesh.V, mesh.T, two);
  const Eigen::MatrixXd all = h1.distances(sources);
  EXPECT_EQ((all - h2.distances(sources)).cwiseAbs().maxCoeff(), 0.0);
  for (Index j = 0; j < sources.size(); ++j)
  {
    const Eigen::MatrixXd single = h1.distances(sources.segment(j, 1));
    EXPECT_LE((single.col(0) - all.col(j)).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_EQ(all(sources(j), j), 0.0);
  }
  // Symmetry of the square: distance from corner 0 at corner 2 equals from 2 at 0.
  EXPECT_NEAR(all(2, 0), all(0, 2), 0.02);
  // Precomputed operators give the same factorizations and distances.
  const GeodesicHeat h3(mesh.V, mesh.T, gradient_operator(mesh.V, mesh.T),
    simplex_volumes(mesh.V, mesh.T), one);
  EXPECT_EQ((all - h3.distances(sources)).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_TRUE(test::throws_error(
    [&] { GeodesicHeat(mesh.V, mesh.T, gradient_operator(mesh.V, mesh.T), Eigen::VectorXd(3)); },
    ErrorCode::SizeMismatch, { "volumes" }));
}

TEST(GeodesicHeat, DistanceToASetIsNearTheMinimumOverItsSources)
{
  const DomainMesh mesh = square_mesh(3000);
  const GeodesicHeat heat(mesh.V, mesh.T);
  const Eigen::VectorXd d = heat.distance_to_set({ 0, 2 });
  const Eigen::MatrixXd single = heat.distances((Eigen::VectorXi(2) << 0, 2).finished());
  EXPECT_EQ(std::min(d(0), d(2)), 0.0);
  double worst = 0.0;
  for (Index v = 0; v < mesh.V.rows(); ++v)
    worst = std::max(worst, std::abs(d(v) - single.row(v).minCoeff()));
  std::printf("set of two corners: max |d - min(d0, d2)| = %.4f\n", worst);
  EXPECT_LT(worst, 0.05);
}

TEST(GeodesicHeat, OtherComponentsAreInfinitelyFar)
{
  // Two separate triangles.
  Eigen::MatrixXd V(6, 2);
  V << 0, 0, 1, 0, 0, 1, 3, 0, 4, 0, 3, 1;
  Eigen::MatrixXi T(2, 3);
  T << 0, 1, 2, 3, 4, 5;
  const GeodesicHeat heat(V, T);
  const Eigen::MatrixXd D = heat.distances(Eigen::VectorXi::Constant(1, 4));
  for (int v = 0; v < 3; ++v)
    EXPECT_TRUE(std::isinf(D(v, 0)));
  EXPECT_EQ(D(4, 0), 0.0);
  EXPECT_TRUE(std::isfinite(D(3, 0)) && std::isfinite(D(5, 0)));
  const Eigen::VectorXd s = heat.distance_to_set({ 0, 3 });
  EXPECT_EQ(s(0), 0.0);
  EXPECT_EQ(s(3), 0.0);
}

TEST(GeodesicHeat, Errors)
{
  const DomainMesh mesh = square_mesh(200);
  GeodesicHeatOptions o;
  o.time_factor = 0.0;
  EXPECT_TRUE(test::throws_error([&] { GeodesicHeat(mesh.V, mesh.T, o); },
    ErrorCode::InvalidArgument, { "time_factor" }));
  o = {};
  o.threads = -1;
  EXPECT_TRUE(test::throws_error(
    [&] { GeodesicHeat(mesh.V, mesh.T, o); }, ErrorCode::InvalidArgument, { "threads" }));
  const GeodesicHeat heat(mesh.V, mesh.T);
  EXPECT_TRUE(test::throws_error(
    [&] { heat.distances(Eigen::VectorXi::Constant(1, static_cast<int>(mesh.V.rows()))); },
    ErrorCode::InvalidArgument, { "source 0", "outside" }));
  EXPECT_TRUE(test::throws_error(
    [&] { heat.distance_to_set({}); }, ErrorCode::InvalidArgument, { "at least one" }));
  // an unreferenced vertex
  Eigen::MatrixXd V(4, 2);
  V << 0, 0, 1, 0, 0, 1, 5, 5;
  Eigen::MatrixXi T(1, 3);
  T << 0, 1, 2;
  EXPECT_TRUE(test::throws_error(
    [&] { GeodesicHeat(V, T); }, ErrorCode::InvalidArgument, { "vertex 3", "no element" }));
  // degenerate element (from fem_operators)
  V.row(2) << 2, 0;
  EXPECT_TRUE(test::throws_error([&] { GeodesicHeat(V.topRows(3), T); }, ErrorCode::InvalidArgument,
    { "degenerate" }));
  // cancellation
  EXPECT_TRUE(test::throws_error(
    [&] { heat.distances(Eigen::VectorXi::Constant(1, 0), [](double) { return false; }); },
    ErrorCode::Cancelled));
  // no sources: an empty matrix
  EXPECT_EQ(heat.distances(Eigen::VectorXi()).cols(), 0);
}

} // namespace
} // namespace bary
