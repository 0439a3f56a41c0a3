// Tests for core/solvers/min_quad_with_fixed.h: Dirichlet problems for the P1 Laplacian on triangle
// and tetrahedral grids of the unit square / cube (linear precision, O(h^2) convergence to a
// harmonic quadratic), the optimality condition with a linear term, batches of right-hand
// sides, and the error paths.
//
// Tolerances. The stiffness matrices here have O(1) entries (2D) and condition numbers
// O(h^-2) <= ~1e3, so solutions carry errors of ~cond * eps ~ 1e-13 relative at most; 1e-12 is
// the bound used for "exact" results, and bitwise equality where the code copies values.
#include "core/common/error.h"
#include "core/solvers/fem_operators.h"
#include "core/solvers/min_quad_with_fixed.h"
#include "error_matchers.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace
{
using namespace bary;
using bary::test::throws_error;
using Backend = SparseCholesky::Backend;
using SparseMatrix = Eigen::SparseMatrix<double>;

const double kPi = std::acos(-1.0);

struct Mesh
{
  Eigen::MatrixXd V;
  Eigen::MatrixXi T;
  Eigen::VectorXi boundary; ///< vertices on the boundary of the unit square / cube
};

/// A smooth map of [0,1]^dim onto itself, x -> x + 0.1 prod_l sin(pi x_l) (1, ..., 1): it
/// keeps every boundary vertex on the boundary (the bump vanishes there, up to sin(pi) ~ 1e-16)
/// and has Jacobian determinant 1 + 0.1 pi sum_k cos(pi x_k) prod_{l != k} sin(pi x_l) > 0.5.
/// The distorted meshes are no longer uniform right-triangle / Kuhn grids, whose P1 Laplacian
/// is the 5-point (2D) / 7-point (3D) stencil that reproduces quadratics exactly and would hide
/// the O(h^2) error.
void distort(Eigen::MatrixXd& V)
{
  for (Index i = 0; i < V.rows(); ++i)
  {
    double bump = 0.1;
    for (Index l = 0; l < V.cols(); ++l)
      bump *= std::sin(kPi * V(i, l));
    V.row(i).array() += bump;
  }
}

/// [0,1]^2 with n by n cells split into two triangles each (alternating diagonals).
Mesh square_grid(int n, bool distorted)
{
  Mesh m;
  m.V.resize((n + 1) * (n + 1), 2);
  std::vector<int> boundary;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
    {
      const int id = j * (n + 1) + i;
      m.V.row(id) << double(i) / n, double(j) / n;
      if (i == 0 || j == 0 || i == n || j == n)
        boundary.push_back(id);
    }
  m.T.resize(2 * n * n, 3);
  int t = 0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
    {
      const int a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
      if ((i + j) % 2 == 0)
      {
        m.T.row(t++) << a, b, d;
        m.T.row(t++) << a, d, c;
      }
      else
      {
        m.T.row(t++) << a, b, c;
        m.T.row(t++) << b, d, c;
      }
    }
  m.boundary = Eigen::Map<const Eigen::VectorXi>(boundary.data(), Index(boundary.size()));
  if (distorted)
    distort(m.V);
  return m;
}

/// Kuhn subdivision of [0,1]^3: n^3 cubes of 6 tetrahedra each.
Mesh cube_grid(int n, bool distorted)
{
  Mesh m;
  const int s = n + 1;
  auto id = [s](int i, int j, int k) { return (k * s + j) * s + i; };
  m.V.resize(s * s * s, 3);
  std::vector<int> boundary;
  for (int k = 0; k <= n; ++k)
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i)
      {
        m.V.row(id(i, j, k)) << double(i) / n, double(j) / n, double(k) / n;
        if (i == 0 || j == 0 || k == 0 || i == n || j == n || k == n)
          boundary.push_back(id(i, j, k));
      }
  static const std::array<std::array<int, 3>, 6> orders = { { { 0, 1, 2 }, { 0, 2, 1 },
    { 1, 0, 2 }, { 1, 2, 0 }, { 2, 0, 1 }, { 2, 1, 0 } } };
  m.T.resize(6 * n * n * n, 4);
  int t = 0;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        for (const auto& order : orders)
        {
          std::array<int, 3> p = { i, j, k };
          m.T(t, 0) = id(p[0], p[1], p[2]);
          for (int step = 0; step < 3; ++step)
          {
            ++p[static_cast<std::size_t>(order[static_cast<std::size_t>(step)])];
            m.T(t, step + 1) = id(p[0], p[1], p[2]);
          }
          ++t;
        }
  m.boundary = Eigen::Map<const Eigen::VectorXi>(boundary.data(), Index(boundary.size()));
  if (distorted)
    distort(m.V);
  return m;
}

