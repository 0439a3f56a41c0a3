// Tests of core/surface/weighted_averages: forward and inverse problems of Panozzo et al. 2013
// (§3.3-3.4) on surfaces made in the test with known embeddings (the identity in R^3 and the
// smooth lift into R^8 of surface_catalogue.h).
#include "core/detail/simd.h"
#include "core/surface/weighted_averages.h"
#include "error_matchers.h"
#include "surface_catalogue.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

using namespace bary;
using bary::test::throws_error;

namespace
{

/// Anchors at the surface points closest to the given positions.
std::vector<SurfacePoint> anchors_at(const SurfaceMesh& m, const Eigen::MatrixXd& P)
{
  return closest_surface_points(m, P);
}

/// Random convex weights (#rows by n).
DenseWeights convex_weights(Index rows, Index n, std::mt19937& rng)
{
  std::uniform_real_distribution<double> u(0, 1);
  DenseWeights W(rows, n);
  for (Index r = 0; r < rows; ++r)
  {
    for (Index i = 0; i < n; ++i)
      W(r, i) = u(rng);
    W.row(r) /= W.row(r).sum();
  }
  return W;
}

/// Four anchors around the north pole of the unit sphere, on a cap of angular radius `radius`.
Eigen::MatrixXd cap_anchors(double radius, int count = 4)
{
  Eigen::MatrixXd P(count, 3);
  const double pi = std::acos(-1.0);
  for (int i = 0; i < count; ++i)
  {
    const double a = 2 * pi * i / count + 0.3;
    P.row(i) << std::sin(radius) * std::cos(a), std::sin(radius) * std::sin(a), std::cos(radius);
  }
  return P;
}

/// Random points on the surface inside the cap around the north pole of angular radius r.
std::vector<SurfacePoint> cap_points(const SurfaceMesh& m, double r, int count, std::mt19937& rng)
{
  std::uniform_real_distribution<double> u(-1, 1);
  Eigen::MatrixXd P(count, 3);
  for (int i = 0; i < count; ++i)
  {
    Eigen::Vector3d p;
    do
      p = Eigen::Vector3d(u(rng) * std::sin(r), u(rng) * std::sin(r), 1.0);
    while (std::acos(p.normalized()(2)) > r);
    P.row(i) = p.normalized().transpose();
  }
  return closest_surface_points(m, P);
}

} // namespace

// On a flat patch the forward problem is the planar affine combination, exactly.
TEST(WeightedAverages, FlatPatchIsTheAffineCombination)
{
  const auto g = test::flat_grid(10);
  SurfaceMesh m(g.V, g.F);
  std::mt19937 rng(1);
  Eigen::MatrixXd A(5, 3);
  A << -0.7, -0.6, 0, 0.65, -0.55, 0, 0.6, 0.7, 0, -0.5, 0.66, 0, 0.05, 0.1, 0;
  const auto anchors = anchors_at(m, A);
  DenseWeights W = convex_weights(300, 5, rng);
  W.row(0) << 1.2, -0.2, 0, 0, 0; // an affine (not convex) combination inside the patch
  Eigen::MatrixXd E8 = Eigen::MatrixXd::Zero(m.vertex_count(), 8);
  E8.leftCols(3) = m.V;
  for (const Eigen::MatrixXd& E : { m.V, E8 })
  {
    const WeightedAverages wa(m, E);
    for (const auto search : { ForwardOptions::Search::Local, ForwardOptions::Search::BruteForce })
    {
      ForwardOptions options;
      options.search = search;
      const ForwardResult r = wa.forward(anchors, W, options);
      EXPECT_EQ(r.failures, 0);
      const Eigen::MatrixXd expected = W * A;
      EXPECT_LT((r.positions - expected).cwiseAbs().maxCoeff(), 1e-12);
    }
  }
}

