// Tests for core/deformation/linear_blend_skinning.h: Eq. (1) of Jacobson et al. 2011 on hand-made weights
// and transforms, and the §3.4 rotations inferred from pseudo-edges.
#include "core/common/error.h"
#include "core/deformation/linear_blend_skinning.h"
#include "core/detail/simd.h"
#include "error_matchers.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace
{
using namespace bary;
using bary::test::throws_error;

Eigen::MatrixXd affine(const Eigen::MatrixXd& A, const Eigen::VectorXd& t)
{
  Eigen::MatrixXd T(A.rows(), A.cols() + 1);
  T << A, t;
  return T;
}

/// Random points and random weights with rows summing to 1 (some zeros).
void random_setup(int np, int m, int dim, Points& X, DenseWeights& W)
{
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  X.resize(np, dim);
  W.resize(np, m);
  for (int p = 0; p < np; ++p)
  {
    for (int k = 0; k < dim; ++k)
      X(p, k) = 2.0 * uniform(rng) - 1.0;
    for (int j = 0; j < m; ++j)
      W(p, j) = uniform(rng) < 0.3 ? 0.0 : uniform(rng);
    if (W.row(p).sum() == 0.0)
      W(p, 0) = 1.0;
    W.row(p) /= W.row(p).sum();
  }
}

TEST(LinearBlendSkinning, SameTransformOnEveryHandleMovesEveryPointByIt)
{
  // Partition of unity: if every handle carries T, every point moves by T (to rounding).
  for (const int dim : { 2, 3 })
  {
    Points X;
    DenseWeights W;
    random_setup(200, 5, dim, X, W);
    const Eigen::MatrixXd A = Eigen::MatrixXd::Random(dim, dim);
    const Eigen::VectorXd t = Eigen::VectorXd::Random(dim);
    const AffineTransforms transforms(5, affine(A, t));
    const Points Y = linear_blend_skinning(X, W, transforms);
    const Points expected = (X * A.transpose()).rowwise() + t.transpose();
    EXPECT_LE((Y - expected).cwiseAbs().maxCoeff(), 1e-14) << dim << "D";
    // Identity transforms leave the points where they are.
    const AffineTransforms identity(5, affine(Eigen::MatrixXd::Identity(dim, dim), Eigen::VectorXd::Zero(dim)));
    EXPECT_LE((linear_blend_skinning(X, W, identity) - X).cwiseAbs().maxCoeff(), 1e-15);
  }
}

TEST(LinearBlendSkinning, BlendsTheHandlesTransformsLinearly)
{
  // One point, two handles, weights 0.25 / 0.75: x' = 0.25 T0 x + 0.75 T1 x.
  Points X(1, 2);
  X << 1.0, 2.0;
  DenseWeights W(1, 2);
  W << 0.25, 0.75;
  const Eigen::MatrixXd T0 = affine(Eigen::Matrix2d::Identity(), Eigen::Vector2d(1.0, 0.0));
  const Eigen::MatrixXd T1 = affine(2.0 * Eigen::Matrix2d::Identity(), Eigen::Vector2d(0.0, -1.0));
  const Points Y = linear_blend_skinning(X, W, { T0, T1 });
  // T0 x = (2, 2), T1 x = (2, 3): 0.25 (2, 2) + 0.75 (2, 3) = (2, 2.75).
  EXPECT_DOUBLE_EQ(Y(0, 0), 2.0);
  EXPECT_DOUBLE_EQ(Y(0, 1), 2.75);
}

TEST(LinearBlendSkinning, SparseEqualsDenseAndThreadsDoNotMatter)
{
  Points X;
  DenseWeights W;
  random_setup(500, 6, 3, X, W);
  AffineTransforms transforms;
  for (int j = 0; j < 6; ++j)
    transforms.push_back(affine(Eigen::MatrixXd::Random(3, 3), Eigen::VectorXd::Random(3)));
  const Points dense = linear_blend_skinning(X, W, transforms, 1);
  const SparseWeights S = W.sparseView();
  const Points sparse = linear_blend_skinning(X, S, transforms, 1);
  EXPECT_LE((dense - sparse).cwiseAbs().maxCoeff(), 1e-15);
  for (const int threads : { 2, 4 })
  {
    EXPECT_TRUE((linear_blend_skinning(X, W, transforms, threads).array() == dense.array()).all());
    EXPECT_TRUE((linear_blend_skinning(X, S, transforms, threads).array() == sparse.array()).all());
  }
}

/// Eq. (1) term by term, for every stored weight: the independent reference for the kernels.
Points term_by_term(const Points& X, const DenseWeights& W, const AffineTransforms& transforms)
{
  const Index dim = X.cols();
  Points Y = Points::Zero(X.rows(), dim);
  for (Index p = 0; p < X.rows(); ++p)
    for (Index j = 0; j < W.cols(); ++j)
    {
      const Eigen::MatrixXd& T = transforms[static_cast<std::size_t>(j)];
      Y.row(p) += W(p, j) * (T.leftCols(dim) * X.row(p).transpose() + T.col(dim)).transpose();
    }
  return Y;
}

TEST(LinearBlendSkinning, KernelsMatchEquationOneTermByTermAtEverySimdLevel)
{
  // The 2D/3D kernels accumulate sum_j w_j [A_j | t_j] first (vector multiply-adds, even and
  // odd weights apart) and apply it once; the reference sums w_j (A_j x + t_j). Both are
  // sums of ~#handles products of magnitude <= ~4 here, so they agree to a few units of
  // rounding: 1e-14. Odd and even handle counts (the kernels' tail), 1D through the generic
  // path, dense and sparse weights, the AVX2 and the portable build of the kernels.
  const detail::SimdLevel supported = detail::supported_simd_level();
  for (const int dim : { 1, 2, 3 })
    for (const int m : { 1, 5, 20 })
    {
      Points X;
      DenseWeights W;
      random_setup(301, m, dim, X, W);
      AffineTransforms transforms;
      for (int j = 0; j < m; ++j)
        transforms.push_back(
          affine(Eigen::MatrixXd::Random(dim, dim), Eigen::VectorXd::Random(dim)));
      const Points expected = term_by_term(X, W, transforms);
      const SparseWeights S = W.sparseView();
      Points at_level[2];
      for (const auto level : { detail::SimdLevel::Portable, detail::SimdLevel::AVX2 })
      {
        if (detail::set_simd_level(level) != level)
          continue; // this CPU has no AVX2
        const Points dense = linear_blend_skinning(X, W, transforms, 1);
        const Points sparse = linear_blend_skinning(X, S, transforms, 1);
        EXPECT_LE((dense - expected).cwiseAbs().maxCoeff(), 1e-14) << dim << "D, " << m;
        EXPECT_LE((sparse - expected).cwiseAbs().maxCoeff(), 1e-14) << dim << "D, " << m;
        // the thread that computes a point does not change it
        EXPECT_TRUE((linear_blend_skinning(X, W, transforms, 2).array() == dense.array()).all());
        EXPECT_TRUE((linear_blend_skinning(X, S, transforms, 2).array() == sparse.array()).all());
        at_level[static_cast<int>(level)] = dense;
      }
      detail::set_simd_level(supported);
      if (at_level[1].size() > 0)
      { // the levels differ by the fused multiply-adds only
        EXPECT_LE((at_level[0] - at_level[1]).cwiseAbs().maxCoeff(), 1e-14);
      }
    }
}

TEST(LinearBlendSkinning, LargePointSetsAreSplitOverThreadsWithoutChangingAPoint)
{
  // 20,000 points: the kernels hand blocks of points to two threads (under 2,048, one).
  Points X;
  DenseWeights W;
  random_setup(20000, 7, 3, X, W);
  AffineTransforms transforms;
  for (int j = 0; j < 7; ++j)
    transforms.push_back(affine(Eigen::MatrixXd::Random(3, 3), Eigen::VectorXd::Random(3)));
  const Points one = linear_blend_skinning(X, W, transforms, 1);
  EXPECT_TRUE((linear_blend_skinning(X, W, transforms, 2).array() == one.array()).all());
  EXPECT_LE((one - term_by_term(X, W, transforms)).cwiseAbs().maxCoeff(), 1e-14);
}

TEST(LinearBlendSkinning, Errors)
{
  Points X(2, 2);
  X << 0, 0, 1, 1;
  DenseWeights W(2, 2);
  W << 1, 0, 0, 1;
  const AffineTransforms two(2, affine(Eigen::Matrix2d::Identity(), Eigen::Vector2d::Zero()));
  EXPECT_TRUE(throws_error([&] { linear_blend_skinning(X, DenseWeights(3, 2), two); },
    ErrorCode::SizeMismatch, { "3 rows" }));
  EXPECT_TRUE(throws_error([&] { linear_blend_skinning(X, W, AffineTransforms(1, two[0])); },
    ErrorCode::SizeMismatch, { "transforms" }));
  AffineTransforms wrong = two;
  wrong[1] = Eigen::MatrixXd::Identity(2, 2);
  EXPECT_TRUE(throws_error([&] { linear_blend_skinning(X, W, wrong); }, ErrorCode::SizeMismatch,
    { "transform 1", "2 by 3" }));
  AffineTransforms nan = two;
  nan[0](0, 2) = std::nan("");
  EXPECT_TRUE(throws_error([&] { linear_blend_skinning(X, W, nan); }, ErrorCode::NonFinite, { "transform 0" }));
  Points X_nan = X;
  X_nan(1, 0) = std::nan("");
  EXPECT_TRUE(throws_error([&] { linear_blend_skinning(X_nan, W, two); }, ErrorCode::NonFinite, { "point 1" }));
  DenseWeights W_nan = W;
  W_nan(0, 1) = std::nan("");
  EXPECT_TRUE(throws_error([&] { linear_blend_skinning(X, W_nan, two); }, ErrorCode::NonFinite, { "point 0" }));
  const SparseWeights S_nan = W_nan.sparseView(0.0, 0.0);
  EXPECT_TRUE(throws_error([&] { linear_blend_skinning(X, S_nan, two); }, ErrorCode::NonFinite, { "point 0" }));
  DenseWeights W_inf = W;
  W_inf(1, 0) = INFINITY;
  EXPECT_TRUE(throws_error([&] { linear_blend_skinning(X, W_inf, two); }, ErrorCode::NonFinite, { "point 1" }));
  // finite input whose blend overflows: named, not returned as infinity
  const AffineTransforms huge(2, affine(1e308 * Eigen::Matrix2d::Identity(), Eigen::Vector2d::Zero()));
  Points X_big = X;
  X_big(1, 0) = 10.0;
  EXPECT_TRUE(throws_error([&] { linear_blend_skinning(X_big, W, huge); }, ErrorCode::NonFinite,
    { "point 1", "overflows" }));
  EXPECT_TRUE(throws_error([&] { linear_blend_skinning(X, W, two, -1); }, ErrorCode::InvalidArgument, { "threads" }));
}

TEST(PseudoEdges, RigidMotionIn2DIsRecovered)
{
  // Handles rotated by 30 degrees about (0.3, -0.2) and translated: every handle with pseudo
  // edges gets exactly that rotation, and every transform maps its handle onto its posed place.
  Points rest(4, 2);
  rest << 0, 0, 1, 0, 1, 1, 0.2, 0.7;
  const double theta = M_PI / 6.0;
  Eigen::Matrix2d R;
  R << std::cos(theta), -std::sin(theta), std::sin(theta), std::cos(theta);
  const Eigen::Vector2d c(0.3, -0.2), shift(2.0, 1.0);
  Points posed(4, 2);
  for (int h = 0; h < 4; ++h)
    posed.row(h) = (R * (rest.row(h).transpose() - c) + c + shift).transpose();
  const Eigen::MatrixXi edges = (Eigen::MatrixXi(3, 2) << 0, 1, 1, 2, 2, 0).finished(); // handle 3 has none
  const AffineTransforms T = transforms_from_pseudo_edges(rest, posed, edges);
  ASSERT_EQ(T.size(), 4u);
  for (int h = 0; h < 3; ++h)
    EXPECT_LE((T[h].leftCols(2) - R).cwiseAbs().maxCoeff(), 1e-14) << "handle " << h;
  EXPECT_LE((T[3].leftCols(2) - Eigen::Matrix2d::Identity()).cwiseAbs().maxCoeff(), 0.0);
  for (int h = 0; h < 4; ++h)
  {
    const Eigen::Vector2d moved = T[h].leftCols(2) * rest.row(h).transpose() + T[h].col(2);
    EXPECT_LE((moved - posed.row(h).transpose()).cwiseAbs().maxCoeff(), 1e-14);
  }
}

TEST(PseudoEdges, AnglesAreAveraged)
{
  // Handle 0 with two edges: one turned by +20 degrees, one by +40: it gets +30.
  Points rest(3, 2), posed(3, 2);
  rest << 0, 0, 1, 0, 0, 1;
  const double a = 20.0 * M_PI / 180.0, b = 40.0 * M_PI / 180.0;
  posed << 0, 0, std::cos(a), std::sin(a), -std::sin(b), std::cos(b);
  const AffineTransforms T =
    transforms_from_pseudo_edges(rest, posed, (Eigen::MatrixXi(2, 2) << 0, 1, 0, 2).finished());
  const double angle = std::atan2(T[0](1, 0), T[0](0, 0));
  EXPECT_NEAR(angle, 30.0 * M_PI / 180.0, 1e-14);
}

TEST(PseudoEdges, RigidMotionIn3DIsRecovered)
{
  // Handles in the plane z = 0.3, rotated about an axis along z and translated: every edge is
  // perpendicular to the axis, so its smallest rotation is exactly R, and so is the average.
  Points rest(4, 3);
  rest << 0, 0, 0.3, 1, 0, 0.3, 0, 1, 0.3, 0.6, 0.8, 0.3;
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Points posed = (rest * R.transpose()).rowwise() + Eigen::RowVector3d(0.5, -1.0, 2.0);
  const Eigen::MatrixXi edges = (Eigen::MatrixXi(5, 2) << 0, 1, 0, 2, 1, 2, 1, 3, 2, 3).finished();
  const AffineTransforms T = transforms_from_pseudo_edges(rest, posed, edges);
  ASSERT_EQ(T.size(), 4u);
  for (int h = 0; h < 4; ++h)
  {
    EXPECT_LE((T[h].leftCols(3) - R).cwiseAbs().maxCoeff(), 1e-14) << "handle " << h;
    const Eigen::Vector3d moved = T[h].leftCols(3) * rest.row(h).transpose() + T[h].col(3);
    EXPECT_LE((moved - posed.row(h).transpose()).cwiseAbs().maxCoeff(), 1e-14);
  }
  // Quaternion average: edges turned by 20 and 40 degrees about z give 30 degrees.
  Points rest2(3, 3), posed2(3, 3);
  rest2 << 0, 0, 0, 1, 0, 0, 0, 1, 0;
  const double a = 20.0 * M_PI / 180.0, b = 40.0 * M_PI / 180.0;
  posed2 << 0, 0, 0, std::cos(a), std::sin(a), 0, -std::sin(b), std::cos(b), 0;
  const AffineTransforms T2 =
    transforms_from_pseudo_edges(rest2, posed2, (Eigen::MatrixXi(2, 2) << 0, 1, 0, 2).finished());
  const Eigen::Matrix3d expected =
    Eigen::AngleAxisd(30.0 * M_PI / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  EXPECT_LE((T2[0].leftCols(3) - expected).cwiseAbs().maxCoeff(), 1e-14);
  // One edge in a general direction: exactly the smallest rotation taking it to its posed
  // direction (it fixes the axis r x q).
  const Eigen::Matrix3d S = Eigen::AngleAxisd(0.9, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const Points posed3 = rest * S.transpose();
  const AffineTransforms one =
    transforms_from_pseudo_edges(rest, posed3, (Eigen::MatrixXi(1, 2) << 0, 3).finished());
  const Eigen::Vector3d r = (rest.row(3) - rest.row(0)).transpose().normalized();
  const Eigen::Vector3d q = (posed3.row(3) - posed3.row(0)).transpose().normalized();
  const Eigen::Matrix3d A = one[0].leftCols(3);
  EXPECT_LE((A * r - q).cwiseAbs().maxCoeff(), 1e-14);
  const Eigen::Vector3d axis = r.cross(q).normalized();
  EXPECT_LE((A * axis - axis).cwiseAbs().maxCoeff(), 1e-14);
  EXPECT_NEAR(A.determinant(), 1.0, 1e-14);
}

TEST(PseudoEdges, Errors)
{
  Points rest(2, 2), posed(2, 2);
  rest << 0, 0, 1, 0;
  posed << 0, 0, 0, 1;
  EXPECT_TRUE(throws_error(
    [&] { transforms_from_pseudo_edges(rest, posed, (Eigen::MatrixXi(1, 2) << 0, 2).finished()); },
    ErrorCode::InvalidArgument, { "pseudo-edge 0" }));
  EXPECT_TRUE(throws_error(
    [&] { transforms_from_pseudo_edges(rest, posed, (Eigen::MatrixXi(1, 2) << 1, 1).finished()); },
    ErrorCode::InvalidArgument, { "itself" }));
  Points collapsed = posed;
  collapsed.row(1) = collapsed.row(0);
  EXPECT_TRUE(throws_error(
    [&] { transforms_from_pseudo_edges(rest, collapsed, (Eigen::MatrixXi(1, 2) << 0, 1).finished()); },
    ErrorCode::InvalidArgument, { "zero length when posed" }));
  EXPECT_TRUE(throws_error([&] { transforms_from_pseudo_edges(rest, Points(3, 2), Eigen::MatrixXi()); },
    ErrorCode::SizeMismatch));
  EXPECT_TRUE(throws_error([&] { transforms_from_pseudo_edges(Points(2, 4), Points(2, 4), Eigen::MatrixXi()); },
    ErrorCode::SizeMismatch));
  EXPECT_TRUE(throws_error([&] { transforms_from_pseudo_edges(rest, posed, Eigen::MatrixXi::Zero(1, 3)); },
    ErrorCode::SizeMismatch));
  Points nan = posed;
  nan(0, 0) = std::nan("");
  EXPECT_TRUE(throws_error([&] { transforms_from_pseudo_edges(rest, nan, Eigen::MatrixXi()); }, ErrorCode::NonFinite));
}

} // namespace