Eigen::VectorXd evaluate(const Eigen::MatrixXd& V, const std::function<double(const Eigen::RowVectorXd&)>& f)
{
  Eigen::VectorXd values(V.rows());
  for (Index i = 0; i < V.rows(); ++i)
    values(i) = f(V.row(i));
  return values;
}

Eigen::MatrixXd rows_of(const Eigen::MatrixXd& X, const Eigen::VectorXi& rows)
{
  Eigen::MatrixXd R(rows.size(), X.cols());
  for (Index i = 0; i < rows.size(); ++i)
    R.row(i) = X.row(rows(i));
  return R;
}

Eigen::MatrixXd random_matrix(Index rows, Index cols, unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::MatrixXd B(rows, cols);
  for (Index j = 0; j < cols; ++j)
    for (Index i = 0; i < rows; ++i)
      B(i, j) = u(rng);
  return B;
}

std::vector<Backend> backends()
{
  std::vector<Backend> b = { Backend::Eigen };
  if (SparseCholesky::cholmod_available())
    b.push_back(Backend::Cholmod);
  return b;
}

const char* name(Backend b)
{
  return b == Backend::Eigen ? "Eigen" : "Cholmod";
}

TEST(MinQuadWithFixed, HarmonicSolutionReproducesLinearFunctions)
{
  // With Dirichlet data from f = a . x + c the discrete harmonic function is f itself: f is in
  // the P1 space and (K f)_i = 0 at every interior vertex.
  for (Backend backend : backends())
    for (bool distorted : { false, true })
    {
      SCOPED_TRACE(std::string(name(backend)) + (distorted ? " distorted" : " uniform"));
      for (const Mesh& m : { square_grid(12, distorted), cube_grid(4, distorted) })
      {
        const Eigen::VectorXd f = evaluate(m.V, [](const Eigen::RowVectorXd& x) {
          return 0.3 + 1.1 * x(0) - 0.7 * x(1) + (x.size() == 3 ? 0.4 * x(2) : 0.0);
        });
        MinQuadWithFixed solver;
        solver.precompute(stiffness_matrix(m.V, m.T), m.boundary, backend);
        EXPECT_EQ(solver.unknown().size() + m.boundary.size(), m.V.rows());
        const Eigen::MatrixXd X = solver.solve(Eigen::MatrixXd(), rows_of(f, m.boundary));
        ASSERT_EQ(X.rows(), m.V.rows());
        ASSERT_EQ(X.cols(), 1);
        EXPECT_LT((X.col(0) - f).cwiseAbs().maxCoeff(), 1e-12);
      }
    }
}

/// Errors of the discrete harmonic extension of f's boundary values on mesh m.
struct HarmonicError
{
  double max = 0.0; ///< max over the vertices of |x_i - f(v_i)|
  double l2 = 0.0;  ///< sqrt(e^T M e) with M the lumped mass matrix: the discrete L2 norm
};

HarmonicError harmonic_error(const Mesh& m, const std::function<double(const Eigen::RowVectorXd&)>& f)
{
  const Eigen::VectorXd exact = evaluate(m.V, f);
  const Eigen::MatrixXd X = min_quad_with_fixed(
    stiffness_matrix(m.V, m.T), Eigen::MatrixXd(), m.boundary, rows_of(exact, m.boundary));
  const Eigen::VectorXd e = X.col(0) - exact;
  return { e.cwiseAbs().maxCoeff(), std::sqrt(e.dot(mass_matrix(m.V, m.T) * e)) };
}

