// Tests for core/imaging: ImageGrid, displacement fields (trilinear sampling with ITK's rules,
// the Jacobian determinant, the inverse) and image resampling. References are analytic: affine
// and rigid fields, a sinusoidal field whose finite differences and inverse are known, shifted
// label maps.
#include "core/common/error.h"
#include "core/imaging/displacement_field.h"
#include "core/imaging/image_grid.h"
#include "core/imaging/image_resampling.h"
#include "error_matchers.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <limits>
#include <random>
#include <set>

namespace
{
using namespace bary;
using bary::test::throws_error;

/// A grid with anisotropic spacing, a non-zero origin and a rotated direction (unit columns).
ImageGrid oblique_grid(Index n0 = 12, Index n1 = 10, Index n2 = 9)
{
  ImageGrid g;
  g.size = { { n0, n1, n2 } };
  g.origin = Eigen::Vector3d(-3.0, 7.5, 1.25);
  g.spacing = Eigen::Vector3d(0.8, 1.1, 1.5);
  g.direction = Eigen::AngleAxisd(0.4, Eigen::Vector3d(1.0, 2.0, -0.5).normalized()).toRotationMatrix();
  return g;
}

/// The field of an analytic map f on the grid: u(p) = f(p) - p at the voxels.
template<class F>
DisplacementField field_of(const ImageGrid& g, F&& f)
{
  const Points P = grid_points(g);
  Points Q(P.rows(), 3);
  for (Index v = 0; v < P.rows(); ++v)
    Q.row(v) = f(Eigen::Vector3d(P.row(v).transpose())).transpose();
  return displacement_field_from_points(g, Q);
}

/// Random physical points whose continuous indices lie in [lo, n - 1 - lo] on every axis.
std::vector<Eigen::Vector3d> points_inside(const ImageGrid& g, int count, double lo, unsigned seed)
{
  std::mt19937 rng(seed);
  std::vector<Eigen::Vector3d> P;
  for (int s = 0; s < count; ++s)
  {
    Eigen::Vector3d c;
    for (int a = 0; a < 3; ++a)
      c(a) = std::uniform_real_distribution<double>(lo, double(g.size[a] - 1) - lo)(rng);
    P.push_back(g.point(c));
  }
  return P;
}

TEST(ImageGrid, IndexAndPointAreInverseForAnObliqueGrid)
{
  ImageGrid g = oblique_grid();
  // a non-orthogonal (sheared) direction with unit columns is supported
  g.direction.col(1) = (g.direction.col(1) + 0.3 * g.direction.col(0)).normalized();
  validate_image_grid(g);
  const Eigen::Vector3d c(2.25, -0.5, 7.75);
  const Eigen::Vector3d p = g.point(c);
  EXPECT_LE((g.continuous_index(p) - c).norm(), 1e-12);
  // the definition: origin + direction (spacing ∘ index)
  const Eigen::Vector3d expected =
    g.origin + c(0) * 0.8 * g.direction.col(0) + c(1) * 1.1 * g.direction.col(1) + c(2) * 1.5 * g.direction.col(2);
  EXPECT_LE((p - expected).norm(), 1e-12);
  const Points P = grid_points(g);
  EXPECT_LE((P.row(g.voxel(3, 4, 5)).transpose() - g.point(3, 4, 5)).norm(), 1e-12);
}

TEST(ImageGrid, FromBoundsCoversTheBox)
{
  const ImageGrid g =
    grid_from_bounds(Eigen::Vector3d(-1, 0, 2), Eigen::Vector3d(1, 0.95, 2), Eigen::Vector3d(0.5, 0.25, 1));
  EXPECT_EQ(g.size[0], 5); // -1, -0.5, 0, 0.5, 1
  EXPECT_EQ(g.size[1], 5); // 0 .. 1 (the last centre beyond 0.95)
  EXPECT_EQ(g.size[2], 1);
  EXPECT_TRUE(throws_error([] { grid_from_bounds(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), Eigen::Vector3d(0.1, 0, 0.1)); },
    ErrorCode::InvalidArgument, { "spacing" }));
  EXPECT_TRUE(throws_error([] { grid_from_bounds(Eigen::Vector3d::Ones(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones()); },
    ErrorCode::InvalidArgument, { "inverted" }));
  EXPECT_TRUE(throws_error([] { grid_from_bounds(Eigen::Vector3d::Zero(), Eigen::Vector3d::Constant(1e6), Eigen::Vector3d::Constant(1e-3)); },
    ErrorCode::InvalidArgument, { "2^31" }));
}

TEST(ImageGrid, ValidationNamesTheProblem)
{
  ImageGrid g = oblique_grid();
  g.spacing(1) = 0.0;
  EXPECT_TRUE(throws_error([&] { validate_image_grid(g, "the reference image"); },
    ErrorCode::InvalidArgument, { "the reference image", "spacing", "positive" }));
  g = oblique_grid();
  g.direction.col(2) = g.direction.col(0);
  EXPECT_TRUE(throws_error([&] { validate_image_grid(g); }, ErrorCode::InvalidArgument, { "singular" }));
  g = oblique_grid();
  g.direction(0, 0) = 2.0;
  EXPECT_TRUE(throws_error([&] { validate_image_grid(g); }, ErrorCode::InvalidArgument, { "unit" }));
  g = oblique_grid();
  g.origin(2) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(throws_error([&] { validate_image_grid(g); }, ErrorCode::NonFinite, { "origin" }));
  g = oblique_grid();
  g.size[1] = 0;
  EXPECT_TRUE(throws_error([&] { validate_image_grid(g); }, ErrorCode::InvalidArgument, { "axis 1" }));
}

TEST(DisplacementField, TrilinearReproducesAnAffineFieldExactly)
{
  const ImageGrid g = oblique_grid();
  Eigen::Matrix3d A;
  A << 0.1, -0.2, 0.05, 0.3, 0.0, -0.1, 0.02, 0.15, -0.25;
  const Eigen::Vector3d b(1.0, -2.0, 0.5);
  const DisplacementField field = field_of(g, [&](const Eigen::Vector3d& p) { return Eigen::Vector3d(p + A * p + b); });
  const FieldSampler sampler(field);
  // between the outer voxel centres trilinear interpolation is exact for affine functions;
  // rounding: |A p + b| ~ 10, so 1e-12 relative
  for (const Eigen::Vector3d& p : points_inside(g, 500, 0.0, 1))
    EXPECT_LE((sampler.displacement(p) - (A * p + b)).norm(), 1e-12 * (1.0 + (A * p + b).norm()));
  const Points P = grid_points(g);
  const Points moved = transform_points(field, P.topRows(50), 2);
  for (Index v = 0; v < 50; ++v)
  {
    const Eigen::Vector3d p = P.row(v).transpose();
    EXPECT_LE((moved.row(v).transpose() - (p + A * p + b)).norm(), 1e-12 * (1.0 + p.norm()));
  }
}

TEST(DisplacementField, OutsideAndBorderFollowITK)
{
  // itk::DisplacementFieldTransform (ITK 5.2): inside iff every continuous index is in
  // [-0.5, n - 0.5); neighbours clamped to the grid; outside: zero displacement.
  const ImageGrid g = oblique_grid(4, 5, 6);
  const DisplacementField field = field_of(g, [](const Eigen::Vector3d& p) {
    return Eigen::Vector3d(p + Eigen::Vector3d(p(1), 2.0, -p(0)));
  });
  const FieldSampler sampler(field);
  const Eigen::Vector3d border = g.point(Eigen::Vector3d(-0.4, 2.0, 3.0)); // half-voxel margin
  const Eigen::Vector3d border_voxel = g.point(Eigen::Vector3d(0.0, 2.0, 3.0));
  EXPECT_TRUE(sampler.inside(border));
  EXPECT_LE((sampler.displacement(border) - field.values.col(g.voxel(0, 2, 3))).norm(), 1e-12);
  EXPECT_LE((sampler.displacement(border) - Eigen::Vector3d(border_voxel(1), 2.0, -border_voxel(0))).norm(), 1e-12);
  const Eigen::Vector3d upper = g.point(Eigen::Vector3d(3.49, 2.0, 3.0));
  EXPECT_TRUE(sampler.inside(upper));
  EXPECT_LE((sampler.displacement(upper) - field.values.col(g.voxel(3, 2, 3))).norm(), 1e-12);
  for (const Eigen::Vector3d& c : { Eigen::Vector3d(-0.51, 2, 3), Eigen::Vector3d(3.5, 2, 3),
         Eigen::Vector3d(1, 2, 5.5), Eigen::Vector3d(1, -7, 3) })
  {
    EXPECT_FALSE(sampler.inside(g.point(c))) << c.transpose();
    EXPECT_EQ(sampler.displacement(g.point(c)), Eigen::Vector3d::Zero()) << c.transpose();
  }
}

TEST(DisplacementField, InverseOfARigidFieldIsTheInverseRigidMotion)
{
  ImageGrid g;
  g.size = { { 21, 19, 17 } };
  g.spacing = Eigen::Vector3d(0.5, 0.6, 0.7);
  g.origin = Eigen::Vector3d(-5, -5.4, -5.6);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.17, Eigen::Vector3d(0.3, -1, 0.6).normalized()).toRotationMatrix();
  const Eigen::Vector3d t(0.4, -0.3, 0.2);
  // |R - I| = 2 sin(0.085) ~ 0.17: a contraction, the plain iteration converges
  const DisplacementField field = field_of(g, [&](const Eigen::Vector3d& p) { return Eigen::Vector3d(R * p + t); });
  InverseFieldOptions options;
  options.threads = 2;
  const InverseFieldResult inv = invert_displacement_field(field, options);
  EXPECT_DOUBLE_EQ(inv.tolerance, 1e-4 * 0.5);
  const FieldSampler sampler(field);
  Index checked = 0, interior_not_converged = 0;
  for (Index k = 0; k < g.size[2]; ++k)
    for (Index j = 0; j < g.size[1]; ++j)
      for (Index i = 0; i < g.size[0]; ++i)
      {
        const Eigen::Vector3d y = g.point(i, j, k);
        const Eigen::Vector3d x_star = R.transpose() * (y - t);
        const Eigen::Vector3d c = g.continuous_index(x_star);
        // where the preimage is between the outer voxel centres the sampled field is the rigid
        // motion exactly; the converged iterate is within the tolerance of x* (R is an isometry)
        if ((c.array() < 1.0).any() || (c.array() > Eigen::Array3d(g.size[0] - 2.0, g.size[1] - 2.0, g.size[2] - 2.0)).any())
          continue;
        ++checked;
        const Eigen::Vector3d v = inv.inverse.values.col(g.voxel(i, j, k));
        const Eigen::Vector3d x = y + v;
        if ((x + sampler.displacement(x) - y).norm() > inv.tolerance)
          ++interior_not_converged;
        EXPECT_LE((x - x_star).norm(), inv.tolerance * (1.0 + 1e-9)) << i << " " << j << " " << k;
      }
  EXPECT_GT(checked, 1000);
  EXPECT_EQ(interior_not_converged, 0);
  EXPECT_LE(inv.not_converged, inv.voxels - checked); // only where the preimage is near or outside the border
  EXPECT_EQ(inv.not_converged, inv.not_converged_at_border);
  EXPECT_GE(inv.max_residual, 0.0);
  EXPECT_LE(inv.mean_residual, inv.max_residual);
}