TEST(WeightedAverages, OneHotWeightsGiveTheAnchor)
{
  const auto s = test::icosphere(3);
  SurfaceMesh m(s.V, s.F);
  const WeightedAverages wa(m, test::lift8(m.V));
  const Eigen::MatrixXd A = cap_anchors(0.4, 6);
  const auto anchors = anchors_at(m, A);
  const DenseWeights W = DenseWeights::Identity(6, 6);
  const ForwardResult r = wa.forward(anchors, W);
  ASSERT_EQ(r.failures, 0);
  const Eigen::MatrixXd X = surface_point_positions(m.F, m.V, anchors);
  EXPECT_LT((r.positions - X).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(WeightedAverages, InverseInterpolatesAndSumsToOne)
{
  const auto s = test::icosphere(3);
  SurfaceMesh m(s.V, s.F);
  const WeightedAverages wa(m, test::lift8(m.V));
  const auto anchors = anchors_at(m, cap_anchors(0.5, 5));
  const DenseWeights at_anchors = wa.inverse(anchors, anchors);
  EXPECT_LT((at_anchors - DenseWeights::Identity(5, 5)).cwiseAbs().maxCoeff(), 1e-12);
  std::mt19937 rng(2);
  const auto points = cap_points(m, 0.5, 500, rng);
  const DenseWeights W = wa.inverse(anchors, points);
  for (Index p = 0; p < W.rows(); ++p)
    EXPECT_NEAR(W.row(p).sum(), 1.0, 1e-10);
  // The tangential constraint of Eq. (13): the point is a Phong projection of sum w_i y_i.
  const Eigen::MatrixXd Y = wa.embed(anchors), X = wa.embed(points);
  for (Index p = 0; p < W.rows(); ++p)
  {
    const Eigen::VectorXd ybar = (W.row(p) * Y).transpose();
    const Eigen::MatrixXd P = wa.phong().psi(points[p].face, points[p].barycentric);
    EXPECT_LT((P * (X.row(p).transpose() - ybar)).norm(), 1e-10);
  }
}

// forward(inverse(x)) = x: the round trip of §4.4, on the sphere's cap covered by the anchors.
TEST(WeightedAverages, RoundTripReturnsThePoint)
{
  const auto s = test::icosphere(4);
  SurfaceMesh m(s.V, s.F);
  for (const bool lift : { false, true })
  {
    const WeightedAverages wa(m, lift ? test::lift8(m.V) : m.V);
    const auto anchors = anchors_at(m, cap_anchors(0.6, 8));
    std::mt19937 rng(3);
    const auto points = cap_points(m, 0.5, 2000, rng);
    const DenseWeights W = wa.inverse(anchors, points);
    const ForwardResult r = wa.forward(anchors, W);
    EXPECT_EQ(r.failures, 0);
    const Eigen::MatrixXd X = surface_point_positions(m.F, m.V, points);
    std::vector<double> error(points.size());
    for (std::size_t p = 0; p < points.size(); ++p)
      error[p] = (r.positions.row(p) - X.row(p)).norm();
    std::sort(error.begin(), error.end());
    EXPECT_LT(error[error.size() / 2], 1e-10) << "median, lift " << lift;
    EXPECT_LT(error.back(), 1e-8) << "max, lift " << lift;
  }
}

// The local search finds the brute-force answer (Definition 2's closest Phong projection).
TEST(WeightedAverages, LocalSearchAgreesWithBruteForce)
{
  const auto s = test::torus(40, 20);
  SurfaceMesh m(s.V, s.F);
  const WeightedAverages wa(m, test::lift8(m.V));
  Eigen::MatrixXd A(4, 3);
  A << 1.4, 0.0, 0.0, 1.3, 0.3, 0.25, 1.3, -0.3, 0.25, 1.2, 0.1, -0.3;
  const auto anchors = anchors_at(m, A);
  std::mt19937 rng(4);
  const DenseWeights W = convex_weights(500, 4, rng);
  const ForwardResult local = wa.forward(anchors, W);
  ForwardOptions brute;
  brute.search = ForwardOptions::Search::BruteForce;
  const ForwardResult all = wa.forward(anchors, W, brute);
  EXPECT_EQ(local.failures, 0);
  EXPECT_EQ(all.failures, 0);
  EXPECT_LT((local.positions - all.positions).cwiseAbs().maxCoeff(), 1e-10);
  EXPECT_LT(local.triangles_tried * 20, all.triangles_tried);
}

// Along a path of weights the average moves continuously (no jumps at edges: the point of
// Phong projection), and warm starts give the same points.
TEST(WeightedAverages, SmoothAlongAPathOfWeights)
{
  const auto s = test::icosphere(4);
  SurfaceMesh m(s.V, s.F);
  const WeightedAverages wa(m, test::lift8(m.V));
  const auto anchors = anchors_at(m, cap_anchors(0.5, 4));
  const int steps = 2000;
  DenseWeights W(steps, 4);
  for (int k = 0; k < steps; ++k)
  {
    const double t = static_cast<double>(k) / (steps - 1);
    W.row(k) << (1 - t) * 0.7, t * 0.7, 0.15, 0.15;
  }
  const ForwardResult cold = wa.forward(anchors, W);
  ForwardOptions warm_options;
  warm_options.warm_start = true;
  const ForwardResult warm = wa.forward(anchors, W, warm_options);
  ASSERT_EQ(cold.failures, 0);
  ASSERT_EQ(warm.failures, 0);
  EXPECT_LT((cold.positions - warm.positions).cwiseAbs().maxCoeff(), 1e-10);
  EXPECT_LT(warm.triangles_tried, cold.triangles_tried + 1);
  // The path is about 0.7 * (chord between two anchors) long: steps of ~4e-4. A jump across a
  // triangle would be ~mean edge length (0.08).
  double largest = 0, total = 0;
  for (int k = 1; k < steps; ++k)
  {
    const double d = (cold.positions.row(k) - cold.positions.row(k - 1)).norm();
    largest = std::max(largest, d);
    total += d;
  }
  EXPECT_LT(largest, 3 * total / (steps - 1));
}

TEST(WeightedAverages, ResultsDoNotDependOnThreads)
{
  const auto s = test::icosphere(3);
  SurfaceMesh m(s.V, s.F);
  const WeightedAverages wa(m, test::lift8(m.V));
  const auto anchors = anchors_at(m, cap_anchors(0.5, 6));
  std::mt19937 rng(6);
  const DenseWeights W = convex_weights(3000, 6, rng);
  ForwardOptions one, two;
  one.threads = 1;
  two.threads = 2;
  one.warm_start = two.warm_start = true;
  const ForwardResult a = wa.forward(anchors, W, one), b = wa.forward(anchors, W, two);
  EXPECT_EQ(a.triangles_tried, b.triangles_tried);
  EXPECT_TRUE(a.positions.cwiseEqual(b.positions).all() || a.positions.hasNaN());
  const auto points = cap_points(m, 0.4, 1000, rng);
  InverseOptions i1, i2;
  i1.threads = 1;
  i2.threads = 2;
  EXPECT_TRUE(wa.inverse(anchors, points, i1).cwiseEqual(wa.inverse(anchors, points, i2)).all());
}

// The AVX2 + FMA kernels (a * b + c rounded once) and the portable ones (what a CPU without
// them runs) agree to rounding: the forward problem (search and Phong projection, dense and
// sparse weights, D = 8 and the general D = 3) and the inverse problem.
TEST(WeightedAverages, InstructionSetsAgree)
{
  if (detail::supported_simd_level() != detail::SimdLevel::AVX2)
    GTEST_SKIP() << "this CPU has no AVX2 and FMA: only the portable kernels run";
  const auto s = test::icosphere(3);
  SurfaceMesh m(s.V, s.F);
  std::mt19937 rng(8);
  for (const bool lift : { false, true })
  {
    const WeightedAverages wa(m, lift ? test::lift8(m.V) : m.V);
    const auto anchors = anchors_at(m, cap_anchors(0.6, 12));
    const DenseWeights W = convex_weights(2000, 12, rng);
    const SparseWeights S = W.sparseView();
    const auto points = cap_points(m, 0.5, 1000, rng);
    struct Run
    {
      ForwardResult dense, sparse;
      DenseWeights inverse;
    };
    auto run = [&](detail::SimdLevel level) {
      detail::set_simd_level(level);
      Run r{ wa.forward(anchors, W), wa.forward(anchors, S, ForwardOptions{}),
        wa.inverse(anchors, points) };
      detail::set_simd_level(detail::supported_simd_level());
      return r;
    };
    const Run avx2 = run(detail::SimdLevel::AVX2), portable = run(detail::SimdLevel::Portable);
    EXPECT_EQ(avx2.dense.failures, 0) << "lift " << lift;
    EXPECT_EQ(portable.dense.failures, 0) << "lift " << lift;
    EXPECT_EQ(avx2.sparse.failures, 0) << "lift " << lift;
    // unit sphere: positions in units of its radius
    EXPECT_LT((avx2.dense.positions - portable.dense.positions).cwiseAbs().maxCoeff(), 1e-12)
      << "lift " << lift;
    EXPECT_LT((avx2.sparse.positions - portable.sparse.positions).cwiseAbs().maxCoeff(), 1e-12)
      << "lift " << lift;
    EXPECT_LT((avx2.inverse - portable.inverse).cwiseAbs().maxCoeff(), 1e-12) << "lift " << lift;
    // The single-precision search only chooses where to start: dense and sparse weights give
    // the projections of the same averages.
    EXPECT_LT((avx2.dense.positions - avx2.sparse.positions).cwiseAbs().maxCoeff(), 1e-12);
  }
}

TEST(WeightedAverages, FailedQueriesAreReportedNotReturned)
{
  const auto s = test::icosphere(2);
  SurfaceMesh m(s.V, s.F);
  const WeightedAverages wa(m, m.V);
  // Two antipodal anchors with equal weights average to the sphere's centre: every point of
  // the sphere is as close, and the search cap of 3 triangles stops before it finds one.
  Eigen::MatrixXd A(2, 3);
  A << 0, 0, 1, 0, 0, -1;
  const auto anchors = anchors_at(m, A);
  DenseWeights W(1, 2);
  W << 0.5, 0.5;
  ForwardOptions capped;
  capped.max_triangles = 1;
  const ForwardResult r = wa.forward(anchors, W, capped);
  if (r.failures == 1)
  {
    EXPECT_FALSE(r.valid[0]);
    EXPECT_TRUE(std::isnan(r.positions(0, 0)));
    EXPECT_EQ(r.points[0].face, -1);
  }
  else
    EXPECT_TRUE(r.valid[0]);
}

TEST(WeightedAverages, BadInputIsRefusedNamingTheProblem)
{
  const auto s = test::icosphere(2);
  SurfaceMesh m(s.V, s.F);
  const WeightedAverages wa(m, m.V);
  const auto anchors = anchors_at(m, cap_anchors(0.5, 3));
  DenseWeights W(2, 3);
  W << 0.2, 0.3, 0.5, 0.2, 0.3, 0.6;
  EXPECT_TRUE(throws_error([&] { wa.forward(anchors, W); }, ErrorCode::InvalidArgument, { "row 1", "sums to 1.1" }));
  EXPECT_TRUE(throws_error([&] { wa.forward(anchors, W.leftCols(2)); }, ErrorCode::SizeMismatch, { "2 columns", "3 anchors" }));
  W(1, 2) = std::nan("");
  EXPECT_TRUE(throws_error([&] { wa.forward(anchors, W); }, ErrorCode::NonFinite, { "row 1" }));
  EXPECT_TRUE(throws_error([&] { wa.forward({}, W.leftCols(0)); }, ErrorCode::EmptyInput, { "no anchors" }));
  auto bad = anchors;
  bad[1].face = 100000;
  EXPECT_TRUE(throws_error([&] { wa.inverse(bad, anchors); }, ErrorCode::InvalidArgument, { "anchor 1", "triangle 100000" }));
  bad = anchors;
  bad[2].barycentric << 0.5, 0.5, 0.5;
  EXPECT_TRUE(throws_error([&] { wa.inverse(anchors, bad); }, ErrorCode::InvalidArgument, { "point 2", "sum to 1" }));
  InverseOptions gamma;
  gamma.gamma = 0.5;
  EXPECT_TRUE(throws_error([&] { wa.inverse(anchors, anchors, gamma); }, ErrorCode::InvalidArgument, { "gamma" }));
}
