// Tests for core/deformation/cage_deformation.h: deform_points (dense and sparse) and sparsify_weights.
#include "cage_catalogue.h"
#include "core/deformation/cage_deformation.h"
#include "core/common/error.h"
#include "core/coordinates/mean_value_coordinates.h"
#include "error_matchers.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace
{
using namespace bary;
using bary::test::throws_error;

// Deformation adds W * C on top of the weights' own rounding: with weights satisfying
// reproduction to 1e-12 diam * sum|w| (see mean_value_coordinates_test.cpp) and an affine map
// of norm ~2, 1e-11 * diam is a safe bound for points 1e-3 diam from the cage.
constexpr double kDeformTol = 1e-11;

void expect_rows_near(const Points& a, const Points& b, double tol, const std::string& what)
{
  ASSERT_EQ(a.rows(), b.rows()) << what;
  ASSERT_EQ(a.cols(), b.cols()) << what;
  for (Index p = 0; p < a.rows(); ++p)
    EXPECT_LE((a.row(p) - b.row(p)).norm(), tol) << what << ", point " << p;
}

TEST(DeformPoints, IdentityDeformationReproducesThePoints)
{
  auto check = [](const test::CatalogueCage& entry) {
    const Points P = test::sample_inside(entry.cage, 100, 1e-3, 21);
    const DenseWeights W = MeanValueCoordinates(entry.cage).evaluate(P).W;
    expect_rows_near(
      deform_points(W, entry.cage.V), P, kDeformTol * entry.cage.diameter(), entry.name);
  };
  for (const auto& entry : test::builtin_cages_2d())
    check(entry);
  for (const auto& entry : test::cages_3d())
    check(entry);
}

TEST(DeformPoints, AffineMapOfTheCageMovesInsidePointsAffinely2D)
{
  Eigen::Matrix2d A;
  A << 1.3, -0.4, 0.7, 0.9; // rotation, shear and anisotropic scaling
  const Eigen::RowVector2d b(-2.0, 5.0);
  for (const auto& entry : test::builtin_cages_2d())
  {
    const Points P = test::sample_inside(entry.cage, 100, 1e-3, 22);
    const DenseWeights W = MeanValueCoordinates(entry.cage).evaluate(P).W;
    const Eigen::MatrixXd C = (entry.cage.V * A.transpose()).rowwise() + b;
    const Points expected = (P * A.transpose()).rowwise() + b;
    expect_rows_near(
      deform_points(W, C), expected, kDeformTol * 2.0 * entry.cage.diameter(), entry.name);
  }
}

TEST(DeformPoints, AffineMapOfTheCageMovesInsidePointsAffinely3D)
{
  Eigen::Matrix3d A;
  A << 0.8, -0.5, 0.1, 0.4, 1.2, -0.3, 0.2, 0.3, 1.5;
  const Eigen::RowVector3d b(1.0, -3.0, 0.5);
  for (const auto& entry : test::cages_3d())
  {
    const Points P = test::sample_inside(entry.cage, 100, 1e-3, 23);
    const DenseWeights W = MeanValueCoordinates(entry.cage).evaluate(P).W;
    const Eigen::MatrixXd C = (entry.cage.V * A.transpose()).rowwise() + b;
    const Points expected = (P * A.transpose()).rowwise() + b;
    expect_rows_near(
      deform_points(W, C), expected, kDeformTol * 2.0 * entry.cage.diameter(), entry.name);
  }
}

TEST(DeformPoints, HandComputedProduct)
{
  DenseWeights W(2, 3);
  W << 0.5, 0.25, 0.25, //
    0.0, 1.0, 0.0;
  Eigen::MatrixXd C(3, 2);
  C << 0, 0, 4, 0, 0, 8;
  Points expected(2, 2);
  expected << 1, 2, //   0.5 * (0,0) + 0.25 * (4,0) + 0.25 * (0,8)
    4, 0;
  EXPECT_EQ(deform_points(W, C), expected);
}

TEST(DeformPoints, SparseAndDenseAgree)
{
  // Dyadic weights and integer coordinates: every product and sum is exact, so the results
  // must be identical whatever the summation order.
  DenseWeights W(3, 4);
  W << 0.5, 0.25, 0.0, 0.25, //
    0.0, 0.0, 1.0, 0.0,      //
    0.125, 0.375, 0.25, 0.25;
  Eigen::MatrixXd C(4, 3);
  C << 0, 0, 0, 8, 0, 0, 0, 8, 0, 0, 0, 8;
  const SparseWeights S = W.sparseView();
  EXPECT_EQ(deform_points(S, C), deform_points(W, C));

  // And on real mean value weights, to rounding.
  const Cage cage = test::u_box();
  const Points P = test::sample_inside(cage, 50, 1e-3, 24);
  const DenseWeights M = MeanValueCoordinates(cage).evaluate(P).W;
  const SparseWeights Ms = sparsify_weights(M, -std::numeric_limits<double>::infinity(), false);
  ASSERT_EQ(Ms.nonZeros(), M.size() - (M.array() == 0.0).count());
  expect_rows_near(deform_points(Ms, cage.V), deform_points(M, cage.V), 1e-14 * cage.diameter(),
    "sparse vs dense");
}

TEST(DeformPoints, ErrorPaths)
{
  const DenseWeights W = DenseWeights::Constant(2, 3, 1.0 / 3);
  const SparseWeights S = W.sparseView();
  const Eigen::MatrixXd C4 = Eigen::MatrixXd::Zero(4, 2);
  EXPECT_TRUE(throws_error([&] { deform_points(W, C4); }, ErrorCode::SizeMismatch,
    { "3 columns", "4 deformed control points" }));
  EXPECT_TRUE(throws_error([&] { deform_points(S, C4); }, ErrorCode::SizeMismatch,
    { "3 columns", "4 deformed control points" }));

  Eigen::MatrixXd C = Eigen::MatrixXd::Zero(3, 2);
  C(1, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(throws_error([&] { deform_points(W, C); }, ErrorCode::NonFinite));
  EXPECT_TRUE(throws_error([&] { deform_points(S, C); }, ErrorCode::NonFinite));
  C(1, 1) = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(throws_error([&] { deform_points(W, C); }, ErrorCode::NonFinite));

  const Eigen::MatrixXd empty(0, 2);
  EXPECT_TRUE(
    throws_error([&] { deform_points(DenseWeights(2, 0), empty); }, ErrorCode::EmptyInput));
  EXPECT_TRUE(
    throws_error([&] { deform_points(SparseWeights(2, 0), empty); }, ErrorCode::EmptyInput));
}

TEST(DeformPoints, NoPointsGiveNoPoints)
{
  const Points out = deform_points(DenseWeights(0, 3), Eigen::MatrixXd::Ones(3, 2));
  EXPECT_EQ(out.rows(), 0);
  EXPECT_EQ(out.cols(), 2);
}

// --- sparsify_weights ---------------------------------------------------------------------------

DenseWeights sample_weights()
{
  DenseWeights W(4, 4);
  W << 0.5, 0.3, 0.2, 0.0,  //
    0.6, -0.1, 0.5, 0.0,    //
    0.001, 0.002, 0.0, 0.0, //
    0.25, 0.25, 0.25, 0.25;
  return W;
}

TEST(SparsifyWeights, ThresholdIsStrict)
{
  Index empty = -1;
  const SparseWeights S = sparsify_weights(sample_weights(), 0.25, false, &empty);
  // Kept (> 0.25): row 0: 0.5, 0.3; row 1: 0.6, 0.5; row 2: none; row 3: none (0.25 is not > 0.25).
  EXPECT_EQ(S.nonZeros(), 4);
  EXPECT_EQ(empty, 2);
  const DenseWeights D = S;
  DenseWeights expected = DenseWeights::Zero(4, 4);
  expected(0, 0) = 0.5;
  expected(0, 1) = 0.3;
  expected(1, 0) = 0.6;
  expected(1, 2) = 0.5;
  EXPECT_EQ(D, expected);
}

TEST(SparsifyWeights, RenormalizeMakesRowsSumToOne)
{
  Index empty = -1;
  const DenseWeights D = sparsify_weights(sample_weights(), 0.25, true, &empty);
  EXPECT_EQ(empty, 2);
  // Row 0: 0.5 and 0.3 over 0.8 -> 5/8, 3/8. Row 1: 0.6 and 0.5 over 1.1 -> 6/11, 5/11.
  EXPECT_NEAR(D(0, 0), 5.0 / 8, 1e-15);
  EXPECT_NEAR(D(0, 1), 3.0 / 8, 1e-15);
  EXPECT_NEAR(D(1, 0), 6.0 / 11, 1e-15);
  EXPECT_NEAR(D(1, 2), 5.0 / 11, 1e-15);
  EXPECT_EQ(D(1, 1), 0.0);
  // Rows left empty stay empty (not NaN).
  EXPECT_TRUE((D.row(2).array() == 0.0).all());
  EXPECT_TRUE((D.row(3).array() == 0.0).all());
}

TEST(SparsifyWeights, ZeroThresholdDropsZerosAndNegatives)
{
  Index empty = -1;
  const SparseWeights S = sparsify_weights(sample_weights(), 0.0, false, &empty);
  // Positive entries: 3 + 2 + 2 + 4.
  EXPECT_EQ(S.nonZeros(), 11);
  EXPECT_EQ(empty, 0);
  const DenseWeights D = S;
  EXPECT_EQ(D(1, 1), 0.0);
  EXPECT_EQ(D(2, 1), 0.002);
}

TEST(SparsifyWeights, RenormalizedMeanValueWeightsStillSumToOne)
{
  const Cage cage = test::regular_polygon(64);
  const Points P = test::sample_inside(cage, 100, 1e-3, 25);
  const DenseWeights W = MeanValueCoordinates(cage).evaluate(P).W;
  const double threshold = 5e-3; // drops the far vertices of points near the boundary
  Index empty = -1;
  const SparseWeights S = sparsify_weights(W, threshold, true, &empty);
  EXPECT_EQ(empty, 0);
  EXPECT_EQ(S.nonZeros(), (W.array() > threshold).count());
  EXPECT_LT(S.nonZeros(), W.size()) << "some weights should have been dropped";
  for (Index p = 0; p < S.rows(); ++p)
    EXPECT_NEAR(S.row(p).sum(), 1.0, 1e-14) << "row " << p;
}

TEST(SparsifyWeights, EmptyRowsArgumentIsOptional)
{
  EXPECT_NO_THROW(sparsify_weights(sample_weights(), 0.9, true));
  EXPECT_EQ(sparsify_weights(sample_weights(), 0.9, true).nonZeros(), 0);
}
} // namespace
