// Tests of core/spline: Bernstein-Bézier pieces, the global control net and its C1 conditions,
// the Jacobian test, and DECLeS editing (Rodrigues, Stolfi, Gomide 2014). References are
// independent of the code under test: pointwise products and finite differences for the Bézier
// operations, global polynomials and truncated powers (C1 by construction, or only C0) for the
// conditions, Eigen's rank-revealing LU for the exact elimination, the paper's count g - 2 for a
// vertex's conditions.
#include "core/detail/exact_elimination.h"
#include "core/meshing/domain_mesh.h"
#include "core/spline/decles.h"
#include "core/spline/spline_fit.h"
#include "core/spline/triangular_spline.h"
#include "error_matchers.h"

#include <Eigen/LU>
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>

using namespace bary;
using bary::test::throws_error;

namespace
{

/// A regular grid of nx by ny squares on [x0, x0 + nx h] x [y0, y0 + ny h], each cut in two;
/// with @p alternate the diagonals alternate (interior vertex degrees 4 and 8), else all go
/// the same way (degree 6).
void grid(int nx, int ny, double h, bool alternate, Eigen::MatrixXd& V, Eigen::MatrixXi& T)
{
  V.resize((nx + 1) * (ny + 1), 2);
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i)
      V.row(j * (nx + 1) + i) << -1.0 + h * i, -0.5 + h * j;
  T.resize(2 * nx * ny, 3);
  int t = 0;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i)
    {
      const int a = j * (nx + 1) + i, b = a + 1, c = a + nx + 2, d = a + nx + 1;
      if (!alternate || (i + j) % 2 == 0)
      {
        T.row(t++) << a, b, c;
        T.row(t++) << a, c, d;
      }
      else
      {
        T.row(t++) << a, b, d;
        T.row(t++) << b, c, d;
      }
    }
}

std::shared_ptr<SplineNet> grid_net(int nx, int ny, bool alternate, int degree = 5)
{
  Eigen::MatrixXd V;
  Eigen::MatrixXi T;
  grid(nx, ny, 0.25, alternate, V, T);
  return std::make_shared<SplineNet>(V, T, degree);
}

/// An irregular triangulation (CGAL's mesher in a non-convex polygon): vertices of degree 3 to 9.
std::shared_ptr<SplineNet> irregular_net(int degree = 5)
{
  Cage c;
  c.V.resize(7, 2);
  c.V << 0, 0, 1.3, 0.1, 1.1, 0.7, 0.6, 0.5, 0.4, 1.2, -0.2, 0.9, 0.1, 0.4;
  PolygonMeshOptions o;
  o.target_cells = 60;
  const DomainMesh m = mesh_polygon(c, o);
  return std::make_shared<SplineNet>(m.V, m.T, degree);
}

/// Coefficients of a global function given per triangle by its Bézier coefficients (shared
/// points written by every triangle: they must agree, checked).
TriangularSpline from_pieces(
  std::shared_ptr<const SplineNet> net, const std::function<Eigen::MatrixXd(Index)>& piece)
{
  Eigen::MatrixXd X = Eigen::MatrixXd::Constant(net->num_points(), 1, NAN);
  for (Index t = 0; t < net->num_triangles(); ++t)
  {
    const Eigen::MatrixXd C = piece(t);
    for (int r = 0; r < C.rows(); ++r)
    {
      const Index g = net->local_to_global()(t, r);
      if (std::isfinite(X(g, 0)))
      {
        EXPECT_NEAR(X(g, 0), C(r, 0), 1e-12) << "shared control point " << g;
      }
      X(g, 0) = C(r, 0);
    }
  }
  return TriangularSpline(net, X);
}

/// Bézier coefficients (degree d) over triangle t of the product of the linear functions
/// l_1 ... l_q (each given by its values at the domain vertices: a function of the position).
Eigen::MatrixXd product_piece(const SplineNet& net, Index t,
  const std::vector<std::function<double(const Eigen::Vector2d&)>>& factors)
{
  Eigen::VectorXd p = Eigen::VectorXd::Ones(1);
  int deg = 0;
  for (const auto& f : factors)
  {
    Eigen::VectorXd l(3); // degree-1 coefficients: the values at the corners (row order)
    const auto& V = net.vertices();
    const auto& T = net.triangles();
    l[bezier_index(1, 1, 0)] = f(V.row(T(t, 0)));
    l[bezier_index(1, 0, 1)] = f(V.row(T(t, 1)));
    l[bezier_index(1, 0, 0)] = f(V.row(T(t, 2)));
    p = bezier_product(p, deg, l, 1);
    ++deg;
  }
  Eigen::MatrixXd C = p;
  for (; deg < net.degree(); ++deg)
    C = bezier_elevate(C, deg);
  return C;
}

Eigen::Vector3d random_barycentric(std::mt19937& rng)
{
  std::uniform_real_distribution<double> u(0, 1);
  double a = u(rng), b = u(rng);
  if (a + b > 1)
  {
    a = 1 - a;
    b = 1 - b;
  }
  return { 1 - a - b, a, b };
}

} // namespace

