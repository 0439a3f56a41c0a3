// Tests of core/surface/surface_curves: the uniform cubic B-spline weights (partition of unity,
// the basis at the knots, continuity, open and closed curves) and curves on a surface as
// forward problems (on a flat patch: the planar B-spline).
#include "core/surface/surface_curves.h"
#include "core/surface/weighted_averages.h"
#include "error_matchers.h"
#include "surface_catalogue.h"

#include <gtest/gtest.h>

using namespace bary;
using bary::test::throws_error;

TEST(SurfaceCurves, BSplineWeightsArePartitionOfUnityWithTheKnotValues)
{
  for (const bool closed : { false, true })
  {
    const DenseWeights W = bspline_weights(7, 10, closed);
    EXPECT_EQ(W.rows(), closed ? 70 : 41);
    EXPECT_EQ(W.cols(), 7);
    for (Index r = 0; r < W.rows(); ++r)
    {
      EXPECT_NEAR(W.row(r).sum(), 1.0, 1e-15);
      EXPECT_GE(W.row(r).minCoeff(), 0.0);
      EXPECT_LE((W.row(r).array() > 0).count(), 4);
    }
    // At a knot (t = 0 of segment s) the weights are 1/6, 4/6, 1/6 on c_s, c_{s+1}, c_{s+2}.
    for (Index s = 0; s < (closed ? 7 : 4); ++s)
    {
      const auto row = W.row(s * 10);
      EXPECT_NEAR(row(s % 7), 1.0 / 6, 1e-15);
      EXPECT_NEAR(row((s + 1) % 7), 4.0 / 6, 1e-15);
      EXPECT_NEAR(row((s + 2) % 7), 1.0 / 6, 1e-15);
    }
    // Consecutive samples differ by at most max|B_k'| dt = 2/3 x 0.1 (continuity, also across knots).
    for (Index r = 1; r < W.rows(); ++r)
      EXPECT_LE((W.row(r) - W.row(r - 1)).cwiseAbs().maxCoeff(), 0.1 * 2.0 / 3 + 1e-12);
  }
  // The open curve ends at t = 1 of its last segment: 1/6, 4/6, 1/6 on c_{m-3}, c_{m-2}, c_{m-1}.
  const DenseWeights W = bspline_weights(5, 4, false);
  EXPECT_NEAR(W(W.rows() - 1, 2), 1.0 / 6, 1e-15);
  EXPECT_NEAR(W(W.rows() - 1, 3), 4.0 / 6, 1e-15);
  EXPECT_NEAR(W(W.rows() - 1, 4), 1.0 / 6, 1e-15);
}

TEST(SurfaceCurves, OnAFlatPatchTheCurveIsThePlanarBSpline)
{
  const auto g = test::flat_grid(16);
  SurfaceMesh m(g.V, g.F);
  const WeightedAverages wa(m, m.V);
  Eigen::MatrixXd C(6, 3);
  C << -0.8, -0.8, 0, 0.7, -0.7, 0, 0.8, 0.6, 0, -0.2, 0.8, 0, -0.7, 0.1, 0, 0.1, -0.1, 0;
  const auto controls = closest_surface_points(m, C);
  for (const bool closed : { false, true })
  {
    const DenseWeights W = bspline_weights(6, 20, closed);
    ForwardOptions warm;
    warm.warm_start = true;
    const ForwardResult r = wa.forward(controls, W, warm);
    EXPECT_EQ(r.failures, 0);
    EXPECT_LT((r.positions - W * C).cwiseAbs().maxCoeff(), 1e-12);
  }
}

TEST(SurfaceCurves, Errors)
{
  EXPECT_TRUE(throws_error([] { bspline_weights(3, 10, false); }, ErrorCode::InvalidArgument, { "at least 4 control points" }));
  EXPECT_TRUE(throws_error([] { bspline_weights(5, 0, true); }, ErrorCode::InvalidArgument, { "[1, 100000]" }));
}
