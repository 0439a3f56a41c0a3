// Tests for core/solvers/sparse_cholesky.h: a 2D Poisson-type problem and a 3D bi-Laplacian with every
// backend, agreement between them, badly scaled SPD matrices, given orderings, the definiteness
// test, the error paths and the thread-count independence of the supernodal factor.
//
// Tolerances. A = L + I with L the 5-point graph Laplacian of a grid has eigenvalues in
// [1, 9], so cond(A) <= 9: a backward-stable Cholesky solve gives a relative residual of a few
// eps times the fill (~ 1e-15) and a relative error below cond(A) times that. 1e-12 leaves a
// margin of 100x on both.
#include "core/common/error.h"
#include "core/detail/simd.h"
#include "core/solvers/sparse_cholesky.h"
#include "error_matchers.h"

#include <Eigen/Dense>
#include <gtest/gtest.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include <algorithm>
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
  switch (param_info.param)
  {
    case Backend::Eigen: return "Eigen";
    case Backend::Cholmod: return "Cholmod";
    case Backend::Supernodal: return "Supernodal";
    default: return "Automatic";
  }
}

TEST(SparseCholesky, BackendNames)
{
  EXPECT_STREQ(to_string(Backend::Automatic), "automatic");
  EXPECT_STREQ(to_string(Backend::Cholmod), "cholmod");
  EXPECT_STREQ(to_string(Backend::Eigen), "eigen");
  EXPECT_STREQ(to_string(Backend::Supernodal), "supernodal");
}

INSTANTIATE_TEST_SUITE_P(Backends, SparseCholeskyBackend,
  ::testing::Values(Backend::Eigen, Backend::Cholmod, Backend::Supernodal), backend_name);

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
  EXPECT_EQ(SparseCholesky(Backend::Supernodal).backend(), Backend::Supernodal);
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

/// (L + I)^2 for the 7-point graph Laplacian L of an n^3 grid: a bi-Laplacian-like stencil (two
/// rings) whose factor has dense separator blocks, i.e. large supernodes; SPD with eigenvalues
/// in [1, 169].
SparseMatrix grid_bilaplacian_3d(int n)
{
  std::vector<Eigen::Triplet<double>> triplets;
  auto id = [n](int i, int j, int k) { return (k * n + j) * n + i; };
  const int N = n * n * n;
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
      {
        const int a = id(i, j, k);
        triplets.emplace_back(a, a, 1.0);
        const int neighbours[3][3] = { { i + 1, j, k }, { i, j + 1, k }, { i, j, k + 1 } };
        for (const auto& m : neighbours)
          if (m[0] < n && m[1] < n && m[2] < n)
          {
            const int b = id(m[0], m[1], m[2]);
            triplets.emplace_back(a, b, -1.0);
            triplets.emplace_back(b, a, -1.0);
            triplets.emplace_back(a, a, 1.0);
            triplets.emplace_back(b, b, 1.0);
          }
      }
  SparseMatrix L(N, N);
  L.setFromTriplets(triplets.begin(), triplets.end());
  return SparseMatrix(L * L);
}

TEST_P(SparseCholeskyBackend, BiLaplacianWithLargeSupernodes)
{
  // 11^3 = 1331 unknowns: the factor's top separators are dense blocks of ~200 columns, so the
  // supernodal backend goes through its blocked GEMM / LLT / TRSM paths. Against a dense LLT
  // (independent code): relative error <= cond (169) * ~1e-15.
  const SparseMatrix A = grid_bilaplacian_3d(11);
  const Eigen::MatrixXd B = random_matrix(A.rows(), 3, 6);
  SparseCholesky solver(GetParam());
  solver.compute(A);
  const Eigen::MatrixXd X = solver.solve(B);
  EXPECT_LT(relative_residual(A, X, B), 1e-12);
  const Eigen::MatrixXd reference = Eigen::MatrixXd(A).llt().solve(B);
  EXPECT_LT((X - reference).cwiseAbs().maxCoeff() / reference.cwiseAbs().maxCoeff(), 1e-11);
  // One column at a time gives the same (the multi-column solve is the same algorithm).
  const Eigen::MatrixXd x1 = solver.solve(B.col(1));
  EXPECT_LT((x1 - X.col(1)).cwiseAbs().maxCoeff() / X.col(1).cwiseAbs().maxCoeff(), 1e-13);
  EXPECT_GT(solver.factor_entries(), double(A.nonZeros()) / 2);
  if (GetParam() != Backend::Eigen)
  {
    EXPECT_GT(solver.factor_flops(), solver.factor_entries());
  }
}

