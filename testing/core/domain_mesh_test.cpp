// Tests for core/meshing/domain_mesh.h: meshing the interior of 2D polygons (CGAL) and 3D closed
// surfaces (TetGen).
//
// Properties, over the catalogue (cage_catalogue.h) and the LBC authors' cages when the shared
// data is present: the Lagrange property (cage vertices are mesh vertices at their exact
// coordinates), the mesh fills the cage (total area/volume, boundary on the cage, boundary
// faces cover the cage), orientation, the size and quality bounds, Steiner points, holes,
// boundary preservation, validation and failure paths, progress and cancellation.
//
// Tolerances. u = 2^-53 ~ 1.1e-16.
// - Total area / volume: a sum of #T positive terms, each rounded with a relative error of a
//   few u; the boundary vertices the mesher inserts on cage edges/faces are rounded to a few u
//   of the cage size, which moves the total by ~u diam * perimeter. 1e-12 (2D) / 1e-10 (3D,
//   as asked) relative are far above both.
// - Points on the cage: midpoints of edges are rounded, so boundary vertices lie within a few u
//   of the cage size of it: 1e-12 * diam.
// - Angle and radius-edge bounds: the meshers compare rounded quantities with the bound, so a
//   slack of 1e-6 relative (0.01 degree) is enough.
#include "cage_catalogue.h"
#include "core/detail/tetgen_mesher.h"
#include "core/meshing/domain_mesh.h"
#include "core/common/error.h"
#include "core/solvers/fem_operators.h"
#include "error_matchers.h"

#include <Eigen/Geometry>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace
{

using bary::Cage;
using bary::DomainMesh;
using bary::Error;
using bary::ErrorCode;
using bary::Index;
using bary::PolygonMeshOptions;
using bary::SurfaceMeshOptions;
using bary::test::CatalogueCage;
using bary::test::throws_error;

constexpr double kPi = 3.14159265358979323846;

// --- Geometry helpers (independent of core) ---------------------------------------------------

double triangle_area(const Eigen::MatrixXd& V, const Eigen::MatrixXi& T, Index t)
{
  const Eigen::Vector2d a = V.row(T(t, 0)), b = V.row(T(t, 1)), c = V.row(T(t, 2));
  return 0.5 * ((b - a).x() * (c - a).y() - (b - a).y() * (c - a).x());
}

double triangle_min_angle(const Eigen::MatrixXd& V, const Eigen::MatrixXi& T, Index t)
{
  double m = 180.0;
  for (int k = 0; k < 3; ++k)
  {
    const Eigen::Vector2d a = V.row(T(t, k)), b = V.row(T(t, (k + 1) % 3)),
                          c = V.row(T(t, (k + 2) % 3));
    const double cosine = (b - a).normalized().dot((c - a).normalized());
    m = std::min(m, std::acos(std::clamp(cosine, -1.0, 1.0)) * 180.0 / kPi);
  }
  return m;
}

/// Interior angle (degrees) of the polygon at each vertex.
std::vector<double> interior_angles(const Cage& cage)
{
  const Eigen::MatrixXd& V = cage.V;
  const Index n = V.rows();
  const double orientation = bary::signed_measure(cage) > 0 ? 1.0 : -1.0;
  std::vector<double> angles;
  for (Index i = 0; i < n; ++i)
  {
    const Eigen::Vector2d p = V.row((i + n - 1) % n), c = V.row(i), q = V.row((i + 1) % n);
    const Eigen::Vector2d a = q - c, b = p - c;
    // angle from a to b, counter-clockwise, in [0, 360)
    double ang = std::atan2(a.x() * b.y() - a.y() * b.x(), a.dot(b)) * 180.0 / kPi;
    if (orientation < 0)
      ang = -ang;
    if (ang < 0)
      ang += 360.0;
    angles.push_back(ang);
  }
  return angles;
}

double tet_volume(const Eigen::MatrixXd& V, const Eigen::MatrixXi& T, Index t)
{
  const Eigen::Vector3d a = V.row(T(t, 0)), b = V.row(T(t, 1)), c = V.row(T(t, 2)),
                        d = V.row(T(t, 3));
  return (b - a).dot((c - a).cross(d - a)) / 6.0;
}

/// Circumradius / shortest edge of tetrahedron t.
double radius_edge_ratio(const Eigen::MatrixXd& V, const Eigen::MatrixXi& T, Index t)
{
  const Eigen::Vector3d a = V.row(T(t, 0));
  Eigen::Matrix3d A;
  Eigen::Vector3d rhs;
  double shortest = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k)
  {
    const Eigen::Vector3d e = V.row(T(t, k + 1)).transpose() - a;
    A.row(k) = 2.0 * e.transpose();
    rhs(k) = e.squaredNorm();
  }
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j)
      shortest = std::min(shortest, (V.row(T(t, i)) - V.row(T(t, j))).norm());
  const Eigen::Vector3d centre = A.fullPivLu().solve(rhs); // relative to a
  return centre.norm() / shortest;
}

/// Edges (a < b) used by exactly one triangle.
std::vector<std::pair<int, int>> boundary_edges(const Eigen::MatrixXi& T)
{
  std::map<std::pair<int, int>, int> count;
  for (Index t = 0; t < T.rows(); ++t)
    for (int k = 0; k < 3; ++k)
    {
      const int a = T(t, k), b = T(t, (k + 1) % 3);
      ++count[{ std::min(a, b), std::max(a, b) }];
    }
  std::vector<std::pair<int, int>> out;
  for (const auto& [e, c] : count)
    if (c == 1)
      out.push_back(e);
  return out;
}

/// Faces (sorted triples) used by exactly one tetrahedron, and their orientation seen from
/// outside (the tetrahedron's face, oriented away from its fourth vertex).
std::vector<std::array<int, 3>> boundary_faces(const Eigen::MatrixXi& T)
{
  std::map<std::array<int, 3>, int> count;
  for (Index t = 0; t < T.rows(); ++t)
    for (int k = 0; k < 4; ++k)
    {
      std::array<int, 3> f{ T(t, (k + 1) % 4), T(t, (k + 2) % 4), T(t, (k + 3) % 4) };
      std::sort(f.begin(), f.end());
      ++count[f];
    }
  std::vector<std::array<int, 3>> out;
  for (const auto& [f, c] : count)
    if (c == 1)
      out.push_back(f);
  return out;
}

double polygon_distance(const Eigen::MatrixXd& R, const Eigen::Vector2d& p)
{
  Cage c;
  c.V = R;
  return bary::test::boundary_distance(c, p.data());
}

double surface_area(const Cage& cage)
{
  double a = 0.0;
  for (Index f = 0; f < cage.F.rows(); ++f)
  {
    const Eigen::Vector3d p = cage.V.row(cage.F(f, 0)), q = cage.V.row(cage.F(f, 1)),
                          r = cage.V.row(cage.F(f, 2));
    a += 0.5 * (q - p).cross(r - p).norm();
  }
  return a;
}

