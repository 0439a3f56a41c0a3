// Tests for core/solvers/fem_operators.h on meshes built here: a structured triangle grid of the unit
// square, the same grid rotated into 3D (a flat surface patch), the unit cube split into 5
// tetrahedra, and a Kuhn (6 tetrahedra per cube) grid of the unit cube.
//
// Tolerances. Every quantity is a sum of a few products of O(1) numbers (coordinates in [0, 1]
// or rotated copies of them), so its rounding error is a small multiple of eps = 2.2e-16 times
// the magnitude of the terms. Entries of K are O(1) in 2D and O(h) in 3D; sums over a whole
// mesh add #T terms. The tolerances below are a few hundred eps times the scale of the terms
// (1e-13 for one element or row, 1e-12 for whole-mesh sums of up to a few thousand terms),
// far below any modelling error they could hide (which would be O(1)).
#include "core/common/error.h"
#include "core/solvers/fem_operators.h"
#include "error_matchers.h"

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace
{
using namespace bary;
using bary::test::throws_error;

struct Mesh
{
  std::string name;
  Eigen::MatrixXd V;
  Eigen::MatrixXi T;
  double volume = 0.0; ///< total area / volume in closed form
};

/// [0,1]^2 with nx by ny cells, each split into two triangles along alternating diagonals (so
/// both diagonal directions occur). Counter-clockwise.
Mesh triangle_grid(int nx, int ny)
{
  Mesh m;
  m.name = "triangle_grid";
  m.V.resize((nx + 1) * (ny + 1), 2);
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i)
      m.V.row(j * (nx + 1) + i) << double(i) / nx, double(j) / ny;
  m.T.resize(2 * nx * ny, 3);
  int t = 0;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i)
    {
      const int a = j * (nx + 1) + i, b = a + 1, c = a + nx + 1, d = c + 1;
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
  m.volume = 1.0;
  return m;
}

/// A fixed rotation (not axis-aligned) and offset.
Eigen::Matrix3d rotation()
{
  return (Eigen::AngleAxisd(0.7, Eigen::Vector3d(1.0, 2.0, 3.0).normalized()) *
    Eigen::AngleAxisd(-0.4, Eigen::Vector3d(0.0, 1.0, -1.0).normalized()))
    .toRotationMatrix();
}

/// The triangle grid rotated into 3D: a flat surface patch of area 1.
Mesh surface_patch(int nx, int ny)
{
  Mesh m = triangle_grid(nx, ny);
  m.name = "surface_patch";
  Eigen::MatrixXd V3 = Eigen::MatrixXd::Zero(m.V.rows(), 3);
  V3.leftCols(2) = m.V;
  m.V = (V3 * rotation().transpose()).rowwise() + Eigen::RowVector3d(0.3, -1.2, 2.5);
  return m;
}

/// Cube corner v = x + 2y + 4z with x, y, z in {0, 1}.
Eigen::MatrixXd cube_vertices()
{
  Eigen::MatrixXd V(8, 3);
  for (int v = 0; v < 8; ++v)
    V.row(v) << (v & 1), (v >> 1) & 1, (v >> 2) & 1;
  return V;
}

/// The unit cube as 5 tetrahedra: the regular one on the even corners {0, 3, 5, 6} (volume
/// 1/3) and one corner tetrahedron at each odd corner (volume 1/6 each).
Mesh cube_five_tets()
{
  Mesh m;
  m.name = "cube_five_tets";
  m.V = cube_vertices();
  m.T.resize(5, 4);
  m.T << 0, 3, 5, 6, //
    1, 0, 3, 5,      //
    2, 0, 3, 6,      //
    4, 0, 5, 6,      //
    7, 3, 5, 6;
  m.volume = 1.0;
  return m;
}

/// Kuhn subdivision of [0,1]^3 into n^3 cubes of 6 tetrahedra each (one per ordering of the
/// axes along the main diagonal of the cube), all of volume h^3 / 6.
Mesh kuhn_grid(int n)
{
  Mesh m;
  m.name = "kuhn_grid";
  const int s = n + 1;
  auto id = [s](int i, int j, int k) { return (k * s + j) * s + i; };
  m.V.resize(s * s * s, 3);
  for (int k = 0; k <= n; ++k)
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i)
        m.V.row(id(i, j, k)) << double(i) / n, double(j) / n, double(k) / n;
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
  m.volume = 1.0;
  return m;
}

std::vector<Mesh> catalogue()
{
  return { triangle_grid(5, 4), surface_patch(4, 5), cube_five_tets(), kuhn_grid(3) };
}

/// Values of the linear function a . x + c at the vertices.
Eigen::VectorXd linear(const Eigen::MatrixXd& V, const Eigen::VectorXd& a, double c)
{
  return (V * a).array() + c;
}

Eigen::VectorXd some_gradient(Index dim)
{
  Eigen::VectorXd a(dim);
  if (dim == 2)
    a << 0.7, -1.3;
  else
    a << 0.7, -1.3, 0.4;
  return a;
}

/// Vertices on the boundary of [0,1]^dim (before any rotation).
bool on_unit_box_boundary(const Eigen::RowVectorXd& x)
{
  for (Index k = 0; k < x.size(); ++k)
    if (x(k) == 0.0 || x(k) == 1.0)
      return true;
  return false;
}

double max_abs(const Eigen::SparseMatrix<double>& A)
{
  return Eigen::MatrixXd(A).cwiseAbs().maxCoeff();
}

// --- volumes --------------------------------------------------------------------------------