TEST(DisplacementField, ForwardThenInverseReturnsThePointsOnASmoothField)
{
  // u = A (sin k y, sin k z, sin k x): Lipschitz L = A k = 0.3. Bounds (isotropic spacing h,
  // trilinear error <= h^2 / 8 sum_a max |d_aa f| per component):
  //   e_u = sqrt(3) h^2 A k^2 / 8 (the sampled u against the analytic u),
  //   the inverse v: |v''| <= A k^2 / (1 - L)^3, e_v = sqrt(3) 3 h^2 A k^2 / (8 (1 - L)^3),
  //   nodal inverse of the sampled field against the analytic inverse <= e_u / (1 - L) + tol,
  // so |T_h(y + I_h v_h(y)) - y| <= e_u + (1 + L) (e_u / (1 - L) + tol + e_v).
  const double A = 0.6, k = 0.5, L = A * k;
  auto run = [&](double h, unsigned seed) {
    ImageGrid g;
    const Index n = Index(std::lround(12.0 / h)) + 1;
    g.size = { { n, n, n } };
    g.spacing = Eigen::Vector3d::Constant(h);
    g.origin = Eigen::Vector3d::Constant(-6.0);
    const DisplacementField field = field_of(g, [&](const Eigen::Vector3d& p) {
      return Eigen::Vector3d(p + A * Eigen::Vector3d(std::sin(k * p(1)), std::sin(k * p(2)), std::sin(k * p(0))));
    });
    const InverseFieldResult inv = invert_displacement_field(field);
    // the field does not vanish at the grid's border, where ITK's rule cuts it to zero: voxels
    // whose preimage is beyond the grid do not converge, and only those
    EXPECT_EQ(inv.not_converged - inv.not_converged_at_border, 0) << "h " << h;
    EXPECT_GT(inv.not_converged_at_border, 0) << "h " << h;
    const double e_u = std::sqrt(3.0) * h * h * A * k * k / 8.0;
    const double e_v = std::sqrt(3.0) * 3.0 * h * h * A * k * k / (8.0 * std::pow(1.0 - L, 3));
    const double bound = e_u + (1.0 + L) * (e_u / (1.0 - L) + inv.tolerance + e_v);
    const FieldSampler forward(field), backward(inv.inverse);
    // at the voxels more than max |u| + 1 from the border every residual is within the tolerance
    const Index m = Index(std::ceil((A + 1.0) / h));
    double worst_node = 0.0;
    for (Index kk = m; kk < n - m; ++kk)
      for (Index jj = m; jj < n - m; ++jj)
        for (Index ii = m; ii < n - m; ++ii)
        {
          const Eigen::Vector3d y = g.point(ii, jj, kk), x = y + inv.inverse.values.col(g.voxel(ii, jj, kk));
          worst_node = std::max(worst_node, (x + forward.displacement(x) - y).norm());
        }
    EXPECT_LE(worst_node, inv.tolerance) << "h " << h;
    double worst = 0.0;
    // away from the border by more than max |u| = A, so that every preimage is inside
    for (const Eigen::Vector3d& y : points_inside(g, 400, (A + 1.0) / h, seed))
    {
      const Eigen::Vector3d x = y + backward.displacement(y);
      worst = std::max(worst, (x + forward.displacement(x) - y).norm());
    }
    EXPECT_LE(worst, bound) << "h " << h;
    return worst;
  };
  const double coarse = run(0.5, 3), fine = run(0.25, 4);
  // second order: halving h divides the error by about 4
  EXPECT_LT(fine, coarse / 2.5);
}