std::vector<int> sorted_vertices(const std::vector<std::pair<int, int>>& edges)
{
  std::set<int> s;
  for (const auto& [a, b] : edges)
  {
    s.insert(a);
    s.insert(b);
  }
  return { s.begin(), s.end() };
}

/// The boundary weights write every boundary vertex as an affine, non-negative combination of
/// the cage vertices.
void expect_boundary_weights(const DomainMesh& mesh, const Cage& cage, double tol)
{
  ASSERT_EQ(mesh.boundary_weights.rows(), static_cast<Index>(mesh.boundary_vertices.size()));
  ASSERT_EQ(mesh.boundary_weights.cols(), cage.num_controls());
  const Eigen::MatrixXd W = Eigen::MatrixXd(mesh.boundary_weights);
  for (Index r = 0; r < W.rows(); ++r)
  {
    const int v = mesh.boundary_vertices[static_cast<std::size_t>(r)];
    EXPECT_NEAR(W.row(r).sum(), 1.0, 1e-14) << "boundary vertex " << v;
    EXPECT_GE(W.row(r).minCoeff(), 0.0) << "boundary vertex " << v;
    EXPECT_LE((W.row(r) * cage.V - mesh.V.row(v)).norm(), tol) << "boundary vertex " << v;
    EXPECT_LE((W.row(r).array() != 0.0).count(), cage.dimension()) << "boundary vertex " << v;
  }
}

std::string cage_name(const ::testing::TestParamInfo<CatalogueCage>& info)
{
  return info.param.name;
}

// --- 2D: properties over the catalogue --------------------------------------------------------

class PolygonMeshProperties : public ::testing::TestWithParam<CatalogueCage>
{
protected:
  const Cage& cage() const { return GetParam().cage; }
};

TEST_P(PolygonMeshProperties, DefaultMeshFillsThePolygonWithQualityTriangles)
{
  const Cage& c = cage();
  const PolygonMeshOptions options; // 3000 cells, 20 degrees
  const DomainMesh mesh = bary::mesh_polygon(c, options);
  const Index nc = c.num_controls();
  const double diam = c.diameter();
  const double area = std::abs(bary::signed_measure(c));
  ASSERT_EQ(mesh.V.cols(), 2);
  ASSERT_EQ(mesh.T.cols(), 3);
  EXPECT_EQ(mesh.dimension(), 2);

  // Lagrange property: cage vertex i is mesh vertex control_vertex(i) at the exact coordinates.
  ASSERT_EQ(mesh.control_vertex.size(), nc);
  for (Index i = 0; i < nc; ++i)
  {
    EXPECT_EQ(mesh.control_vertex(i), i);
    EXPECT_TRUE((mesh.V.row(mesh.control_vertex(i)).array() == c.V.row(i).array()).all())
      << "cage vertex " << i;
  }
  // Every vertex is used.
  std::vector<char> used(static_cast<std::size_t>(mesh.V.rows()), 0);
  for (Index t = 0; t < mesh.T.rows(); ++t)
    for (int k = 0; k < 3; ++k)
    {
      ASSERT_GE(mesh.T(t, k), 0);
      ASSERT_LT(mesh.T(t, k), mesh.V.rows());
      used[static_cast<std::size_t>(mesh.T(t, k))] = 1;
    }
  EXPECT_EQ(std::count(used.begin(), used.end(), 0), 0);

  // Area, orientation, size bound, angle bound away from sharp corners.
  const double max_area = area / options.target_cells;
  const std::vector<double> corner = interior_angles(c);
  double total = 0.0, smallest = 180.0;
  for (Index t = 0; t < mesh.T.rows(); ++t)
  {
    const double a = triangle_area(mesh.V, mesh.T, t);
    EXPECT_GT(a, 0.0) << "triangle " << t << " is not counter-clockwise";
    EXPECT_LE(a, max_area * (1 + 1e-12)) << "triangle " << t;
    total += a;
    bool at_sharp_corner = false;
    for (int k = 0; k < 3; ++k)
      if (mesh.T(t, k) < nc && corner[static_cast<std::size_t>(mesh.T(t, k))] < options.min_angle_degrees)
        at_sharp_corner = true;
    if (!at_sharp_corner)
      smallest = std::min(smallest, triangle_min_angle(mesh.V, mesh.T, t));
  }
  EXPECT_NEAR(total, area, 1e-12 * area);
  EXPECT_GE(smallest, options.min_angle_degrees - 0.01);
  // target_cells: every triangle is at most area / target, so there are at least that many;
  // in practice about 1.5 times as many.
  EXPECT_GE(mesh.T.rows(), options.target_cells);
  EXPECT_LE(mesh.T.rows(), 2 * options.target_cells);

  // The boundary lies on the polygon: both end points and the midpoint of every boundary edge.
  const auto bedges = boundary_edges(mesh.T);
  for (const auto& [a, b] : bedges)
  {
    const Eigen::Vector2d pa = mesh.V.row(a), pb = mesh.V.row(b);
    EXPECT_LE(polygon_distance(c.V, pa), 1e-12 * diam) << "vertex " << a;
    EXPECT_LE(polygon_distance(c.V, 0.5 * (pa + pb)), 1e-12 * diam) << "edge " << a << "-" << b;
  }
  EXPECT_EQ(mesh.boundary_vertices, sorted_vertices(bedges));
  EXPECT_TRUE(mesh.hole_boundary_vertices.empty());
  EXPECT_EQ(mesh.steiner_vertex.size(), 0);
  expect_boundary_weights(mesh, c, 1e-12 * diam);
  EXPECT_GE(mesh.seconds, 0.0);
}

TEST_P(PolygonMeshProperties, MaxAreaBoundsEveryTriangle)
{
  const Cage& c = cage();
  const double area = std::abs(bary::signed_measure(c));
  PolygonMeshOptions options;
  options.max_area = area / 500.0;
  options.target_cells = 1; // ignored: max_area > 0 wins
  const DomainMesh mesh = bary::mesh_polygon(c, options);
  double total = 0.0;
  for (Index t = 0; t < mesh.T.rows(); ++t)
  {
    const double a = triangle_area(mesh.V, mesh.T, t);
    EXPECT_LE(a, options.max_area * (1 + 1e-12));
    total += a;
  }
  EXPECT_NEAR(total, area, 1e-12 * area);
  EXPECT_GE(mesh.T.rows(), 500);
}