TEST(SimplexVolumes, SumToTheKnownTotal)
{
  for (const Mesh& m : catalogue())
  {
    SCOPED_TRACE(m.name);
    const Eigen::VectorXd vol = simplex_volumes(m.V, m.T);
    ASSERT_EQ(vol.size(), m.T.rows());
    EXPECT_TRUE((vol.array() > 0.0).all());
    EXPECT_NEAR(vol.sum(), m.volume, 1e-13);
  }
}

TEST(SimplexVolumes, HandComputedElements)
{
  const Mesh cube = cube_five_tets();
  const Eigen::VectorXd vol = simplex_volumes(cube.V, cube.T);
  EXPECT_NEAR(vol(0), 1.0 / 3.0, 1e-15); // the regular tetrahedron on the even corners
  for (int t = 1; t < 5; ++t)
    EXPECT_NEAR(vol(t), 1.0 / 6.0, 1e-15);
  // A 3-4-5 right triangle has area 6 in the plane and anywhere in space.
  Eigen::MatrixXd V2(3, 2);
  V2 << 0, 0, 3, 0, 0, 4;
  const Eigen::MatrixXi T = (Eigen::MatrixXi(1, 3) << 0, 1, 2).finished();
  EXPECT_NEAR(simplex_volumes(V2, T)(0), 6.0, 1e-14);
  Eigen::MatrixXd V3 = Eigen::MatrixXd::Zero(3, 3);
  V3.leftCols(2) = V2;
  V3 = V3 * rotation().transpose();
  EXPECT_NEAR(simplex_volumes(V3, T)(0), 6.0, 1e-13);
}

TEST(SimplexVolumes, OrientationDoesNotMatter)
{
  Mesh m = cube_five_tets();
  const Eigen::VectorXd before = simplex_volumes(m.V, m.T);
  m.T.col(1).swap(m.T.col(2));
  EXPECT_EQ(simplex_volumes(m.V, m.T), before);
}

// --- stiffness matrix -----------------------------------------------------------------------

TEST(StiffnessMatrix, HandComputedTriangleIsMinusTheCotangentMatrix)
{
  // Right isosceles triangle: angle 90 deg at vertex 0, 45 deg at 1 and 2.
  // K_ij = -1/2 cot(angle opposite ij): K_12 = -cot(90)/2 = 0, K_01 = K_02 = -cot(45)/2 = -1/2.
  Eigen::MatrixXd V(3, 2);
  V << 0, 0, 1, 0, 0, 1;
  const Eigen::MatrixXi T = (Eigen::MatrixXi(1, 3) << 0, 1, 2).finished();
  Eigen::Matrix3d expected;
  expected << 1.0, -0.5, -0.5, //
    -0.5, 0.5, 0.0,           //
    -0.5, 0.0, 0.5;
  EXPECT_LT((Eigen::MatrixXd(stiffness_matrix(V, T)) - expected).cwiseAbs().maxCoeff(), 1e-15);
  // Intrinsic: the same triangle scaled by 2.5 (K is scale-invariant in 2D), rotated into 3D.
  Eigen::MatrixXd V3 = Eigen::MatrixXd::Zero(3, 3);
  V3.leftCols(2) = 2.5 * V;
  V3 = (V3 * rotation().transpose()).rowwise() + Eigen::RowVector3d(1.0, 2.0, 3.0);
  EXPECT_LT((Eigen::MatrixXd(stiffness_matrix(V3, T)) - expected).cwiseAbs().maxCoeff(), 1e-14);
}

TEST(StiffnessMatrix, HandComputedReferenceTetrahedron)
{
  // lambda_1..3 = x, y, z, lambda_0 = 1 - x - y - z, volume 1/6: K_ij = grad_i . grad_j / 6.
  Eigen::MatrixXd V(4, 3);
  V << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1;
  const Eigen::MatrixXi T = (Eigen::MatrixXi(1, 4) << 0, 1, 2, 3).finished();
  Eigen::Matrix4d expected;
  expected << 3, -1, -1, -1, //
    -1, 1, 0, 0,            //
    -1, 0, 1, 0,            //
    -1, 0, 0, 1;
  expected /= 6.0;
  EXPECT_LT((Eigen::MatrixXd(stiffness_matrix(V, T)) - expected).cwiseAbs().maxCoeff(), 1e-15);
}

TEST(StiffnessMatrix, AnnihilatesConstants)
{
  for (const Mesh& m : catalogue())
  {
    SCOPED_TRACE(m.name);
    const Eigen::SparseMatrix<double> K = stiffness_matrix(m.V, m.T);
    ASSERT_EQ(K.rows(), m.V.rows());
    ASSERT_EQ(K.cols(), m.V.rows());
    const Eigen::VectorXd ones = Eigen::VectorXd::Ones(m.V.rows());
    EXPECT_LT((K * ones).cwiseAbs().maxCoeff(), 1e-13 * max_abs(K));
  }
}

TEST(StiffnessMatrix, QuadraticFormOfALinearFunctionIsGradientSquaredTimesVolume)
{
  // f = a . x + c is in the P1 space, so f^T K f = integral |grad f|^2 = |a|^2 |Omega|. For the
  // surface patch a is taken in the patch's plane (rotated with it).
  for (const Mesh& m : catalogue())
  {
    SCOPED_TRACE(m.name);
    Eigen::VectorXd a = some_gradient(m.V.cols());
    if (m.name == "surface_patch")
      a = rotation() * Eigen::Vector3d(0.7, -1.3, 0.0);
    const Eigen::VectorXd f = linear(m.V, a, 0.25);
    const double form = f.dot(stiffness_matrix(m.V, m.T) * f);
    EXPECT_NEAR(form, a.squaredNorm() * m.volume, 1e-12 * a.squaredNorm());
  }
}