TEST(MinQuadWithFixed, ConvergesAtSecondOrderToAHarmonicQuadratic)
{
  // f = x^2 - y^2 is harmonic in 2D and 3D. On smoothly distorted grids the P1 solution's
  // error is O(h^2). Observed orders log2(e(h) / e(h/2)) over three grids (2D: 8, 16, 32
  // cells per side; 3D: 6, 12, 24), measured when this test was written:
  //   2D  L2 1.89, 1.96   max 1.92, 2.04
  //   3D  L2 1.92, 1.98   max 1.74, 1.98   (the coarsest 3D grid is still pre-asymptotic)
  // Asserted: both L2 orders and the finer max-norm order > 1.8.
  const auto f = [](const Eigen::RowVectorXd& x) { return x(0) * x(0) - x(1) * x(1); };
  struct Case
  {
    const char* label;
    std::array<HarmonicError, 3> e;
  };
  const std::array<Case, 2> cases = { {
    { "2D", { harmonic_error(square_grid(8, true), f), harmonic_error(square_grid(16, true), f),
              harmonic_error(square_grid(32, true), f) } },
    { "3D", { harmonic_error(cube_grid(6, true), f), harmonic_error(cube_grid(12, true), f),
              harmonic_error(cube_grid(24, true), f) } },
  } };
  for (const Case& c : cases)
  {
    SCOPED_TRACE(c.label);
    const auto& e = c.e;
    EXPECT_GT(e[0].max, 1e-5) << "the distortion must make the error visible";
    const double l2_coarse = std::log2(e[0].l2 / e[1].l2), l2_fine = std::log2(e[1].l2 / e[2].l2);
    const double max_fine = std::log2(e[1].max / e[2].max);
    EXPECT_GT(l2_coarse, 1.8) << "L2 errors " << e[0].l2 << ", " << e[1].l2 << ", " << e[2].l2;
    EXPECT_GT(l2_fine, 1.8) << "L2 errors " << e[0].l2 << ", " << e[1].l2 << ", " << e[2].l2;
    EXPECT_GT(max_fine, 1.8) << "max errors " << e[0].max << ", " << e[1].max << ", " << e[2].max;
    // Bounded above too: an order well beyond 2 would mean the test problem is degenerate.
    EXPECT_LT(l2_fine, 2.3);
    RecordProperty(std::string("observed_L2_order_") + c.label, std::to_string(l2_fine));
  }
  // Undistorted right-triangle grid: the 5-point stencil is exact on quadratics.
  EXPECT_LT(harmonic_error(square_grid(8, false), f).max, 1e-12);
}

TEST(MinQuadWithFixed, KnownRowsAreReturnedExactly)
{
  const Mesh m = square_grid(6, true);
  const Eigen::MatrixXd Y = random_matrix(m.boundary.size(), 3, 7) * 1e3;
  MinQuadWithFixed solver;
  solver.precompute(stiffness_matrix(m.V, m.T), m.boundary);
  const Eigen::MatrixXd X = solver.solve(random_matrix(m.V.rows(), 3, 8), Y);
  EXPECT_EQ(rows_of(X, m.boundary), Y); // bitwise
}

TEST(MinQuadWithFixed, SatisfiesTheOptimalityCondition)
{
  // (A x + B)_u = 0 on the unknowns for any B and Y, with known indices in arbitrary order.
  const Mesh m = square_grid(10, true);
  const SparseMatrix A = stiffness_matrix(m.V, m.T) + mass_matrix(m.V, m.T, MassMatrixType::Full);
  Eigen::VectorXi known = m.boundary.reverse();
  std::swap(known(0), known(5));
  const Eigen::MatrixXd B = random_matrix(m.V.rows(), 2, 9);
  const Eigen::MatrixXd Y = random_matrix(known.size(), 2, 10);
  for (Backend backend : backends())
  {
    SCOPED_TRACE(name(backend));
    MinQuadWithFixed solver;
    solver.precompute(A, known, backend);
    EXPECT_EQ(solver.known(), known);
    const Eigen::MatrixXd X = solver.solve(B, Y);
    EXPECT_EQ(rows_of(X, known), Y);
    const Eigen::MatrixXd gradient = A * X + B;
    EXPECT_LT(rows_of(gradient, solver.unknown()).cwiseAbs().maxCoeff(), 1e-12);
    // unknown() is the complement of known, ascending.
    for (Index u = 1; u < solver.unknown().size(); ++u)
      EXPECT_LT(solver.unknown()(u - 1), solver.unknown()(u));
  }
}