TEST(DisplacementField, JacobianMatchesCentralDifferencesAndReportsFolds)
{
  // u = (a sin(k x), 0, 0): central differences give det = 1 + a k cos(k x) sin(k h) / (k h)
  // at the interior voxels exactly (up to rounding); a k > 1 folds where that is <= 0.
  ImageGrid g;
  g.size = { { 40, 3, 3 } };
  g.spacing = Eigen::Vector3d(0.25, 1, 1);
  const double k = 0.7, h = 0.25;
  for (const double a : { 0.5, 2.5 })
  {
    const DisplacementField field = field_of(g, [&](const Eigen::Vector3d& p) {
      return Eigen::Vector3d(p(0) + a * std::sin(k * p(0)), p(1), p(2));
    });
    Eigen::VectorXd det;
    const JacobianStatistics s = jacobian_statistics(field, 2, &det);
    Index folded = 0;
    for (Index i = 1; i + 1 < g.size[0]; ++i)
    {
      const double expected = 1.0 + a * k * std::cos(k * i * h) * std::sin(k * h) / (k * h);
      EXPECT_NEAR(det(g.voxel(i, 1, 1)), expected, 1e-12) << i;
      if (expected <= 0.0)
        folded += 9; // the 3 x 3 voxels of that x
    }
    if (a < 1.0 / k)
    {
      EXPECT_EQ(s.folded, 0);
      EXPECT_EQ(s.first_folded, -1);
      EXPECT_GT(s.minimum, 0.0);
    }
    else
    {
      EXPECT_GT(folded, 0);
      EXPECT_GE(s.folded, folded); // the one-sided ends may add their own
      EXPECT_LT(s.minimum, 0.0);
      EXPECT_GE(s.first_folded, 0);
      EXPECT_LE(det(s.first_folded), 0.0);
      // a folded field has no inverse: the iteration cannot converge everywhere, and says so
      const InverseFieldResult inv = invert_displacement_field(field);
      EXPECT_GT(inv.not_converged, 0);
      EXPECT_GE(inv.first_not_converged, 0);
      EXPECT_GT(inv.max_residual, inv.tolerance);
    }
  }
}