TEST(StiffnessMatrix, SurfacePatchSeesOnlyTheTangentialGradient)
{
  // A linear function of space restricted to a flat patch has the tangential part of a as
  // gradient: f^T K f = |a - (a.n) n|^2 * area.
  const Mesh m = surface_patch(4, 5);
  const Eigen::Vector3d n = rotation().col(2);
  const Eigen::Vector3d a(0.7, -1.3, 0.4);
  const Eigen::VectorXd f = linear(m.V, a, -0.5);
  const double tangential = (a - a.dot(n) * n).squaredNorm();
  EXPECT_NEAR(f.dot(stiffness_matrix(m.V, m.T) * f), tangential * m.volume, 1e-12);
}

TEST(StiffnessMatrix, LinearFunctionsAreDiscretelyHarmonicAtInteriorVertices)
{
  // The Laplacian of a linear function is zero: (K f)_i = 0 at every interior vertex (the
  // boundary rows carry the Neumann flux and are not zero).
  for (const Mesh& m : { triangle_grid(5, 4), kuhn_grid(3), cube_five_tets() })
  {
    SCOPED_TRACE(m.name);
    const Eigen::VectorXd f = linear(m.V, some_gradient(m.V.cols()), 0.25);
    const Eigen::SparseMatrix<double> K = stiffness_matrix(m.V, m.T);
    const Eigen::VectorXd Kf = K * f;
    int interior = 0;
    for (Index i = 0; i < m.V.rows(); ++i)
      if (!on_unit_box_boundary(m.V.row(i)))
      {
        ++interior;
        EXPECT_NEAR(Kf(i), 0.0, 1e-13 * max_abs(K) * f.cwiseAbs().maxCoeff()) << "vertex " << i;
      }
    if (m.name != "cube_five_tets") // the 5-tet cube has no interior vertex
    {
      EXPECT_GT(interior, 0);
    }
  }
  // The same on the surface patch, whose interior vertices are those of the planar grid.
  const Mesh flat = triangle_grid(4, 5);
  const Mesh patch = surface_patch(4, 5);
  const Eigen::VectorXd f = linear(patch.V, Eigen::Vector3d(0.7, -1.3, 0.4), 0.25);
  const Eigen::VectorXd Kf = stiffness_matrix(patch.V, patch.T) * f;
  for (Index i = 0; i < flat.V.rows(); ++i)
  {
    if (!on_unit_box_boundary(flat.V.row(i)))
    {
      EXPECT_NEAR(Kf(i), 0.0, 1e-12) << "vertex " << i;
    }
  }
}

TEST(StiffnessMatrix, SymmetricPositiveSemidefiniteWithTheConstantsAsKernel)
{
  for (const Mesh& m : { triangle_grid(4, 3), surface_patch(3, 4), cube_five_tets(), kuhn_grid(2) })
  {
    SCOPED_TRACE(m.name);
    const Eigen::MatrixXd K = Eigen::MatrixXd(stiffness_matrix(m.V, m.T));
    EXPECT_EQ(K, K.transpose()); // exactly: (i, j) and (j, i) receive the same numbers
    const Eigen::VectorXd lambda = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(K).eigenvalues();
    const double scale = lambda.cwiseAbs().maxCoeff();
    // Eigenvalues of a symmetric matrix are computed to within ~n eps |K|: >= -1e-13 |K|.
    EXPECT_GE(lambda(0), -1e-13 * scale);
    // Connected mesh: only the constants are in the kernel, the second eigenvalue is positive.
    EXPECT_GT(lambda(1), 1e-6 * scale);
  }
}

TEST(StiffnessMatrix, OrientationDoesNotMatter)
{
  Mesh m = triangle_grid(3, 3);
  const Eigen::MatrixXd before = Eigen::MatrixXd(stiffness_matrix(m.V, m.T));
  for (Index t = 0; t < m.T.rows(); t += 2)
    std::swap(m.T(t, 0), m.T(t, 1));
  EXPECT_LT((Eigen::MatrixXd(stiffness_matrix(m.V, m.T)) - before).cwiseAbs().maxCoeff(), 1e-15);
}

// --- mass matrix ----------------------------------------------------------------------------

TEST(MassMatrix, EveryTypeSumsToTheTotalVolume)
{
  for (const Mesh& m : catalogue())
    for (MassMatrixType type :
      { MassMatrixType::Barycentric, MassMatrixType::Full, MassMatrixType::Voronoi })
    {
      SCOPED_TRACE(m.name + (type == MassMatrixType::Full ? " full"
                               : type == MassMatrixType::Voronoi ? " voronoi" : " barycentric"));
      const Eigen::SparseMatrix<double> M = mass_matrix(m.V, m.T, type);
      ASSERT_EQ(M.rows(), m.V.rows());
      ASSERT_EQ(M.cols(), m.V.rows());
      EXPECT_NEAR(Eigen::MatrixXd(M).sum(), m.volume, 1e-13);
    }
}

TEST(MassMatrix, BarycentricIsAPositiveDiagonalOfVolumeShares)
{
  for (const Mesh& m : catalogue())
  {
    SCOPED_TRACE(m.name);
    Eigen::SparseMatrix<double> M = mass_matrix(m.V, m.T); // default type
    M.makeCompressed();
    EXPECT_EQ(M.nonZeros(), m.V.rows());
    for (Index j = 0; j < M.outerSize(); ++j)
      for (Eigen::SparseMatrix<double>::InnerIterator it(M, j); it; ++it)
      {
        EXPECT_EQ(it.row(), it.col());
        EXPECT_GT(it.value(), 0.0);
      }
    // Vertex shares: 1/(d+1) of each incident element's volume, recomputed here.
    const Eigen::VectorXd vol = simplex_volumes(m.V, m.T);
    Eigen::VectorXd expected = Eigen::VectorXd::Zero(m.V.rows());
    for (Index t = 0; t < m.T.rows(); ++t)
      for (Index k = 0; k < m.T.cols(); ++k)
        expected(m.T(t, k)) += vol(t) / double(m.T.cols());
    EXPECT_LT((Eigen::VectorXd(M.diagonal()) - expected).cwiseAbs().maxCoeff(), 1e-15);
  }
}