TEST(MinQuadWithFixed, ManyRightHandSidesAtOnceEqualOneByOne)
{
  const Mesh m = cube_grid(4, true);
  MinQuadWithFixed solver;
  solver.precompute(stiffness_matrix(m.V, m.T), m.boundary);
  const Eigen::MatrixXd B = random_matrix(m.V.rows(), 5, 11);
  const Eigen::MatrixXd Y = random_matrix(m.boundary.size(), 5, 12);
  const Eigen::MatrixXd X = solver.solve(B, Y);
  ASSERT_EQ(X.cols(), 5);
  const double scale = X.cwiseAbs().maxCoeff();
  for (Index c = 0; c < 5; ++c)
  {
    const Eigen::MatrixXd x = solver.solve(B.col(c), Y.col(c));
    // Multi-column solves may block the triangular solves differently: rounding-level only.
    EXPECT_LT((X.col(c) - x.col(0)).cwiseAbs().maxCoeff(), 1e-13 * scale) << "column " << c;
  }
  // An empty B means B = 0, for any number of columns of Y.
  EXPECT_LT((solver.solve(Eigen::MatrixXd(), Y) - solver.solve(Eigen::MatrixXd::Zero(m.V.rows(), 5), Y))
              .cwiseAbs()
              .maxCoeff(),
    1e-15 * scale);
}

TEST(MinQuadWithFixed, NoKnownRowsWithAnSpdMatrix)
{
  // min 1/2 x^T (K + M) x - x^T M g: the screened Poisson equation (K + M) x = M g.
  const Mesh m = square_grid(8, true);
  const SparseMatrix M = mass_matrix(m.V, m.T, MassMatrixType::Full);
  const SparseMatrix A = stiffness_matrix(m.V, m.T) + M;
  const Eigen::VectorXd g = random_matrix(m.V.rows(), 1, 13).col(0);
  MinQuadWithFixed solver;
  solver.precompute(A, Eigen::VectorXi());
  EXPECT_EQ(solver.unknown().size(), m.V.rows());
  const Eigen::MatrixXd X = solver.solve(-(M * g), Eigen::MatrixXd(0, 1));
  EXPECT_LT((A * X.col(0) - M * g).cwiseAbs().maxCoeff(), 1e-12 * (M * g).cwiseAbs().maxCoeff());
  // Y may be 0 by 0 when B gives the number of columns.
  EXPECT_EQ(solver.solve(-(M * g), Eigen::MatrixXd()), X);
}

TEST(MinQuadWithFixed, EveryRowKnown)
{
  const Mesh m = square_grid(2, false);
  Eigen::VectorXi known = Eigen::VectorXi::LinSpaced(m.V.rows(), 0, int(m.V.rows()) - 1);
  MinQuadWithFixed solver;
  solver.precompute(stiffness_matrix(m.V, m.T), known);
  EXPECT_EQ(solver.unknown().size(), 0);
  const Eigen::MatrixXd Y = random_matrix(m.V.rows(), 2, 14);
  EXPECT_EQ(solver.solve(Eigen::MatrixXd(), Y), Y);
}