TEST_P(PolygonMeshProperties, SteinerPointsInsideBecomeVerticesOthersAreSkipped)
{
  const Cage& c = cage();
  const Index n_in = 40, n_out = 10;
  const bary::Points in = bary::test::sample_inside(c, n_in, 1e-3, 11);
  const bary::Points out = bary::test::sample_outside(c, n_out, 1e-3, 1.5, 12);
  // A point just inside an edge, closer than the tolerance (1e-6 diam) to it.
  const Eigen::RowVector2d a = c.V.row(0), b = c.V.row(1);
  const Eigen::Vector2d inward = bary::test::inward_normal(c, 0);
  const Eigen::RowVector2d near_edge = 0.5 * (a + b) + 1e-9 * c.diameter() * inward.transpose();
  PolygonMeshOptions options;
  options.target_cells = 300;
  options.steiner_points.resize(n_in + n_out + 3, 2);
  options.steiner_points << in, out, near_edge, in.row(3), c.V.row(2);
  const DomainMesh mesh = bary::mesh_polygon(c, options);
  ASSERT_EQ(mesh.steiner_vertex.size(), n_in + n_out + 3);
  std::set<int> seen;
  for (Index s = 0; s < n_in; ++s)
  {
    const int v = mesh.steiner_vertex(s);
    ASSERT_GE(v, 0) << "inside point " << s;
    EXPECT_TRUE((mesh.V.row(v).array() == in.row(s).array()).all()) << "inside point " << s;
    EXPECT_EQ(v, c.num_controls() + s) << "accepted points are numbered after the cage";
    EXPECT_TRUE(seen.insert(v).second);
  }
  for (Index s = n_in; s < n_in + n_out; ++s)
    EXPECT_EQ(mesh.steiner_vertex(s), -1) << "outside point " << s;
  EXPECT_EQ(mesh.steiner_vertex(n_in + n_out), -1) << "point 1e-9 diam from the boundary";
  EXPECT_EQ(mesh.steiner_vertex(n_in + n_out + 1), mesh.steiner_vertex(3)) << "duplicate";
  EXPECT_EQ(mesh.steiner_vertex(n_in + n_out + 2), -1) << "point on a cage vertex";
  // Still a valid mesh of the polygon.
  double total = 0.0;
  for (Index t = 0; t < mesh.T.rows(); ++t)
    total += triangle_area(mesh.V, mesh.T, t);
  EXPECT_NEAR(total, std::abs(bary::signed_measure(c)), 1e-12 * std::abs(bary::signed_measure(c)));
}

INSTANTIATE_TEST_SUITE_P(
  Catalogue, PolygonMeshProperties, ::testing::ValuesIn(bary::test::cages_2d()), cage_name);

// --- 2D: particular cases ---------------------------------------------------------------------

TEST(MeshPolygon, LargestAngleBoundOnPolygonsWithoutSharpCorners)
{
  // The largest bound allowed, CGAL's guaranteed 20.7 degrees: every angle respects it.
  for (const Cage& c : { bary::test::unit_square(), bary::test::u_polygon(),
         bary::test::l_polygon(), bary::test::regular_polygon(64) })
  {
    PolygonMeshOptions options;
    options.min_angle_degrees = bary::kMaxMinAngleDegrees;
    options.target_cells = 1000;
    const DomainMesh mesh = bary::mesh_polygon(c, options);
    double smallest = 180.0;
    for (Index t = 0; t < mesh.T.rows(); ++t)
      smallest = std::min(smallest, triangle_min_angle(mesh.V, mesh.T, t));
    EXPECT_GE(smallest, bary::kMaxMinAngleDegrees - 0.01);
  }
}

TEST(MeshPolygon, SharpCornerKeepsItsAngleOnly)
{
  // A thin wedge (10 degrees at vertex 0): the triangles at that corner cannot be better than
  // the corner; CGAL protects it and leaves small angles only near it.
  Cage c;
  const double half = 5.0 * kPi / 180.0;
  c.V.resize(3, 2);
  c.V << 0, 0, std::cos(half), -std::sin(half), std::cos(half), std::sin(half);
  PolygonMeshOptions options;
  options.target_cells = 500;
  const DomainMesh mesh = bary::mesh_polygon(c, options);
  double total = 0.0;
  Index bad = 0;
  for (Index t = 0; t < mesh.T.rows(); ++t)
  {
    total += triangle_area(mesh.V, mesh.T, t);
    if (triangle_min_angle(mesh.V, mesh.T, t) < options.min_angle_degrees - 0.01)
    {
      ++bad;
      // only near the sharp corner
      const Eigen::Vector2d centroid =
        (mesh.V.row(mesh.T(t, 0)) + mesh.V.row(mesh.T(t, 1)) + mesh.V.row(mesh.T(t, 2))) / 3.0;
      EXPECT_LT(centroid.norm(), 0.5) << "bad triangle " << t << " far from the sharp corner";
    }
  }
  EXPECT_NEAR(total, std::abs(bary::signed_measure(c)), 1e-12);
  EXPECT_LT(bad, mesh.T.rows() / 10);
}

TEST(MeshPolygon, HolesAreNotMeshedAndTheirVerticesFollowTheCage)
{
  Cage c;
  c.V.resize(4, 2);
  c.V << 0, 0, 4, 0, 4, 4, 0, 4;
  PolygonMeshOptions options;
  options.target_cells = 2000;
  Eigen::MatrixXd square_hole(4, 2), triangle_hole(3, 2);
  square_hole << 1, 1, 1, 2, 2, 2, 2, 1; // clockwise: either orientation is accepted
  triangle_hole << 2.5, 2.5, 3.5, 2.5, 3.0, 3.5;
  options.holes = { square_hole, triangle_hole };
  options.steiner_points.resize(3, 2);
  options.steiner_points << 1.5, 1.5, 3.0, 2.8, 0.5, 0.5; // in hole 0, in hole 1, in the domain
  const DomainMesh mesh = bary::mesh_polygon(c, options);
  const double area = 16.0 - 1.0 - 0.5;
  double total = 0.0;
  for (Index t = 0; t < mesh.T.rows(); ++t)
  {
    total += triangle_area(mesh.V, mesh.T, t);
    const Eigen::Vector2d g =
      (mesh.V.row(mesh.T(t, 0)) + mesh.V.row(mesh.T(t, 1)) + mesh.V.row(mesh.T(t, 2))) / 3.0;
    EXPECT_FALSE(g.x() > 1 && g.x() < 2 && g.y() > 1 && g.y() < 2) << "triangle in hole 0";
    Cage tri;
    tri.V = triangle_hole;
    EXPECT_LT(std::abs(bary::test::winding_number(tri, g.data())), 0.5) << "triangle in hole 1";
  }
  EXPECT_NEAR(total, area, 1e-12 * area);
  // Hole vertices are mesh vertices 4..6 and 8..10, at the exact coordinates.
  for (Index i = 0; i < 4; ++i)
    EXPECT_TRUE((mesh.V.row(4 + i).array() == square_hole.row(i).array()).all());
  for (Index i = 0; i < 3; ++i)
    EXPECT_TRUE((mesh.V.row(8 + i).array() == triangle_hole.row(i).array()).all());
  EXPECT_EQ(mesh.steiner_vertex(0), -1);
  EXPECT_EQ(mesh.steiner_vertex(1), -1);
  EXPECT_EQ(mesh.steiner_vertex(2), 11);
  // Boundary: the outer vertices on the cage, the hole vertices on the holes.
  const auto bedges = boundary_edges(mesh.T);
  std::vector<int> all = mesh.boundary_vertices;
  all.insert(all.end(), mesh.hole_boundary_vertices.begin(), mesh.hole_boundary_vertices.end());
  std::sort(all.begin(), all.end());
  EXPECT_EQ(all, sorted_vertices(bedges));
  for (int v : mesh.boundary_vertices)
    EXPECT_LE(polygon_distance(c.V, mesh.V.row(v).transpose()), 1e-12);
  for (int v : mesh.hole_boundary_vertices)
    EXPECT_LE(std::min(polygon_distance(square_hole, mesh.V.row(v).transpose()),
                polygon_distance(triangle_hole, mesh.V.row(v).transpose())),
      1e-12);
  expect_boundary_weights(mesh, c, 1e-12);
}