/// Integral of f^2 over one element for a linear f with vertex values f, by quadrature rules
/// exact for quadratics: the edge-midpoint rule on triangles (weights 1/3) and the symmetric
/// 4-point rule on tetrahedra (barycentric (a, b, b, b), a = (5 + 3 sqrt 5) / 20,
/// b = (5 - sqrt 5) / 20, weights 1/4).
double integral_of_square(const Eigen::VectorXd& f, double volume)
{
  double sum = 0.0;
  if (f.size() == 3)
  {
    for (int i = 0; i < 3; ++i)
      for (int j = i + 1; j < 3; ++j)
        sum += std::pow((f(i) + f(j)) / 2.0, 2) / 3.0;
  }
  else
  {
    const double a = (5.0 + 3.0 * std::sqrt(5.0)) / 20.0, b = (5.0 - std::sqrt(5.0)) / 20.0;
    for (int q = 0; q < 4; ++q)
    {
      double value = 0.0;
      for (int i = 0; i < 4; ++i)
        value += (i == q ? a : b) * f(i);
      sum += value * value / 4.0;
    }
  }
  return sum * volume;
}

TEST(MassMatrix, FullIsExactForTheSquareOfALinearFunctionOnOneElement)
{
  struct Element
  {
    const char* name;
    Eigen::MatrixXd V;
  };
  std::vector<Element> elements;
  elements.push_back({ "triangle 2D", (Eigen::MatrixXd(3, 2) << 0.1, 0.2, 1.7, 0.4, 0.6, 1.3).finished() });
  elements.push_back({ "triangle 3D",
    (Eigen::MatrixXd(3, 3) << 0.1, 0.2, 0.3, 1.7, 0.4, -0.2, 0.6, 1.3, 0.9).finished() });
  elements.push_back({ "tetrahedron",
    (Eigen::MatrixXd(4, 3) << 0.1, 0.2, 0.3, 1.7, 0.4, -0.2, 0.6, 1.3, 0.9, 0.2, 0.5, 1.6)
      .finished() });
  for (const Element& e : elements)
  {
    SCOPED_TRACE(e.name);
    Eigen::MatrixXi T(1, e.V.rows());
    for (Index k = 0; k < e.V.rows(); ++k)
      T(0, k) = static_cast<int>(k);
    const double volume = simplex_volumes(e.V, T)(0);
    const Eigen::SparseMatrix<double> M = mass_matrix(e.V, T, MassMatrixType::Full);
    Eigen::VectorXd a(e.V.cols());
    a.setLinSpaced(0.9, -1.4);
    const Eigen::VectorXd f = linear(e.V, a, 0.35);
    EXPECT_NEAR(f.dot(M * f), integral_of_square(f, volume), 1e-14);
    // The lumped matrix integrates f exactly (first moments), not f^2.
    const Eigen::SparseMatrix<double> L = mass_matrix(e.V, T, MassMatrixType::Barycentric);
    const double mean = f.mean();
    EXPECT_NEAR(Eigen::VectorXd::Ones(f.size()).dot(L * f), mean * volume, 1e-14);
  }
}

TEST(MassMatrix, FullIsSymmetricPositiveDefinite)
{
  const Mesh m = kuhn_grid(2);
  const Eigen::MatrixXd M = Eigen::MatrixXd(mass_matrix(m.V, m.T, MassMatrixType::Full));
  EXPECT_EQ(M, M.transpose());
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(M).eigenvalues()(0), 0.0);
}

/// The diagonal of a mass matrix, checking that it is diagonal with positive entries.
Eigen::VectorXd positive_diagonal(const Eigen::SparseMatrix<double>& M)
{
  Eigen::SparseMatrix<double> C = M;
  C.makeCompressed();
  EXPECT_EQ(C.nonZeros(), C.rows());
  for (Index j = 0; j < C.outerSize(); ++j)
    for (Eigen::SparseMatrix<double>::InnerIterator it(C, j); it; ++it)
    {
      EXPECT_EQ(it.row(), it.col());
      EXPECT_GT(it.value(), 0.0) << "vertex " << it.row();
    }
  return C.diagonal();
}