TEST_P(SparseCholeskyBackend, GivenOrderingAndTrustedInputGiveTheSameSolution)
{
  const SparseMatrix A = grid_bilaplacian_3d(7);
  const Index n = A.rows();
  const Eigen::MatrixXd B = random_matrix(n, 2, 7);
  SparseCholesky reference_solver(GetParam());
  reference_solver.compute(A);
  const Eigen::MatrixXd reference = reference_solver.solve(B);
  // Identity, reversed and random orderings (the last two are poor: more fill, same answer).
  std::vector<Eigen::VectorXi> orderings(3, Eigen::VectorXi::LinSpaced(n, 0, int(n) - 1));
  orderings[1].reverseInPlace();
  std::mt19937 rng(8);
  std::shuffle(orderings[2].data(), orderings[2].data() + n, rng);
  for (const Eigen::VectorXi& ordering : orderings)
    for (bool trusted : { false, true })
    {
      SparseCholeskySettings settings;
      settings.ordering = ordering;
      settings.trusted = trusted;
      SparseCholesky solver(GetParam());
      solver.compute(A, {}, settings);
      const Eigen::MatrixXd X = solver.solve(B);
      EXPECT_LT((X - reference).cwiseAbs().maxCoeff() / reference.cwiseAbs().maxCoeff(), 1e-12)
        << "trusted " << trusted << ", ordering starts " << ordering(0);
      EXPECT_GT(solver.min_pivot(), 0.0);
    }
  // The backend's own ordering with trusted input is the same computation as without.
  SparseCholeskySettings trusted;
  trusted.trusted = true;
  SparseCholesky solver(GetParam());
  solver.compute(A, {}, trusted);
  EXPECT_EQ(solver.solve(B), reference);
}

TEST_P(SparseCholeskyBackend, GivenOrderingStillDetectsIndefiniteness)
{
  SparseMatrix A = poisson_matrix(6, 6);
  A.coeffRef(10, 11) = A.coeffRef(11, 10) = 20.0;
  SparseCholeskySettings settings;
  settings.ordering = Eigen::VectorXi::LinSpaced(36, 35, 0);
  settings.trusted = true;
  SparseCholesky solver(GetParam());
  EXPECT_TRUE(throws_error([&] { solver.compute(A, {}, settings); }, ErrorCode::InvalidArgument,
    { "not positive definite" }));
  EXPECT_FALSE(solver.computed());
}