TEST(MeshPolygon, InvalidHolesAreRejected)
{
  const Cage c = bary::test::unit_square();
  auto with_hole = [&](Eigen::MatrixXd hole) {
    PolygonMeshOptions o;
    o.target_cells = 100;
    o.holes = { std::move(hole) };
    return o;
  };
  Eigen::MatrixXd touching(3, 2), outside(3, 2), crossing(3, 2), bowtie(4, 2);
  touching << 0.0, 0.5, 0.5, 0.4, 0.5, 0.6; // vertex on the cage's edge 3
  outside << 2, 2, 3, 2, 2, 3;
  crossing << 0.5, 0.5, 1.5, 0.5, 0.5, 0.7;
  bowtie << 0.2, 0.2, 0.8, 0.8, 0.8, 0.2, 0.2, 0.8;
  EXPECT_TRUE(throws_error([&] { bary::mesh_polygon(c, with_hole(touching)); },
    ErrorCode::InvalidCage, { "hole 0", "touches or crosses" }));
  EXPECT_TRUE(throws_error([&] { bary::mesh_polygon(c, with_hole(outside)); },
    ErrorCode::InvalidCage, { "hole 0 lies outside the cage" }));
  EXPECT_TRUE(throws_error([&] { bary::mesh_polygon(c, with_hole(crossing)); },
    ErrorCode::InvalidCage, { "edge 1 of the cage", "edge 0 of hole 0" }));
  EXPECT_TRUE(throws_error([&] { bary::mesh_polygon(c, with_hole(bowtie)); },
    ErrorCode::InvalidCage, { "hole 0: ", "not simple" }));
  Eigen::MatrixXd big(4, 2), small(4, 2);
  big << 0.1, 0.1, 0.9, 0.1, 0.9, 0.9, 0.1, 0.9;
  small << 0.4, 0.4, 0.6, 0.4, 0.6, 0.6, 0.4, 0.6;
  PolygonMeshOptions nested;
  nested.holes = { big, small };
  EXPECT_TRUE(throws_error([&] { bary::mesh_polygon(c, nested); }, ErrorCode::InvalidCage,
    { "hole 1 lies inside hole 0", "nested" }));
  PolygonMeshOptions overlapping;
  overlapping.holes = { big, big };
  EXPECT_TRUE(throws_error([&] { bary::mesh_polygon(c, overlapping); }, ErrorCode::InvalidCage,
    { "hole 0", "hole 1" }));
  PolygonMeshOptions wrong_shape;
  wrong_shape.holes = { Eigen::MatrixXd::Zero(4, 3) };
  EXPECT_TRUE(throws_error(
    [&] { bary::mesh_polygon(c, wrong_shape); }, ErrorCode::SizeMismatch, { "hole 0" }));
}

TEST(MeshPolygon, InvalidCagesAndOptionsAreRejected)
{
  Cage bowtie;
  bowtie.V.resize(4, 2);
  bowtie.V << 0, 0, 1, 1, 1, 0, 0, 1;
  EXPECT_TRUE(throws_error(
    [&] { bary::mesh_polygon(bowtie); }, ErrorCode::InvalidCage, { "not simple" }));
  EXPECT_TRUE(throws_error([&] { bary::mesh_polygon(Cage{}); }, ErrorCode::EmptyInput));
  EXPECT_TRUE(throws_error([&] { bary::mesh_polygon(bary::test::unit_cube()); },
    ErrorCode::SizeMismatch, { "mesh_closed_surface" }));

  const Cage c = bary::test::unit_square();
  PolygonMeshOptions o;
  o.min_angle_degrees = 21; // above CGAL's guaranteed 20.7
  EXPECT_TRUE(throws_error(
    [&] { bary::mesh_polygon(c, o); }, ErrorCode::InvalidArgument, { "min_angle_degrees" }));
  o = {};
  o.target_cells = 0;
  EXPECT_TRUE(throws_error(
    [&] { bary::mesh_polygon(c, o); }, ErrorCode::InvalidArgument, { "target_cells" }));
  o = {};
  o.max_area = 1e-12;
  EXPECT_TRUE(throws_error(
    [&] { bary::mesh_polygon(c, o); }, ErrorCode::InvalidArgument, { "max_area", "limit" }));
  o = {};
  o.max_area = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(throws_error([&] { bary::mesh_polygon(c, o); }, ErrorCode::InvalidArgument));
  o = {};
  o.steiner_tolerance = 0.5;
  EXPECT_TRUE(throws_error(
    [&] { bary::mesh_polygon(c, o); }, ErrorCode::InvalidArgument, { "steiner_tolerance" }));
  o = {};
  o.steiner_points = Eigen::MatrixXd::Constant(2, 3, 0.5);
  EXPECT_TRUE(throws_error(
    [&] { bary::mesh_polygon(c, o); }, ErrorCode::SizeMismatch, { "Steiner" }));
  o.steiner_points = Eigen::MatrixXd::Constant(2, 2, 0.5);
  o.steiner_points(1, 1) = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(throws_error(
    [&] { bary::mesh_polygon(c, o); }, ErrorCode::NonFinite, { "point 1" }));
}

TEST(MeshPolygon, DeterministicAndIndependentOfOrientation)
{
  const Cage c = bary::test::u_polygon();
  PolygonMeshOptions o;
  o.target_cells = 800;
  const DomainMesh a = bary::mesh_polygon(c, o), b = bary::mesh_polygon(c, o);
  EXPECT_TRUE((a.V.array() == b.V.array()).all());
  EXPECT_TRUE((a.T.array() == b.T.array()).all());
  // The clockwise cage gives counter-clockwise triangles too.
  const DomainMesh r = bary::mesh_polygon(bary::test::reversed(c), o);
  for (Index t = 0; t < r.T.rows(); ++t)
    EXPECT_GT(triangle_area(r.V, r.T, t), 0.0);
}