TEST(MassMatrix, VoronoiIsTheVoronoiCellOnRegularGrids)
{
  // Right triangles (a 5 x 4 grid of rectangles, planar and rotated into 3D) and the Kuhn cube
  // grid: the vertices are a rectangular lattice, whose Voronoi cells are hx x hy (x hz) boxes,
  // halved for every coordinate on the boundary of the unit box (the cell clipped to the
  // domain). Analytic, independent of the element split.
  for (const Mesh& m : { triangle_grid(5, 4), surface_patch(5, 4), kuhn_grid(3) })
  {
    SCOPED_TRACE(m.name);
    const Eigen::VectorXd M = positive_diagonal(mass_matrix(m.V, m.T, MassMatrixType::Voronoi));
    const Mesh flat = m.name == "surface_patch" ? triangle_grid(5, 4) : m;
    const double cell = m.name == "kuhn_grid" ? 1.0 / 27.0 : 1.0 / 20.0;
    for (Index v = 0; v < M.size(); ++v)
    {
      double expected = cell;
      for (Index k = 0; k < flat.V.cols(); ++k)
        if (flat.V(v, k) == 0.0 || flat.V(v, k) == 1.0)
          expected /= 2.0;
      EXPECT_NEAR(M(v), expected, 1e-14) << "vertex " << v;
    }
  }
  // Acute (equilateral) triangles of side 1: an interior vertex's Voronoi cell is the regular
  // hexagon of area sqrt(3) / 2.
  const int s = 6;
  Eigen::MatrixXd V(s * s, 2);
  for (int j = 0; j < s; ++j)
    for (int i = 0; i < s; ++i)
      V.row(j * s + i) << i + 0.5 * j, 0.5 * std::sqrt(3.0) * j;
  Eigen::MatrixXi T(2 * (s - 1) * (s - 1), 3);
  int t = 0;
  for (int j = 0; j + 1 < s; ++j)
    for (int i = 0; i + 1 < s; ++i)
    {
      const int a = j * s + i;
      T.row(t++) << a, a + 1, a + s;
      T.row(t++) << a + 1, a + s + 1, a + s;
    }
  const Eigen::VectorXd M = positive_diagonal(mass_matrix(V, T, MassMatrixType::Voronoi));
  for (int j = 1; j + 1 < s; ++j)
    for (int i = 1; i + 1 < s; ++i)
      EXPECT_NEAR(M(j * s + i), 0.5 * std::sqrt(3.0), 1e-14) << "vertex " << i << "," << j;
  EXPECT_NEAR(M.sum(), simplex_volumes(V, T).sum(), 1e-12);
}

TEST(MassMatrix, VoronoiIsPositiveOnObtuseTriangles)
{
  // One obtuse triangle (area 0.5): Meyer et al.'s rule gives the obtuse corner half the area
  // and the others a quarter; the circumcentric parts would be (8.125, -3.8125, -3.8125).
  Eigen::MatrixXd V(3, 2);
  V << 2.0, 0.25, 0.0, 0.0, 4.0, 0.0; // obtuse at corner 0
  const Eigen::MatrixXi T = (Eigen::MatrixXi(1, 3) << 0, 1, 2).finished();
  const Eigen::VectorXd M = positive_diagonal(mass_matrix(V, T, MassMatrixType::Voronoi));
  EXPECT_NEAR(M(0), 0.25, 1e-15);
  EXPECT_NEAR(M(1), 0.125, 1e-15);
  EXPECT_NEAR(M(2), 0.125, 1e-15);
  // A jittered grid with many obtuse triangles: positive, sums to the area.
  Mesh m = triangle_grid(8, 8);
  for (Index v = 0; v < m.V.rows(); ++v)
    if (!on_unit_box_boundary(m.V.row(v)))
      m.V.row(v) += 0.04 * Eigen::RowVector2d(std::sin(17.0 * v), std::cos(11.0 * v));
  int obtuse = 0;
  for (Index t = 0; t < m.T.rows(); ++t)
    for (int i = 0; i < 3; ++i)
    {
      const Eigen::RowVector2d a = m.V.row(m.T(t, i)), b = m.V.row(m.T(t, (i + 1) % 3)),
                               c = m.V.row(m.T(t, (i + 2) % 3));
      obtuse += (b - a).dot(c - a) < 0.0;
    }
  EXPECT_GT(obtuse, 20);
  const Eigen::VectorXd Mj = positive_diagonal(mass_matrix(m.V, m.T, MassMatrixType::Voronoi));
  EXPECT_NEAR(Mj.sum(), 1.0, 1e-13);
}

/// The circumcentric (signed) decomposition of a tetrahedron: corner i gets the signed volumes
/// of the tetrahedra (p_i, m_ij, c_ijk, c) over the ordered pairs (j, k), with m_ij the edge
/// midpoint, c_ijk the face circumcentre, c the circumcentre, each signed by the orientation of
/// (i, j, k, l). Equal to the Voronoi parts when the tetrahedron is well-centred.
std::array<double, 4> circumcentric_parts(const Eigen::MatrixXd& P)
{
  auto point = [&](int i) { return Eigen::Vector3d(P.row(i).transpose()); };
  auto det = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
    return a.dot(b.cross(c));
  };
  Eigen::Matrix3d A;
  Eigen::Vector3d rhs;
  for (int r = 0; r < 3; ++r)
  {
    A.row(r) = (point(r + 1) - point(0)).transpose();
    rhs(r) = 0.5 * (point(r + 1) - point(0)).squaredNorm();
  }
  const Eigen::Vector3d c = point(0) + A.fullPivLu().solve(rhs);
  auto face_centre = [&](int i, int j, int k) {
    const Eigen::Vector3d u = point(j) - point(i), v = point(k) - point(i);
    Eigen::Matrix2d G;
    G << u.dot(u), u.dot(v), u.dot(v), v.dot(v);
    const Eigen::Vector2d st = G.inverse() * Eigen::Vector2d(0.5 * u.dot(u), 0.5 * v.dot(v));
    return Eigen::Vector3d(point(i) + st(0) * u + st(1) * v);
  };
  std::array<double, 4> part{};
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      for (int k = 0; k < 4; ++k)
      {
        if (j == i || k == i || k == j)
          continue;
        const int l = 6 - i - j - k;
        const double orientation =
          det(point(j) - point(i), point(k) - point(i), point(l) - point(i)) > 0 ? 1.0 : -1.0;
        const Eigen::Vector3d m = 0.5 * (point(i) + point(j));
        part[std::size_t(i)] +=
          orientation * det(m - point(i), face_centre(i, j, k) - point(i), c - point(i)) / 6.0;
      }
  return part;
}