// --- Bernstein-Bézier pieces --------------------------------------------------------------

TEST(BezierTriangle, BasisEvaluationDerivativeElevationProduct)
{
  std::mt19937 rng(1);
  std::normal_distribution<double> g;
  for (int d : { 1, 2, 5, 7 })
  {
    Eigen::MatrixXd C(bezier_count(d), 2);
    for (Index r = 0; r < C.rows(); ++r)
      C.row(r) << g(rng), g(rng);
    for (int s = 0; s < 20; ++s)
    {
      const Eigen::Vector3d b = random_barycentric(rng);
      std::vector<double> B(static_cast<size_t>(bezier_count(d)));
      bernstein_basis(d, b, B.data());
      double sum = 0;
      Eigen::RowVector2d viaBasis = Eigen::RowVector2d::Zero();
      for (int r = 0; r < bezier_count(d); ++r)
      {
        sum += B[static_cast<size_t>(r)];
        viaBasis += B[static_cast<size_t>(r)] * C.row(r);
      }
      EXPECT_NEAR(sum, 1.0, 1e-14);
      EXPECT_LT((viaBasis - bezier_evaluate(C, d, b)).norm(), 1e-12);
      // Directional derivative against central differences along u = (-1, 1, 0).
      const Eigen::Vector3d u(-1, 1, 0);
      const double eps = 1e-6;
      const Eigen::RowVectorXd fd =
        (bezier_evaluate(C, d, b + eps * u) - bezier_evaluate(C, d, b - eps * u)) / (2 * eps);
      EXPECT_LT((fd - bezier_evaluate(bezier_derivative(C, d, u), d - 1, b)).norm(), 1e-7);
      // Elevation keeps the polynomial.
      EXPECT_LT((bezier_evaluate(bezier_elevate(C, d), d + 1, b) - bezier_evaluate(C, d, b)).norm(),
        1e-12);
      // Product: pointwise.
      const Eigen::VectorXd pq = bezier_product(C.col(0), d, C.col(1), d);
      const double expect = bezier_evaluate(C, d, b)[0] * bezier_evaluate(C, d, b)[1];
      EXPECT_NEAR(bezier_evaluate(pq, 2 * d, b)[0], expect, 1e-11);
    }
  }
}

TEST(BezierTriangle, SubtriangleCoefficientsDescribeTheSamePolynomial)
{
  std::mt19937 rng(2);
  std::normal_distribution<double> g;
  const int d = 6;
  Eigen::MatrixXd C(bezier_count(d), 1);
  for (Index r = 0; r < C.rows(); ++r)
    C(r, 0) = g(rng);
  const Eigen::Vector3d a(0.6, 0.2, 0.2), b(0.1, 0.8, 0.1), c(0.2, 0.3, 0.5);
  const Eigen::MatrixXd S = bezier_subtriangle(C, d, a, b, c);
  for (int s = 0; s < 20; ++s)
  {
    const Eigen::Vector3d w = random_barycentric(rng);
    const Eigen::Vector3d x = w[0] * a + w[1] * b + w[2] * c;
    EXPECT_NEAR(bezier_evaluate(S, d, w)[0], bezier_evaluate(C, d, x)[0], 1e-12);
  }
}

// --- The control net ------------------------------------------------------------------------

TEST(SplineNet, CountsNumberingAndTypes)
{
  for (int d : { 5, 6, 8 })
  {
    const auto net = grid_net(4, 3, true, d);
    const Index nv = 20, nt = 24, ne = 43, interior_edges = ne - 14;
    EXPECT_EQ(net->edges().rows(), ne);
    EXPECT_EQ(net->num_points(), nv + ne * (d - 1) + nt * (d - 1) * (d - 2) / 2);
    EXPECT_EQ(static_cast<Index>(net->conditions().size()), interior_edges * d);
    // Nominal positions are distinct (one control point per position) and each condition's
    // coefficients are an affine combination (sum 0 with the -1).
    std::set<std::pair<long long, long long>> seen;
    for (Index p = 0; p < net->num_points(); ++p)
      EXPECT_TRUE(seen.insert({ std::llround(net->nominal()(p, 0) * 1e9),
                                std::llround(net->nominal()(p, 1) * 1e9) })
                    .second);
    for (const auto& c : net->conditions())
      EXPECT_NEAR(c.coefficient[0] + c.coefficient[1] + c.coefficient[2] + c.coefficient[3], 0.0,
        1e-15);
    // Table 1 on one triangle of degree d.
    std::map<ControlPointType, int> count;
    for (int r = 0; r < bezier_count(d); ++r)
      ++count[net->type(net->local_to_global()(0, r))];
    EXPECT_EQ(count[ControlPointType::Corner], 3);
    EXPECT_EQ(count[ControlPointType::EdgeCorner], 6);
    EXPECT_EQ(count[ControlPointType::Edge], 3 * (d - 3));
    EXPECT_EQ(count[ControlPointType::InnerCorner], 3);
    EXPECT_EQ(count[ControlPointType::InnerEdge], 3 * (d - 4));
    EXPECT_EQ(count[ControlPointType::Interior], (d - 4) * (d - 5) / 2);
  }
}