TEST(MeshPolygon, ProgressIsMonotoneAndCancellable)
{
  const Cage c = bary::test::unit_square();
  PolygonMeshOptions o;
  o.target_cells = 20000;
  std::vector<double> fractions;
  bary::mesh_polygon(c, o, [&](double f) {
    fractions.push_back(f);
    return true;
  });
  ASSERT_GE(fractions.size(), 5u);
  EXPECT_TRUE(std::is_sorted(fractions.begin(), fractions.end()));
  EXPECT_EQ(fractions.front(), 0.0);
  EXPECT_EQ(fractions.back(), 1.0);
  // Cancelled during the refinement.
  EXPECT_TRUE(throws_error(
    [&] { bary::mesh_polygon(c, o, [](double f) { return f <= 0.2; }); }, ErrorCode::Cancelled));
}

TEST(MeshPolygon, LbcCagesMeshWithAbout3000Cells)
{
  const auto cages = bary::test::shared_cages_2d();
  if (cages.empty())
    GTEST_SKIP() << "no LBC cages in " << bary::test::shared_cage_directory();
  for (const CatalogueCage& entry : cages)
  {
    const DomainMesh mesh = bary::mesh_polygon(entry.cage);
    EXPECT_GE(mesh.T.rows(), 3000) << entry.name;
    EXPECT_LE(mesh.T.rows(), 6000) << entry.name;
    RecordProperty(entry.name + "_vertices", static_cast<int>(mesh.V.rows()));
  }
}

// --- 3D: properties over the catalogue --------------------------------------------------------

class SurfaceMeshProperties : public ::testing::TestWithParam<CatalogueCage>
{
protected:
  const Cage& cage() const { return GetParam().cage; }
};

/// Checks what every tetrahedralization of @p c must satisfy.
void expect_tet_mesh_fills_cage(const DomainMesh& mesh, const Cage& c)
{
  const Index nc = c.num_controls();
  const double diam = c.diameter();
  const double volume = std::abs(bary::signed_measure(c));
  ASSERT_EQ(mesh.V.cols(), 3);
  ASSERT_EQ(mesh.T.cols(), 4);
  ASSERT_EQ(mesh.control_vertex.size(), nc);
  for (Index i = 0; i < nc; ++i)
  {
    EXPECT_EQ(mesh.control_vertex(i), i);
    EXPECT_TRUE((mesh.V.row(mesh.control_vertex(i)).array() == c.V.row(i).array()).all())
      << "cage vertex " << i;
  }
  std::vector<char> used(static_cast<std::size_t>(mesh.V.rows()), 0);
  double total = 0.0;
  for (Index t = 0; t < mesh.T.rows(); ++t)
  {
    for (int k = 0; k < 4; ++k)
      used[static_cast<std::size_t>(mesh.T(t, k))] = 1;
    const double v = tet_volume(mesh.V, mesh.T, t);
    double longest = 0.0;
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j)
        longest = std::max(longest, (mesh.V.row(mesh.T(t, i)) - mesh.V.row(mesh.T(t, j))).norm());
    EXPECT_GT(v, 1e-12 * longest * longest * longest) << "tetrahedron " << t
                                                      << " is inverted or degenerate";
    total += v;
  }
  EXPECT_EQ(std::count(used.begin(), used.end(), 0), 0) << "unused vertices";
  EXPECT_NEAR(total, volume, 1e-10 * volume);

  // Boundary faces lie on the cage (vertices and centroids) and cover it (same total area).
  const auto bfaces = boundary_faces(mesh.T);
  std::set<int> bverts;
  double barea = 0.0;
  for (const auto& f : bfaces)
  {
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (int v : f)
    {
      bverts.insert(v);
      centroid += mesh.V.row(v).transpose() / 3.0;
    }
    EXPECT_LE(bary::test::boundary_distance(c, centroid.data()), 1e-12 * diam);
    const Eigen::Vector3d a = mesh.V.row(f[0]), b = mesh.V.row(f[1]), d = mesh.V.row(f[2]);
    barea += 0.5 * (b - a).cross(d - a).norm();
  }
  for (int v : bverts)
  {
    const Eigen::Vector3d p = mesh.V.row(v).transpose();
    EXPECT_LE(bary::test::boundary_distance(c, p.data()), 1e-12 * diam) << "boundary vertex " << v;
  }
  const double area = surface_area(c);
  EXPECT_NEAR(barea, area, 1e-10 * area);
  EXPECT_EQ(mesh.boundary_vertices, std::vector<int>(bverts.begin(), bverts.end()));
  EXPECT_TRUE(mesh.hole_boundary_vertices.empty());
  expect_boundary_weights(mesh, c, 1e-12 * diam);
}

TEST_P(SurfaceMeshProperties, QualityMeshWithVolumeBound)
{
  const Cage& c = cage();
  const double volume = std::abs(bary::signed_measure(c));
  SurfaceMeshOptions options;
  options.max_volume = 1e-3 * volume;
  const DomainMesh mesh = bary::mesh_closed_surface(c, options);
  expect_tet_mesh_fills_cage(mesh, c);
  // TetGen's radius-edge bound holds for every tetrahedron away from the cage; a few touching
  // the cage may exceed it (see SurfaceMeshOptions::radius_edge_ratio).
  std::vector<char> on_cage(static_cast<std::size_t>(mesh.V.rows()), 0);
  for (int v : mesh.boundary_vertices)
    on_cage[static_cast<std::size_t>(v)] = 1;
  Index above = 0;
  for (Index t = 0; t < mesh.T.rows(); ++t)
  {
    EXPECT_LE(tet_volume(mesh.V, mesh.T, t), options.max_volume * (1 + 1e-9)) << "tet " << t;
    const double ratio = radius_edge_ratio(mesh.V, mesh.T, t);
    if (ratio <= options.radius_edge_ratio * (1 + 1e-6))
      continue;
    ++above;
    const bool touches = on_cage[static_cast<std::size_t>(mesh.T(t, 0))] ||
      on_cage[static_cast<std::size_t>(mesh.T(t, 1))] ||
      on_cage[static_cast<std::size_t>(mesh.T(t, 2))] || on_cage[static_cast<std::size_t>(mesh.T(t, 3))];
    EXPECT_TRUE(touches) << "tetrahedron " << t << " away from the cage has ratio " << ratio;
  }
  EXPECT_LE(above, mesh.T.rows() / 50) << "more than 2% of the tetrahedra exceed the bound";
  if (GetParam().convex)
  {
    EXPECT_EQ(above, 0) << "the cube and the octahedron meet the bound everywhere";
  }
  EXPECT_GE(mesh.T.rows(), 1000);
}