TEST(MassMatrix, VoronoiOfTetrahedra)
{
  const Eigen::MatrixXi T = (Eigen::MatrixXi(1, 4) << 0, 1, 2, 3).finished();
  // Regular: a quarter each (symmetry).
  const Mesh cube = cube_five_tets();
  const Eigen::MatrixXd regular = (Eigen::MatrixXd(4, 3) << cube.V.row(0), cube.V.row(3),
    cube.V.row(5), cube.V.row(6)).finished();
  Eigen::VectorXd M = positive_diagonal(mass_matrix(regular, T, MassMatrixType::Voronoi));
  for (int i = 0; i < 4; ++i)
    EXPECT_NEAR(M(i), 1.0 / 12.0, 1e-15);
  // Well-centred (circumcentre and face circumcentres inside): the circumcentric parts.
  const Eigen::MatrixXd well = (Eigen::MatrixXd(4, 3) << 0.0, 0.0, 0.0, 1.1, 0.1, 0.0, 0.45,
    0.95, 0.05, 0.5, 0.35, 0.9).finished();
  const std::array<double, 4> dual = circumcentric_parts(well);
  M = positive_diagonal(mass_matrix(well, T, MassMatrixType::Voronoi));
  for (int i = 0; i < 4; ++i)
  {
    EXPECT_GT(dual[std::size_t(i)], 0.0);
    EXPECT_NEAR(M(i), dual[std::size_t(i)], 1e-14) << "corner " << i;
  }
  // Circumcentre outside (a flat tetrahedron): some circumcentric part is negative; the
  // Voronoi parts are positive and equal the share of the tetrahedron nearest to each corner,
  // estimated here by sampling (200,000 uniform points: standard error < 0.0012 of the volume).
  const Eigen::MatrixXd flat = (Eigen::MatrixXd(4, 3) << 0.0, 0.0, 0.0, 2.0, 0.0, 0.0, 1.0,
    1.5, 0.0, 0.9, 0.6, 0.15).finished();
  const std::array<double, 4> signed_parts = circumcentric_parts(flat);
  EXPECT_LT(*std::min_element(signed_parts.begin(), signed_parts.end()), 0.0);
  const double volume = simplex_volumes(flat, T)(0);
  M = positive_diagonal(mass_matrix(flat, T, MassMatrixType::Voronoi));
  EXPECT_NEAR(M.sum(), volume, 1e-15);
  std::array<int, 4> nearest{};
  std::uint64_t state = 12345;
  auto uniform = [&state] {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return double(state >> 11) / 9007199254740992.0;
  };
  const int samples = 200000;
  for (int n = 0; n < samples; ++n)
  {
    // uniform in the tetrahedron: sorted uniforms as barycentric coordinates
    std::array<double, 3> u = { uniform(), uniform(), uniform() };
    std::sort(u.begin(), u.end());
    const double b[4] = { u[0], u[1] - u[0], u[2] - u[1], 1.0 - u[2] };
    Eigen::RowVector3d x = Eigen::RowVector3d::Zero();
    for (int i = 0; i < 4; ++i)
      x += b[i] * flat.row(i);
    int best = 0;
    for (int i = 1; i < 4; ++i)
      if ((x - flat.row(i)).squaredNorm() < (x - flat.row(best)).squaredNorm())
        best = i;
    ++nearest[std::size_t(best)];
  }
  for (int i = 0; i < 4; ++i)
    EXPECT_NEAR(M(i) / volume, double(nearest[std::size_t(i)]) / samples, 0.006) << "corner " << i;
}

TEST(MassMatrix, VoronoiOfRandomTetrahedra)
{
  // Jittered regular tetrahedra, some well-centred (their Voronoi parts have a closed form,
  // checked against the circumcentric parts computed above by another construction), some not
  // (clipped by the bisector planes): every part positive, the parts sum to the volume.
  const Eigen::MatrixXi T = (Eigen::MatrixXi(1, 4) << 0, 1, 2, 3).finished();
  std::uint64_t state = 777;
  auto uniform = [&state] {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return double(state >> 11) / 9007199254740992.0;
  };
  int well_centred = 0, other = 0;
  for (int trial = 0; trial < 400; ++trial)
  {
    Eigen::MatrixXd P(4, 3);
    P << 1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1;
    for (int i = 0; i < 4; ++i)
      for (int k = 0; k < 3; ++k)
        P(i, k) += 1.2 * (uniform() - 0.5);
    const double volume = simplex_volumes(P, T)(0);
    if (!(volume > 1e-3))
      continue;
    // Well-centred: the circumcentre's barycentric coordinates >= 0 and no obtuse face angle.
    Eigen::Matrix4d A;
    for (int i = 0; i < 4; ++i)
      A.col(i) << P.row(i).transpose(), 1.0;
    Eigen::Matrix3d E;
    Eigen::Vector3d rhs;
    for (int r = 0; r < 3; ++r)
    {
      E.row(r) = P.row(r + 1) - P.row(0);
      rhs(r) = 0.5 * E.row(r).squaredNorm();
    }
    const Eigen::Vector3d c = P.row(0).transpose() + E.fullPivLu().solve(rhs);
    const Eigen::Vector4d bary = A.fullPivLu().solve((Eigen::Vector4d() << c, 1.0).finished());
    bool well = bary.minCoeff() >= 0.0;
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j)
        for (int k = j + 1; k < 4; ++k)
          if (j != i && k != i && (P.row(j) - P.row(i)).dot(P.row(k) - P.row(i)) < 0.0)
            well = false;
    const Eigen::VectorXd M = positive_diagonal(mass_matrix(P, T, MassMatrixType::Voronoi));
    EXPECT_NEAR(M.sum(), volume, 1e-14 * volume) << "trial " << trial;
    if (well)
    {
      ++well_centred;
      const std::array<double, 4> dual = circumcentric_parts(P);
      for (int i = 0; i < 4; ++i)
        EXPECT_NEAR(M(i), dual[std::size_t(i)], 1e-13 * volume) << "trial " << trial << " corner " << i;
    }
    else
      ++other;
  }
  EXPECT_GT(well_centred, 20);
  EXPECT_GT(other, 20);
}

