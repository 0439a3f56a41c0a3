// Tests for core/meshing/mesh_point_locator.h: point location and piecewise-linear interpolation on
// triangle and tetrahedron meshes made by domain_mesh.h.
//
// Properties: barycentric coordinates of inside points are non-negative and reproduce the point;
// interpolating the vertex coordinates reproduces the query (linear precision); mesh vertices
// get their own row; points on shared edges/faces get the same value from every element;
// outside points under each policy; thread-count independence; agreement with an independent
// brute-force search over all elements; validation; progress and cancellation.
//
// Tolerances. u = 2^-53 ~ 1.1e-16. The barycentric coordinates come from Cramer's rule on the
// element's edge vectors: each is a ratio of determinants accurate to a few u relative to the
// element's size, so sum_k lambda_k v_k - x is a few u times the element's coordinates: 1e-12
// of the mesh diameter leaves a wide margin. Their sum is 1 to one rounding (lambda_0 =
// 1 - the others): 1e-14.
#include "cage_catalogue.h"
#include "core/meshing/domain_mesh.h"
#include "core/common/error.h"
#include "core/meshing/mesh_point_locator.h"
#include "error_matchers.h"

#include <Eigen/Geometry>

#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace
{

using bary::Cage;
using bary::DenseWeights;
using bary::DomainMesh;
using bary::ErrorCode;
using bary::Index;
using bary::MeshPointLocator;
using bary::OutsidePolicy;
using bary::Points;
using bary::test::throws_error;

/// A meshed cage, built once per test program.
struct MeshCase
{
  std::string name;
  Cage cage;
  DomainMesh mesh;
};

const MeshCase& mesh_case(const std::string& name)
{
  static std::map<std::string, std::unique_ptr<MeshCase>> cache;
  auto& slot = cache[name];
  if (!slot)
  {
    slot = std::make_unique<MeshCase>();
    slot->name = name;
    if (name == "square")
    {
      slot->cage = bary::test::unit_square();
      slot->mesh = bary::mesh_polygon(slot->cage); // 3000 cells
    }
    else if (name == "u_shape")
    {
      slot->cage = bary::test::u_polygon();
      bary::PolygonMeshOptions o;
      o.target_cells = 500;
      slot->mesh = bary::mesh_polygon(slot->cage, o);
    }
    else if (name == "cube")
    {
      slot->cage = bary::test::unit_cube();
      bary::SurfaceMeshOptions o;
      o.max_volume = 1e-3;
      slot->mesh = bary::mesh_closed_surface(slot->cage, o);
    }
    else // u_box
    {
      slot->cage = bary::test::u_box();
      bary::SurfaceMeshOptions o;
      o.max_volume = 2e-2;
      slot->mesh = bary::mesh_closed_surface(slot->cage, o);
    }
  }
  return *slot;
}

/// Vertex positions followed by a column of ones: #V by dim+1.
DenseWeights coordinates_and_one(const Eigen::MatrixXd& V)
{
  DenseWeights W(V.rows(), V.cols() + 1);
  W.leftCols(V.cols()) = V;
  W.col(V.cols()).setOnes();
  return W;
}

DenseWeights random_weights(Index rows, Index cols, std::uint64_t seed)
{
  bary::test::Rng rng(seed);
  DenseWeights W(rows, cols);
  for (Index i = 0; i < rows; ++i)
    for (Index j = 0; j < cols; ++j)
      W(i, j) = rng.uniform(-1.0, 1.0);
  return W;
}

Eigen::VectorXd point_of(const MeshPointLocator::Location& loc, const DomainMesh& mesh)
{
  Eigen::VectorXd p = Eigen::VectorXd::Zero(mesh.V.cols());
  for (Index k = 0; k <= mesh.V.cols(); ++k)
    p += loc.barycentric(k) * mesh.V.row(mesh.T(loc.element, k)).transpose();
  return p;
}

class LocatorProperties : public ::testing::TestWithParam<std::string>
{
protected:
  const MeshCase& data() const { return mesh_case(GetParam()); }
};

TEST_P(LocatorProperties, BarycentricCoordinatesReproduceInsidePoints)
{
  const MeshCase& m = data();
  const MeshPointLocator locator(m.mesh.V, m.mesh.T);
  const double diam = m.cage.diameter();
  const Points P = bary::test::sample_inside(m.cage, 2000, 0.0, 101);
  for (Index p = 0; p < P.rows(); ++p)
  {
    const Eigen::VectorXd x = P.row(p).transpose();
    const MeshPointLocator::Location loc = locator.locate(x.data());
    ASSERT_TRUE(loc.inside) << "point " << p;
    ASSERT_GE(loc.element, 0);
    ASSERT_LT(loc.element, m.mesh.T.rows());
    EXPECT_EQ(loc.distance, 0.0);
    const Index corners = m.mesh.T.cols();
    EXPECT_GE(loc.barycentric.head(corners).minCoeff(), -1e-12) << "point " << p;
    EXPECT_NEAR(loc.barycentric.head(corners).sum(), 1.0, 1e-14);
    if (corners == 3)
    {
      EXPECT_EQ(loc.barycentric(3), 0.0);
    }
    EXPECT_LE((point_of(loc, m.mesh) - x).norm(), 1e-12 * diam) << "point " << p;
  }
}

TEST_P(LocatorProperties, InterpolatingTheCoordinatesReproducesThePoints)
{
  const MeshCase& m = data();
  const MeshPointLocator locator(m.mesh.V, m.mesh.T);
  const Index dim = m.mesh.V.cols();
  const Points P = bary::test::sample_inside(m.cage, 2000, 0.0, 102);
  const MeshPointLocator::Result r = locator.interpolate(coordinates_and_one(m.mesh.V), P);
  EXPECT_TRUE(r.outside.empty());
  EXPECT_TRUE(r.outside_distance.empty());
  ASSERT_EQ(r.W.rows(), P.rows());
  ASSERT_EQ(r.W.cols(), dim + 1);
  EXPECT_LE((r.W.leftCols(dim) - P).cwiseAbs().maxCoeff(), 1e-12 * m.cage.diameter());
  EXPECT_LE((r.W.col(dim).array() - 1.0).abs().maxCoeff(), 1e-14);
}

TEST_P(LocatorProperties, MeshVerticesGetTheirOwnWeights)
{
  const MeshCase& m = data();
  const MeshPointLocator locator(m.mesh.V, m.mesh.T);
  const DenseWeights R = random_weights(m.mesh.V.rows(), 5, 7);
  const MeshPointLocator::Result r =
    locator.interpolate(R, m.mesh.V); // the vertices themselves as queries
  EXPECT_TRUE(r.outside.empty());
  EXPECT_LE((r.W - R).cwiseAbs().maxCoeff(), 1e-12);
}

TEST_P(LocatorProperties, SharedEdgesAndFacesGetOneValue)
{
  // Midpoints of interior edges (2D) and centroids of interior faces (3D) lie in two elements;
  // whichever is chosen, the interpolant is the average of the shared vertices' weights.
  const MeshCase& m = data();
  const DomainMesh& mesh = m.mesh;
  const MeshPointLocator locator(mesh.V, mesh.T);
  const Index corners = mesh.T.cols(), dim = mesh.V.cols();
  std::map<std::vector<int>, int> count;
  for (Index t = 0; t < mesh.T.rows(); ++t)
    for (Index skip = 0; skip < corners; ++skip)
    {
      std::vector<int> f;
      for (Index k = 0; k < corners; ++k)
        if (k != skip)
          f.push_back(mesh.T(t, k));
      std::sort(f.begin(), f.end());
      ++count[f];
    }
  std::vector<std::vector<int>> shared;
  for (const auto& [f, c] : count)
    if (c == 2)
      shared.push_back(f);
  ASSERT_GT(shared.size(), 100u);
  shared.resize(std::min<std::size_t>(shared.size(), 1500));
  Points P(static_cast<Index>(shared.size()), dim);
  for (std::size_t i = 0; i < shared.size(); ++i)
  {
    Eigen::VectorXd c = Eigen::VectorXd::Zero(dim);
    for (int v : shared[i])
      c += mesh.V.row(v).transpose();
    P.row(static_cast<Index>(i)) = c.transpose() / static_cast<double>(dim);
  }
  const DenseWeights R = random_weights(mesh.V.rows(), 4, 8);
  const MeshPointLocator::Result r = locator.interpolate(R, P);
  EXPECT_TRUE(r.outside.empty());
  for (std::size_t i = 0; i < shared.size(); ++i)
  {
    Eigen::RowVectorXd expected = Eigen::RowVectorXd::Zero(R.cols());
    for (int v : shared[i])
      expected += R.row(v) / static_cast<double>(dim);
    EXPECT_LE((r.W.row(static_cast<Index>(i)) - expected).cwiseAbs().maxCoeff(), 1e-12)
      << "shared " << (dim == 2 ? "edge " : "face ") << i;
    // The chosen element is one of the two that share it, and the choice is reproducible.
    const Eigen::VectorXd x = P.row(static_cast<Index>(i)).transpose();
    const auto a = locator.locate(x.data()), b = locator.locate(x.data());
    EXPECT_EQ(a.element, b.element);
    Index contains = 0;
    for (int v : shared[i])
      for (Index k = 0; k < corners; ++k)
        contains += mesh.T(a.element, k) == v;
    EXPECT_EQ(contains, dim);
  }
}

TEST_P(LocatorProperties, ResultsDoNotDependOnTheNumberOfThreads)
{
  const MeshCase& m = data();
  const MeshPointLocator locator(m.mesh.V, m.mesh.T);
  Points P(3000, m.mesh.V.cols());
  P << bary::test::sample_inside(m.cage, 2000, 0.0, 103),
    bary::test::sample_outside(m.cage, 1000, 0.0, 1.5, 104);
  const DenseWeights R = random_weights(m.mesh.V.rows(), 6, 9);
  const int before = omp_get_max_threads();
  std::vector<MeshPointLocator::Result> results;
  for (int threads : { 1, 2, 4 })
  {
    omp_set_num_threads(threads);
    results.push_back(locator.interpolate(R, P, OutsidePolicy::Nearest));
  }
  omp_set_num_threads(before);
  for (std::size_t i = 1; i < results.size(); ++i)
  {
    EXPECT_TRUE((results[i].W.array() == results[0].W.array()).all()) << "run " << i;
    EXPECT_EQ(results[i].outside, results[0].outside);
    EXPECT_EQ(results[i].outside_distance, results[0].outside_distance);
  }
  EXPECT_EQ(results[0].outside.size(), 1000u);
}

TEST_P(LocatorProperties, AgreesWithBruteForceOverAllElements)
{
  // Independent brute force: every element as a small cage, inside by winding number, distance
  // by cage_catalogue's boundary_distance; the nearest element wins.
  const MeshCase& m = data();
  const DomainMesh& mesh = m.mesh;
  const MeshPointLocator locator(mesh.V, mesh.T);
  const double diam = m.cage.diameter();
  const Index corners = mesh.T.cols(), dim = mesh.V.cols();
  std::vector<Cage> elements(static_cast<std::size_t>(mesh.T.rows()));
  std::vector<Eigen::VectorXd> lo(elements.size()), hi(elements.size());
  for (Index t = 0; t < mesh.T.rows(); ++t)
  {
    Cage& e = elements[static_cast<std::size_t>(t)];
    e.V.resize(corners, dim);
    for (Index k = 0; k < corners; ++k)
      e.V.row(k) = mesh.V.row(mesh.T(t, k));
    if (dim == 3)
    {
      e.F.resize(4, 3);
      e.F << 1, 2, 3, 0, 3, 2, 0, 1, 3, 0, 2, 1;
    }
    lo[static_cast<std::size_t>(t)] = e.V.colwise().minCoeff().transpose();
    hi[static_cast<std::size_t>(t)] = e.V.colwise().maxCoeff().transpose();
  }
  bary::test::Rng rng(105);
  const Eigen::VectorXd blo = m.cage.V.colwise().minCoeff().transpose();
  const Eigen::VectorXd bhi = m.cage.V.colwise().maxCoeff().transpose();
  const Eigen::VectorXd centre = 0.5 * (blo + bhi), half = 0.65 * (bhi - blo);
  Index inside = 0;
  for (int p = 0; p < 2000; ++p)
  {
    Eigen::VectorXd x(dim);
    for (Index k = 0; k < dim; ++k)
      x(k) = centre(k) + half(k) * rng.uniform(-1.0, 1.0);
    double best = std::numeric_limits<double>::infinity();
    Index best_t = -1;
    for (std::size_t t = 0; t < elements.size(); ++t)
    {
      // distance to the element's box is a lower bound
      const double box = (x - x.cwiseMax(lo[t]).cwiseMin(hi[t])).norm();
      if (box > best)
        continue;
      const double d = std::abs(bary::test::winding_number(elements[t], x.data())) > 0.5
        ? 0.0
        : bary::test::boundary_distance(elements[t], x.data());
      if (d < best)
      {
        best = d;
        best_t = static_cast<Index>(t);
      }
    }
    const MeshPointLocator::Location loc = locator.locate(x.data());
    ASSERT_GE(best_t, 0);
    EXPECT_NEAR(loc.distance, best, 1e-12 * diam) << "point " << p;
    EXPECT_EQ(loc.inside, best <= locator.absolute_tolerance()) << "point " << p;
    // The located element is as near as the brute-force one, and the barycentric coordinates
    // describe the closest point.
    EXPECT_NEAR((point_of(loc, mesh) - x).norm(), best, 1e-12 * diam) << "point " << p;
    EXPECT_GE(loc.barycentric.minCoeff(), loc.inside ? -1e-12 : 0.0);
    if (best == 0.0)
    {
      ++inside;
      EXPECT_NEAR(std::abs(bary::test::winding_number(
                    elements[static_cast<std::size_t>(loc.element)], x.data())),
        1.0, 1e-9)
        << "point " << p << ": the located element does not contain it";
    }
  }
  EXPECT_GT(inside, 300);
  EXPECT_LT(inside, 1900);
}

std::string mesh_name(const ::testing::TestParamInfo<std::string>& info)
{
  return info.param;
}

INSTANTIATE_TEST_SUITE_P(Meshes, LocatorProperties,
  ::testing::Values("square", "u_shape", "cube", "u_box"), mesh_name);

// --- Outside points ---------------------------------------------------------------------------

TEST(MeshPointLocator, OutsidePolicies2D)
{
  const MeshCase& m = mesh_case("square");
  const MeshPointLocator locator(m.mesh.V, m.mesh.T);
  Points P(4, 2);
  P << 0.5, 0.5, 1.5, 0.5, -1, -1, 0.25, 2;
  const DenseWeights X = m.mesh.V;

  EXPECT_TRUE(throws_error([&] { locator.interpolate(X, P); }, ErrorCode::PointsOutside,
    { "3 of 4 points lie outside the mesh", "first is point 1", "(1.5, 0.5)", "distance 0.5",
      "OutsidePolicy::Nearest" }));

  const MeshPointLocator::Result nearest = locator.interpolate(X, P, OutsidePolicy::Nearest);
  EXPECT_EQ(nearest.outside, (std::vector<Index>{ 1, 2, 3 }));
  ASSERT_EQ(nearest.outside_distance.size(), 3u);
  EXPECT_NEAR(nearest.outside_distance[0], 0.5, 1e-15);
  EXPECT_NEAR(nearest.outside_distance[1], std::sqrt(2.0), 1e-15);
  EXPECT_NEAR(nearest.outside_distance[2], 1.0, 1e-15);
  Points closest(4, 2);
  closest << 0.5, 0.5, 1.0, 0.5, 0.0, 0.0, 0.25, 1.0;
  EXPECT_LE((nearest.W - closest).cwiseAbs().maxCoeff(), 1e-15);

  const MeshPointLocator::Result nan = locator.interpolate(X, P, OutsidePolicy::NaN);
  EXPECT_EQ(nan.outside, (std::vector<Index>{ 1, 2, 3 }));
  EXPECT_NEAR(nan.W(0, 0), 0.5, 1e-15);
  for (Index p = 1; p < 4; ++p)
    EXPECT_TRUE(nan.W.row(p).array().isNaN().all()) << "point " << p;

  const Eigen::Vector2d x1 = P.row(1).transpose();
  const MeshPointLocator::Location loc = locator.locate(x1.data());
  EXPECT_FALSE(loc.inside);
  EXPECT_NEAR(loc.distance, 0.5, 1e-15);
  EXPECT_GE(loc.barycentric.minCoeff(), 0.0);
  EXPECT_NEAR(loc.barycentric.sum(), 1.0, 1e-15);
}

TEST(MeshPointLocator, OutsidePolicies3DAndTheTolerance)
{
  const MeshCase& m = mesh_case("cube");
  const MeshPointLocator locator(m.mesh.V, m.mesh.T);
  const double tol = locator.absolute_tolerance();
  EXPECT_NEAR(tol, 1e-10 * std::sqrt(3.0), 1e-20);
  Points P(3, 3);
  P << 2.0, 0.5, 0.25, 0.5, 0.5, 1.0 + 0.5 * tol, 0.5, 0.5, 1.0 + 2.0 * tol;
  const MeshPointLocator::Result r =
    locator.interpolate(DenseWeights(m.mesh.V), P, OutsidePolicy::Nearest);
  // Within the tolerance counts as inside (weights of the closest point).
  EXPECT_EQ(r.outside, (std::vector<Index>{ 0, 2 }));
  EXPECT_NEAR(r.outside_distance[0], 1.0, 1e-15);
  EXPECT_NEAR(r.outside_distance[1], 2.0 * tol, 1e-16);
  EXPECT_LE((r.W.row(0) - Eigen::RowVector3d(1.0, 0.5, 0.25)).norm(), 1e-15);
  EXPECT_LE((r.W.row(1) - Eigen::RowVector3d(0.5, 0.5, 1.0)).norm(), 1e-15);
  EXPECT_TRUE(throws_error([&] { locator.interpolate(DenseWeights(m.mesh.V), P); },
    ErrorCode::PointsOutside, { "2 of 3 points", "first is point 0" }));
}

// --- Validation, progress, degenerate elements ------------------------------------------------

TEST(MeshPointLocator, InvalidInputsAreRejected)
{
  const MeshCase& m = mesh_case("square");
  const Eigen::MatrixXd& V = m.mesh.V;
  const Eigen::MatrixXi& T = m.mesh.T;
  EXPECT_TRUE(throws_error([&] { MeshPointLocator(V, Eigen::MatrixXi(0, 3)); },
    ErrorCode::EmptyInput));
  EXPECT_TRUE(throws_error([&] { MeshPointLocator(V, T.leftCols(2)); }, ErrorCode::SizeMismatch,
    { "3 vertices per element" }));
  EXPECT_TRUE(throws_error([&] { MeshPointLocator(Eigen::MatrixXd::Zero(4, 4), T); },
    ErrorCode::SizeMismatch, { "2 or 3 coordinates" }));
  Eigen::MatrixXi bad = T;
  bad(7, 1) = static_cast<int>(V.rows());
  EXPECT_TRUE(throws_error([&] { MeshPointLocator(V, bad); }, ErrorCode::InvalidArgument,
    { "element 7", "vertex " + std::to_string(V.rows()) }));
  Eigen::MatrixXd nan = V;
  nan(3, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(throws_error([&] { MeshPointLocator(nan, T); }, ErrorCode::NonFinite, { "vertex 3" }));
  EXPECT_TRUE(throws_error([&] { MeshPointLocator(V, T, -1.0); }, ErrorCode::InvalidArgument,
    { "tolerance" }));

  const MeshPointLocator locator(V, T);
  EXPECT_TRUE(throws_error([&] { locator.interpolate(DenseWeights::Zero(3, 2), V); },
    ErrorCode::SizeMismatch, { "rows" }));
  EXPECT_TRUE(throws_error([&] { locator.interpolate(DenseWeights(V), Points::Zero(2, 3)); },
    ErrorCode::SizeMismatch, { "coordinates" }));
  Points P = Points::Constant(2, 2, 0.5);
  P(1, 0) = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(throws_error([&] { locator.interpolate(DenseWeights(V), P); }, ErrorCode::NonFinite,
    { "point 1" }));
}

TEST(MeshPointLocator, ProgressAndCancellation)
{
  const MeshCase& m = mesh_case("square");
  const MeshPointLocator locator(m.mesh.V, m.mesh.T);
  const Points P = bary::test::sample_inside(m.cage, 20000, 0.0, 106);
  std::vector<double> fractions;
  locator.interpolate(DenseWeights(m.mesh.V), P, OutsidePolicy::Error, [&](double f) {
    fractions.push_back(f);
    return true;
  });
  ASSERT_GE(fractions.size(), 2u);
  EXPECT_TRUE(std::is_sorted(fractions.begin(), fractions.end()));
  EXPECT_EQ(fractions.back(), 1.0);
  EXPECT_TRUE(throws_error(
    [&] { locator.interpolate(DenseWeights(m.mesh.V), P, OutsidePolicy::Error, [](double f) { return f < 0.3; }); },
    ErrorCode::Cancelled));
}

TEST(MeshPointLocator, DegenerateElementsAreTolerated)
{
  // Two triangles of the unit square plus a flat one along the diagonal (zero area): points
  // are located in the proper triangles, the flat one is never preferred.
  Eigen::MatrixXd V(4, 2);
  V << 0, 0, 1, 0, 1, 1, 0, 1;
  Eigen::MatrixXi T(3, 3);
  T << 0, 1, 2, 0, 2, 3, 0, 2, 0;
  const MeshPointLocator locator(V, T);
  bary::test::Rng rng(107);
  for (int i = 0; i < 200; ++i)
  {
    const Eigen::Vector2d x(rng.uniform(), rng.uniform());
    const auto loc = locator.locate(x.data());
    EXPECT_TRUE(loc.inside);
    EXPECT_LT(loc.element, 2);
    Eigen::Vector2d p = Eigen::Vector2d::Zero();
    for (int k = 0; k < 3; ++k)
      p += loc.barycentric(k) * V.row(T(loc.element, k)).transpose();
    EXPECT_LE((p - x).norm(), 1e-15);
  }
  // A mesh with only a flat element still answers (nearest point on it).
  Eigen::MatrixXi flat(1, 3);
  flat << 0, 2, 0;
  const MeshPointLocator degenerate(V, flat);
  const Eigen::Vector2d q(1.0, 0.0);
  const auto loc = degenerate.locate(q.data());
  EXPECT_FALSE(loc.inside);
  EXPECT_NEAR(loc.distance, std::sqrt(0.5), 1e-15);
}

} // namespace