TEST_P(SparseCholeskyBackend, PrincipalSubmatrixWithoutFormingIt)
{
  // M = A(rows, rows) for every third row of a 3D bi-Laplacian, rows listed in a scrambled
  // order: the same solution as factoring the formed M, with and without a given ordering,
  // trusted (the supernodal backend then reads M from A) or not.
  const SparseMatrix A = grid_bilaplacian_3d(9);
  std::vector<int> list;
  for (int i = 0; i < A.rows(); ++i)
    if (i % 3 != 1)
      list.push_back(i);
  std::mt19937 rng(10);
  std::shuffle(list.begin(), list.end(), rng);
  const Eigen::VectorXi rows = Eigen::Map<const Eigen::VectorXi>(list.data(), Index(list.size()));
  const Index m = rows.size();
  SparseMatrix M(m, m);
  {
    std::vector<Eigen::Triplet<double>> triplets;
    const Eigen::MatrixXd dense(A);
    for (Index i = 0; i < m; ++i)
      for (Index j = 0; j < m; ++j)
        if (dense(rows(i), rows(j)) != 0.0)
          triplets.emplace_back(int(i), int(j), dense(rows(i), rows(j)));
    M.setFromTriplets(triplets.begin(), triplets.end());
  }
  const Eigen::MatrixXd B = random_matrix(m, 2, 11);
  const Eigen::MatrixXd reference = Eigen::MatrixXd(M).llt().solve(B);
  Eigen::VectorXi reversed = Eigen::VectorXi::LinSpaced(m, int(m) - 1, 0);
  for (bool trusted : { false, true })
    for (bool ordered : { false, true })
    {
      SparseCholeskySettings settings;
      settings.trusted = trusted;
      if (ordered)
        settings.ordering = reversed;
      SparseCholesky solver(GetParam());
      solver.compute_principal(A, rows, settings);
      EXPECT_EQ(solver.rows(), m);
      const Eigen::MatrixXd X = solver.solve(B);
      EXPECT_LT((X - reference).cwiseAbs().maxCoeff() / reference.cwiseAbs().maxCoeff(), 1e-11)
        << "trusted " << trusted << ", ordered " << ordered;
      EXPECT_GT(solver.min_pivot(), 0.0);
    }
  // Errors name A's rows.
  SparseMatrix bad = A;
  bad.coeffRef(rows(5), rows(5)) = -1.0;
  SparseCholeskySettings trusted;
  trusted.trusted = true;
  SparseCholesky solver(GetParam());
  EXPECT_TRUE(throws_error([&] { solver.compute_principal(bad, rows, trusted); },
    ErrorCode::InvalidArgument,
    { "not positive definite", "(" + std::to_string(rows(5)) + ", " + std::to_string(rows(5)) + ")" }));
  EXPECT_TRUE(throws_error([&] { solver.compute_principal(A, Eigen::VectorXi::Constant(2, 3), trusted); },
    ErrorCode::InvalidArgument, { "row 3 is listed twice" }));
  EXPECT_TRUE(throws_error([&] { solver.compute_principal(A, Eigen::VectorXi::Constant(1, -1), trusted); },
    ErrorCode::InvalidArgument, { "outside" }));
  EXPECT_TRUE(throws_error([&] { solver.compute_principal(A, Eigen::VectorXi(), trusted); },
    ErrorCode::EmptyInput));
}

TEST(SparseCholesky, RefactoringInPlaceReusesStorageButNotACopysFactor)
{
  // An active-set solver refactors one SparseCholesky on growing and shrinking principal
  // submatrices: each factorization (in the storage of the one it replaces when that is large
  // enough, or new storage) solves its own submatrix, and a copy taken before a refactoring
  // keeps solving the submatrix it was made for.
  const SparseMatrix A = grid_bilaplacian_3d(8);
  const Eigen::MatrixXd dense(A);
  auto principal = [&](int count) {
    return Eigen::VectorXi(Eigen::VectorXi::LinSpaced(count, 0, count - 1));
  };
  auto check = [&](const SparseCholesky& solver, const Eigen::VectorXi& rows, const char* what) {
    const Index m = rows.size();
    Eigen::MatrixXd M(m, m);
    for (Index i = 0; i < m; ++i)
      for (Index j = 0; j < m; ++j)
        M(i, j) = dense(rows(i), rows(j));
    const Eigen::MatrixXd B = random_matrix(m, 1, 21);
    const Eigen::MatrixXd reference = M.llt().solve(B);
    ASSERT_EQ(solver.rows(), m) << what;
    EXPECT_LT((solver.solve(B) - reference).cwiseAbs().maxCoeff() / reference.cwiseAbs().maxCoeff(),
      1e-11)
      << what;
  };
  SparseCholeskySettings settings;
  settings.trusted = true;
  SparseCholesky solver(SparseCholesky::Backend::Supernodal);
  solver.compute_principal(A, principal(200), settings);
  check(solver, principal(200), "first");
  solver.compute_principal(A, principal(400), settings); // larger: new storage, with room
  check(solver, principal(400), "grown");
  solver.compute_principal(A, principal(420), settings); // a little larger: in that room
  check(solver, principal(420), "grown a little");
  const SparseCholesky copy = solver; // shares the factor
  solver.compute_principal(A, principal(300), settings); // smaller, while a copy shares it
  check(solver, principal(300), "shrunk");
  check(copy, principal(420), "the copy after its original was refactored");
  solver.compute_principal(A, principal(150), settings);
  check(solver, principal(150), "shrunk again");
  check(copy, principal(420), "the copy, later");
}