// --- gradient operator ----------------------------------------------------------------------

TEST(GradientOperator, ExactOnLinearFunctions)
{
  for (const Mesh& m : catalogue())
  {
    SCOPED_TRACE(m.name);
    const Index dim = m.V.cols();
    const Eigen::SparseMatrix<double> G = gradient_operator(m.V, m.T);
    ASSERT_EQ(G.rows(), m.T.rows() * dim);
    ASSERT_EQ(G.cols(), m.V.rows());
    // For the surface patch take a in the plane, so that the gradient is a itself.
    Eigen::VectorXd a = some_gradient(dim);
    if (m.name == "surface_patch")
      a = rotation() * Eigen::Vector3d(0.7, -1.3, 0.0);
    const Eigen::VectorXd g = G * linear(m.V, a, 0.25);
    for (Index t = 0; t < m.T.rows(); ++t)
      EXPECT_LT((g.segment(t * dim, dim) - a).cwiseAbs().maxCoeff(), 1e-12) << "element " << t;
  }
}

TEST(GradientOperator, SurfaceGradientIsTheTangentialProjection)
{
  const Mesh m = surface_patch(3, 2);
  const Eigen::Vector3d n = rotation().col(2);
  const Eigen::Vector3d a(0.7, -1.3, 0.4);
  const Eigen::Vector3d tangential = a - a.dot(n) * n;
  const Eigen::VectorXd g = gradient_operator(m.V, m.T) * linear(m.V, a, 0.0);
  for (Index t = 0; t < m.T.rows(); ++t)
    EXPECT_LT((g.segment<3>(3 * t) - tangential).cwiseAbs().maxCoeff(), 1e-12) << "element " << t;
}

TEST(GradientOperator, WeightedNormalProductIsTheStiffnessMatrix)
{
  // K = G^T diag(vol repeated dim times) G: both integrate grad phi_i . grad phi_j.
  for (const Mesh& m : catalogue())
  {
    SCOPED_TRACE(m.name);
    const Index dim = m.V.cols();
    const Eigen::SparseMatrix<double> G = gradient_operator(m.V, m.T);
    const Eigen::VectorXd vol = simplex_volumes(m.V, m.T);
    Eigen::VectorXd weights(m.T.rows() * dim);
    for (Index t = 0; t < m.T.rows(); ++t)
      weights.segment(t * dim, dim).setConstant(vol(t));
    const Eigen::SparseMatrix<double> K = stiffness_matrix(m.V, m.T);
    const Eigen::SparseMatrix<double> GtWG = G.transpose() * weights.asDiagonal() * G;
    EXPECT_LT(max_abs(GtWG - K), 1e-12 * max_abs(K));
  }
}

// --- validation -----------------------------------------------------------------------------

/// Runs every operator on (V, T) and checks that each throws the same error.
::testing::AssertionResult all_throw(const Eigen::MatrixXd& V, const Eigen::MatrixXi& T,
  ErrorCode code, std::initializer_list<std::string> fragments)
{
  const std::vector<std::pair<const char*, std::function<void()>>> calls = {
    { "simplex_volumes", [&] { simplex_volumes(V, T); } },
    { "stiffness_matrix", [&] { stiffness_matrix(V, T); } },
    { "mass_matrix barycentric", [&] { mass_matrix(V, T); } },
    { "mass_matrix full", [&] { mass_matrix(V, T, MassMatrixType::Full); } },
    { "gradient_operator", [&] { gradient_operator(V, T); } },
  };
  for (const auto& call : calls)
  {
    ::testing::AssertionResult r = throws_error(call.second, code, fragments);
    if (!r)
      return ::testing::AssertionFailure() << call.first << ": " << r.message();
  }
  return ::testing::AssertionSuccess();
}

TEST(FemValidation, DegenerateTriangleIsNamed)
{
  Eigen::MatrixXd V(4, 2);
  V << 0, 0, 1, 0, 0, 1, 2, 0;
  Eigen::MatrixXi T(2, 3);
  T << 0, 1, 2, //
    0, 1, 3;    // collinear
  EXPECT_TRUE(all_throw(V, T, ErrorCode::InvalidArgument,
    { "element 1 (vertices 0, 1, 3)", "degenerate triangle" }));
  // A repeated vertex, on a surface.
  Eigen::MatrixXd V3 = Eigen::MatrixXd::Zero(3, 3);
  V3 << 0, 0, 0, 1, 0, 0, 0, 1, 0;
  EXPECT_TRUE(all_throw(V3, (Eigen::MatrixXi(1, 3) << 0, 1, 1).finished(),
    ErrorCode::InvalidArgument, { "element 0 (vertices 0, 1, 1)", "degenerate" }));
}

TEST(FemValidation, DegenerateTetrahedronIsNamed)
{
  Mesh m = cube_five_tets();
  m.T.row(3) << 0, 1, 2, 3; // the bottom face's four corners: coplanar
  EXPECT_TRUE(all_throw(m.V, m.T, ErrorCode::InvalidArgument,
    { "element 3 (vertices 0, 1, 2, 3)", "degenerate tetrahedron", "volume is 0" }));
}

TEST(FemValidation, ThinButValidElementsAreAccepted)
{
  // Aspect ratio 1e8: far from the 64 eps threshold, must not be refused.
  Eigen::MatrixXd V(3, 2);
  V << 0, 0, 1, 0, 0.5, 1e-8;
  const Eigen::MatrixXi T = (Eigen::MatrixXi(1, 3) << 0, 1, 2).finished();
  EXPECT_NEAR(simplex_volumes(V, T)(0), 0.5e-8, 1e-22);
  EXPECT_NO_THROW(stiffness_matrix(V, T));
}