TEST_P(SurfaceMeshProperties, PreserveBoundaryKeepsTheCageFaces)
{
  const Cage& c = cage();
  SurfaceMeshOptions options;
  options.preserve_boundary = true;
  options.max_volume = 1e-2 * std::abs(bary::signed_measure(c));
  const DomainMesh mesh = bary::mesh_closed_surface(c, options);
  expect_tet_mesh_fills_cage(mesh, c);
  std::set<std::array<int, 3>> cage_faces;
  for (Index f = 0; f < c.F.rows(); ++f)
  {
    std::array<int, 3> s{ c.F(f, 0), c.F(f, 1), c.F(f, 2) };
    std::sort(s.begin(), s.end());
    cage_faces.insert(s);
  }
  const auto bfaces = boundary_faces(mesh.T);
  const std::set<std::array<int, 3>> mesh_faces(bfaces.begin(), bfaces.end());
  EXPECT_EQ(mesh_faces, cage_faces);
  std::vector<int> cage_vertices(static_cast<std::size_t>(c.num_controls()));
  std::iota(cage_vertices.begin(), cage_vertices.end(), 0);
  EXPECT_EQ(mesh.boundary_vertices, cage_vertices);
}

TEST_P(SurfaceMeshProperties, SteinerPointsInsideAreInsertedExactly)
{
  const Cage& c = cage();
  const Index n_in = 60, n_out = 10;
  const bary::Points in = bary::test::sample_inside(c, n_in, 1e-3, 21);
  const bary::Points out = bary::test::sample_outside(c, n_out, 1e-3, 1.5, 22);
  const Eigen::RowVector3d a = c.V.row(c.F(0, 0)), b = c.V.row(c.F(0, 1)), d = c.V.row(c.F(0, 2));
  const Eigen::Vector3d n = bary::test::inward_normal(c, 0);
  const Eigen::RowVector3d near_face = (a + b + d) / 3.0 + 1e-9 * c.diameter() * n.transpose();
  SurfaceMeshOptions options;
  options.max_volume = 1e-2 * std::abs(bary::signed_measure(c));
  options.steiner_points.resize(n_in + n_out + 3, 3);
  options.steiner_points << in, out, near_face, in.row(5), in.row(7) + Eigen::RowVector3d(1e-9, 0, 0);
  for (const bool preserve : { false, true })
  {
    options.preserve_boundary = preserve;
    const DomainMesh mesh = bary::mesh_closed_surface(c, options);
    expect_tet_mesh_fills_cage(mesh, c);
    ASSERT_EQ(mesh.steiner_vertex.size(), n_in + n_out + 3);
    for (Index s = 0; s < n_in; ++s)
    {
      const int v = mesh.steiner_vertex(s);
      ASSERT_GE(v, 0) << "inside point " << s;
      EXPECT_EQ(v, c.num_controls() + s);
      EXPECT_TRUE((mesh.V.row(v).array() == in.row(s).array()).all()) << "inside point " << s;
    }
    for (Index s = n_in; s < n_in + n_out; ++s)
      EXPECT_EQ(mesh.steiner_vertex(s), -1) << "outside point " << s;
    EXPECT_EQ(mesh.steiner_vertex(n_in + n_out), -1) << "point 1e-9 diam from a face";
    EXPECT_EQ(mesh.steiner_vertex(n_in + n_out + 1), mesh.steiner_vertex(5)) << "duplicate";
    EXPECT_EQ(mesh.steiner_vertex(n_in + n_out + 2), mesh.steiner_vertex(7)) << "near-duplicate";
  }
}

INSTANTIATE_TEST_SUITE_P(
  Catalogue, SurfaceMeshProperties, ::testing::ValuesIn(bary::test::cages_3d()), cage_name);

// --- 3D: particular cases ---------------------------------------------------------------------

TEST(MeshClosedSurface, TargetCellsAndNoBounds)
{
  const Cage c = bary::test::unit_cube();
  SurfaceMeshOptions options;
  options.target_cells = 1000;
  const DomainMesh mesh = bary::mesh_closed_surface(c, options);
  expect_tet_mesh_fills_cage(mesh, c);
  EXPECT_GE(mesh.T.rows(), 1000);
  EXPECT_LE(mesh.T.rows(), 5000);
  for (Index t = 0; t < mesh.T.rows(); ++t)
    EXPECT_LE(tet_volume(mesh.V, mesh.T, t), 1e-3 * (1 + 1e-9));

  // No volume bound and no quality refinement: the cube's 8 vertices only.
  SurfaceMeshOptions coarse;
  coarse.radius_edge_ratio = 0.0;
  const DomainMesh minimal = bary::mesh_closed_surface(c, coarse);
  expect_tet_mesh_fills_cage(minimal, c);
  EXPECT_EQ(minimal.V.rows(), 8);
}

TEST(MeshClosedSurface, InvalidCagesGiveTheValidationError)
{
  Cage open = bary::test::unit_cube();
  open.F.conservativeResize(11, 3); // drop one face
  EXPECT_TRUE(throws_error(
    [&] { bary::mesh_closed_surface(open); }, ErrorCode::InvalidCage, { "not closed" }));

  // A cube whose top corner is pushed through the bottom: faces cross.
  Cage crossed = bary::test::unit_cube();
  crossed.V.row(7) << 0.6, 0.6, -0.5;
  EXPECT_TRUE(throws_error(
    [&] { bary::mesh_closed_surface(crossed); }, ErrorCode::InvalidCage, { "self-intersects" }));

  Cage inconsistent = bary::test::unit_cube();
  std::swap(inconsistent.F(0, 1), inconsistent.F(0, 2));
  EXPECT_TRUE(throws_error([&] { bary::mesh_closed_surface(inconsistent); },
    ErrorCode::InvalidCage, { "consistently oriented" }));
  EXPECT_TRUE(throws_error([&] { bary::mesh_closed_surface(bary::test::unit_square()); },
    ErrorCode::SizeMismatch, { "mesh_polygon" }));
}

/// The U box with its notch narrowed to a slit of width @p gap: the notch's bottom edge becomes
/// @p gap long.
Cage slit_box(double gap)
{
  Cage c = bary::test::u_box();
  const double xs[4] = { 1.5 + gap / 2, 1.5 + gap / 2, 1.5 - gap / 2, 1.5 - gap / 2 };
  for (int layer = 0; layer < 2; ++layer)
    for (int i = 0; i < 4; ++i)
      c.V(8 * layer + 3 + i, 0) = xs[i];
  return c;
}