TEST(SplineNet, IdentityReproducesTheDomain)
{
  const auto net = irregular_net();
  const TriangularSpline phi = TriangularSpline::identity(net);
  std::mt19937 rng(3);
  for (Index t = 0; t < net->num_triangles(); ++t)
  {
    const Eigen::Vector3d b = random_barycentric(rng);
    const Eigen::RowVector2d x = b[0] * net->vertices().row(net->triangles()(t, 0)) +
      b[1] * net->vertices().row(net->triangles()(t, 1)) +
      b[2] * net->vertices().row(net->triangles()(t, 2));
    EXPECT_LT((phi.evaluate(t, b) - Eigen::RowVectorXd(x)).norm(), 1e-14);
    EXPECT_LT((phi.jacobian(t, b) - Eigen::Matrix2d::Identity()).norm(), 1e-12);
  }
  const ContinuityReport c = phi.continuity();
  EXPECT_LT(c.max_condition_residual, 1e-15);
  EXPECT_LT(c.max_gradient_jump, 1e-12);
  const JacobianReport j = phi.check_jacobian();
  EXPECT_TRUE(j.positive_everywhere());
  EXPECT_NEAR(j.min_jacobian, 1.0, 1e-12);
  // Located and evaluated points: the identity.
  Points P(100, 2);
  for (Index p = 0; p < P.rows(); ++p)
    P.row(p) = 0.5 * net->vertices().row(net->triangles()(p % net->num_triangles(), 0)) +
      0.5 * net->vertices().row(net->triangles()(p % net->num_triangles(), 1));
  EXPECT_LT((phi.evaluate(phi.locate(P)) - P).norm(), 1e-13);
}

// The conditions against functions whose smoothness is known: a global polynomial (C-infinity)
// and the truncated power (x - x0)_+^2 along a grid line (C1, not C2) satisfy them; (x - x0)_+
// (C0 only) does not, and the gradient jump across the line is its slope.
TEST(SplineNet, ConditionsHoldExactlyForC1FunctionsOnly)
{
  for (bool alternate : { false, true })
    for (int d : { 5, 7 })
    {
      const auto net = grid_net(6, 4, alternate, d);
      using F = std::function<double(const Eigen::Vector2d&)>;
      const F lx = [](const Eigen::Vector2d& x) { return x.x() + 0.3; };
      const F ly = [](const Eigen::Vector2d& x) { return 2 * x.y() - x.x(); };
      const F one = [](const Eigen::Vector2d&) { return 1.0; };
      const TriangularSpline poly =
        from_pieces(net, [&](Index t) { return product_piece(*net, t, { lx, ly, lx }); });
      EXPECT_LT(poly.continuity().max_condition_residual, 1e-14);
      EXPECT_LT(poly.continuity().max_gradient_jump, 1e-12);
      // Cut at x = -0.5 (a grid line): the triangles right of it carry the power.
      auto right = [&](Index t) {
        double cx = 0;
        for (int c = 0; c < 3; ++c)
          cx += net->vertices()(net->triangles()(t, c), 0) / 3;
        return cx > -0.5;
      };
      const F cut = [](const Eigen::Vector2d& x) { return x.x() + 0.5; };
      const F zero = [](const Eigen::Vector2d&) { return 0.0; };
      const TriangularSpline c1 = from_pieces(net, [&](Index t) {
        return right(t) ? product_piece(*net, t, { cut, cut }) : product_piece(*net, t, { zero });
      });
      EXPECT_LT(c1.continuity().max_condition_residual, 1e-14);
      EXPECT_LT(c1.continuity().max_gradient_jump, 1e-12);
      const TriangularSpline c0 = from_pieces(net, [&](Index t) {
        return right(t) ? product_piece(*net, t, { cut }) : product_piece(*net, t, { zero, one });
      });
      EXPECT_GT(c0.continuity().max_condition_residual, 1e-3);
      EXPECT_NEAR(c0.continuity().max_gradient_jump, 1.0, 1e-12);
    }
}