TEST(FemValidation, IndexOutOfRangeIsNamed)
{
  Mesh m = triangle_grid(2, 2);
  const int n = static_cast<int>(m.V.rows());
  m.T(5, 2) = n;
  EXPECT_TRUE(all_throw(m.V, m.T, ErrorCode::InvalidArgument,
    { "element 5", "refers to vertex " + std::to_string(n), "has " + std::to_string(n) + " vertices" }));
  m.T(5, 2) = -1;
  EXPECT_TRUE(all_throw(m.V, m.T, ErrorCode::InvalidArgument, { "element 5", "vertex -1" }));
}

TEST(FemValidation, WrongColumnCounts)
{
  const Mesh tri = triangle_grid(2, 2);
  const Mesh tet = cube_five_tets();
  EXPECT_TRUE(all_throw(tri.V, tri.T.leftCols(2), ErrorCode::SizeMismatch, { "got 2 columns" }));
  Eigen::MatrixXi T5(1, 5);
  T5 << 0, 1, 2, 3, 4;
  EXPECT_TRUE(all_throw(tet.V, T5, ErrorCode::SizeMismatch, { "got 5 columns" }));
  EXPECT_TRUE(all_throw(tri.V.leftCols(1), tri.T, ErrorCode::SizeMismatch, { "2 or 3 coordinates", "got 1" }));
  Eigen::MatrixXd V4 = Eigen::MatrixXd::Zero(tet.V.rows(), 4);
  EXPECT_TRUE(all_throw(V4, tet.T, ErrorCode::SizeMismatch, { "got 4" }));
  EXPECT_TRUE(all_throw(tet.V.leftCols(2), tet.T, ErrorCode::SizeMismatch, { "tetrahedra need 3D vertices" }));
}

TEST(FemValidation, NonFiniteVertexIsNamed)
{
  Mesh m = kuhn_grid(1);
  m.V(5, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(all_throw(m.V, m.T, ErrorCode::NonFinite, { "vertex 5" }));
  m.V(5, 1) = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(all_throw(m.V, m.T, ErrorCode::NonFinite, { "vertex 5" }));
}

TEST(FemValidation, NoElements)
{
  const Mesh m = triangle_grid(1, 1);
  EXPECT_TRUE(all_throw(m.V, Eigen::MatrixXi(0, 3), ErrorCode::EmptyInput, { "no elements" }));
}

TEST(FemValidation, UnreferencedVerticesGiveZeroRows)
{
  Mesh m = triangle_grid(1, 1);
  m.V.conservativeResize(m.V.rows() + 1, Eigen::NoChange);
  m.V.bottomRows(1) << 5.0, 5.0;
  const Index extra = m.V.rows() - 1;
  const Eigen::MatrixXd K = Eigen::MatrixXd(stiffness_matrix(m.V, m.T));
  const Eigen::MatrixXd M = Eigen::MatrixXd(mass_matrix(m.V, m.T));
  EXPECT_EQ(K.row(extra).cwiseAbs().sum(), 0.0);
  EXPECT_EQ(M(extra, extra), 0.0);
}

TEST(BoundaryVertices, TrianglesTetrahedraAndErrors)
{
  // a 3 x 3 grid of the unit square: every vertex but the centre (4) is on the boundary
  Eigen::MatrixXi T(8, 3);
  for (int j = 0, t = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i)
    {
      const int a = 3 * j + i;
      T.row(t++) << a, a + 1, a + 4;
      T.row(t++) << a, a + 4, a + 3;
    }
  EXPECT_EQ(boundary_vertices(T), (std::vector<int>{ 0, 1, 2, 3, 5, 6, 7, 8 }));
  // two triangles sharing an edge: all four; the order of an element's vertices does not matter
  Eigen::MatrixXi two(2, 3);
  two << 2, 0, 1, 1, 3, 2;
  EXPECT_EQ(boundary_vertices(two), (std::vector<int>{ 0, 1, 2, 3 }));
  // a tetrahedron with a vertex (4) inside, split into four: the inner vertex is not boundary
  Eigen::MatrixXi tets(4, 4);
  tets << 4, 1, 2, 3, 0, 4, 2, 3, 0, 1, 4, 3, 0, 1, 2, 4;
  EXPECT_EQ(boundary_vertices(tets), (std::vector<int>{ 0, 1, 2, 3 }));
  EXPECT_TRUE(boundary_vertices(Eigen::MatrixXi(0, 3)).empty());
  EXPECT_TRUE(throws_error(
    [] { boundary_vertices(Eigen::MatrixXi::Zero(1, 5)); }, ErrorCode::SizeMismatch, { "5 vertices" }));
}

} // namespace

TEST(ConnectedComponents, TwoPiecesAndALooseVertex)
{
  // triangles {0,1,2}, {2,3,4} (one piece), {5,6,7} (another); vertex 8 in no element
  Eigen::MatrixXi T(3, 3);
  T << 0, 1, 2, 2, 3, 4, 7, 6, 5;
  const Eigen::VectorXi c = bary::connected_components(9, T);
  ASSERT_EQ(c.size(), 9);
  for (int v : { 0, 1, 2, 3, 4 })
    EXPECT_EQ(c(v), 0) << v;
  for (int v : { 5, 6, 7 })
    EXPECT_EQ(c(v), 1) << v; // numbered by smallest vertex
  EXPECT_EQ(c(8), 2);
  // tetrahedra: one piece through a shared vertex
  Eigen::MatrixXi K(2, 4);
  K << 0, 1, 2, 3, 3, 4, 5, 6;
  EXPECT_EQ(bary::connected_components(7, K).maxCoeff(), 0);
}