TEST(MinQuadWithFixed, UnpinnedComponentIsNamedByItsRowInA)
{
  // Two disjoint squares; only the first one's boundary is known. The second is a pure Neumann
  // problem: singular. The message must name a row of A that belongs to the second square.
  const Mesh a = square_grid(3, false);
  const Index na = a.V.rows();
  Mesh both;
  both.V.resize(2 * na, 2);
  both.V << a.V, a.V.rowwise() + Eigen::RowVector2d(2.0, 0.0);
  both.T.resize(2 * a.T.rows(), 3);
  both.T << a.T, a.T.array() + int(na);
  const SparseMatrix K = stiffness_matrix(both.V, both.T);
  for (Backend backend : backends())
  {
    SCOPED_TRACE(name(backend));
    MinQuadWithFixed solver;
    try
    {
      solver.precompute(K, a.boundary, backend);
      ADD_FAILURE() << "did not throw";
    }
    catch (const Error& e)
    {
      const std::string message = e.what();
      EXPECT_NE(message.find("not positive definite"), std::string::npos) << message;
      const std::size_t at = message.find("at row ");
      ASSERT_NE(at, std::string::npos) << message;
      const long row = std::stol(message.substr(at + 7));
      EXPECT_GE(row, na) << message;
      EXPECT_LT(row, 2 * na) << message;
    }
  }
}

TEST(MinQuadWithFixed, Errors)
{
  const Mesh m = square_grid(3, false);
  const SparseMatrix K = stiffness_matrix(m.V, m.T);
  const int n = static_cast<int>(m.V.rows());
  MinQuadWithFixed solver;
  EXPECT_FALSE(solver.precomputed());
  EXPECT_TRUE(throws_error([&] { solver.solve(Eigen::MatrixXd(), Eigen::MatrixXd(1, 1)); },
    ErrorCode::InvalidArgument, { "before precompute" }));

  EXPECT_TRUE(throws_error([&] { solver.precompute(SparseMatrix(3, 2), Eigen::VectorXi()); },
    ErrorCode::SizeMismatch, { "square" }));
  EXPECT_TRUE(throws_error([&] { solver.precompute(SparseMatrix(0, 0), Eigen::VectorXi()); },
    ErrorCode::EmptyInput));
  EXPECT_TRUE(throws_error([&] { solver.precompute(K, (Eigen::VectorXi(2) << 0, n).finished()); },
    ErrorCode::InvalidArgument, { "known(1) = " + std::to_string(n), "outside" }));
  EXPECT_TRUE(throws_error([&] { solver.precompute(K, (Eigen::VectorXi(3) << 4, 0, 4).finished()); },
    ErrorCode::InvalidArgument, { "row 4 is listed twice", "at 0 and 2" }));
  // The pure Neumann problem is singular.
  EXPECT_TRUE(throws_error([&] { solver.precompute(K, Eigen::VectorXi()); },
    ErrorCode::InvalidArgument, { "not positive definite" }));
  SparseMatrix nan = K;
  nan.coeffRef(1, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(throws_error([&] { solver.precompute(nan, m.boundary); }, ErrorCode::NonFinite,
    { "(1, 1)" }));
  EXPECT_FALSE(solver.precomputed());

  solver.precompute(K, m.boundary);
  const Index nk = m.boundary.size();
  EXPECT_TRUE(throws_error([&] { solver.solve(Eigen::MatrixXd(), Eigen::MatrixXd(nk + 1, 1)); },
    ErrorCode::SizeMismatch, { "Y have " + std::to_string(nk + 1) + " rows" }));
  EXPECT_TRUE(throws_error([&] { solver.solve(Eigen::MatrixXd::Zero(n - 1, 1), Eigen::MatrixXd::Zero(nk, 1)); },
    ErrorCode::SizeMismatch, { "B has " + std::to_string(n - 1) + " rows" }));
  EXPECT_TRUE(throws_error([&] { solver.solve(Eigen::MatrixXd::Zero(n, 2), Eigen::MatrixXd::Zero(nk, 3)); },
    ErrorCode::SizeMismatch, { "3 columns", "has 2" }));
  Eigen::MatrixXd Y = Eigen::MatrixXd::Zero(nk, 1);
  Y(2, 0) = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(throws_error([&] { solver.solve(Eigen::MatrixXd(), Y); }, ErrorCode::NonFinite));
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(n, 1);
  B(0, 0) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(throws_error([&] { solver.solve(B, Eigen::MatrixXd::Zero(nk, 1)); }, ErrorCode::NonFinite));
  // A failed precompute keeps nothing of the previous one.
  EXPECT_THROW(solver.precompute(K, Eigen::VectorXi()), Error);
  EXPECT_FALSE(solver.precomputed());
}

} // namespace
