// Locality statistics and weight reduction (core/analysis/locality_statistics.h): the LBC paper's Eq. 19-21
// checked on hand-computed examples, then reduction of real coordinates (harmonic coordinates of
// a polygon) with each renormalisation.
//
// Tolerances: the hand examples are exact up to the rounding of a few sums (1e-15); after
// RowSum / Affine renormalisation partition of unity (and, for Affine, reproduction) hold to
// the rounding of a row's sum, 1e-13 allowed; with None the partition error equals the dropped
// mass exactly (1e-15).
#include "cage_catalogue.h"
#include "core/meshing/domain_mesh.h"
#include "core/common/error.h"
#include "core/coordinates/harmonic_coordinates.h"
#include "core/analysis/locality_statistics.h"
#include "error_matchers.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

namespace bary
{
namespace
{

/// 4 points, 3 controls.
DenseWeights small_weights()
{
  DenseWeights W(4, 3);
  W << 1.0, 0.0, 0.0,  //
    0.5, 0.5, 0.0,     //
    0.2, 0.3, 0.5,     //
    0.0, 1e-6, 1.0 - 1e-6;
  return W;
}

TEST(LocalityStatistics, HandComputedEqualMeasures)
{
  const DenseWeights W = small_weights();
  const LocalityStatistics s = locality_statistics(W, 0.1, Eigen::VectorXd(), { 0.0, 0.25, 1.0 });
  EXPECT_EQ(s.threshold, 0.1);
  ASSERT_EQ(s.t.size(), 3u);
  // |w| <= 0: entries that are exactly 0: (0,1), (0,2), (1,2), (3,0) -> 4 of 12
  EXPECT_NEAR(s.P[0], 4.0 / 12.0, 1e-15);
  // |w| <= 0.25: also 0.2 and 1e-6 -> 6 of 12
  EXPECT_NEAR(s.P[1], 6.0 / 12.0, 1e-15);
  EXPECT_NEAR(s.P[2], 1.0, 1e-15);
  // sigma (w > 0.1): 1, 2, 3, 1 -> Q(1) = 1, Q(2) = 2/4, Q(3) = 1/4
  ASSERT_EQ(s.k, (std::vector<int>{ 1, 2, 3 }));
  EXPECT_NEAR(s.Q[0], 1.0, 1e-15);
  EXPECT_NEAR(s.Q[1], 0.5, 1e-15);
  EXPECT_NEAR(s.Q[2], 0.25, 1e-15);
  EXPECT_NEAR(s.mean_support, 7.0 / 4.0, 1e-15);
  EXPECT_EQ(s.max_support, 3.0);
  EXPECT_NEAR(std::accumulate(s.Q.begin(), s.Q.end(), 0.0), s.mean_support, 1e-15);
  // control 0 exceeds 0.1 at points 0, 1, 2; control 1 at 1, 2; control 2 at 2, 3
  ASSERT_EQ(s.influence_fraction.size(), 3u);
  EXPECT_NEAR(s.influence_fraction[0], 0.75, 1e-15);
  EXPECT_NEAR(s.influence_fraction[1], 0.5, 1e-15);
  EXPECT_NEAR(s.influence_fraction[2], 0.5, 1e-15);
}

TEST(LocalityStatistics, MeasureWeightedAndDefaults)
{
  const DenseWeights W = small_weights();
  Eigen::VectorXd mu(4);
  mu << 1, 1, 2, 0; // the last point does not count
  const LocalityStatistics s = locality_statistics(W, 0.1, mu);
  EXPECT_NEAR(s.mean_support, (1 + 2 + 2 * 3) / 4.0, 1e-15);
  EXPECT_EQ(s.max_support, 3.0); // the max is over the points, whatever their measure
  EXPECT_NEAR(s.Q[2], 0.5, 1e-15);
  // default t: 0 and 1e-6 .. 1 in quarter decades; P is non-decreasing and ends at 1
  EXPECT_EQ(s.t, default_locality_t());
  EXPECT_EQ(s.t.size(), 26u);
  EXPECT_EQ(s.t.front(), 0.0);
  EXPECT_EQ(s.t.back(), 1.0);
  for (std::size_t j = 1; j < s.P.size(); ++j)
    EXPECT_GE(s.P[j], s.P[j - 1]);
  EXPECT_NEAR(s.P.back(), 1.0, 1e-15);
  // default threshold 1e-3 / #C
  EXPECT_NEAR(locality_statistics(W).threshold, 1e-3 / 3.0, 1e-18);
  // 1e-6 is below 1e-3 / 3: the last point has support 1 by default
  EXPECT_EQ(locality_statistics(W).max_support, 3.0);
  EXPECT_NEAR(locality_statistics(W).mean_support, (1 + 2 + 3 + 1) / 4.0, 1e-15);
}

TEST(LocalityStatistics, VertexMeasuresSumToTheArea)
{
  const DomainMesh mesh = mesh_polygon(test::l_polygon());
  const Eigen::VectorXd mu = vertex_measures(mesh.V, mesh.T);
  EXPECT_EQ(mu.size(), mesh.V.rows());
  EXPECT_NEAR(mu.sum(), 3.0, 1e-12);
  EXPECT_GT(mu.minCoeff(), 0.0);
}

TEST(ReduceWeights, RenormalisationModes)
{
  const DenseWeights W = small_weights();
  Points C(3, 2), P(4, 2);
  C << 0, 0, 1, 0, 0, 1;
  P = W * C; // reproduction holds exactly before reduction
  // threshold 1e-3: only the 1e-6 entry is dropped
  const ReducedWeights none = reduce_weights(W, 1e-3, Renormalization::None, &C, &P);
  EXPECT_EQ(none.nonzeros, 7);
  EXPECT_NEAR(none.partition_error, 1e-6, 1e-15);
  EXPECT_NEAR(none.max_dropped, 1e-6, 1e-18);
  EXPECT_NEAR(none.reproduction_error, 1e-6 / std::sqrt(2.0), 1e-15);
  EXPECT_NEAR(none.memory_fraction, (7 * 12.0 + 5 * 4.0) / (12 * 8.0), 1e-15);

  const ReducedWeights rowsum = reduce_weights(W, 1e-3, &C, &P, true);
  EXPECT_EQ(rowsum.renormalization, Renormalization::RowSum);
  EXPECT_LE(rowsum.partition_error, 1e-15);
  EXPECT_GT(rowsum.reproduction_error, 1e-7); // the last row moved from (0, 1-1e-6 + ...) to c_2
  EXPECT_EQ(rowsum.W.coeff(3, 2), 1.0);
  EXPECT_GE(rowsum.min_weight, 0.0);

  const ReducedWeights affine = reduce_weights(W, 1e-3, Renormalization::Affine, &C, &P);
  EXPECT_LE(affine.partition_error, 1e-13);
  // row 3 keeps only control 2, which cannot reproduce the point: that row falls back to RowSum
  EXPECT_NEAR(affine.reproduction_error, rowsum.reproduction_error, 1e-15);
  EXPECT_EQ(affine.W.coeff(3, 2), 1.0);
  // with a support that spans, both hold exactly: drop nothing but 0 entries
  const Points P3 = P.topRows(3);
  const ReducedWeights exact = reduce_weights(W.topRows(3), 1e-7, Renormalization::Affine, &C, &P3);
  EXPECT_LE(exact.partition_error, 1e-13);
  EXPECT_LE(exact.reproduction_error, 1e-13);
}

TEST(ReduceWeights, HarmonicCoordinatesOfAStar)
{
  // Harmonic coordinates are global: every weight is positive inside, reduction at 1e-3 / n
  // drops many small ones. Affine keeps linear precision exactly; RowSum keeps w >= 0.
  const Cage cage = test::star_polygon(6, 1.0, 0.5);
  HarmonicOptions ho;
  ho.polygon_mesh.target_cells = 1500;
  const HarmonicCoordinates hc(cage, ho);
  const DenseWeights& W = hc.mesh_weights();
  const Points& P = hc.mesh().V;
  const ReducedWeights rowsum = reduce_weights(W, -1.0, &cage.V, &P);
  const ReducedWeights affine = reduce_weights(W, -1.0, Renormalization::Affine, &cage.V, &P);
  std::printf("harmonic, star (12 controls, %ld points): kept %ld of %ld (memory %.2f), dropped "
              "mass <= %.2e; RowSum: reproduction %.2e, Affine: partition %.1e, reproduction "
              "%.1e, min weight %.2e\n",
    static_cast<long>(P.rows()), static_cast<long>(rowsum.nonzeros),
    static_cast<long>(W.size()), rowsum.memory_fraction, rowsum.max_dropped,
    rowsum.reproduction_error, affine.partition_error, affine.reproduction_error,
    affine.min_weight);
  EXPECT_LT(rowsum.nonzeros, W.size());
  EXPECT_LE(rowsum.partition_error, 1e-13);
  EXPECT_GE(rowsum.min_weight, 0.0);
  EXPECT_LE(rowsum.reproduction_error, rowsum.max_dropped * 2.0);
  EXPECT_LE(affine.partition_error, 1e-13);
  EXPECT_LE(affine.reproduction_error, 1e-13);
  EXPECT_GE(affine.min_weight, -rowsum.max_dropped * 10.0);
  // locality statistics agree with the reduction: mean support = stored entries / points
  const LocalityStatistics s = locality_statistics(W);
  EXPECT_NEAR(s.mean_support, static_cast<double>(rowsum.nonzeros) / P.rows(), 1e-12);
}

TEST(LocalityStatistics, Errors)
{
  const DenseWeights W = small_weights();
  EXPECT_TRUE(test::throws_error(
    [&] { locality_statistics(DenseWeights()); }, ErrorCode::EmptyInput, { "empty" }));
  EXPECT_TRUE(test::throws_error(
    [&] { locality_statistics(W, 0.0); }, ErrorCode::InvalidArgument, { "threshold" }));
  EXPECT_TRUE(test::throws_error([&] { locality_statistics(W, 0.1, Eigen::VectorXd::Ones(3)); },
    ErrorCode::SizeMismatch, { "measure" }));
  EXPECT_TRUE(test::throws_error([&] { locality_statistics(W, 0.1, -Eigen::VectorXd::Ones(4)); },
    ErrorCode::InvalidArgument, { ">= 0" }));
  EXPECT_TRUE(test::throws_error([&] { locality_statistics(W, 0.1, Eigen::VectorXd::Zero(4)); },
    ErrorCode::InvalidArgument, { "sum to 0" }));
  DenseWeights bad = W;
  bad(2, 1) = std::nan("");
  EXPECT_TRUE(test::throws_error(
    [&] { locality_statistics(bad); }, ErrorCode::NonFinite, { "point 2" }));
  Points C(3, 2), P(4, 2);
  C.setZero();
  P.setZero();
  EXPECT_TRUE(test::throws_error(
    [&] { reduce_weights(W, 0.1, &C, nullptr); }, ErrorCode::SizeMismatch, { "both" }));
  EXPECT_TRUE(test::throws_error([&] { reduce_weights(W, 0.1, Renormalization::Affine); },
    ErrorCode::InvalidArgument, { "Affine" }));
  Points C4(4, 2);
  C4.setZero();
  EXPECT_TRUE(test::throws_error(
    [&] { reduce_weights(W, 0.1, &C4, &P); }, ErrorCode::SizeMismatch, { "control points" }));
  DenseWeights zero_row = W;
  zero_row.row(1).setConstant(1e-9);
  EXPECT_TRUE(test::throws_error(
    [&] { reduce_weights(zero_row, 0.1); }, ErrorCode::InvalidArgument, { "point 1" }));
}

} // namespace
} // namespace bary