/// The U box with its notch turned into a trapezoid whose top opening is @p gap wide: two
/// parts of the surface nearly touch, without any short edge (volume 5.5 - gap / 2).
Cage notch_box(double gap)
{
  Cage c = bary::test::u_box();
  const double pts[4][2] = { { 1.5 + gap / 2, 2 }, { 2, 1 }, { 1, 1 }, { 1.5 - gap / 2, 2 } };
  for (int layer = 0; layer < 2; ++layer)
    for (int i = 0; i < 4; ++i)
    {
      c.V(8 * layer + 3 + i, 0) = pts[i][0];
      c.V(8 * layer + 3 + i, 1) = pts[i][1];
    }
  return c;
}

TEST(MeshClosedSurface, NearlyTouchingFeaturesAreRejectedNotCrashed)
{
  // TetGen 1.5.0 merges vertices closer than 1e-8 of the bounding-box diagonal: on the slit it
  // then crashed (segfault), on the notch it silently closed the gap. Both pass validate_cage
  // (exact predicates) and are reported by the feature-size check instead.
  const Cage slit = slit_box(1e-9);
  bary::validate_cage(slit);
  EXPECT_TRUE(throws_error([&] { bary::mesh_closed_surface(slit); }, ErrorCode::InvalidCage,
    { "edge (4, 5) is only 1e-09 long" }));
  const Cage notch = notch_box(1e-9);
  bary::validate_cage(notch);
  EXPECT_TRUE(throws_error([&] { bary::mesh_closed_surface(notch); }, ErrorCode::InvalidCage,
    { "faces", "nearly touch", "vertex 3 is 1e-09 from face" }));
  // Wider gaps are meshed.
  SurfaceMeshOptions coarse;
  coarse.radius_edge_ratio = 0.0;
  for (const Cage& c : { slit_box(0.2), notch_box(1e-5) })
    expect_tet_mesh_fills_cage(bary::mesh_closed_surface(c, coarse), c);
}

TEST(MeshClosedSurface, TetgenErrorsBecomeBaryErrors)
{
  const Cage c = bary::test::unit_cube();
  // 'w' (weighted Delaunay) cannot go with 'p': TetGen throws its input error (10). (TetGen
  // prints one line about it on stdout; the library never passes such switches.)
  EXPECT_TRUE(throws_error(
    [&] { bary::detail::tetgen_tetrahedralize(c.V, c.F, Eigen::MatrixXd(), "pzQw"); },
    ErrorCode::InvalidArgument, { "TetGen failed with error 10", "pzQw" }));
  // The wrapper itself works on valid switches.
  const bary::detail::TetgenOutput out =
    bary::detail::tetgen_tetrahedralize(c.V, c.F, Eigen::MatrixXd(), "pzQ");
  EXPECT_EQ(out.V.rows(), 8);
  EXPECT_EQ(out.boundary_faces.rows(), 12);
  EXPECT_EQ(out.boundary_face_input.minCoeff(), 0);
  EXPECT_EQ(out.boundary_face_input.maxCoeff(), 11);
}

TEST(MeshClosedSurface, InvalidOptionsAreRejected)
{
  const Cage c = bary::test::unit_cube();
  SurfaceMeshOptions o;
  o.radius_edge_ratio = 0.8;
  EXPECT_TRUE(throws_error(
    [&] { bary::mesh_closed_surface(c, o); }, ErrorCode::InvalidArgument, { "radius_edge_ratio" }));
  o = {};
  o.max_volume = 1e-12;
  EXPECT_TRUE(throws_error(
    [&] { bary::mesh_closed_surface(c, o); }, ErrorCode::InvalidArgument, { "max_volume", "limit" }));
  o = {};
  o.target_cells = -1;
  EXPECT_TRUE(throws_error(
    [&] { bary::mesh_closed_surface(c, o); }, ErrorCode::InvalidArgument, { "target_cells" }));
  o = {};
  o.steiner_tolerance = 1e-9;
  EXPECT_TRUE(throws_error(
    [&] { bary::mesh_closed_surface(c, o); }, ErrorCode::InvalidArgument, { "steiner_tolerance" }));
  o = {};
  o.steiner_points = Eigen::MatrixXd::Constant(3, 2, 0.5);
  EXPECT_TRUE(throws_error(
    [&] { bary::mesh_closed_surface(c, o); }, ErrorCode::SizeMismatch, { "Steiner" }));
}

TEST(MeshClosedSurface, ProgressAndCancellation)
{
  const Cage c = bary::test::unit_cube();
  SurfaceMeshOptions o;
  o.max_volume = 1e-2;
  std::vector<double> fractions;
  bary::mesh_closed_surface(c, o, [&](double f) {
    fractions.push_back(f);
    return true;
  });
  ASSERT_GE(fractions.size(), 3u);
  EXPECT_TRUE(std::is_sorted(fractions.begin(), fractions.end()));
  EXPECT_EQ(fractions.front(), 0.0);
  EXPECT_EQ(fractions.back(), 1.0);
  EXPECT_TRUE(throws_error([&] { bary::mesh_closed_surface(c, o, [](double f) { return f < 0.5; }); },
    ErrorCode::Cancelled));
}

TEST(MeshClosedSurface, Deterministic)
{
  const Cage c = bary::test::noisy_icosphere(2, 0.1, 5);
  SurfaceMeshOptions o;
  o.max_volume = 1e-2;
  const DomainMesh a = bary::mesh_closed_surface(c, o), b = bary::mesh_closed_surface(c, o);
  EXPECT_TRUE((a.V.array() == b.V.array()).all());
  EXPECT_TRUE((a.T.array() == b.T.array()).all());
}

TEST(DefaultTargetCells, TrianglesAndTetrahedra)
{
  EXPECT_EQ(bary::default_target_cells(2), 3000);
  EXPECT_EQ(bary::default_target_cells(3), 20000);
  EXPECT_EQ(PolygonMeshOptions().target_cells, bary::default_target_cells(2));
}

TEST(DomainMeshForCage, MatchesTheCageVerticesOfAGivenMesh)
{
  const Cage cage = bary::test::star_polygon(5, 1.0, 0.5);
  PolygonMeshOptions o;
  o.target_cells = 200;
  const DomainMesh made = bary::mesh_polygon(cage, o);
  // the mesh as if read from a file, its vertices shuffled: reverse the vertex order
  const Index nv = made.V.rows();
  const Eigen::MatrixXd V = made.V.colwise().reverse();
  Eigen::MatrixXi T = made.T;
  for (Index t = 0; t < T.rows(); ++t)
    for (Index k = 0; k < 3; ++k)
      T(t, k) = static_cast<int>(nv - 1 - T(t, k));
  std::vector<double> seen;
  const DomainMesh mesh = bary::domain_mesh_for_cage(cage, V, T, [&](double f) {
    seen.push_back(f);
    return true;
  });
  ASSERT_EQ(mesh.control_vertex.size(), cage.num_controls());
  for (Index i = 0; i < cage.num_controls(); ++i)
  {
    EXPECT_EQ(mesh.control_vertex(i), nv - 1 - made.control_vertex(i)) << "cage vertex " << i;
    EXPECT_EQ((mesh.V.row(mesh.control_vertex(i)) - cage.V.row(i)).norm(), 0.0);
  }
  EXPECT_EQ(mesh.boundary_vertices, bary::boundary_vertices(T));
  EXPECT_EQ(mesh.boundary_weights.rows(), static_cast<Index>(mesh.boundary_vertices.size()));
  ASSERT_FALSE(seen.empty());
  EXPECT_EQ(seen.back(), 1.0);
  EXPECT_TRUE(std::is_sorted(seen.begin(), seen.end()));
  EXPECT_TRUE(throws_error(
    [&] { bary::domain_mesh_for_cage(cage, V, T, [](double f) { return f < 0.2; }); },
    ErrorCode::Cancelled, { "matching the domain mesh to the cage was cancelled" }));
}