TEST(DisplacementField, ResultsDoNotDependOnTheThreadCount)
{
  const ImageGrid g = oblique_grid(30, 25, 20);
  const DisplacementField field = field_of(g, [](const Eigen::Vector3d& p) {
    return Eigen::Vector3d(p + 0.4 * Eigen::Vector3d(std::sin(0.3 * p(1)), std::cos(0.2 * p(2)), std::sin(0.25 * p(0))));
  });
  InverseFieldOptions one, two;
  one.threads = 1;
  two.threads = 2;
  const InverseFieldResult a = invert_displacement_field(field, one), b = invert_displacement_field(field, two);
  EXPECT_TRUE(a.inverse.values == b.inverse.values);
  EXPECT_EQ(a.mean_residual, b.mean_residual);
  EXPECT_EQ(a.max_residual, b.max_residual);
  EXPECT_EQ(a.not_converged, b.not_converged);
  EXPECT_EQ(jacobian_statistics(field, 1).minimum, jacobian_statistics(field, 2).minimum);
}

TEST(DisplacementField, BadInputIsRefused)
{
  DisplacementField field = field_of(oblique_grid(4, 4, 4), [](const Eigen::Vector3d& p) { return p; });
  field.values(1, 37) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(throws_error([&] { FieldSampler s(field); }, ErrorCode::NonFinite, { "voxel (1, 1, 2)" }));
  EXPECT_TRUE(throws_error([&] { invert_displacement_field(field); }, ErrorCode::NonFinite, { "NaN" }));
  field.values.resize(3, 10);
  field.values.setZero();
  EXPECT_TRUE(throws_error([&] { jacobian_statistics(field); }, ErrorCode::SizeMismatch, { "10 displacements for 64 voxels" }));
  const ImageGrid g = oblique_grid(4, 4, 4);
  EXPECT_TRUE(throws_error([&] { displacement_field_from_points(g, Points::Zero(63, 3)); }, ErrorCode::SizeMismatch));
  Points Q = grid_points(g);
  Q(5, 0) = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(throws_error([&] { displacement_field_from_points(g, Q); }, ErrorCode::NonFinite, { "voxel (1, 1, 0)" }));
  const DisplacementField ok = field_of(g, [](const Eigen::Vector3d& p) { return p; });
  EXPECT_TRUE(throws_error([&] { transform_points(ok, Points::Zero(3, 2)); }, ErrorCode::SizeMismatch));
  Points P = Points::Zero(2, 3);
  P(1, 2) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(throws_error([&] { transform_points(ok, P); }, ErrorCode::NonFinite));
  InverseFieldOptions bad;
  bad.max_iterations = 0;
  EXPECT_TRUE(throws_error([&] { invert_displacement_field(ok, bad); }, ErrorCode::InvalidArgument, { "iterations" }));
}