TEST(SplineNet, RefusesBadTriangulations)
{
  Eigen::MatrixXd V;
  Eigen::MatrixXi T;
  grid(2, 2, 0.5, false, V, T);
  EXPECT_TRUE(throws_error([&] { SplineNet(V, T, 4); }, ErrorCode::InvalidArgument, { "degree 4" }));
  EXPECT_TRUE(throws_error([&] { SplineNet(V, T, 13); }, ErrorCode::InvalidArgument, { "degree 13" }));
  EXPECT_TRUE(throws_error(
    [&] { SplineNet(V, Eigen::MatrixXi(0, 3)); }, ErrorCode::EmptyInput, { "no triangle" }));
  {
    Eigen::MatrixXd W = V;
    W(4, 1) = NAN;
    EXPECT_TRUE(throws_error([&] { SplineNet(W, T); }, ErrorCode::NonFinite, { "vertex 4" }));
  }
  {
    Eigen::MatrixXi U = T;
    U(3, 2) = 99;
    EXPECT_TRUE(throws_error([&] { SplineNet(V, U); }, ErrorCode::InvalidArgument, { "vertex 99" }));
  }
  {
    Eigen::MatrixXd W = V; // vertex 4 (the centre) onto vertex 1: triangle (0, 1, 4) degenerate
    W.row(4) = W.row(1);
    EXPECT_TRUE(throws_error([&] { SplineNet(W, T); }, ErrorCode::InvalidCage, { "degenerate" }));
  }
  {
    Eigen::MatrixXi U = T; // one triangle reversed
    std::swap(U(2, 1), U(2, 2));
    EXPECT_TRUE(throws_error([&] { SplineNet(V, U); }, ErrorCode::InvalidCage, { "clockwise" }));
  }
  {
    // A second and a third triangle on the border edge (0, 1): non-manifold.
    Eigen::MatrixXd W(V.rows() + 2, 2);
    W << V, Eigen::RowVector2d(-0.75, -0.9), Eigen::RowVector2d(-0.75, -1.2);
    const int n = static_cast<int>(V.rows());
    Eigen::MatrixXi U(T.rows() + 2, 3);
    U << T, Eigen::RowVector3i(0, n, 1), Eigen::RowVector3i(1, 0, n + 1);
    EXPECT_TRUE(throws_error([&] { SplineNet(W, U); }, ErrorCode::InvalidCage, { "edge (0, 1)" }));
  }
  {
    // Two triangles touching at one vertex only: a bow tie.
    Eigen::MatrixXd W(5, 2);
    W << 0, 0, 1, 0, 1, 1, -1, 0, -1, -1;
    Eigen::MatrixXi U(2, 3);
    U << 0, 1, 2, 0, 3, 4;
    EXPECT_TRUE(throws_error([&] { SplineNet(W, U); }, ErrorCode::InvalidCage, { "vertex 0", "manifold" }));
  }
  {
    Eigen::MatrixXd W(V.rows() + 1, 2);
    W << V, Eigen::RowVector2d(5, 5);
    EXPECT_TRUE(throws_error([&] { SplineNet(W, T); }, ErrorCode::InvalidCage, { "vertex 9", "no triangle" }));
  }
  {
    // All clockwise: accepted, reversed.
    Eigen::MatrixXi U = T;
    U.col(1).swap(U.col(2));
    const SplineNet net(V, U);
    EXPECT_TRUE(net.reversed());
    EXPECT_EQ(net.triangles(), T);
  }
}

// --- Non-degeneracy (§3.4) -------------------------------------------------------------------

TEST(SplineJacobian, DeterminantPolynomialAndAConstructedFold)
{
  const auto net = grid_net(4, 2, true);
  TriangularSpline phi = TriangularSpline::identity(net);
  // A smooth C1 deformation: the identity plus a product of linear functions (a quadratic map).
  std::mt19937 rng(4);
  Eigen::MatrixXd X = phi.values();
  // The quadratic map (x + 0.2 x y, y + 0.1 x^2) has the Bézier coefficients of its pieces from
  // products of linear functions.
  using F = std::function<double(const Eigen::Vector2d&)>;
  const F fx = [](const Eigen::Vector2d& p) { return p.x(); };
  const F fy = [](const Eigen::Vector2d& p) { return p.y(); };
  const F one = [](const Eigen::Vector2d&) { return 1.0; };
  const TriangularSpline ax = from_pieces(net, [&](Index t) {
    return Eigen::MatrixXd(product_piece(*net, t, { fx, one }) + 0.2 * product_piece(*net, t, { fx, fy }));
  });
  const TriangularSpline ay = from_pieces(net, [&](Index t) {
    return Eigen::MatrixXd(product_piece(*net, t, { fy, one }) + 0.1 * product_piece(*net, t, { fx, fx }));
  });
  X.col(0) = ax.values().col(0);
  X.col(1) = ay.values().col(0);
  phi = TriangularSpline(net, X);
  const JacobianReport j = phi.check_jacobian();
  // det = (1 + 0.2 y)(1) - (0.2 x)(0.2 x) > 0 on [-1, 1] x [-0.5, 0]; its minimum at a corner.
  EXPECT_TRUE(j.positive_everywhere());
  EXPECT_NEAR(j.min_jacobian, (1 + 0.2 * -0.5) - 0.04, 1e-12);
  for (int s = 0; s < 30; ++s)
  {
    const Index t = s % net->num_triangles();
    const Eigen::Vector3d b = random_barycentric(rng);
    const Eigen::MatrixXd J = phi.jacobian(t, b);
    const Eigen::RowVectorXd x = TriangularSpline::identity(net).evaluate(t, b);
    EXPECT_NEAR(J.determinant(), (1 + 0.2 * x[1]) - 0.04 * x[0] * x[0], 1e-12);
  }
  // A fold: an interior vertex's control point moved past its neighbours.
  Eigen::MatrixXd Y = TriangularSpline::identity(net).values();
  const Index v = 7; // (-0.5, -0.25): interior of the 4 x 2 grid
  Y.row(v) += Eigen::RowVector2d(0.6, 0.0);
  const TriangularSpline folded(net, Y);
  const JacobianReport f = folded.check_jacobian();
  ASSERT_FALSE(f.folded.empty());
  for (size_t k = 0; k < f.folded.size(); ++k)
  {
    const Index t = f.folded[k];
    const Eigen::Vector3d b = net->barycentric(t, f.fold_points[k]);
    EXPECT_LE(folded.jacobian(t, b).determinant(), 1e-12) << "triangle " << t;
  }
  EXPECT_LT(f.min_jacobian, 0.0);
  EXPECT_TRUE(throws_error([&] { TriangularSpline::constant(net, 1).check_jacobian(); },
    ErrorCode::InvalidArgument, { "deformation" }));
}

