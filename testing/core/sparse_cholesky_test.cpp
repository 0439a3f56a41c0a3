// Tests for core/sparse_cholesky.h: a 2D Poisson-type problem with both backends, agreement
// between them, badly scaled SPD matrices, the definiteness test and the error paths.
//
// Tolerances. A = L + I with L the 5-point graph Laplacian of a grid has eigenvalues in
// [1, 9], so cond(A) <= 9: a backward-stable Cholesky solve gives a relative residual of a few
// eps times the fill (~ 1e-15) and a relative error below cond(A) times that. 1e-12 leaves a
// margin of 100x on both.
#include "core/error.h"
#include "core/sparse_cholesky.h"
#include "error_matchers.h"

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <ostream>
#include <random>
#include <string>
#include <thread>
#include <vector>

namespace bary
{
/// GoogleTest printer: the backend's name instead of a byte dump.
inline void PrintTo(SparseCholesky::Backend backend, std::ostream* os)
{
  *os << to_string(backend);
}
} // namespace bary

namespace
{
using namespace bary;
using bary::test::throws_error;
using Backend = SparseCholesky::Backend;
using SparseMatrix = Eigen::SparseMatrix<double>;

/// 5-point graph Laplacian of an nx by ny grid of vertices (natural boundary: singular, the
/// constants are its kernel).
SparseMatrix grid_laplacian(int nx, int ny)
{
  std::vector<Eigen::Triplet<double>> triplets;
  auto id = [nx](int i, int j) { return j * nx + i; };
  auto edge = [&](int a, int b) {
    triplets.emplace_back(a, b, -1.0);
    triplets.emplace_back(b, a, -1.0);
    triplets.emplace_back(a, a, 1.0);
    triplets.emplace_back(b, b, 1.0);
  };
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i)
    {
      if (i + 1 < nx)
        edge(id(i, j), id(i + 1, j));
      if (j + 1 < ny)
        edge(id(i, j), id(i, j + 1));
    }
  SparseMatrix L(nx * ny, nx * ny);
  L.setFromTriplets(triplets.begin(), triplets.end());
  return L;
}

SparseMatrix identity(Index n)
{
  SparseMatrix I(n, n);
  I.setIdentity();
  return I;
}

