// Tests for core/detail/row_cholesky.h: LBC's sparse Cholesky solved for row-major blocks.
#include "core/detail/row_cholesky.h"
#include "core/common/error.h"
#include "core/detail/simd.h"
#include "error_matchers.h"

#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <vector>

namespace
{
using namespace bary;
using bary::test::throws_error;

/// The 5-point Laplacian of a side x side grid plus a shift: sparse, symmetric positive definite.
Eigen::SparseMatrix<double> grid_matrix(int side, double shift)
{
  const int n = side * side;
  std::vector<Eigen::Triplet<double>> t;
  for (int j = 0; j < side; ++j)
    for (int i = 0; i < side; ++i)
    {
      const int v = j * side + i;
      t.emplace_back(v, v, 4.0 + shift);
      if (i + 1 < side)
      {
        t.emplace_back(v, v + 1, -1.0);
        t.emplace_back(v + 1, v, -1.0);
      }
      if (j + 1 < side)
      {
        t.emplace_back(v, v + side, -1.0);
        t.emplace_back(v + side, v, -1.0);
      }
    }
  Eigen::SparseMatrix<double> A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

DenseWeights random_block(Index rows, Index cols, unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  DenseWeights B(rows, cols);
  for (Index i = 0; i < B.size(); ++i)
    B.data()[i] = u(rng);
  return B;
}

TEST(RowCholesky, SolvesLikeADenseCholesky)
{
  const Eigen::SparseMatrix<double> A = grid_matrix(12, 0.1);
  detail::RowCholesky chol;
  chol.factor(A);
  EXPECT_EQ(chol.rows(), 144);
  EXPECT_GE(chol.nonzeros(), 144);
  const Eigen::MatrixXd dense = Eigen::MatrixXd(A);
  for (const Index k : { Index(1), Index(3), Index(4), Index(5), Index(6), Index(8), Index(11) })
  {
    const DenseWeights B = random_block(144, k, 7u + static_cast<unsigned>(k));
    DenseWeights X = B;
    chol.solve(X, 2);
    const Eigen::MatrixXd expected = dense.llt().solve(Eigen::MatrixXd(B));
    EXPECT_LE((Eigen::MatrixXd(X) - expected).cwiseAbs().maxCoeff(), 1e-12) << k << " columns";
  }
}

TEST(RowCholesky, ResultsDoNotDependOnTheThreads)
{
  const Eigen::SparseMatrix<double> A = grid_matrix(10, 0.5);
  detail::RowCholesky chol;
  chol.factor(A);
  const DenseWeights B = random_block(100, 7, 3u);
  DenseWeights one = B, three = B;
  chol.solve(one, 1);
  chol.solve(three, 3);
  EXPECT_EQ(std::memcmp(one.data(), three.data(), sizeof(double) * one.size()), 0);
  DenseWeights empty(100, 0);
  chol.solve(empty, 2); // no columns: nothing to do
}

TEST(RowCholesky, NotPositiveDefiniteIsAnError)
{
  EXPECT_TRUE(throws_error([] { detail::RowCholesky().factor(grid_matrix(4, -8.0)); },
    ErrorCode::InvalidArgument, { "not positive definite" }));
}
// The AVX2 solves (four doubles a vector, no FMA) run the portable build's operations: the same
// bits, for every column split (fixed sizes and the general loop).
TEST(RowCholesky, AVX2AndPortableSolvesAreBitwiseEqual)
{
  if (detail::supported_simd_level() != detail::SimdLevel::AVX2)
    GTEST_SKIP() << "this CPU has no AVX2 and FMA";
  const Eigen::SparseMatrix<double> A = grid_matrix(11, 0.3);
  detail::RowCholesky chol;
  chol.factor(A);
  for (const Index k : { Index(3), Index(4), Index(6), Index(8), Index(16), Index(34), Index(37) })
    for (const int threads : { 1, 2 })
    {
      const DenseWeights B = random_block(121, k, 40u + static_cast<unsigned>(k));
      DenseWeights portable = B, avx2 = B;
      detail::set_simd_level(detail::SimdLevel::Portable);
      chol.solve(portable, threads);
      detail::set_simd_level(detail::SimdLevel::AVX2);
      chol.solve(avx2, threads);
      EXPECT_EQ(std::memcmp(portable.data(), avx2.data(), sizeof(double) * B.size()), 0)
        << k << " columns, " << threads << " threads";
      EXPECT_FALSE((Eigen::MatrixXd(portable) - Eigen::MatrixXd(B)).isZero()) << "nothing solved";
    }
  detail::set_simd_level(detail::supported_simd_level());
}

} // namespace