// --- Exact elimination (§4.3.2) ---------------------------------------------------------------

// Around an interior vertex of degree g the g conditions t = 0 (its 1-disk) have rank g - 2
// (§4.3.2: "two are implied by the other g - 2").
TEST(SplineExact, VertexConditionsHaveRankDegreeMinusTwo)
{
  const auto net = irregular_net();
  int checked = 0;
  for (Index v = 0; v < net->num_vertices(); ++v)
  {
    std::vector<Index> rows;
    for (Index c = 0; c < static_cast<Index>(net->conditions().size()); ++c)
    {
      const auto& q = net->conditions()[static_cast<size_t>(c)];
      const auto& e = net->edges();
      if (q.t == 0 && e(q.edge, 0) == v)
        rows.push_back(c);
      if (q.t == net->degree() - 1 && e(q.edge, 1) == v)
        rows.push_back(c);
    }
    // Interior vertex: as many interior edges as triangles.
    Index tris = 0;
    for (Index t = 0; t < net->num_triangles(); ++t)
      for (int k = 0; k < 3; ++k)
        tris += net->triangles()(t, k) == v;
    if (static_cast<Index>(rows.size()) != tris)
      continue;
    // Unknowns: the vertex and its edge corners.
    std::map<Index, int> col;
    for (Index c : rows)
      for (Index p : net->conditions()[static_cast<size_t>(c)].point)
        col.emplace(p, static_cast<int>(col.size()));
    std::vector<detail::ExactCondition> in;
    for (Index c : rows)
    {
      const auto& q = net->conditions()[static_cast<size_t>(c)];
      detail::ExactCondition r;
      for (int k = 0; k < 4; ++k)
      {
        r.column[static_cast<size_t>(k)] = col.at(q.point[static_cast<size_t>(k)]);
        r.vertex[static_cast<size_t>(k)] = { net->vertices()(q.vertex[static_cast<size_t>(k)], 0),
          net->vertices()(q.vertex[static_cast<size_t>(k)], 1) };
      }
      in.push_back(r);
    }
    const auto ex = detail::eliminate_exact(in, static_cast<int>(col.size()), 0);
    EXPECT_EQ(static_cast<Index>(ex.independent.size()), tris - 2) << "vertex " << v;
    ++checked;
  }
  EXPECT_GT(checked, 5);
}

// The rows kept by the exact elimination are independent and span E: their count is the rank of
// E's columns of the derived points, found independently by Eigen's full-pivoting LU.
TEST(SplineExact, KeptRowsEqualTheRank)
{
  for (const auto& net : { irregular_net(), grid_net(6, 4, true), grid_net(6, 4, false, 6) })
  {
    SplineEditor editor(TriangularSpline::identity(net));
    for (Index a = 0; a < net->num_points(); a += 7)
    {
      const EditSets s = editor.select({ a }, a % 3);
      std::map<Index, Index> col;
      for (Index p : s.derived)
        col.emplace(p, static_cast<Index>(col.size()));
      Eigen::MatrixXd A = Eigen::MatrixXd::Zero(static_cast<Index>(s.constraints.size()),
        static_cast<Index>(col.size()) + 1);
      for (size_t r = 0; r < s.constraints.size(); ++r)
      {
        const auto& q = net->conditions()[static_cast<size_t>(s.constraints[r])];
        for (int k = 0; k < 4; ++k)
        {
          const auto it = col.find(q.point[static_cast<size_t>(k)]);
          if (it != col.end())
            A(static_cast<Index>(r), it->second) += q.coefficient[static_cast<size_t>(k)];
          else if (q.point[static_cast<size_t>(k)] == a)
            A(static_cast<Index>(r), A.cols() - 1) += q.coefficient[static_cast<size_t>(k)];
        }
      }
      Eigen::FullPivLU<Eigen::MatrixXd> lu(A.leftCols(A.cols() - 1));
      lu.setThreshold(1e-10);
      EXPECT_EQ(lu.rank(), static_cast<Index>(s.independent.size())) << "anchor " << a;
      // Property 2: the anchor's column lies in the span (rank does not grow).
      Eigen::FullPivLU<Eigen::MatrixXd> lu2(A);
      lu2.setThreshold(1e-10);
      EXPECT_EQ(lu2.rank(), lu.rank()) << "anchor " << a;
    }
  }
}

// --- DECLeS editing ---------------------------------------------------------------------------