/// The grid Laplacian plus the identity: SPD with eigenvalues in [1, 9].
SparseMatrix poisson_matrix(int nx, int ny)
{
  return grid_laplacian(nx, ny) + identity(Index(nx) * ny);
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

double relative_residual(const SparseMatrix& A, const Eigen::MatrixXd& X, const Eigen::MatrixXd& B)
{
  return (A * X - B).cwiseAbs().maxCoeff() / B.cwiseAbs().maxCoeff();
}

SparseMatrix dense_to_sparse(const Eigen::MatrixXd& D)
{
  return D.sparseView();
}

/// Both backends, CHOLMOD skipped when BaryLab was built without it.
class SparseCholeskyBackend : public ::testing::TestWithParam<Backend>
{
protected:
  void SetUp() override
  {
    if (GetParam() == Backend::Cholmod && !SparseCholesky::cholmod_available())
      GTEST_SKIP() << "BaryLab was built without CHOLMOD";
  }
};

TEST_P(SparseCholeskyBackend, SolvesAPoissonProblem)
{
  const SparseMatrix A = poisson_matrix(40, 30);
  const Eigen::MatrixXd B = random_matrix(A.rows(), 3, 1);
  SparseCholesky solver(GetParam());
  EXPECT_EQ(solver.backend(), GetParam());
  EXPECT_FALSE(solver.computed());
  solver.compute(A);
  EXPECT_TRUE(solver.computed());
  EXPECT_EQ(solver.rows(), A.rows());
  const Eigen::MatrixXd X = solver.solve(B);
  ASSERT_EQ(X.rows(), A.rows());
  ASSERT_EQ(X.cols(), 3);
  EXPECT_LT(relative_residual(A, X, B), 1e-12);
  // Against a dense factorization (independent code path): relative error <= cond(A) * 1e-15.
  const Eigen::MatrixXd reference = Eigen::MatrixXd(A).llt().solve(B);
  EXPECT_LT((X - reference).cwiseAbs().maxCoeff() / reference.cwiseAbs().maxCoeff(), 1e-12);
  // Every pivot of a unit-diagonal SPD matrix lies in [lambda_min, 1] of the scaled matrix.
  EXPECT_GT(solver.min_pivot(), 0.05);
  EXPECT_LE(solver.min_pivot(), 1.0);
}

TEST_P(SparseCholeskyBackend, BadlyScaledMatrixIsSolvedAccurately)
{
  // A = S P S with P the Poisson matrix and S spanning 24 orders of magnitude (units, graded
  // meshes): cond(A) ~ 1e24, yet the solve is accurate because the backend rescales to unit
  // diagonal. Check the scaled residual S^-1 (A x - b), where the errors live.
  const SparseMatrix P = poisson_matrix(20, 20);
  Eigen::VectorXd s(P.rows());
  for (Index i = 0; i < s.size(); ++i)
    s(i) = std::pow(10.0, -12.0 + 24.0 * double(i % 17) / 16.0);
  const SparseMatrix A = s.asDiagonal() * P * s.asDiagonal();
  const Eigen::VectorXd x_true = random_matrix(P.rows(), 1, 2).col(0).cwiseQuotient(s);
  const Eigen::VectorXd b = A * x_true;
  SparseCholesky solver(GetParam());
  solver.compute(A);
  const Eigen::VectorXd x = solver.solve(b);
  EXPECT_LT((s.asDiagonal() * (x - x_true)).cwiseAbs().maxCoeff(), 1e-12);
}

TEST_P(SparseCholeskyBackend, NegativeDiagonalIsNotPositiveDefinite)
{
  SparseMatrix A = poisson_matrix(5, 5);
  A.coeffRef(7, 7) = -2.0;
  SparseCholesky solver(GetParam());
  EXPECT_TRUE(throws_error([&] { solver.compute(A); }, ErrorCode::InvalidArgument,
    { "not positive definite", "diagonal entry (7, 7) is -2" }));
  EXPECT_FALSE(solver.computed());
}

TEST_P(SparseCholeskyBackend, IndefiniteMatrixWithPositiveDiagonalIsNotPositiveDefinite)
{
  // Eigenvalues 3 and -1.
  Eigen::MatrixXd D(2, 2);
  D << 1, 2, 2, 1;
  SparseCholesky solver(GetParam());
  EXPECT_TRUE(throws_error([&] { solver.compute(dense_to_sparse(D)); }, ErrorCode::InvalidArgument,
    { "not positive definite" }));
  // The same block hidden in a larger SPD matrix.
  SparseMatrix A = poisson_matrix(6, 6);
  A.coeffRef(10, 11) = A.coeffRef(11, 10) = 20.0;
  EXPECT_TRUE(throws_error([&] { solver.compute(A); }, ErrorCode::InvalidArgument,
    { "not positive definite" }));
}

TEST_P(SparseCholeskyBackend, ExactlyAndNumericallySingularMatrices)
{
  SparseCholesky solver(GetParam());
  // [[1, 1], [1, 1]]: the second pivot is exactly 0 (LDL^T: zero pivot; LL^T: fails).
  Eigen::MatrixXd D(2, 2);
  D << 1, 1, 1, 1;
  EXPECT_TRUE(throws_error([&] { solver.compute(dense_to_sparse(D)); }, ErrorCode::InvalidArgument,
    { "not positive definite" }));
  // [[1, c], [c, 1]] with c = 1 - 2^-50: positive definite in exact arithmetic, second pivot
  // 1 - c^2 ~ 2^-49 = 1.8e-15, below the test's 16 n eps = 7.1e-15: numerically singular.
  const double c = 1.0 - std::ldexp(1.0, -50);
  D << 1, c, c, 1;
  EXPECT_TRUE(throws_error([&] { solver.compute(dense_to_sparse(D)); }, ErrorCode::InvalidArgument,
    { "not positive definite", "smallest pivot", "at row", "numerically singular" }));
  // c = 1 - 2^-20: second pivot ~ 2e-6, accepted, and reported by min_pivot().
  const double c2 = 1.0 - std::ldexp(1.0, -20);
  D << 1, c2, c2, 1;
  ASSERT_NO_THROW(solver.compute(dense_to_sparse(D)));
  EXPECT_NEAR(solver.min_pivot(), 1.0 - c2 * c2, 1e-12);
}

TEST_P(SparseCholeskyBackend, SingularLaplacianIsNotPositiveDefinite)
{
  // The Laplacian with natural boundary conditions is only semidefinite: its last pivot is 0
  // up to rounding (~ n eps), which the definiteness test refuses whatever its sign.
  for (int n : { 3, 10, 40 })
  {
    SparseCholesky solver(GetParam());
    EXPECT_TRUE(throws_error([&] { solver.compute(grid_laplacian(n, n)); },
      ErrorCode::InvalidArgument, { "not positive definite", "fixed (known) vertex" }))
      << n << " by " << n;
  }
  // Two components, one of them pinned: still singular.
  SparseMatrix L = grid_laplacian(4, 4);
  SparseMatrix A(32, 32);
  std::vector<Eigen::Triplet<double>> triplets;
  for (Index j = 0; j < L.outerSize(); ++j)
    for (SparseMatrix::InnerIterator it(L, j); it; ++it)
    {
      triplets.emplace_back(it.row(), it.col(), it.value());
      triplets.emplace_back(it.row() + 16, it.col() + 16, it.value());
    }
  triplets.emplace_back(0, 0, 1.0);
  A.setFromTriplets(triplets.begin(), triplets.end());
  SparseCholesky solver(GetParam());
  EXPECT_TRUE(throws_error([&] { solver.compute(A); }, ErrorCode::InvalidArgument,
    { "not positive definite" }));
  // Pinning the second component too makes it SPD.
  A.coeffRef(16, 16) += 1.0;
  EXPECT_NO_THROW(solver.compute(A));
}

TEST_P(SparseCholeskyBackend, SolveWithoutColumnsAndCopiesShareTheFactor)
{
  const SparseMatrix A = poisson_matrix(8, 8);
  SparseCholesky solver(GetParam());
  solver.compute(A);
  EXPECT_EQ(solver.solve(Eigen::MatrixXd(64, 0)).cols(), 0);

  const Eigen::MatrixXd B = random_matrix(64, 2, 3);
  const SparseCholesky copy = solver;
  const Eigen::MatrixXd X = copy.solve(B);
  // Re-factoring the original leaves the copy's factorization alone.
  solver.compute(2.0 * A);
  EXPECT_EQ(copy.solve(B), X);
  EXPECT_LT((solver.solve(B) - 0.5 * X).cwiseAbs().maxCoeff(), 1e-14);
}

TEST_P(SparseCholeskyBackend, ConcurrentSolvesAgree)
{
  const SparseMatrix A = poisson_matrix(20, 20);
  SparseCholesky solver(GetParam());
  solver.compute(A);
  const Eigen::MatrixXd B = random_matrix(A.rows(), 2, 4);
  const Eigen::MatrixXd expected = solver.solve(B);
  std::vector<Eigen::MatrixXd> results(4);
  std::vector<std::thread> threads;
  for (std::size_t t = 0; t < results.size(); ++t)
    threads.emplace_back([&, t] {
      for (int repeat = 0; repeat < 20; ++repeat)
        results[t] = solver.solve(B);
    });
  for (std::thread& thread : threads)
    thread.join();
  for (const Eigen::MatrixXd& X : results)
    EXPECT_EQ(X, expected);
}

std::string backend_name(const ::testing::TestParamInfo<Backend>& param_info)
{
  return param_info.param == Backend::Eigen ? "Eigen" : "Cholmod";
}

TEST(SparseCholesky, BackendNames)
{
  EXPECT_STREQ(to_string(Backend::Automatic), "automatic");
  EXPECT_STREQ(to_string(Backend::Cholmod), "cholmod");
  EXPECT_STREQ(to_string(Backend::Eigen), "eigen");
}

INSTANTIATE_TEST_SUITE_P(Backends, SparseCholeskyBackend,
  ::testing::Values(Backend::Eigen, Backend::Cholmod), backend_name);

TEST(SparseCholesky, BackendsAgree)
{
  if (!SparseCholesky::cholmod_available())
    GTEST_SKIP() << "BaryLab was built without CHOLMOD";
  const SparseMatrix A = poisson_matrix(50, 40);
  const Eigen::MatrixXd B = random_matrix(A.rows(), 4, 5);
  SparseCholesky cholmod(Backend::Cholmod), eigen(Backend::Eigen);
  cholmod.compute(A);
  eigen.compute(A);
  const Eigen::MatrixXd Xc = cholmod.solve(B), Xe = eigen.solve(B);
  // Both are within cond(A) * few eps of the exact solution, so within 1e-12 of each other.
  EXPECT_LT((Xc - Xe).cwiseAbs().maxCoeff() / Xe.cwiseAbs().maxCoeff(), 1e-12);
  // Both report the same smallest pivot (same matrix, different orderings: not bitwise).
  EXPECT_GT(cholmod.min_pivot(), 0.0);
  EXPECT_GT(eigen.min_pivot(), 0.0);
}

TEST(SparseCholesky, ReportsTheBackendInUse)
{
  EXPECT_EQ(SparseCholesky().backend(),
    SparseCholesky::cholmod_available() ? Backend::Cholmod : Backend::Eigen);
  EXPECT_EQ(SparseCholesky(Backend::Automatic).backend(),
    SparseCholesky::cholmod_available() ? Backend::Cholmod : Backend::Eigen);
  EXPECT_EQ(SparseCholesky(Backend::Eigen).backend(), Backend::Eigen);
  if (SparseCholesky::cholmod_available())
    EXPECT_EQ(SparseCholesky(Backend::Cholmod).backend(), Backend::Cholmod);
  else
    EXPECT_TRUE(throws_error([] { SparseCholesky s(Backend::Cholmod); },
      ErrorCode::InvalidArgument, { "built without CHOLMOD", "Backend::Eigen" }));
}

TEST(SparseCholesky, SolveBeforeCompute)
{
  const SparseCholesky solver;
  EXPECT_TRUE(throws_error([&] { solver.solve(Eigen::MatrixXd::Ones(3, 1)); },
    ErrorCode::InvalidArgument, { "before", "compute" }));
  EXPECT_EQ(solver.rows(), 0);
  EXPECT_EQ(solver.min_pivot(), 0.0);
}

TEST(SparseCholesky, FailedComputeForgetsThePreviousFactorization)
{
  SparseCholesky solver;
  solver.compute(poisson_matrix(3, 3));
  SparseMatrix bad = poisson_matrix(3, 3);
  bad.coeffRef(0, 0) = -1.0;
  EXPECT_THROW(solver.compute(bad), Error);
  EXPECT_FALSE(solver.computed());
  EXPECT_TRUE(throws_error([&] { solver.solve(Eigen::MatrixXd::Ones(9, 1)); },
    ErrorCode::InvalidArgument, { "before" }));
}

TEST(SparseCholesky, InvalidInputs)
{
  SparseCholesky solver;
  EXPECT_TRUE(throws_error([&] { solver.compute(SparseMatrix(3, 4)); }, ErrorCode::SizeMismatch,
    { "square", "3 by 4" }));
  EXPECT_TRUE(throws_error([&] { solver.compute(SparseMatrix(0, 0)); }, ErrorCode::EmptyInput));

  SparseMatrix nan = poisson_matrix(3, 3);
  nan.coeffRef(4, 5) = nan.coeffRef(5, 4) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(throws_error([&] { solver.compute(nan); }, ErrorCode::NonFinite, { "non-finite entry at" }));

  // row_ids renames rows in messages (e.g. for a submatrix), and must have n entries.
  const Eigen::VectorXi ids = Eigen::VectorXi::LinSpaced(9, 100, 108);
  EXPECT_TRUE(throws_error([&] { solver.compute(nan, ids); }, ErrorCode::NonFinite,
    { "non-finite entry at (10" }));
  EXPECT_TRUE(throws_error([&] { solver.compute(poisson_matrix(3, 3), ids.head(8)); },
    ErrorCode::SizeMismatch, { "row_ids has 8 entries" }));

  SparseMatrix asymmetric = poisson_matrix(3, 3);
  asymmetric.coeffRef(1, 2) = 0.5;
  EXPECT_TRUE(throws_error([&] { solver.compute(asymmetric); }, ErrorCode::InvalidArgument,
    { "not symmetric", "(1, 2)", "(2, 1)" }));

  // A zero diagonal (a vertex no element references) is caught before factoring.
  SparseMatrix zero_row = poisson_matrix(3, 3);
  zero_row.prune([](const Index& i, const Index& j, const double&) { return i != 4 && j != 4; });
  EXPECT_TRUE(throws_error([&] { solver.compute(zero_row); }, ErrorCode::InvalidArgument,
    { "not positive definite", "(4, 4) is 0" }));

  solver.compute(poisson_matrix(3, 3));
  EXPECT_TRUE(throws_error([&] { solver.solve(Eigen::MatrixXd::Ones(8, 1)); },
    ErrorCode::SizeMismatch, { "8 rows", "9 by 9" }));
  Eigen::MatrixXd B = Eigen::MatrixXd::Ones(9, 2);
  B(3, 1) = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(throws_error([&] { solver.solve(B); }, ErrorCode::NonFinite));
}

TEST(SparseCholesky, RoundingLevelAsymmetryIsAccepted)
{
  // Products like K M^-1 K are symmetric only up to rounding.
  SparseMatrix A = poisson_matrix(4, 4);
  A.coeffRef(1, 0) *= 1.0 + 1e-14;
  EXPECT_NO_THROW(SparseCholesky().compute(A));
}

} // namespace
