// Tests for core/analysis/weight_statistics.h, on hand-built matrices whose statistics are worked out
// by hand in the comments.
#include "cage_catalogue.h"
#include "core/common/error.h"
#include "core/coordinates/mean_value_coordinates.h"
#include "core/analysis/weight_statistics.h"
#include "error_matchers.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace
{
using namespace bary;
using bary::test::throws_error;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Three points, three controls.
//   row 0: 0.5, 0.5, 0     sum 1,   significant 2 (zero is not > threshold)
//   row 1: 1.25, -0.25, 0  sum 1,   significant 1, one negative weight
//   row 2: 0.2, 0.3, 0.4   sum 0.9, significant 3, partition error 0.1
DenseWeights hand_weights()
{
  DenseWeights W(3, 3);
  W << 0.5, 0.5, 0.0, //
    1.25, -0.25, 0.0, //
    0.2, 0.3, 0.4;
  return W;
}

TEST(WeightStatistics, HandBuiltMatrixWithoutCage)
{
  const WeightStatistics s = weight_statistics(hand_weights());
  EXPECT_EQ(s.points, 3);
  EXPECT_EQ(s.controls, 3);
  EXPECT_EQ(s.min_weight, -0.25);
  EXPECT_EQ(s.max_weight, 1.25);
  EXPECT_EQ(s.negative_weights, 1);
  EXPECT_EQ(s.non_finite_rows, 0);
  EXPECT_NEAR(s.max_partition_error, 0.1, 1e-15);
  EXPECT_NEAR(s.mean_partition_error, 0.1 / 3, 1e-15);
  EXPECT_FALSE(s.has_reproduction);
  EXPECT_EQ(s.max_reproduction_error, 0.0);
  ASSERT_EQ(s.significant.size(), 3u);
  EXPECT_EQ(s.significant[0], 2);
  EXPECT_EQ(s.significant[1], 1);
  EXPECT_EQ(s.significant[2], 3);
  EXPECT_EQ(s.max_significant, 3);
  EXPECT_DOUBLE_EQ(s.mean_significant, 2.0); // (2 + 1 + 3) / 3
}

TEST(WeightStatistics, DefaultThresholdIsTheLbcPapers)
{
  // Zhang et al. 2014 count weights above 1e-3 / #C.
  EXPECT_EQ(weight_statistics(hand_weights()).threshold, 1e-3 / 3);
  EXPECT_EQ(weight_statistics(DenseWeights::Constant(1, 8, 0.125)).threshold, 1e-3 / 8);
  // Just above and just below it: with #C = 4 the threshold is 2.5e-4.
  DenseWeights W(1, 4);
  W << 2.6e-4, 2.4e-4, 0.5, 1.0 - 0.5 - 2.6e-4 - 2.4e-4;
  EXPECT_EQ(weight_statistics(W).significant[0], 3);
}

TEST(WeightStatistics, ExplicitThreshold)
{
  WeightStatisticsOptions options;
  options.threshold = 0.45;
  // Above 0.45: row 0: 0.5, 0.5 -> 2; row 1: 1.25 -> 1; row 2: none -> 0.
  const WeightStatistics s = weight_statistics(hand_weights(), nullptr, nullptr, options);
  EXPECT_EQ(s.threshold, 0.45);
  EXPECT_EQ(s.significant, (std::vector<Index>{ 2, 1, 0 }));
  EXPECT_EQ(s.max_significant, 2);
  EXPECT_DOUBLE_EQ(s.mean_significant, 1.0);
  // A threshold of 0 is allowed (only negative values select the default).
  options.threshold = 0.0;
  EXPECT_EQ(weight_statistics(hand_weights(), nullptr, nullptr, options).threshold, 0.0);
}

TEST(WeightStatistics, ReproductionError)
{
  // Controls c0 = (0,0), c1 = (1,0), c2 = (0,1); bounding-box diagonal sqrt(2).
  //   row 0 reproduces 0.5 c1 = (0.5, 0); P0 = (0.5, 0): error 0.
  //   row 1 reproduces -0.25 c1 = (-0.25, 0); P1 = (-0.25, 0): error 0.
  //   row 2 reproduces 0.3 c1 + 0.4 c2 = (0.3, 0.4); P2 = (0, 0): error |(0.3, 0.4)| = 0.5.
  // Relative to the diameter: max 0.5 / sqrt(2), mean (0.5 / sqrt(2)) / 3.
  Eigen::MatrixXd C(3, 2);
  C << 0, 0, 1, 0, 0, 1;
  Points P(3, 2);
  P << 0.5, 0, -0.25, 0, 0, 0;
  const WeightStatistics s = weight_statistics(hand_weights(), &C, &P);
  EXPECT_TRUE(s.has_reproduction);
  EXPECT_NEAR(s.max_reproduction_error, 0.5 / std::sqrt(2.0), 1e-15);
  EXPECT_NEAR(s.mean_reproduction_error, 0.5 / std::sqrt(2.0) / 3, 1e-15);
  // The other statistics do not depend on the cage.
  EXPECT_NEAR(s.max_partition_error, 0.1, 1e-15);
  EXPECT_EQ(s.negative_weights, 1);
}

TEST(WeightStatistics, ReproductionWithADegenerateCageUsesUnitDiameter)
{
  // All controls at one point: the diameter is 0, so errors are absolute.
  const Eigen::MatrixXd C = Eigen::MatrixXd::Ones(3, 2);
  Points P(3, 2);
  P << 1, 1, 1, 1, 1, 4;
  DenseWeights W = DenseWeights::Constant(3, 3, 1.0 / 3);
  const WeightStatistics s = weight_statistics(W, &C, &P);
  EXPECT_NEAR(s.max_reproduction_error, 3.0, 1e-15); // |(1,1) - (1,4)|
  EXPECT_NEAR(s.mean_reproduction_error, 1.0, 1e-15);
}

TEST(WeightStatistics, NonFiniteRowsAreExcluded)
{
  DenseWeights W(5, 3);
  W << 0.5, 0.5, 0.0,                                     //
    kNaN, kNaN, kNaN,                                     //
    1.25, -0.25, 0.0,                                     //
    std::numeric_limits<double>::infinity(), -100.0, 0.0, //
    0.2, 0.3, 0.4;
  const WeightStatistics s = weight_statistics(W);
  EXPECT_EQ(s.points, 5);
  EXPECT_EQ(s.non_finite_rows, 2);
  // The finite rows are hand_weights(): the same statistics, -100 from row 3 ignored.
  EXPECT_EQ(s.min_weight, -0.25);
  EXPECT_EQ(s.max_weight, 1.25);
  EXPECT_EQ(s.negative_weights, 1);
  EXPECT_NEAR(s.max_partition_error, 0.1, 1e-15);
  EXPECT_NEAR(s.mean_partition_error, 0.1 / 3, 1e-15);
  EXPECT_EQ(s.significant, (std::vector<Index>{ 2, 0, 1, 0, 3 }));
  EXPECT_DOUBLE_EQ(s.mean_significant, 2.0);

  // With a cage, the non-finite rows are excluded from the reproduction error too.
  Eigen::MatrixXd C(3, 2);
  C << 0, 0, 1, 0, 0, 1;
  Points P(5, 2);
  P << 0.5, 0, 9, 9, -0.25, 0, 9, 9, 0.3, 0.4;
  const WeightStatistics r = weight_statistics(W, &C, &P);
  EXPECT_EQ(r.max_reproduction_error, 0.0);
  EXPECT_TRUE(std::isfinite(r.mean_reproduction_error));
}

TEST(WeightStatistics, AllRowsNonFinite)
{
  const DenseWeights W = DenseWeights::Constant(2, 3, kNaN);
  const WeightStatistics s = weight_statistics(W);
  EXPECT_EQ(s.non_finite_rows, 2);
  EXPECT_TRUE(std::isnan(s.min_weight));
  EXPECT_TRUE(std::isnan(s.max_weight));
  EXPECT_EQ(s.max_partition_error, 0.0);
  EXPECT_EQ(s.mean_significant, 0.0);
}

TEST(WeightStatistics, MeanValueWeightsOfTheSquare)
{
  // End to end: MVC on a convex cage have partition of unity, reproduction and no negatives.
  const Cage square = test::unit_square();
  const Points P = test::sample_inside(square, 200, 1e-3, 31);
  const DenseWeights W = MeanValueCoordinates(square).evaluate(P).W;
  const WeightStatistics s = weight_statistics(W, &square.V, &P);
  EXPECT_LT(s.max_partition_error, 1e-14);
  EXPECT_LT(s.max_reproduction_error, 1e-13);
  EXPECT_EQ(s.negative_weights, 0);
  EXPECT_GE(s.min_weight, 0.0);
  EXPECT_LE(s.max_weight, 1.0);
  EXPECT_EQ(s.max_significant, 4); // MVC are global: all 4 weights are significant
}

TEST(WeightStatistics, ErrorPaths)
{
  EXPECT_TRUE(throws_error([] { weight_statistics(DenseWeights(0, 3)); }, ErrorCode::EmptyInput));
  EXPECT_TRUE(throws_error([] { weight_statistics(DenseWeights(3, 0)); }, ErrorCode::EmptyInput));
  const DenseWeights W = hand_weights();
  const Eigen::MatrixXd C = Eigen::MatrixXd::Zero(3, 2);
  const Points P = Points::Zero(3, 2);
  EXPECT_TRUE(throws_error([&] { weight_statistics(W, &C, nullptr); }, ErrorCode::InvalidArgument));
  EXPECT_TRUE(throws_error([&] { weight_statistics(W, nullptr, &P); }, ErrorCode::InvalidArgument));
  const Eigen::MatrixXd C4 = Eigen::MatrixXd::Zero(4, 2);
  EXPECT_TRUE(throws_error([&] { weight_statistics(W, &C4, &P); }, ErrorCode::SizeMismatch,
    { "3 components", "4 control points" }));
  const Points P2 = Points::Zero(2, 2);
  EXPECT_TRUE(throws_error(
    [&] { weight_statistics(W, &C, &P2); }, ErrorCode::SizeMismatch, { "3 rows", "2 points" }));
  const Points P3d = Points::Zero(3, 3);
  EXPECT_TRUE(throws_error(
    [&] { weight_statistics(W, &C, &P3d); }, ErrorCode::SizeMismatch, { "dimension" }));
}
} // namespace