// Long random edit sequences (translations, rotations, scales; anchors of every type; delta_max
// 0 to 4; several anchors at once) keep the spline C1 to rounding, put the anchors exactly where
// the edit says, and undo/redo and replaying the log reproduce the values bit for bit.
TEST(SplineEditor, RandomEditSequencesKeepC1)
{
  for (const auto& net : { irregular_net(), grid_net(8, 4, true), grid_net(8, 4, false, 6) })
  {
    const TriangularSpline start = TriangularSpline::identity(net);
    SplineEditor editor(start);
    std::mt19937 rng(5);
    std::uniform_int_distribution<Index> pick(0, net->num_points() - 1);
    std::uniform_real_distribution<double> u(-1, 1);
    std::map<ControlPointType, int> types;
    const double h = net->mean_edge_length();
    for (int e = 0; e < 120; ++e)
    {
      SplineEdit edit;
      edit.anchors = { pick(rng) };
      if (e % 5 == 4)
      {
        const Index b = pick(rng);
        if (b != edit.anchors[0])
          edit.anchors.push_back(b);
      }
      edit.delta_max = e % 5;
      edit.op = static_cast<SplineEditOp>(e % 3);
      edit.by = Eigen::Vector2d(u(rng), u(rng)) * 0.05 * h;
      edit.center = net->nominal().row(pick(rng)).transpose();
      edit.angle_degrees = 10 * u(rng);
      edit.factor = 1 + 0.1 * u(rng);
      for (Index a : edit.anchors)
        ++types[net->type(a)];
      Eigen::MatrixXd before = editor.spline().values();
      const SplineEditReport r = editor.apply(edit);
      EXPECT_EQ(r.sets.expansions, 0) << "the type rules were not enough for anchor " << edit.anchors[0];
      EXPECT_LT(r.residual, 1e-12 * (1 + h));
      if (edit.op == SplineEditOp::Translate)
      {
        for (Index a : edit.anchors)
          EXPECT_LT((editor.spline().values().row(a) - before.row(a) - edit.by.transpose()).norm(),
            1e-15);
      }
      // Only A and D moved.
      std::set<Index> moved(r.sets.anchors.begin(), r.sets.anchors.end());
      moved.insert(r.sets.derived.begin(), r.sets.derived.end());
      for (Index p = 0; p < net->num_points(); ++p)
      {
        if (!moved.count(p))
        {
          ASSERT_EQ(editor.spline().values().row(p), before.row(p)) << "point " << p;
        }
      }
    }
    for (auto t : { ControlPointType::Corner, ControlPointType::EdgeCorner, ControlPointType::Edge,
           ControlPointType::InnerCorner, ControlPointType::InnerEdge })
      EXPECT_GT(types[t], 0) << to_string(t);
    const ContinuityReport c = editor.spline().continuity();
    EXPECT_LT(c.max_condition_residual / h, 1e-9);
    EXPECT_LT(c.max_gradient_jump, 1e-9);
    EXPECT_GT((editor.spline().values() - start.values()).norm(), 0.01 * h);

    // Replay the log on a fresh editor: the same bits.
    SplineEditor replay(start);
    for (const SplineEdit& e : editor.log())
      replay.apply(e);
    EXPECT_EQ(replay.spline().values(), editor.spline().values());
    // Undo everything: the identity, bit for bit; redo everything: the edited spline.
    const Eigen::MatrixXd edited = editor.spline().values();
    while (editor.undo())
    {
    }
    EXPECT_EQ(editor.spline().values(), start.values());
    while (editor.redo())
    {
    }
    EXPECT_EQ(editor.spline().values(), edited);
    // Degree elevation keeps the map and C1.
    const TriangularSpline up = editor.spline().elevated();
    EXPECT_EQ(up.net().degree(), net->degree() + 1);
    EXPECT_LT(up.continuity().max_condition_residual / h, 1e-9);
    std::mt19937 r2(6);
    for (Index t = 0; t < net->num_triangles(); t += 3)
    {
      const Eigen::Vector3d b = random_barycentric(r2);
      EXPECT_LT((up.evaluate(t, b) - editor.spline().evaluate(t, b)).norm(), 1e-13);
    }
  }
}

// Locality (§3.3, §4.2): with delta_max = 0 an edit moves only control points of the triangles
// around the anchor's vertex star, the same number of points on a grid four times as large.
TEST(SplineEditor, LocalEditsStayLocal)
{
  for (bool alternate : { false, true })
  {
    std::vector<size_t> sizes;
    for (int scale : { 1, 2 })
    {
      const auto net = grid_net(8 * scale, 4 * scale, alternate);
      SplineEditor editor(TriangularSpline::identity(net));
      // The vertex nearest the domain's centre (for the alternating grid, of degree 8 at both
      // sizes, since both have an even number of squares per side).
      const Index centre = editor.nearest_point(Eigen::Vector2d(0.0, 0.0));
      ASSERT_EQ(net->type(centre), ControlPointType::Corner);
      SplineEdit edit;
      edit.anchors = { centre };
      edit.by = Eigen::Vector2d(0.01, 0.02);
      const SplineEditReport r = editor.apply(edit);
      // Every moved point lies in a triangle with a vertex within one edge of the anchor.
      std::set<int> near;
      for (Index e = 0; e < net->edges().rows(); ++e)
        for (int k = 0; k < 2; ++k)
          if (net->edges()(e, k) == centre)
            near.insert(net->edges()(e, 1 - k));
      near.insert(static_cast<int>(centre));
      std::set<Index> allowed;
      for (Index t = 0; t < net->num_triangles(); ++t)
        for (int k = 0; k < 3; ++k)
          if (near.count(net->triangles()(t, k)))
            for (int r2 = 0; r2 < bezier_count(5); ++r2)
              allowed.insert(net->local_to_global()(t, r2));
      for (Index p : r.sets.derived)
        EXPECT_TRUE(allowed.count(p)) << "derived point " << p;
      sizes.push_back(r.sets.derived.size());
    }
    EXPECT_EQ(sizes[0], sizes[1]);
  }
}