TEST(SparseCholesky, RowAdditionsAndDeletionsMatchARefactorization)
{
  if (!SparseCholesky::cholmod_available())
    GTEST_SKIP() << "BaryLab was built without CHOLMOD";
  // Rounds of random row changes to M = A(rows, rows), A a 3D bi-Laplacian; after each round
  // the modified factor solves like a fresh factorization of the new submatrix.
  const SparseMatrix A = grid_bilaplacian_3d(8);
  const int n = int(A.rows());
  std::mt19937 rng(12);
  std::vector<char> inside(std::size_t(n), 0);
  std::vector<int> list;
  for (int i = 0; i < n; ++i)
    if (rng() % 3 != 0)
    {
      inside[std::size_t(i)] = 1;
      list.push_back(i);
    }
  SparseCholeskySettings settings;
  settings.trusted = true;
  SparseCholesky solver(Backend::Supernodal);
  solver.compute_principal(A, Eigen::Map<const Eigen::VectorXi>(list.data(), Index(list.size())), settings);
  ASSERT_TRUE(solver.modifiable());
  EXPECT_EQ(solver.principal_rows(), list);
  const SparseCholesky before = solver; // keeps its factorization (copy on write)
  const Eigen::VectorXd b_before = random_matrix(Index(list.size()), 1, 13).col(0);
  const Eigen::VectorXd x_before = before.solve(b_before);
  int changed = 0;
  for (int round = 0; round < 12; ++round)
  {
    std::vector<int> add, remove;
    for (int k = 0; k < 1 + round * 3; ++k)
    {
      const int i = int(rng() % unsigned(n));
      if (std::find(add.begin(), add.end(), i) != add.end() ||
        std::find(remove.begin(), remove.end(), i) != remove.end())
        continue;
      (inside[std::size_t(i)] ? remove : add).push_back(i);
    }
    solver.modify_principal(A, Eigen::Map<const Eigen::VectorXi>(add.data(), Index(add.size())),
      Eigen::Map<const Eigen::VectorXi>(remove.data(), Index(remove.size())));
    changed += int(add.size() + remove.size());
    for (int i : remove)
      inside[std::size_t(i)] = 0;
    for (int i : add)
      inside[std::size_t(i)] = 1;
    // The documented row order: the remaining rows in their order, then the added ones.
    std::vector<int> expected;
    for (int i : list)
      if (inside[std::size_t(i)] && std::find(add.begin(), add.end(), i) == add.end())
        expected.push_back(i);
    expected.insert(expected.end(), add.begin(), add.end());
    ASSERT_EQ(solver.principal_rows(), expected) << "round " << round;
    list = expected;
    const Eigen::VectorXi rows = Eigen::Map<const Eigen::VectorXi>(list.data(), Index(list.size()));
    SparseCholesky fresh(Backend::Supernodal);
    fresh.compute_principal(A, rows, settings);
    const Eigen::MatrixXd B = random_matrix(rows.size(), 2, unsigned(14 + round));
    const Eigen::MatrixXd X = solver.solve(B), reference = fresh.solve(B);
    ASSERT_EQ(X.rows(), rows.size());
    EXPECT_LT((X - reference).cwiseAbs().maxCoeff() / reference.cwiseAbs().maxCoeff(), 1e-11)
      << "round " << round << " after " << changed << " changed rows";
  }
  EXPECT_EQ(before.solve(b_before), x_before);
  // Errors.
  const Eigen::VectorXi one = Eigen::VectorXi::Constant(1, list.front());
  EXPECT_TRUE(throws_error([&] { solver.modify_principal(A, one, Eigen::VectorXi()); },
    ErrorCode::InvalidArgument, { "already a row" }));
  int outside = 0;
  while (inside[std::size_t(outside)])
    ++outside;
  EXPECT_TRUE(throws_error(
    [&] { solver.modify_principal(A, Eigen::VectorXi(), Eigen::VectorXi::Constant(1, outside)); },
    ErrorCode::InvalidArgument, { "is not a row" }));
  EXPECT_TRUE(throws_error([&] { solver.modify_principal(poisson_matrix(3, 3), one, one); },
    ErrorCode::SizeMismatch));
  SparseCholesky eigen(Backend::Eigen);
  eigen.compute_principal(A, Eigen::VectorXi::LinSpaced(10, 0, 9), settings);
  EXPECT_FALSE(eigen.modifiable());
  EXPECT_TRUE(throws_error([&] { eigen.modify_principal(A, one, Eigen::VectorXi()); },
    ErrorCode::InvalidArgument, { "compute_principal" }));
  // A row whose addition makes the matrix indefinite.
  SparseMatrix bad = A;
  bad.coeffRef(outside, outside) = 1e-3;
  SparseCholesky small(Backend::Supernodal);
  std::vector<int> neighbours;
  for (SparseMatrix::InnerIterator it(A, outside); it; ++it)
    if (it.row() != outside)
      neighbours.push_back(int(it.row()));
  small.compute_principal(bad, Eigen::Map<const Eigen::VectorXi>(neighbours.data(), Index(neighbours.size())), settings);
  EXPECT_TRUE(throws_error(
    [&] { small.modify_principal(bad, Eigen::VectorXi::Constant(1, outside), Eigen::VectorXi()); },
    ErrorCode::InvalidArgument, { "not positive definite" }));
}