ScalarImage random_labels(const ImageGrid& g, unsigned seed)
{
  std::mt19937 rng(seed);
  const double labels[] = { 0, 1, 2, 1000, 65535 };
  ScalarImage im;
  im.grid = g;
  im.values.resize(size_t(g.voxel_count()));
  for (double& v : im.values)
    v = labels[std::uniform_int_distribution<int>(0, 4)(rng)];
  return im;
}

TEST(ImageResampling, IdentityWarpLeavesTheImageUnchanged)
{
  const ImageGrid g = oblique_grid();
  ScalarImage im = random_labels(g, 5);
  std::mt19937 rng(6);
  for (double& v : im.values)
    v += std::uniform_real_distribution<double>(-0.5, 0.5)(rng);
  DisplacementField zero;
  zero.grid = g;
  zero.values = Eigen::Matrix3Xd::Zero(3, g.voxel_count());
  for (const Interpolation mode : { Interpolation::Nearest, Interpolation::Linear })
  {
    ResampleOptions options;
    options.interpolation = mode;
    const ResampleResult a = warp_image(im, g, zero, options);
    EXPECT_TRUE(a.values == im.values);
    EXPECT_EQ(a.outside, 0);
    const ResampleResult b = resample_image(im, g, PointMap{}, options);
    EXPECT_TRUE(b.values == im.values);
  }
}