TEST(SplineEditor, BadEditsLeaveTheSplineUnchanged)
{
  const auto net = grid_net(4, 2, true);
  SplineEditor editor(TriangularSpline::identity(net));
  const Eigen::MatrixXd before = editor.spline().values();
  SplineEdit e;
  e.anchors = { 3 };
  e.by = Eigen::Vector2d(0.1, 0);
  editor.set_pinned({ 3, 4 });
  EXPECT_TRUE(throws_error([&] { editor.apply(e); }, ErrorCode::InvalidArgument, { "control point 3", "pinned" }));
  editor.set_pinned({});
  e.anchors = { net->num_points() };
  EXPECT_TRUE(throws_error([&] { editor.apply(e); }, ErrorCode::InvalidArgument, { "not a control point" }));
  e.anchors = { 3, 3 };
  EXPECT_TRUE(throws_error([&] { editor.apply(e); }, ErrorCode::InvalidArgument, { "twice" }));
  e.anchors = {};
  EXPECT_TRUE(throws_error([&] { editor.apply(e); }, ErrorCode::EmptyInput));
  e.anchors = { 3 };
  e.by = Eigen::Vector2d(NAN, 0);
  EXPECT_TRUE(throws_error([&] { editor.apply(e); }, ErrorCode::NonFinite));
  e.by = Eigen::Vector3d(1, 0, 0);
  EXPECT_TRUE(throws_error([&] { editor.apply(e); }, ErrorCode::InvalidArgument, { "2 values" }));
  e.by = Eigen::Vector2d(0.1, 0);
  e.delta_max = -1;
  EXPECT_TRUE(throws_error([&] { editor.apply(e); }, ErrorCode::InvalidArgument, { "delta_max" }));
  e.delta_max = 0;
  e.op = SplineEditOp::Scale;
  e.factor = 0;
  EXPECT_TRUE(throws_error([&] { editor.apply(e); }, ErrorCode::InvalidArgument, { "not positive" }));
  // Every point around anchor 3 pinned: no derived point can follow.
  std::vector<Index> pins;
  for (Index p = 0; p < net->num_points(); ++p)
    if (p != 3)
      pins.push_back(p);
  editor.set_pinned(pins);
  e.op = SplineEditOp::Translate;
  EXPECT_TRUE(throws_error([&] { editor.apply(e); }, ErrorCode::InvalidArgument, { "cannot keep the spline C1" }));
  EXPECT_EQ(editor.spline().values(), before);
  EXPECT_FALSE(editor.can_undo());
  // A scalar spline: rotations refused, translations by one value.
  SplineEditor scalar(TriangularSpline::constant(net, 0.0));
  e.op = SplineEditOp::Rotate;
  EXPECT_TRUE(throws_error([&] { scalar.apply(e); }, ErrorCode::InvalidArgument, { "rotate" }));
  e.op = SplineEditOp::Translate;
  e.by = Eigen::VectorXd::Constant(1, 0.2);
  scalar.apply(e);
  EXPECT_DOUBLE_EQ(scalar.spline().values()(3, 0), 0.2);
  EXPECT_LT(scalar.spline().continuity().max_condition_residual, 1e-14);
  // A spline that is not C1 is refused.
  Eigen::MatrixXd X = TriangularSpline::identity(net).values();
  X(net->conditions()[0].point[0], 0) += 0.01;
  EXPECT_TRUE(throws_error([&] { SplineEditor(TriangularSpline(net, X)); }, ErrorCode::InvalidArgument, { "not C1" }));
}