TEST(SparseCholesky, InvalidOrderings)
{
  const SparseMatrix A = poisson_matrix(3, 3);
  SparseCholesky solver;
  SparseCholeskySettings settings;
  settings.ordering = Eigen::VectorXi::LinSpaced(8, 0, 7);
  EXPECT_TRUE(throws_error([&] { solver.compute(A, {}, settings); }, ErrorCode::SizeMismatch,
    { "ordering has 8 entries", "size 9" }));
  settings.ordering = Eigen::VectorXi::LinSpaced(9, 0, 8);
  settings.ordering(4) = 2;
  EXPECT_TRUE(throws_error([&] { solver.compute(A, {}, settings); }, ErrorCode::InvalidArgument,
    { "not a permutation", "entry 4 is 2 again" }));
  settings.ordering(4) = 9;
  EXPECT_TRUE(throws_error([&] { solver.compute(A, {}, settings); }, ErrorCode::InvalidArgument,
    { "entry 4 is 9, out of range" }));
}

TEST(SparseCholesky, SupernodalFactorDoesNotDependOnTheThreadCount)
{
  // Eigen parallelizes large matrix products when called outside a parallel region (or in a
  // one-thread one), with blocking that depends on the thread count; the supernodal backend
  // keeps its products single-threaded so the factor is bitwise the same everywhere.
  const SparseMatrix A = grid_bilaplacian_3d(12);
  const Eigen::MatrixXd B = random_matrix(A.rows(), 5, 9);
  auto solve = [&] {
    SparseCholesky solver(Backend::Supernodal);
    solver.compute(A);
    return Eigen::MatrixXd(solver.solve(B));
  };
  const Eigen::MatrixXd outside = solve();
  Eigen::MatrixXd one_thread, two_threads[2];
#pragma omp parallel num_threads(1)
  one_thread = solve();
#pragma omp parallel num_threads(2)
  {
#ifdef _OPENMP
    const int t = omp_get_thread_num();
#else
    const int t = 0;
#endif
    two_threads[t] = solve();
  }
  EXPECT_EQ(one_thread, outside);
  EXPECT_EQ(two_threads[0], outside);
  if (two_threads[1].size() != 0)
  {
    EXPECT_EQ(two_threads[1], outside);
  }
}