TEST(ImageResampling, NearestNeighbourPreservesLabels)
{
  const ImageGrid g = oblique_grid(20, 18, 16);
  const ScalarImage im = random_labels(g, 7);
  // a pull-back by exactly two voxels along i: out(i, j, k) = in(i + 2, j, k), the default
  // value where i + 2 is beyond the image
  const Eigen::Vector3d shift = 2.0 * g.spacing(0) * g.direction.col(0);
  ResampleOptions options;
  options.interpolation = Interpolation::Nearest;
  options.default_value = -1;
  const ResampleResult r = resample_image(
    im, g, [&](const Eigen::Vector3d& y) { return Eigen::Vector3d(y + shift); }, options);
  for (Index k = 0; k < g.size[2]; ++k)
    for (Index j = 0; j < g.size[1]; ++j)
      for (Index i = 0; i < g.size[0]; ++i)
        ASSERT_EQ(r.values[size_t(g.voxel(i, j, k))],
          i + 2 < g.size[0] ? im.values[size_t(g.voxel(i + 2, j, k))] : -1.0);
  EXPECT_EQ(r.outside, 2 * g.size[1] * g.size[2]);
  // through a smooth field's inverse: only the input's labels (or the default) come out
  const DisplacementField field = field_of(g, [](const Eigen::Vector3d& p) {
    return Eigen::Vector3d(p + 0.7 * Eigen::Vector3d(std::sin(0.4 * p(1)), std::sin(0.3 * p(2)), std::cos(0.35 * p(0))));
  });
  const InverseFieldResult inv = invert_displacement_field(field);
  const ResampleResult w = warp_image(im, g, inv.inverse, options);
  const std::set<double> allowed = { -1, 0, 1, 2, 1000, 65535 };
  for (const double v : w.values)
    ASSERT_TRUE(allowed.count(v)) << v;
}

TEST(ImageResampling, LinearInterpolationIsExactForAffineIntensities)
{
  const ImageGrid g = oblique_grid();
  const Eigen::Vector3d a(0.3, -1.2, 0.7);
  ScalarImage im;
  im.grid = g;
  const Points P = grid_points(g);
  for (Index v = 0; v < P.rows(); ++v)
    im.values.push_back(5.0 + a.dot(P.row(v).transpose()));
  // a small rotation about the image's centre: the output voxels far from the border map inside
  const Eigen::Vector3d centre = g.point(Eigen::Vector3d(5.5, 4.5, 4.0));
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const PointMap map = [&](const Eigen::Vector3d& y) { return Eigen::Vector3d(centre + R * (y - centre)); };
  const ResampleResult r = resample_image(im, g, map, {});
  Index checked = 0;
  for (Index v = 0; v < P.rows(); ++v)
  {
    const Eigen::Vector3d x = map(P.row(v).transpose());
    const Eigen::Vector3d c = g.continuous_index(x);
    if ((c.array() < 0).any() || (c.array() > Eigen::Array3d(11, 9, 8)).any())
      continue;
    ++checked;
    EXPECT_NEAR(r.values[size_t(v)], 5.0 + a.dot(x), 1e-11);
  }
  EXPECT_GT(checked, 300);
}

TEST(ImageResampling, BadInputIsRefused)
{
  const ImageGrid g = oblique_grid(3, 3, 3);
  ScalarImage im = random_labels(g, 8);
  im.values[4] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(throws_error([&] { resample_image(im, g, PointMap{}); }, ErrorCode::NonFinite, { "voxel 4" }));
  im.values.pop_back();
  EXPECT_TRUE(throws_error([&] { resample_image(im, g, PointMap{}); }, ErrorCode::SizeMismatch, { "26 values for 27 voxels" }));
  im = random_labels(g, 8);
  EXPECT_TRUE(throws_error([&] {
    resample_image(im, g, [](const Eigen::Vector3d&) { return Eigen::Vector3d::Constant(std::nan("")); });
  }, ErrorCode::NonFinite, { "NaN" }));
  DisplacementField wrong;
  wrong.grid = g;
  wrong.values = Eigen::Matrix3Xd::Zero(3, 5);
  EXPECT_TRUE(throws_error([&] { warp_image(im, g, wrong); }, ErrorCode::SizeMismatch));
}

} // namespace