// Fitting: a C1 spline sampled at its nominal positions is recovered; a smooth non-polynomial map
// is approximated by a C1 spline whose error falls like h^6 (degree 5) when the grid is refined.
TEST(SplineFit, RecoversSplinesAndConvergesOnSmoothMaps)
{
  const auto net = irregular_net();
  SplineEditor editor(TriangularSpline::identity(net));
  SplineEdit e;
  e.near = { Eigen::Vector2d(0.6, 0.4) };
  e.by = Eigen::Vector2d(0.05, -0.03);
  e.delta_max = 3;
  editor.apply(e);
  const TriangularSpline& target = editor.spline();
  const auto where = target.locate(net->nominal());
  // Without regularization: exactly (to rounding); with the default membrane term: within its
  // small bias.
  const SplineFit fit = fit_spline(net, net->nominal(), target.evaluate(where), 0.0);
  EXPECT_LT((fit.spline->values() - target.values()).cwiseAbs().maxCoeff(), 1e-10);
  const SplineFit biased = fit_spline(net, net->nominal(), target.evaluate(where));
  EXPECT_LT((biased.spline->values() - target.values()).cwiseAbs().maxCoeff(), 1e-4);
  EXPECT_LT(fit.spline->continuity().max_condition_residual, 1e-13);
  EXPECT_LT(fit.independent_conditions, fit.conditions);

  auto map = [](const Points& X) {
    Eigen::MatrixXd Y(X.rows(), 2);
    for (Index p = 0; p < X.rows(); ++p)
      Y.row(p) << X(p, 0) + 0.05 * std::sin(9 * X(p, 1)), X(p, 1) + 0.05 * std::cos(7 * X(p, 0));
    return Y;
  };
  std::vector<double> errors;
  for (int scale : { 1, 2 })
  {
    // [-1, 0] x [-0.5, 0] with squares of side 0.25 / scale.
    Eigen::MatrixXd V;
    Eigen::MatrixXi T;
    grid(4 * scale, 2 * scale, 0.25 / scale, true, V, T);
    const auto g = std::make_shared<SplineNet>(V, T, 5);
    const SplineFit f = fit_spline(g, g->nominal(), map(g->nominal()), 0.0);
    EXPECT_LT(f.spline->continuity().max_condition_residual, 1e-13);
    // Error at points that are not samples.
    Points Q(400, 2);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> ux(-1.0, 0.0), uy(-0.5, 0.0);
    for (Index p = 0; p < Q.rows(); ++p)
      Q.row(p) << ux(rng), uy(rng);
    const Eigen::MatrixXd Vq = f.spline->evaluate(f.spline->locate(Q));
    errors.push_back((Vq - map(Q)).rowwise().norm().maxCoeff());
  }
  EXPECT_LT(errors[0], 1e-3);
  // h^6: 64 times smaller; measured 1.1e-5 -> 2.1e-7.
  EXPECT_LT(errors[1], errors[0] / 30) << errors[0] << " " << errors[1];
  EXPECT_TRUE(throws_error([&] { fit_spline(net, Points(0, 2), Eigen::MatrixXd(0, 2)); }, ErrorCode::EmptyInput));
  EXPECT_TRUE(throws_error([&] {
    Points far(1, 2);
    far << 5, 5;
    fit_spline(net, far, Eigen::MatrixXd::Zero(1, 2));
  }, ErrorCode::PointsOutside));
}

// The 2.5D deformation (§5) is continuous across the prisms' vertical faces: at points of every
// interior edge the xy deformation and both height splines agree from the two triangles, so
// (phi, sigma0 + t (sigma1 - sigma0)) does too, for every t.
TEST(SplinePrism, ContinuousAcrossPrismFaces)
{
  const auto net = irregular_net();
  SplineEditor xy(TriangularSpline::identity(net)), bottom(TriangularSpline::constant(net, -0.1)),
    top(TriangularSpline::constant(net, 0.1));
  std::mt19937 rng(9);
  std::uniform_int_distribution<Index> pick(0, net->num_points() - 1);
  for (int k = 0; k < 20; ++k)
  {
    SplineEdit e;
    e.anchors = { pick(rng) };
    e.delta_max = k % 4;
    e.by = Eigen::Vector2d(0.02, -0.01);
    xy.apply(e);
    e.by = Eigen::VectorXd::Constant(1, 0.01 * (k % 3 - 1));
    (k % 2 ? top : bottom).apply(e);
  }
  double worst = 0;
  const auto& E = net->edges();
  const auto& ET = net->edge_triangles();
  for (Index ed = 0; ed < E.rows(); ++ed)
  {
    if (ET(ed, 0) < 0 || ET(ed, 1) < 0)
      continue;
    for (double a : { 0.0, 0.3, 0.7, 1.0 })
    {
      const Eigen::Vector2d x = net->vertices().row(E(ed, 0)).transpose() +
        a * (net->vertices().row(E(ed, 1)) - net->vertices().row(E(ed, 0))).transpose();
      for (double t : { 0.0, 0.4, 1.0 })
      {
        Eigen::Vector3d side[2];
        for (int s = 0; s < 2; ++s)
        {
          const Index tri = ET(ed, s);
          const Eigen::Vector3d b = net->barycentric(tri, x);
          const Eigen::RowVectorXd p = xy.spline().evaluate(tri, b);
          const double z0 = bottom.spline().evaluate(tri, b)[0], z1 = top.spline().evaluate(tri, b)[0];
          side[s] = Eigen::Vector3d(p[0], p[1], z0 + t * (z1 - z0));
        }
        worst = std::max(worst, (side[0] - side[1]).norm());
      }
    }
  }
  EXPECT_LT(worst, 1e-14);
  EXPECT_GT((top.spline().values().array() - 0.1).abs().maxCoeff(), 1e-3);
}