TEST(SparseCholesky, SupernodalKernelsOnEitherInstructionSetAgree)
{
  // The supernodal backend's dense kernels (descendant updates, the panels' LL^T and triangular
  // solves, the solve of one right-hand side) run on AVX2 + FMA where the CPU has them and on Eigen's portable kernels otherwise:
  // the same factorization up to rounding. Sizes 11^3 (blocks of ~200 columns) and 6^3 with a
  // random ordering (odd block shapes: the masked row tails, 1-3 column tails), each against a
  // dense LLT: relative error <= cond (169) * ~1e-15, with margin.
  struct LevelScope
  {
    ~LevelScope() { detail::set_simd_level(detail::supported_simd_level()); }
  } restore;
  for (int size : { 11, 6 })
  {
    const SparseMatrix A = grid_bilaplacian_3d(size);
    const Index n = A.rows();
    const Eigen::MatrixXd B = random_matrix(n, 2, 21);
    const Eigen::MatrixXd reference = Eigen::MatrixXd(A).llt().solve(B);
    SparseCholeskySettings settings;
    if (size == 6)
    {
      settings.ordering = Eigen::VectorXi::LinSpaced(n, 0, int(n) - 1);
      std::mt19937 rng(5);
      std::shuffle(settings.ordering.data(), settings.ordering.data() + n, rng);
    }
    std::vector<Eigen::MatrixXd> solutions;
    for (detail::SimdLevel level : { detail::SimdLevel::Portable, detail::SimdLevel::AVX2 })
    {
      if (detail::set_simd_level(level) != level)
        continue; // no AVX2 here: the portable path alone
      SparseCholesky solver(Backend::Supernodal);
      solver.compute(A, {}, settings);
      solutions.push_back(solver.solve(B));
      // One right-hand side has a kernel of its own on AVX2.
      const Eigen::MatrixXd x1 = solver.solve(B.col(1));
      EXPECT_LT((x1 - reference.col(1)).cwiseAbs().maxCoeff() / reference.col(1).cwiseAbs().maxCoeff(),
        1e-11)
        << size;
      EXPECT_LT(relative_residual(A, solutions.back(), B), 1e-12) << size;
      EXPECT_LT((solutions.back() - reference).cwiseAbs().maxCoeff() / reference.cwiseAbs().maxCoeff(),
        1e-11)
        << size;
    }
    if (solutions.size() == 2)
    {
      EXPECT_LT((solutions[0] - solutions[1]).cwiseAbs().maxCoeff() / reference.cwiseAbs().maxCoeff(),
        1e-12)
        << size;
    }
  }
  // A pivot that fails inside a large panel is reported at its row on either path: A's last
  // row (eliminated last by the natural ordering, deep in the root supernode) lowered by 1.5
  // times its Schur complement, so only the last pivot is negative.
  SparseMatrix A = grid_bilaplacian_3d(8);
  const Index n = A.rows();
  const Eigen::VectorXd last = Eigen::MatrixXd(A).llt().solve(Eigen::VectorXd::Unit(n, n - 1));
  A.coeffRef(n - 1, n - 1) -= 1.5 / last(n - 1);
  SparseCholeskySettings natural;
  natural.ordering = Eigen::VectorXi::LinSpaced(n, 0, int(n) - 1);
  for (detail::SimdLevel level : { detail::SimdLevel::Portable, detail::SimdLevel::AVX2 })
  {
    if (detail::set_simd_level(level) != level)
      continue;
    SparseCholesky solver(Backend::Supernodal);
    EXPECT_TRUE(throws_error([&] { solver.compute(A, {}, natural); }, ErrorCode::InvalidArgument,
      { "not positive definite", "failed at row " + std::to_string(n - 1) }))
      << static_cast<int>(level);
  }
}