TEST(DomainMeshForCage, ErrorsSayWhatToGive)
{
  // a mesh of the unit square, a cage with a fifth vertex above it
  const Cage square = bary::test::unit_square();
  PolygonMeshOptions o;
  o.target_cells = 200;
  const DomainMesh mesh = bary::mesh_polygon(square, o);
  Cage pentagon;
  pentagon.V.resize(5, 2);
  pentagon.V << 0, 0, 1, 0, 1, 1, 0.5, 1.5, 0, 1;
  EXPECT_TRUE(throws_error([&] { bary::domain_mesh_for_cage(pentagon, mesh.V, mesh.T); },
    ErrorCode::InvalidArgument,
    { "the domain mesh does not fit the cage: cage vertex 3 at (0.5, 1.5) is not a boundary "
      "vertex of the mesh (the nearest one is ",
      " x the cage diameter away, allowed 1e-6): give a mesh of this cage's interior that has "
      "the cage vertices as vertices" }));
  // a tetrahedral domain for a 2D cage
  SurfaceMeshOptions so;
  so.target_cells = 100;
  const DomainMesh tets = bary::mesh_closed_surface(bary::test::unit_cube(), so);
  EXPECT_TRUE(throws_error([&] { bary::domain_mesh_for_cage(square, tets.V, tets.T); },
    ErrorCode::InvalidArgument,
    { "the domain mesh is made of tetrahedra but the cage is 2D: give a triangulation of the "
      "cage's interior, in its plane" }));
  // triangles for a 3D cage
  EXPECT_TRUE(throws_error([&] { bary::domain_mesh_for_cage(bary::test::unit_cube(), mesh.V, mesh.T); },
    ErrorCode::InvalidArgument,
    { "made of triangles but the cage is 3D: give a tetrahedralization of the cage's interior" }));
}

} // namespace

// --- extreme scales and bounded work (issue 17) -----------------------------------------------

TEST(MeshClosedSurface, PowerOfTwoScalesGiveTheSameMeshScaled)
{
  // The cage is meshed at a normalised scale and the vertices scaled back, exactly.
  const Cage unit = bary::test::unit_cube();
  SurfaceMeshOptions o;
  o.target_cells = 500;
  const DomainMesh ref = bary::mesh_closed_surface(unit, o);
  for (const int k : { 250, -250, 1000, -1000 })
  {
    SCOPED_TRACE(k);
    Cage c = unit;
    c.V *= std::ldexp(1.0, k);
    SurfaceMeshOptions scaled = o;
    const DomainMesh mesh = bary::mesh_closed_surface(c, scaled);
    ASSERT_EQ(mesh.T, ref.T);
    EXPECT_EQ(mesh.V, ref.V * std::ldexp(1.0, k));
    // a volume bound scales with the cube of the lengths
    scaled.target_cells = 0;
    scaled.max_volume = std::ldexp(1.0 / 500, 3 * k);
    if (std::abs(k) < 300)
    {
      EXPECT_GE(bary::mesh_closed_surface(c, scaled).num_elements(), 500);
    }
  }
}

TEST(MeshClosedSurface, NonPowerOfTwoExtremeScalesMeshTheCube)
{
  // 1e75 and 1e100 crashed TetGen, 1e-75 aborted it, 1e-50 ran it out of memory (issue 17).
  for (const double scale : { 1e300, 1e100, 1e75, 1e-50, 1e-75, 1e-300 })
  {
    SCOPED_TRACE(scale);
    Cage c = bary::test::unit_cube();
    c.V *= scale;
    SurfaceMeshOptions o;
    o.target_cells = 500;
    const DomainMesh mesh = bary::mesh_closed_surface(c, o);
    EXPECT_GE(mesh.num_elements(), 500);
    double volume = 0.0;
    for (Index t = 0; t < mesh.T.rows(); ++t)
    {
      Eigen::Matrix3d E;
      for (int k = 0; k < 3; ++k)
        E.col(k) = (mesh.V.row(mesh.T(t, k + 1)) - mesh.V.row(mesh.T(t, 0))).transpose() / scale;
      const double v = E.determinant() / 6.0;
      EXPECT_GT(v, 0.0);
      volume += v;
    }
    EXPECT_NEAR(volume, 1.0, 1e-12);
  }
}

TEST(MeshPolygon, PowerOfTwoScalesGiveTheSameMeshScaled)
{
  const Cage unit = bary::test::u_polygon();
  PolygonMeshOptions o;
  o.target_cells = 300;
  const DomainMesh ref = bary::mesh_polygon(unit, o);
  for (const int k : { 400, -400 })
  {
    Cage c = unit;
    c.V *= std::ldexp(1.0, k);
    const DomainMesh mesh = bary::mesh_polygon(c, o);
    ASSERT_EQ(mesh.T, ref.T);
    EXPECT_EQ(mesh.V, ref.V * std::ldexp(1.0, k));
  }
}

TEST(MeshClosedSurface, RefinementThatCannotEndIsBoundedAndRefused)
{
  const Cage c = bary::test::unit_cube();
  SurfaceMeshOptions o;
  for (const double ratio : { 1.0, 1.05 }) // 1.0 on the kidney cage ran 4 min to 4.8 GB
  {
    o.radius_edge_ratio = ratio;
    EXPECT_TRUE(throws_error([&] { bary::mesh_closed_surface(c, o); }, ErrorCode::InvalidArgument,
      { "radius_edge_ratio", "[1.1, 10]" }));
  }
  // a quality bound not met within the vertices TetGen may add
  o = {};
  o.target_cells = 20000;
  o.max_added_vertices = 200;
  EXPECT_TRUE(throws_error([&] { bary::mesh_closed_surface(c, o); }, ErrorCode::NotConverged,
    { "radius-edge ratio 1.414", "after 200", "raise radius_edge_ratio" }));
  o.max_added_vertices = -1;
  EXPECT_TRUE(throws_error(
    [&] { bary::mesh_closed_surface(c, o); }, ErrorCode::InvalidArgument, { "max_added_vertices" }));
}
