// Harmonic coordinates (core/coordinates/harmonic_coordinates.h).
//
// Tolerances:
// - Partition of unity and linear reproduction hold exactly for the discrete solution (constants
//   and linear functions are discrete-harmonic for P1 elements), so only the solver's round-off
//   remains: the factorization's backward error times cond(K_II) ~ 1e-16 * 1e4 for these mesh
//   sizes; we allow 1e-10 (reproduction relative to the cage diameter).
// - Against the analytic solution (square: bilinear functions), P1 elements converge like
//   O(h^2); the test measures the order over three meshes instead of fixing an absolute error.
#include "cage_catalogue.h"
#include "core/common/error.h"
#include "core/coordinates/harmonic_coordinates.h"
#include "error_matchers.h"

#include <gtest/gtest.h>

#include <cmath>

namespace bary
{
namespace
{
constexpr double kSolverTol = 1e-10;

HarmonicOptions with_cells(int cells)
{
  HarmonicOptions o;
  o.polygon_mesh.target_cells = cells;
  o.surface_mesh.target_cells = cells;
  return o;
}

/// Bilinear hat of the unit square's corner i (the catalogue's square is (0,0), (1,0), (1,1),
/// (0,1)): harmonic, and linear along every edge, hence the exact harmonic coordinate.
double bilinear(int i, double x, double y)
{
  switch (i)
  {
    case 0: return (1 - x) * (1 - y);
    case 1: return x * (1 - y);
    case 2: return x * y;
    default: return (1 - x) * y;
  }
}

void expect_properties(const HarmonicCoordinates& hc, const Points& P, double nonneg_tol)
{
  const DenseWeights W = hc.evaluate(P);
  const Cage& cage = hc.cage();
  for (Index p = 0; p < P.rows(); ++p)
  {
    EXPECT_NEAR(W.row(p).sum(), 1.0, kSolverTol) << "point " << p;
    const Eigen::RowVectorXd x = W.row(p) * cage.V;
    EXPECT_LE((x - P.row(p)).norm(), kSolverTol * cage.diameter()) << "point " << p;
    EXPECT_GE(W.row(p).minCoeff(), -nonneg_tol) << "point " << p;
  }
}
} // namespace

TEST(HarmonicCoordinates, SquareConvergesToBilinearAtSecondOrder)
{
  const Cage square = test::unit_square();
  const Points P = test::sample_inside(square, 400, 1e-3, 11);
  std::vector<double> h, error;
  for (int cells : { 200, 800, 3200 })
  {
    const HarmonicCoordinates hc(square, with_cells(cells));
    const DenseWeights W = hc.evaluate(P);
    double e = 0.0;
    for (Index p = 0; p < P.rows(); ++p)
      for (int i = 0; i < 4; ++i)
        e = std::max(e, std::abs(W(p, i) - bilinear(i, P(p, 0), P(p, 1))));
    h.push_back(std::sqrt(1.0 / hc.mesh().T.rows())); // typical edge length
    error.push_back(e);
  }
  for (std::size_t k = 0; k + 1 < h.size(); ++k)
  {
    const double order = std::log(error[k] / error[k + 1]) / std::log(h[k] / h[k + 1]);
    EXPECT_GT(order, 1.6) << "observed order between meshes " << k << " and " << k + 1
                          << " (errors " << error[k] << ", " << error[k + 1] << ")";
  }
  EXPECT_LT(error.back(), 2e-3);
}

TEST(HarmonicCoordinates, PropertiesOnTheCatalogue2D)
{
  for (const auto& entry : test::builtin_cages_2d())
  {
    SCOPED_TRACE(entry.name);
    const HarmonicCoordinates hc(entry.cage, with_cells(1500));
    // Lagrange: at the cage vertices (mesh vertices) the weights are the unit vectors.
    const DenseWeights Wv = hc.evaluate(entry.cage.V);
    EXPECT_LE((Wv - DenseWeights::Identity(entry.cage.num_controls(), entry.cage.num_controls()))
                .cwiseAbs()
                .maxCoeff(),
      1e-12);
    // 2D CGAL meshes are (constrained) Delaunay: the discrete maximum principle holds.
    expect_properties(hc, test::sample_inside(entry.cage, 300, 1e-3, 5), 1e-12);
    EXPECT_LE(hc.report().max_residual, 1e-10);
  }
}

TEST(HarmonicCoordinates, LinearOnCageEdges)
{
  const Cage cage = test::l_polygon();
  const HarmonicCoordinates hc(cage, with_cells(800));
  const Index n = cage.num_controls();
  for (Index i = 0; i < n; ++i)
  {
    const Index j = (i + 1) % n;
    for (double t : { 0.25, 0.5, 0.8 })
    {
      const Points x = (1 - t) * cage.V.row(i) + t * cage.V.row(j);
      const DenseWeights W = hc.evaluate(x, OutsidePolicy::Nearest);
      Eigen::RowVectorXd expected = Eigen::RowVectorXd::Zero(n);
      expected(i) = 1 - t;
      expected(j) = t;
      EXPECT_LE((W.row(0) - expected).cwiseAbs().maxCoeff(), 1e-12) << "edge " << i << " t " << t;
    }
  }
}

TEST(HarmonicCoordinates, PropertiesOnCatalogue3D)
{
  for (const Cage& cage : { test::unit_cube(), test::octahedron(), test::u_box() })
  {
    const HarmonicCoordinates hc(cage, with_cells(4000));
    const DenseWeights Wv = hc.evaluate(cage.V);
    EXPECT_LE(
      (Wv - DenseWeights::Identity(cage.num_controls(), cage.num_controls())).cwiseAbs().maxCoeff(),
      1e-12);
    // 3D P1 elements have no discrete maximum principle: small negative values are possible
    expect_properties(hc, test::sample_inside(cage, 300, 1e-3, 7), 1e-2);
    EXPECT_LE(hc.report().max_residual, 1e-10);
    EXPECT_GT(hc.report().mesh_cells, 1000);
  }
}

TEST(HarmonicCoordinates, BarycentricOnCageFaces3D)
{
  const Cage cube = test::unit_cube();
  const HarmonicCoordinates hc(cube, with_cells(2000));
  for (Index f = 0; f < cube.F.rows(); ++f)
  {
    const Eigen::Vector3d b(0.2, 0.3, 0.5);
    Points x = Points::Zero(1, 3);
    for (int k = 0; k < 3; ++k)
      x.row(0) += b(k) * cube.V.row(cube.F(f, k));
    const DenseWeights W = hc.evaluate(x, OutsidePolicy::Nearest);
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(W(0, cube.F(f, k)), b(k), 1e-12) << "face " << f;
    EXPECT_NEAR(W.row(0).sum(), 1.0, 1e-12);
  }
}

// The Dirichlet values are hat functions: in [0, 1] and summing to 1 exactly as far as a double
// can say it, even where rounding puts a boundary vertex a hair off its edge or face (a value of
// -1e-16 there made BBW refuse the kidney's given tet mesh: Eq. 6 bounds every fixed value).
TEST(HarmonicCoordinates, BoundaryValuesAreBoundedAndSumToOne)
{
  for (const Cage& cage : { test::noisy_icosphere(1, 0.1, 7), test::regular_polygon(11, 1.3) })
  {
    const int dim = cage.dimension();
    // the cage's edges: a polygon's consecutive vertices, a surface's triangle sides
    std::vector<std::pair<Index, Index>> edges;
    if (dim == 2)
      for (Index i = 0; i < cage.V.rows(); ++i)
        edges.emplace_back(i, (i + 1) % cage.V.rows());
    else
      for (Index f = 0; f < cage.F.rows(); ++f)
        for (int e = 0; e < 3; ++e)
          edges.emplace_back(cage.F(f, e), cage.F(f, (e + 1) % 3));
    std::vector<Eigen::RowVectorXd> points;
    for (std::size_t e = 0; e < edges.size(); ++e)
      for (int s = 1; s < 40; ++s)
      {
        // a point on the edge computed in floating point
        const double t = 0.0137 * s + 1e-3 * static_cast<double>(e % 7);
        points.push_back((1.0 - t) * cage.V.row(edges[e].first) + t * cage.V.row(edges[e].second));
      }
    ASSERT_FALSE(points.empty());
    Eigen::MatrixXd V(static_cast<Index>(points.size()), dim);
    std::vector<int> boundary;
    for (std::size_t k = 0; k < points.size(); ++k)
    {
      V.row(static_cast<Index>(k)) = points[k];
      boundary.push_back(static_cast<int>(k));
    }
    const DenseWeights values = cage_boundary_values(cage, V, boundary, 1e-9);
    EXPECT_GE(values.minCoeff(), 0.0) << dim << "D";
    EXPECT_LE(values.maxCoeff(), 1.0) << dim << "D";
    for (Index k = 0; k < values.rows(); ++k)
      ASSERT_NEAR(values.row(k).sum(), 1.0, 4e-16) << dim << "D, point " << k;
    // and still the interpolant: the values reproduce the point to rounding
    EXPECT_LE((values * cage.V - V).cwiseAbs().maxCoeff(), 1e-12 * cage.diameter());
  }
}

TEST(HarmonicCoordinates, InsertedPointsAreMeshVertices)
{
  const Cage cage = test::u_polygon();
  const Points P = test::sample_inside(cage, 50, 1e-2, 3);
  HarmonicOptions options = with_cells(500);
  options.polygon_mesh.steiner_points = P;
  const HarmonicCoordinates hc(cage, options);
  for (Index s = 0; s < P.rows(); ++s)
  {
    const int v = hc.mesh().steiner_vertex(s);
    ASSERT_GE(v, 0) << "point " << s << " is inside and must be inserted";
    EXPECT_EQ((hc.mesh().V.row(v) - P.row(s)).norm(), 0.0);
    // evaluating at an inserted point returns that vertex's finite-element weights
    EXPECT_LE((hc.evaluate(P.row(s)).row(0) - hc.mesh_weights().row(v)).cwiseAbs().maxCoeff(), 1e-14);
  }
}

TEST(HarmonicCoordinates, OutsidePolicies)
{
  const Cage square = test::unit_square();
  const HarmonicCoordinates hc(square, with_cells(300));
  Points P(3, 2);
  P << 0.5, 0.5, 1.5, 0.5, -1, -1;
  EXPECT_TRUE(test::throws_error([&] { hc.evaluate(P); }, ErrorCode::PointsOutside,
    { "2 of 3 points lie outside", "point 1" }));
  std::vector<Index> outside;
  const DenseWeights nearest = hc.evaluate(P, OutsidePolicy::Nearest, &outside);
  EXPECT_EQ(outside, (std::vector<Index>{ 1, 2 }));
  // nearest point of (1.5, 0.5) is (1, 0.5): weights of corners 1 and 2 are 1/2
  EXPECT_NEAR(nearest(1, 1), 0.5, 1e-12);
  EXPECT_NEAR(nearest(1, 2), 0.5, 1e-12);
  // nearest point of (-1, -1) is corner 0
  EXPECT_NEAR(nearest(2, 0), 1.0, 1e-12);
  const DenseWeights nan = hc.evaluate(P, OutsidePolicy::NaN, &outside);
  EXPECT_TRUE(nan.row(0).allFinite());
  EXPECT_TRUE(std::isnan(nan(1, 0)) && std::isnan(nan(2, 3)));
}

TEST(HarmonicCoordinates, MeshWhoseBoundaryLeavesTheCageIsRejected)
{
  const Cage square = test::unit_square();
  const HarmonicCoordinates good(square, with_cells(100));
  DomainMesh mesh = good.mesh();
  mesh.V.row(mesh.boundary_vertices.back()) *= 1.01; // a boundary vertex off the cage
  bool on_corner = false;
  for (Index i = 0; i < mesh.control_vertex.size(); ++i)
    on_corner = on_corner || mesh.control_vertex(i) == mesh.boundary_vertices.back();
  EXPECT_TRUE(test::throws_error([&] { HarmonicCoordinates h(square, mesh); },
    ErrorCode::InvalidArgument, { on_corner ? "cage vertex" : "does not lie on the cage" }));
}

TEST(HarmonicCoordinates, InvalidCageAndCancellation)
{
  Cage bowtie;
  bowtie.V.resize(4, 2);
  bowtie.V << 0, 0, 1, 1, 1, 0, 0, 1;
  EXPECT_TRUE(test::throws_error([&] { HarmonicCoordinates h(bowtie); }, ErrorCode::InvalidCage, { "not simple" }));
  int calls = 0;
  EXPECT_TRUE(test::throws_error(
    [&] { HarmonicCoordinates h(test::unit_square(), with_cells(200), [&](double) { return ++calls < 2; }); },
    ErrorCode::Cancelled, { "cancelled" }));
}

} // namespace bary