TEST(SparseCholesky, SupernodalAvx512KernelsMatchAvx2BitForBit)
{
  // Where the CPU has AVX-512, the descendant updates and the panels' products run on 16-row
  // panels of 512-bit vectors (up to 8 columns) instead of 8-row panels of 256-bit ones: every
  // entry is still summed over the same columns in the same order with the same FMAs, so the
  // factor and the solutions must be identical, not merely close. Sizes 11^3 and 7^3 with a
  // random ordering (masked row tails of 1-15 rows, 1-7 column tails) and 9^3 natural order.
  const bool before = detail::avx512_enabled();
  if (detail::set_simd_level(detail::SimdLevel::AVX2) != detail::SimdLevel::AVX2 ||
    !detail::set_avx512_enabled(true))
  {
    detail::set_simd_level(detail::supported_simd_level());
    detail::set_avx512_enabled(before);
    GTEST_SKIP() << "no AVX-512 on this CPU";
  }
  struct Restore
  {
    bool avx512;
    ~Restore()
    {
      detail::set_simd_level(detail::supported_simd_level());
      detail::set_avx512_enabled(avx512);
    }
  } restore{ before };
  for (int size : { 11, 7, 9 })
  {
    const SparseMatrix A = grid_bilaplacian_3d(size);
    const Index n = A.rows();
    const Eigen::MatrixXd B = random_matrix(n, 3, 31);
    SparseCholeskySettings settings;
    settings.ordering = Eigen::VectorXi::LinSpaced(n, 0, int(n) - 1);
    if (size == 7)
    {
      std::mt19937 rng(9);
      std::shuffle(settings.ordering.data(), settings.ordering.data() + n, rng);
    }
    else if (size == 11)
      settings.ordering = Eigen::VectorXi();
    std::vector<Eigen::MatrixXd> solutions;
    for (bool wide : { false, true })
    {
      ASSERT_EQ(detail::set_avx512_enabled(wide), wide);
      SparseCholesky solver(Backend::Supernodal);
      solver.compute(A, {}, settings);
      solutions.push_back(solver.solve(B));
      EXPECT_LT(relative_residual(A, solutions.back(), B), 1e-12) << size;
    }
    EXPECT_TRUE((solutions[0].array() == solutions[1].array()).all())
      << size << ": largest difference " << (solutions[0] - solutions[1]).cwiseAbs().maxCoeff();
  }
}

TEST(SparseCholesky, RoundingLevelAsymmetryIsAccepted)
{
  // Products like K M^-1 K are symmetric only up to rounding.
  SparseMatrix A = poisson_matrix(4, 4);
  A.coeffRef(1, 0) *= 1.0 + 1e-14;
  EXPECT_NO_THROW(SparseCholesky().compute(A));
  // Also with an entry on one side only (a rounding-level value the other side lost): the
  // supernodal backend, which reads both triangles, factors (A + A^T) / 2.
  A.coeffRef(0, 5) = 1e-17;
  for (Backend backend : { Backend::Eigen, Backend::Supernodal })
  {
    SparseCholesky solver(backend);
    ASSERT_NO_THROW(solver.compute(A));
    const Eigen::VectorXd b = Eigen::VectorXd::Ones(16);
    EXPECT_LT((A * solver.solve(b) - b).norm(), 1e-12);
  }
}

} // namespace
