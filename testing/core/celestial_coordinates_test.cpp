// Tests for core/coordinates/celestial_coordinates.h (T- and S-Celestial coordinates, Cerveró et al. 2016).
//
// What is checked, on random control sets with fixed seeds, in 2D and 3D, for both schemes:
// positivity, partition of unity, reproduction, the Lagrange property, smoothness (finite
// differences along segments), similarity invariance (and the lack of affine invariance),
// independence of lambda (SCC), the hull boundary (faces, edges, vertices, collinear and
// coplanar controls on a face, continuity from inside), points outside (both policies),
// every validation branch, warm versus cold starts, thread-count independence, cancellation,
// and non-convergence. Independent checks recompute Eq. (9) (TCC) and Eq. (11)/(15) (SCC) in
// long double from the returned psi / c, and Eq. (3) from them; 1D faces have a closed form.
//
// Tolerances. u = 2^-53 ~ 1.1e-16.
// - Partition of unity: each row is divided by its sum: |sum - 1| <= (n + 1) u ~ 7e-15 for the
//   n <= 60 controls used; kSumTol = 1e-14.
// - Reproduction: Newton stops at |sum beta_i q_i| <= tol * sum beta_i, which bounds
//   |sum alpha_i v_i - p| by tol * max d_i <= tol * diam (tol = 1e-12 by default), plus the
//   rounding of the sum, n u max|v_i| ~ 1e-14 diam. kReproTol = 2e-12 (of the diameter).
// - Independent residuals (long double): the returned solution is the one Newton stopped at,
//   whose relative residual was <= 1e-12 in double; recomputing q_i in long double moves it by
//   ~ u * |x| * n; kEquationTol = 1e-11.
// - Invariance: two solves with tolerance 1e-12 each give weights within ~ cond * 1e-12;
//   kInvarianceTol = 1e-9 (measured: <= 2e-12).
// - Warm vs cold: both stop within the tolerance of the same root: kWarmColdTol = 1e-9.
// - The AVX2 kernels against the portable code (core/detail/simd.h): fused multiply-adds, sums
//   in four lanes and predicted warm starts move Newton's path, not its root: kWarmColdTol
//   (measured: <= 2.5e-12 on 1e6 interior points; up to 2.4e-8 within 1e-10 of a face, where
//   Newton stops at the rounding floor ~1e-10 instead of 1e-12).
#include "core/coordinates/celestial_coordinates.h"
#include "core/common/error.h"
#include "core/detail/simd.h"
#include "error_matchers.h"
#include "statistics_matchers.h"

#include <Eigen/Geometry>
#include <Eigen/QR>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <numeric>
#include <random>
#include <string>
#include <vector>

namespace bary
{
void PrintTo(CelestialLocation l, std::ostream* os)
{
  const char* names[] = { "Inside", "Boundary", "AtControl", "Outside" };
  *os << names[static_cast<int>(l)];
}
void PrintTo(CelestialScheme s, std::ostream* os)
{
  *os << (s == CelestialScheme::T ? "T" : "S");
}
} // namespace bary

namespace
{
using namespace bary;
using bary::test::throws_error;

constexpr double kSumTol = 1e-14;
constexpr double kReproTol = 2e-12;
constexpr double kEquationTol = 1e-11;
constexpr double kInvarianceTol = 1e-9;
constexpr double kWarmColdTol = 1e-9;
// - Near the hull (within ~1e-8 of the diameter) |x| grows (SCC: |y| ~ h^-1/2, 1e5 at
//   h = 1e-10) and the rounding of a_i = x . q_i (~ u |x|_1) becomes the floor of the
//   residual; Newton then stops at 4 u (|x|_1 + n) (see celestial_coordinates.cpp):
//   kNearHullReproTol = 1e-10.
constexpr double kNearHullReproTol = 1e-10;

using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// %.3g, for RecordProperty (std::to_string prints 0.000000 for 1e-13).
std::string sci(double v)
{
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

double diameter(const Points& V)
{
  return (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm();
}

/// n controls uniform in [-1, 1]^dim plus, if box, the 2^dim corners of [-1.2, 1.2]^dim first.
Points random_controls(int dim, int n, unsigned seed, bool box)
{
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  const int corners = box ? (1 << dim) : 0;
  Points V(corners + n, dim);
  for (int c = 0; c < corners; ++c)
    for (int k = 0; k < dim; ++k)
      V(c, k) = (c >> k) & 1 ? 1.2 : -1.2;
  for (int i = corners; i < corners + n; ++i)
    for (int k = 0; k < dim; ++k)
      V(i, k) = U(rng);
  return V;
}

/// count points inside the hull of V: convex combinations with Exp(1)^3 weights (so some lie
/// near the boundary, none on it), and a few at the centroid of random pairs / triples.
Points random_inside(const Points& V, int count, unsigned seed)
{
  std::mt19937_64 rng(seed);
  std::exponential_distribution<double> E(1.0);
  Points X(count, V.cols());
  for (int p = 0; p < count; ++p)
  {
    Eigen::VectorXd l(V.rows());
    for (Index i = 0; i < V.rows(); ++i)
      l[i] = std::pow(E(rng), 3.0);
    l /= l.sum();
    X.row(p) = l.transpose() * V;
  }
  return X;
}

struct RowErrors
{
  double sum = 0, repro = 0, min_w = std::numeric_limits<double>::infinity();
};

/// Max over rows of |sum w - 1| and |W V - X| / diam, and the min weight.
RowErrors row_errors(const DenseWeights& W, const Points& V, const Points& X)
{
  RowErrors e;
  const double diam = diameter(V);
  for (Index p = 0; p < W.rows(); ++p)
  {
    e.sum = std::max(e.sum, std::abs(W.row(p).sum() - 1.0));
    e.repro = std::max(e.repro, (W.row(p) * V - X.row(p)).norm() / diam);
    e.min_w = std::min(e.min_w, W.row(p).minCoeff());
  }
  return e;
}

CelestialOptions options_for(CelestialScheme scheme)
{
  CelestialOptions o;
  o.scheme = scheme;
  return o;
}

// ------------------------------------------------------------------------------------------
// Properties over schemes x dimensions x control sets.

struct Config
{
  CelestialScheme scheme;
  int dim;
  int n;
  bool box;
};

std::string config_name(const ::testing::TestParamInfo<Config>& info)
{
  const Config& c = info.param;
  return std::string(c.scheme == CelestialScheme::T ? "T" : "S") + std::to_string(c.dim) + "D_" +
    std::to_string(c.n) + (c.box ? "_box" : "");
}

class CelestialProperties : public ::testing::TestWithParam<Config>
{
protected:
  Points controls() const
  {
    const Config& c = GetParam();
    return random_controls(c.dim, c.n, 1000u + static_cast<unsigned>(c.n * 10 + c.dim), c.box);
  }
};

TEST_P(CelestialProperties, PositivePartitionOfUnityReproduction)
{
  const Points V = controls();
  const Points X = random_inside(V, 400, 7);
  const CelestialResult r = celestial_coordinates(V, X, options_for(GetParam().scheme));
  ASSERT_EQ(r.W.rows(), X.rows());
  ASSERT_EQ(r.W.cols(), V.rows());
  EXPECT_TRUE(r.outside.empty());
  EXPECT_TRUE(r.not_converged.empty());
  EXPECT_EQ(r.inside, X.rows());
  const RowErrors e = row_errors(r.W, V, X);
  EXPECT_LE(e.sum, kSumTol);
  EXPECT_LE(e.repro, kReproTol);
  EXPECT_GT(e.min_w, 0.0);
  EXPECT_LE(r.residual.maxCoeff(), 1e-12);
  RecordProperty("max_sum_error", sci(e.sum));
  RecordProperty("max_reproduction_error", sci(e.repro));
  RecordProperty("mean_iterations", sci(r.iterations.cast<double>().mean()));
}

TEST_P(CelestialProperties, LagrangeAtControls)
{
  const Points V = controls();
  const CelestialResult r = celestial_coordinates(V, V, options_for(GetParam().scheme));
  for (Index i = 0; i < V.rows(); ++i)
  {
    EXPECT_EQ(r.hull_location[static_cast<std::size_t>(i)], CelestialLocation::AtControl);
    for (Index j = 0; j < V.rows(); ++j)
      ASSERT_EQ(r.W(i, j), i == j ? 1.0 : 0.0) << "control " << i << ", weight " << j;
  }
  EXPECT_EQ(r.at_control, V.rows());
}

// Finite differences along random segments inside the hull: the weights are continuous (first
// differences O(h)) and smooth: second differences divided by h^2 stay bounded as h shrinks
// (a kink would make them grow like 1/h, a jump like 1/h^2).
TEST_P(CelestialProperties, SmoothAlongSegments)
{
  const Points V = controls();
  const Points ends = random_inside(V, 8, 99);
  const CelestialCoordinates cc(V, options_for(GetParam().scheme));
  const int dim = static_cast<int>(V.cols());
  for (int seg = 0; seg + 1 < ends.rows(); seg += 2)
  {
    const Eigen::RowVectorXd a = ends.row(seg), b = ends.row(seg + 1);
    const double len = (b - a).norm();
    const Eigen::RowVectorXd u = (b - a) / len;
    double prev_m = -1.0;
    for (double h : { 1e-2, 2.5e-3 })
    {
      // 15 evaluation points t_k, each with t_k -/+ h
      Points X(45, dim);
      for (int k = 0; k < 15; ++k)
      {
        const Eigen::RowVectorXd c = a + (0.2 + 0.6 * k / 14.0) * (b - a);
        X.row(3 * k) = c - h * len * u;
        X.row(3 * k + 1) = c;
        X.row(3 * k + 2) = c + h * len * u;
      }
      const CelestialResult r = cc.compute(X);
      double m = 0.0, first = 0.0;
      for (int k = 0; k < 15; ++k)
      {
        const Eigen::RowVectorXd d2 =
          r.W.row(3 * k) - 2.0 * r.W.row(3 * k + 1) + r.W.row(3 * k + 2);
        m = std::max(m, d2.cwiseAbs().maxCoeff() / (h * h));
        first =
          std::max(first, (r.W.row(3 * k + 2) - r.W.row(3 * k)).cwiseAbs().maxCoeff() / (2 * h));
      }
      EXPECT_LT(first, 50.0) << "segment " << seg << ", h " << h;
      if (prev_m >= 0.0)
      {
        EXPECT_LT(m, 1.5 * prev_m + 1e-3)
          << "segment " << seg << ": second differences grow as h shrinks";
      }
      prev_m = m;
    }
  }
}

// Both schemes depend only on the unit vectors q_i and the ratios of the d_i, so a similarity
// (rotation, translation, uniform scale) of controls and points together leaves the weights
// unchanged — also for TCC, whose Eq. (9) is covariant: psi -> R psi. (The paper, Sect. 6,
// says TCC is not rotation invariant; with the unique solution of Eq. (9) it is.)
TEST_P(CelestialProperties, SimilarityInvariant)
{
  const Points V = controls();
  const Points X = random_inside(V, 200, 3);
  const int dim = static_cast<int>(V.cols());
  Eigen::MatrixXd R(dim, dim);
  if (dim == 2)
    R = Eigen::Rotation2Dd(0.7).toRotationMatrix();
  else
    R = Eigen::AngleAxisd(1.1, Eigen::Vector3d(1, -2, 0.5).normalized()).toRotationMatrix();
  const Eigen::RowVectorXd t = Eigen::RowVectorXd::LinSpaced(dim, 3.0, -5.0);
  const double scale = 7.5;
  const Points V2 = (scale * V * R.transpose()).rowwise() + t;
  const Points X2 = (scale * X * R.transpose()).rowwise() + t;
  const CelestialOptions o = options_for(GetParam().scheme);
  const CelestialResult a = celestial_coordinates(V, X, o);
  const CelestialResult b = celestial_coordinates(V2, X2, o);
  const double diff = (a.W - b.W).cwiseAbs().maxCoeff();
  EXPECT_LE(diff, kInvarianceTol);
  RecordProperty("max_weight_change", sci(diff));
  if (o.scheme == CelestialScheme::T)
  { // psi rotates with the configuration
    const Points psi2 = a.solution * R.transpose();
    EXPECT_LE(
      (psi2 - b.solution).cwiseAbs().maxCoeff(), 1e-7 * (1.0 + a.solution.cwiseAbs().maxCoeff()));
  }
}

// ... but not under affine maps: stretching one axis changes the weights (unlike barycentric
// coordinates of a simplex, which are affine invariant).
TEST_P(CelestialProperties, NotAffineInvariant)
{
  const Points V = controls();
  const Points X = random_inside(V, 100, 4);
  Eigen::MatrixXd A = Eigen::MatrixXd::Identity(V.cols(), V.cols());
  A(0, 0) = 3.0;
  const CelestialOptions o = options_for(GetParam().scheme);
  const CelestialResult a = celestial_coordinates(V, X, o);
  const CelestialResult b = celestial_coordinates(V * A, X * A, o);
  EXPECT_GT((a.W - b.W).cwiseAbs().maxCoeff(), 1e-3);
}

// Independent check of the equations the weights come from, in long double, from the returned
// unknown: TCC Eq. (9) sum_i exp(psi . q_i) q_i = r; SCC Eq. (11) sum_i mu_i^2 q_i = 0 with
// mu_i from Eq. (15); and Eq. (3) alpha_i = (beta_i / d_i) / sum_j (beta_j / d_j).
TEST_P(CelestialProperties, SolutionSatisfiesThePapersEquations)
{
  const Points V = controls();
  const Points X = random_inside(V, 150, 11);
  CelestialOptions o = options_for(GetParam().scheme);
  o.lambda = 1.7;
  const CelestialResult r = celestial_coordinates(V, X, o);
  const Index n = V.rows();
  const int dim = static_cast<int>(V.cols());
  double worst_eq = 0.0, worst_alpha = 0.0;
  for (Index p = 0; p < X.rows(); ++p)
  {
    ASSERT_EQ(r.hull_location[static_cast<std::size_t>(p)], CelestialLocation::Inside);
    std::vector<long double> beta(static_cast<std::size_t>(n)), d(static_cast<std::size_t>(n));
    std::vector<std::array<long double, 3>> q(static_cast<std::size_t>(n));
    for (Index i = 0; i < n; ++i)
    {
      long double d2 = 0;
      for (int k = 0; k < dim; ++k)
        d2 += (static_cast<long double>(V(i, k)) - X(p, k)) *
          (static_cast<long double>(V(i, k)) - X(p, k));
      d[static_cast<std::size_t>(i)] = std::sqrt(d2);
      for (int k = 0; k < dim; ++k)
        q[static_cast<std::size_t>(i)][static_cast<std::size_t>(k)] =
          (static_cast<long double>(V(i, k)) - X(p, k)) / d[static_cast<std::size_t>(i)];
    }
    long double norm_c = 0;
    for (int k = 0; k < dim; ++k)
      norm_c += static_cast<long double>(r.solution(p, k)) * r.solution(p, k);
    norm_c = std::sqrt(norm_c);
    for (Index i = 0; i < n; ++i)
    {
      long double a = 0;
      for (int k = 0; k < dim; ++k)
        a += static_cast<long double>(r.solution(p, k)) *
          q[static_cast<std::size_t>(i)][static_cast<std::size_t>(k)];
      if (o.scheme == CelestialScheme::T)
        beta[static_cast<std::size_t>(i)] = std::exp(a); // s = 0
      else
      {
        const long double L = o.lambda;
        const long double mu = a + std::sqrt(a * a + L * L + 2 * L * norm_c); // Eq. (15)
        beta[static_cast<std::size_t>(i)] = mu * mu;
      }
    }
    long double F[3] = { 0, 0, 0 }, sb = 0, sw = 0;
    for (Index i = 0; i < n; ++i)
    {
      for (int k = 0; k < dim; ++k)
        F[k] += beta[static_cast<std::size_t>(i)] *
          q[static_cast<std::size_t>(i)][static_cast<std::size_t>(k)];
      sb += beta[static_cast<std::size_t>(i)];
      sw += beta[static_cast<std::size_t>(i)] / d[static_cast<std::size_t>(i)];
    }
    const long double Fn = std::sqrt(F[0] * F[0] + F[1] * F[1] + F[2] * F[2]);
    worst_eq = std::max(worst_eq, static_cast<double>(Fn / sb));
    for (Index i = 0; i < n; ++i)
      worst_alpha = std::max(worst_alpha,
        std::abs(static_cast<double>(
                   beta[static_cast<std::size_t>(i)] / d[static_cast<std::size_t>(i)] / sw) -
          r.W(p, i)));
  }
  EXPECT_LE(worst_eq, kEquationTol);
  EXPECT_LE(worst_alpha, 1e-10);
  RecordProperty("max_equation_residual", sci(worst_eq));
}

TEST_P(CelestialProperties, WarmAndColdStartsAgree)
{
  const Points V = controls();
  const Points X = random_inside(V, 4000, 21);
  CelestialOptions o = options_for(GetParam().scheme);
  const CelestialResult warm = celestial_coordinates(V, X, o);
  o.warm_start = false;
  const CelestialResult cold = celestial_coordinates(V, X, o);
  EXPECT_LE((warm.W - cold.W).cwiseAbs().maxCoeff(), kWarmColdTol);
  EXPECT_EQ(cold.warm_starts, 0);
  EXPECT_GT(warm.warm_starts, X.rows() * 9 / 10);
  EXPECT_LT(warm.total_iterations, cold.total_iterations);
  RecordProperty("iterations_per_point_warm", sci(double(warm.total_iterations) / X.rows()));
  RecordProperty("iterations_per_point_cold", sci(double(cold.total_iterations) / X.rows()));
}

TEST_P(CelestialProperties, ResultsDoNotDependOnThreads)
{
  const Points V = controls();
  const Points X = random_inside(V, 2000, 5);
  CelestialOptions o = options_for(GetParam().scheme);
  o.threads = 1;
  const CelestialResult one = celestial_coordinates(V, X, o);
  for (int threads : { 2, 3, 0 })
  {
    o.threads = threads;
    const CelestialResult r = celestial_coordinates(V, X, o);
    ASSERT_EQ(std::memcmp(one.W.data(), r.W.data(), sizeof(double) * one.W.size()), 0)
      << threads << " threads";
    EXPECT_EQ(one.iterations, r.iterations);
    EXPECT_EQ(one.total_iterations, r.total_iterations);
  }
}

/// Runs the kernels at one instruction-set level while alive (restores the supported one).
struct SimdLevelScope
{
  explicit SimdLevelScope(detail::SimdLevel level) { detail::set_simd_level(level); }
  ~SimdLevelScope() { detail::set_simd_level(detail::supported_simd_level()); }
};

// The AVX2 + FMA kernels (directions, the S scheme's F and J, the weights, predicted warm
// starts) against the portable code, which is the reference: the same root within the
// tolerance, the properties of the weights, and (S scheme) fewer Newton iterations from the
// predicted starts. Thread independence of the kernels' path: ResultsDoNotDependOnThreads
// (which runs the supported level).
TEST_P(CelestialProperties, KernelAndPortablePathsAgree)
{
  if (detail::supported_simd_level() != detail::SimdLevel::AVX2)
  {
    GTEST_SKIP() << "this CPU has no AVX2 and FMA: only the portable path runs";
  }
  const Points V = controls();
  const Points X = random_inside(V, 2000, 31);
  const CelestialOptions o = options_for(GetParam().scheme);
  CelestialResult portable, kernels;
  {
    SimdLevelScope scope(detail::SimdLevel::Portable);
    portable = celestial_coordinates(V, X, o);
  }
  {
    SimdLevelScope scope(detail::SimdLevel::AVX2);
    kernels = celestial_coordinates(V, X, o);
  }
  const double diff = (kernels.W - portable.W).cwiseAbs().maxCoeff();
  EXPECT_LE(diff, kWarmColdTol);
  const RowErrors e = row_errors(kernels.W, V, X);
  EXPECT_LE(e.sum, kSumTol);
  EXPECT_LE(e.repro, kReproTol);
  EXPECT_GT(e.min_w, 0.0);
  if (GetParam().scheme == CelestialScheme::S)
  {
    EXPECT_LT(double(kernels.total_iterations), 0.9 * double(portable.total_iterations));
  }
  RecordProperty("max_weight_difference", sci(diff));
  RecordProperty("iterations_per_point_portable", sci(double(portable.total_iterations) / X.rows()));
  RecordProperty("iterations_per_point_kernels", sci(double(kernels.total_iterations) / X.rows()));
}

INSTANTIATE_TEST_SUITE_P(Celestial, CelestialProperties,
  ::testing::Values(Config{ CelestialScheme::T, 2, 10, false },
    Config{ CelestialScheme::S, 2, 10, false }, Config{ CelestialScheme::T, 2, 30, true },
    Config{ CelestialScheme::S, 2, 30, true }, Config{ CelestialScheme::T, 3, 10, true },
    Config{ CelestialScheme::S, 3, 10, true }, Config{ CelestialScheme::T, 3, 40, false },
    Config{ CelestialScheme::S, 3, 40, false }),
  config_name);

// Predicted warm starts near the hull: consecutive points (in curve order) lie 1e-7 .. 1e-10
// from different faces of a cube, where y grows like distance^-1/2 and a first-order
// prediction from a neighbour is far off. Such a prediction must be caught (compared with the
// neighbour's plain solution): without that check these points took 21.8 Newton iterations on
// average instead of 7.6. Every point converges, on both paths.
TEST(CelestialS, PredictedStartsNearTheHull)
{
  if (detail::supported_simd_level() != detail::SimdLevel::AVX2)
  {
    GTEST_SKIP() << "this CPU has no AVX2 and FMA: no predicted starts";
  }
  const Points V = random_controls(3, 22, 77, true); // the hull: the cube [-1.2, 1.2]^3
  Points X = random_inside(V, 3000, 78);
  for (Index p = 0; p < X.rows(); ++p)
    X(p, p % 3) = (p % 2 ? 1.2 : -1.2) * (1.0 - std::pow(10.0, -7.0 - double(p % 7) * 0.5));
  const CelestialOptions o = options_for(CelestialScheme::S);
  CelestialResult portable, kernels;
  {
    SimdLevelScope scope(detail::SimdLevel::Portable);
    portable = celestial_coordinates(V, X, o);
  }
  {
    SimdLevelScope scope(detail::SimdLevel::AVX2);
    kernels = celestial_coordinates(V, X, o);
  }
  ASSERT_EQ(kernels.inside, X.rows());
  EXPECT_TRUE(kernels.converged);
  EXPECT_LE(double(kernels.total_iterations), 1.05 * double(portable.total_iterations));
  const RowErrors e = row_errors(kernels.W, V, X);
  EXPECT_LE(e.sum, kSumTol);
  EXPECT_LE(e.repro, 1e-9); // the rounding floor of the residual near the hull, times diam
  EXPECT_GE(e.min_w, 0.0);
  RecordProperty("iterations_per_point_portable", sci(double(portable.total_iterations) / X.rows()));
  RecordProperty("iterations_per_point_kernels", sci(double(kernels.total_iterations) / X.rows()));
}

// ------------------------------------------------------------------------------------------
// Scheme-specific behaviour.

TEST(CelestialS, DoesNotDependOnLambda)
{
  const Points V = random_controls(3, 20, 8, true);
  const Points X = random_inside(V, 300, 9);
  CelestialOptions o;
  o.lambda = 1.5;
  const CelestialResult a = celestial_coordinates(V, X, o);
  for (double lambda : { 2.0, 100.0 })
  {
    o.lambda = lambda;
    const CelestialResult b = celestial_coordinates(V, X, o);
    EXPECT_LE((a.W - b.W).cwiseAbs().maxCoeff(), 1e-12) << "lambda " << lambda;
    // mu_i is homogeneous of degree 1 in (c, lambda): the centre scales with lambda
    EXPECT_LE((b.solution - (lambda / 1.5) * a.solution).cwiseAbs().maxCoeff(),
      1e-9 * lambda * (1.0 + a.solution.cwiseAbs().maxCoeff()));
  }
}

// Symmetric configurations: at the centre of the cube's corners every weight is 1/8 and the
// wrapping sphere is centred at p (c = 0) or psi = 0.
TEST(Celestial, CubeCentre)
{
  Points V(8, 3);
  for (int c = 0; c < 8; ++c)
    V.row(c) << (c & 1), (c >> 1) & 1, (c >> 2) & 1;
  Points X(1, 3);
  X << 0.5, 0.5, 0.5;
  for (CelestialScheme scheme : { CelestialScheme::T, CelestialScheme::S })
  {
    const CelestialResult r = celestial_coordinates(V, X, options_for(scheme));
    for (Index i = 0; i < 8; ++i)
      EXPECT_NEAR(r.W(0, i), 0.125, 1e-15);
    EXPECT_LE(r.solution.norm(), 1e-15);
  }
}

// With d + 1 controls (a simplex) the positive solution of Eq. (4) is unique up to scale, so
// both schemes give the barycentric coordinates.
TEST(Celestial, SimplexGivesBarycentricCoordinates)
{
  Points V(4, 3);
  V << 0, 0, 0, 2, 0.1, 0, 0.3, 1.5, 0, 0.2, 0.4, 1.8;
  const Points X = random_inside(V, 50, 12);
  Eigen::Matrix4d A;
  A.topRows(3) = V.transpose();
  A.row(3).setOnes();
  for (CelestialScheme scheme : { CelestialScheme::T, CelestialScheme::S })
  {
    const CelestialResult r = celestial_coordinates(V, X, options_for(scheme));
    for (Index p = 0; p < X.rows(); ++p)
    {
      Eigen::Vector4d b;
      b << X.row(p).transpose(), 1.0;
      const Eigen::Vector4d bary = A.partialPivLu().solve(b);
      EXPECT_LE((r.W.row(p).transpose() - bary).cwiseAbs().maxCoeff(), 1e-11) << "point " << p;
    }
  }
}

// Paper Fig. 2: a line surrounded by fifteen control points; TCC and SCC give "very similar
// coordinates". Here: 15 controls on three jittered rings around the segment from (0,0,-1) to
// (0,0,1), points along the segment; then a random configuration. Both betas are increasing
// functions of x . q_i that agree to first order (exp(a) ~ 1 + a, m(a)^2 ~ 1 + 2a), so the
// schemes differ little where the controls surround p evenly. Measured along the line: mean
// |W_T - W_S| = 4.7e-5, max 4.2e-4; random (30 + 8 controls, 2000 points): see the printed
// line. We require agreement to 5e-3 (max) and 1e-3 (mean) on the line, 0.05 / 5e-3 on the
// random set, and that they are not identical (> 1e-5 somewhere).
TEST(Celestial, TAndSAgreeQualitatively)
{
  Points V(15, 3);
  std::mt19937_64 rng(15);
  std::uniform_real_distribution<double> U(-0.3, 0.3);
  for (int i = 0; i < 15; ++i)
  {
    const double phi = 2.0 * 3.14159265358979323846 * i / 5.0 + U(rng);
    const double z = -1.5 + 1.5 * (i / 5) + U(rng);
    const double rad = 1.0 + U(rng);
    V.row(i) << rad * std::cos(phi), rad * std::sin(phi), z;
  }
  Points X(201, 3);
  for (int k = 0; k <= 200; ++k)
    X.row(k) << 0.0, 0.0, -1.0 + 2.0 * k / 200.0;
  const CelestialResult t = celestial_coordinates(V, X, options_for(CelestialScheme::T));
  const CelestialResult s = celestial_coordinates(V, X, options_for(CelestialScheme::S));
  const double max_diff = (t.W - s.W).cwiseAbs().maxCoeff();
  const double mean_diff = (t.W - s.W).cwiseAbs().mean();
  RecordProperty("max_T_minus_S", sci(max_diff));
  RecordProperty("mean_T_minus_S", sci(mean_diff));
  std::printf("[ measured ] TCC vs SCC along the line: mean |dW| = %.3g, max |dW| = %.3g\n",
    mean_diff, max_diff);
  EXPECT_LT(max_diff, 5e-3);
  EXPECT_LT(mean_diff, 1e-3);
  EXPECT_GT(max_diff, 1e-5);

  const Points V2 = random_controls(3, 30, 16, true);
  const Points X2 = random_inside(V2, 2000, 17);
  const CelestialResult t2 = celestial_coordinates(V2, X2, options_for(CelestialScheme::T));
  const CelestialResult s2 = celestial_coordinates(V2, X2, options_for(CelestialScheme::S));
  const double max2 = (t2.W - s2.W).cwiseAbs().maxCoeff();
  const double mean2 = (t2.W - s2.W).cwiseAbs().mean();
  const double rel2 = ((t2.W - s2.W).rowwise().lpNorm<1>()).maxCoeff(); // max_p sum_i |dW|
  std::printf("[ measured ] TCC vs SCC, random 3D: mean |dW| = %.3g, max |dW| = %.3g, "
              "max row L1 = %.3g\n",
    mean2, max2, rel2);
  EXPECT_LT(max2, 0.05);
  EXPECT_LT(mean2, 5e-3);
  EXPECT_GT(max2, 1e-5);
}

// TCC user weights (Eq. 8): raising s_j raises alpha_j at every interior point.
TEST(CelestialT, UserWeightsRaiseTheirControlsInfluence)
{
  const Points V = random_controls(3, 12, 31, true);
  const Points X = random_inside(V, 200, 32);
  CelestialOptions o = options_for(CelestialScheme::T);
  const CelestialResult a = celestial_coordinates(V, X, o);
  o.user_weights = Eigen::VectorXd::Zero(V.rows());
  o.user_weights[10] = 2.0;
  const CelestialResult b = celestial_coordinates(V, X, o);
  const RowErrors e = row_errors(b.W, V, X);
  EXPECT_LE(e.sum, kSumTol);
  EXPECT_LE(e.repro, kReproTol);
  EXPECT_GT(e.min_w, 0.0);
  for (Index p = 0; p < X.rows(); ++p)
    EXPECT_GT(b.W(p, 10), a.W(p, 10)) << "point " << p;
  // all-zero user weights are the paper's default (Eq. 7)
  o.user_weights.setZero();
  const CelestialResult c = celestial_coordinates(V, X, o);
  EXPECT_EQ(std::memcmp(a.W.data(), c.W.data(), sizeof(double) * a.W.size()), 0);
}

// ------------------------------------------------------------------------------------------
// The hull boundary.

/// The unit cube's corners plus three interior controls: the faces are squares (4 coplanar
/// controls), the edges have 2 controls.
Points cube_plus_interior()
{
  Points V(11, 3);
  for (int c = 0; c < 8; ++c)
    V.row(c) << (c & 1), (c >> 1) & 1, (c >> 2) & 1;
  V.row(8) << 0.3, 0.6, 0.4;
  V.row(9) << 0.7, 0.2, 0.5;
  V.row(10) << 0.5, 0.8, 0.8;
  return V;
}

std::string scheme_name(const ::testing::TestParamInfo<CelestialScheme>& param)
{
  return param.param == CelestialScheme::T ? "T" : "S";
}

class CelestialBoundary : public ::testing::TestWithParam<CelestialScheme>
{
};

// On a face: only the face's controls have weight, the row is a valid GBC row, and interior
// points converge to it as they approach the face (for SCC and for TCC with s = 0 the boundary
// value is the same scheme in the face, which is the limit from inside).
TEST_P(CelestialBoundary, FacesAreTheLimitFromInside)
{
  const Points V = cube_plus_interior();
  const CelestialCoordinates cc(V, options_for(GetParam()));
  EXPECT_EQ(cc.num_hull_facets(), 6); // squares, not 12 triangles
  // on the square face z = 0 (controls 0-3), on the edge y = z = 0 (controls 0, 1), and inside
  // points at distance h above them
  const std::vector<Eigen::Vector3d> on = { { 0.3, 0.25, 0.0 }, { 0.35, 0.0, 0.0 } };
  const std::vector<Eigen::Vector3d> inward = { { 0, 0, 1 },
    Eigen::Vector3d(0, 1, 1).normalized() };
  for (std::size_t f = 0; f < on.size(); ++f)
  {
    Points X(6, 3);
    X.row(0) = on[f].transpose();
    const double hs[] = { 1e-2, 1e-4, 1e-6, 1e-8, 1e-10 };
    for (int k = 0; k < 5; ++k)
      X.row(k + 1) = (on[f] + hs[k] * inward[f]).transpose();
    const CelestialResult r = cc.compute(X);
    EXPECT_EQ(r.hull_location[0], CelestialLocation::Boundary);
    EXPECT_TRUE(r.solution.row(0).array().isNaN().all()); // the unknown lives in the face
    for (int k = 1; k < 6; ++k)
    {
      EXPECT_EQ(r.hull_location[static_cast<std::size_t>(k)], CelestialLocation::Inside);
      EXPECT_TRUE(r.solution.row(k).allFinite());
    }
    const RowErrors e = row_errors(r.W, V, X);
    EXPECT_LE(e.sum, kSumTol);
    EXPECT_LE(e.repro, kNearHullReproTol);
    EXPECT_GE(e.min_w, 0.0);
    const int on_face = f == 0 ? 4 : 2;
    for (Index i = on_face; i < V.rows(); ++i)
      EXPECT_EQ(r.W(0, i), 0.0) << "control " << i << " is off the face";
    if (f == 1) // an edge with two controls: linear interpolation
    {
      EXPECT_NEAR(r.W(0, 0), 0.65, 1e-15);
      EXPECT_NEAR(r.W(0, 1), 0.35, 1e-15);
    }
    // TCC: |W(h) - W(face)| = O(h) (psi grows like log(1/h)); SCC: O(sqrt(h)) (the centre
    // grows like 1/h, y like h^-1/2, and the face controls' a_i = y . q_i move by y_n h / d_i):
    // SCC is only Hoelder-1/2 continuous at the hull. Measured: see the printed lines.
    std::printf("[ measured ] %s, %s: |W(h) - W(face)| at h = 1e-2 ... 1e-10:",
      GetParam() == CelestialScheme::T ? "TCC" : "SCC", f == 0 ? "square face" : "edge");
    for (int k = 0; k < 5; ++k)
    {
      const double diff = (r.W.row(k + 1) - r.W.row(0)).cwiseAbs().maxCoeff();
      std::printf(" %.2g", diff);
      const double bound = GetParam() == CelestialScheme::T ? 5.0 * hs[k] : 0.1 * std::sqrt(hs[k]);
      EXPECT_LE(diff, bound + 1e-11) << "face " << f << ", h = " << hs[k];
    }
    std::printf("\n");
  }
}

// In 2D, three collinear controls on a hull edge: on that edge both schemes reduce to the 1D
// problem, whose solution is known in closed form: with n+ controls on one side of p and n-
// on the other, beta_+ / beta_- = sqrt(n- / n+) (TCC with s = 0: n+ e^psi = n- e^-psi; SCC:
// mu_+ mu_- = K and n+ mu_+^2 = n- mu_-^2), and alpha_i = (beta_i / d_i) / sum_j.
TEST_P(CelestialBoundary, CollinearControlsOnA2DEdge)
{
  Points V(6, 2);
  V << 0, 0, 1, 0, 2.5, 0, 2.5, 2, 0, 2, 1.2, 1.1; // 0, 1, 2 on the edge y = 0
  const CelestialCoordinates cc(V, options_for(GetParam()));
  EXPECT_EQ(cc.num_hull_facets(), 4);
  Points X(3, 2);
  X << 0.4, 0.0, 1.7, 0.0, 0.4, 1e-9;
  const CelestialResult r = cc.compute(X);
  ASSERT_EQ(r.hull_location[0], CelestialLocation::Boundary);
  ASSERT_EQ(r.hull_location[1], CelestialLocation::Boundary);
  for (int p = 0; p < 2; ++p)
  {
    const double x = X(p, 0);
    const double d[3] = { x, std::abs(1.0 - x), 2.5 - x };
    const int n_plus = x < 1.0 ? 2 : 1, n_minus = 3 - n_plus;
    const double beta_plus = std::sqrt(double(n_minus) / n_plus), beta_minus = 1.0 / beta_plus;
    const double beta[3] = { beta_minus, x < 1.0 ? beta_plus : beta_minus, beta_plus };
    double sum = 0;
    for (int i = 0; i < 3; ++i)
      sum += beta[i] / d[i];
    for (int i = 0; i < 3; ++i)
      EXPECT_NEAR(r.W(p, i), beta[i] / d[i] / sum, 1e-13) << "point " << p << ", control " << i;
    for (int i = 3; i < 6; ++i)
      EXPECT_EQ(r.W(p, i), 0.0);
  }
  // and the point 1e-9 above the edge is close to it: O(h) for TCC, O(sqrt(h)) for SCC
  EXPECT_LE((r.W.row(2) - r.W.row(0)).cwiseAbs().maxCoeff(),
    GetParam() == CelestialScheme::T ? 1e-7 : 3e-5 * 0.5);
}

// Points on the hull within the boundary tolerance but computed with rounding (outside by
// ~1e-17) are on the boundary, not outside, and get valid weights; vertices of the hull that
// are controls are Lagrange points.
TEST_P(CelestialBoundary, RandomPointsOnTheHull)
{
  for (int dim : { 2, 3 })
  {
    const Points V = random_controls(dim, 25, 41 + static_cast<unsigned>(dim), false);
    const CelestialCoordinates cc(V, options_for(GetParam()));
    CelestialOptions probe_options = options_for(GetParam());
    probe_options.outside = CelestialOutsidePolicy::Flag;
    const CelestialCoordinates probe(V, probe_options);
    // points on rays from the centroid, pushed out onto the hull by bisection on the location
    // (Outside or not): they end up within ~1e-16 of the boundary
    std::mt19937_64 rng(5);
    std::uniform_int_distribution<int> pick(0, static_cast<int>(V.rows()) - 1);
    const Eigen::RowVectorXd centre = V.colwise().mean();
    Points X(60, dim);
    for (int p = 0; p < X.rows(); ++p)
    {
      const Eigen::RowVectorXd dir = V.row(pick(rng)) - centre + 0.3 * (V.row(pick(rng)) - centre);
      double lo = 0.0, hi = 10.0;
      for (int it = 0; it < 200; ++it)
      {
        const double mid = 0.5 * (lo + hi);
        Points one(1, dim);
        one.row(0) = centre + mid * dir;
        const CelestialResult r = probe.compute(one);
        (r.hull_location[0] == CelestialLocation::Outside ? hi : lo) = mid;
        if (hi - lo < 1e-15)
          break;
      }
      X.row(p) = centre + lo * dir;
    }
    const CelestialResult r = cc.compute(X);
    for (int p = 0; p < X.rows(); ++p)
      EXPECT_NE(r.hull_location[static_cast<std::size_t>(p)], CelestialLocation::Inside)
        << "point " << p;
    const RowErrors e = row_errors(r.W, V, X);
    EXPECT_LE(e.sum, kSumTol);
    EXPECT_LE(e.repro, 2e-12); // projection onto the face: within the boundary tolerance
    EXPECT_GE(e.min_w, 0.0);
  }
}

// A control 1e-14 outside the middle of a cube edge, in the plane of one face: that face is a
// pentagon whose triangulation by CGAL's exact hull can contain the sliver (0, 8, 1), whose
// plane, computed in floating point after a rotation, is noise. Slivers are dropped (their
// neighbours bound the hull to within the tolerance), the faces stay single facets, and points
// inside and on the hull near the sliver are classified and weighted correctly.
TEST_P(CelestialBoundary, SliverOfNearlyCollinearControls)
{
  Points V(10, 3);
  for (int c = 0; c < 8; ++c)
    V.row(c) << (c & 1), (c >> 1) & 1, (c >> 2) & 1;
  V.row(8) << 0.5, -1e-14, 0.0; // the edge y = z = 0 between controls 0 and 1, pushed out in z = 0
  V.row(9) << 0.4, 0.5, 0.6;
  Points X(5, 3);
  X << 0.3, 0.0, 0.0, // on the edge
    0.5, 1e-9, 1e-9,  // just inside, next to control 8
    0.5, 0.3, 0.0,    // on the face z = 0
    0.25, 1e-6, 2e-6, // inside near the edge
    0.5, 0.5, 0.5;
  for (int rotation = 0; rotation < 20; ++rotation)
  {
    const Eigen::Matrix3d R =
      Eigen::AngleAxisd(0.3 + rotation, Eigen::Vector3d(1, 2 + rotation, -3).normalized())
        .toRotationMatrix();
    const Points Vr = V * R.transpose(), Xr = X * R.transpose();
    const CelestialCoordinates cc(Vr, options_for(GetParam()));
    EXPECT_EQ(cc.num_hull_facets(), 6) << "rotation " << rotation;
    const CelestialResult r = cc.compute(Xr);
    EXPECT_TRUE(r.outside.empty()) << "rotation " << rotation;
    EXPECT_EQ(r.hull_location[0], CelestialLocation::Boundary);
    EXPECT_EQ(r.hull_location[2], CelestialLocation::Boundary);
    EXPECT_EQ(r.hull_location[4], CelestialLocation::Inside);
    const RowErrors e = row_errors(r.W, Vr, Xr);
    EXPECT_LE(e.sum, kSumTol);
    EXPECT_LE(e.repro, kNearHullReproTol);
    EXPECT_GE(e.min_w, 0.0);
  }
}

INSTANTIATE_TEST_SUITE_P(Celestial, CelestialBoundary,
  ::testing::Values(CelestialScheme::T, CelestialScheme::S), scheme_name);

// TCC with s != 0 has no limit at the boundary (psi grows like 1/h there): the boundary rows
// are the face's TCC with the face's s_i (valid GBC rows), but interior points do not converge
// to them. This test documents the jump; measured at h = 1e-6 above the face z = 0 of the
// cube: max |W(h) - W(face)| = 0.13.
TEST(CelestialT, UserWeightsHaveNoLimitAtTheBoundary)
{
  const Points V = cube_plus_interior();
  CelestialOptions o = options_for(CelestialScheme::T);
  o.user_weights = Eigen::VectorXd::Constant(V.rows(), 0.5);
  Points X(2, 3);
  X << 0.3, 0.25, 0.0, 0.3, 0.25, 1e-6;
  const CelestialResult r = celestial_coordinates(V, X, o);
  EXPECT_EQ(r.hull_location[0], CelestialLocation::Boundary);
  const RowErrors e = row_errors(r.W, V, X);
  EXPECT_LE(e.sum, kSumTol);
  EXPECT_LE(e.repro, kNearHullReproTol);
  EXPECT_GE(e.min_w, 0.0);
  const double jump = (r.W.row(1) - r.W.row(0)).cwiseAbs().maxCoeff();
  std::printf("[ measured ] TCC, s = 0.5: |W(1e-6 above the face) - W(face)| = %.3g\n", jump);
  EXPECT_GT(jump, 0.05);
}

// ------------------------------------------------------------------------------------------
// Points outside, near controls, empty input.

TEST(Celestial, OutsidePoints)
{
  const Points V = random_controls(3, 10, 51, true);
  Points X = random_inside(V, 20, 52);
  X.row(3) << 5, 0, 0;
  X.row(17) << 0, 0, -1.2 - 1e-6;
  for (CelestialScheme scheme : { CelestialScheme::T, CelestialScheme::S })
  {
    CelestialOptions o = options_for(scheme);
    EXPECT_TRUE(throws_error([&] { celestial_coordinates(V, X, o); }, ErrorCode::PointsOutside,
      { "2 of 20 points lie outside the convex hull of the 18 control points", "points 3, 17",
        "point 3 is at least 3.8 from the hull", "CelestialOutsidePolicy::Flag",
        "--hull-points auto" }));
    o.outside = CelestialOutsidePolicy::Flag;
    const CelestialResult r = celestial_coordinates(V, X, o);
    EXPECT_EQ(r.outside, (std::vector<Index>{ 3, 17 }));
    EXPECT_TRUE(r.not_converged.empty());
    for (Index p = 0; p < X.rows(); ++p)
    {
      const bool out = p == 3 || p == 17;
      EXPECT_EQ(r.hull_location[static_cast<std::size_t>(p)] == CelestialLocation::Outside, out);
      EXPECT_EQ(r.W.row(p).array().isNaN().all(), out) << "point " << p;
      EXPECT_EQ(std::isnan(r.residual[p]), out);
      EXPECT_EQ(r.location[static_cast<std::size_t>(p)],
        out ? PointLocation::Outside : PointLocation::Inside);
    }
    // The shared result shape: the outside rows are the undefined ones; the statistics.
    EXPECT_EQ(r.undefined, (std::vector<Index>{ 3, 17 }));
    EXPECT_TRUE(r.converged);
    EXPECT_EQ(r.count(PointLocation::Outside), 2);
    EXPECT_EQ(r.count(PointLocation::Inside), r.inside);
    EXPECT_TRUE(test::has_statistics(r.statistics,
      { "hull_facets", "newton_iterations", "mean_newton_iterations", "max_newton_iterations",
        "warm_starts", "cold_restarts", "max_residual", "at_control", "not_converged",
        "solve_seconds", "hull_points_added" }));
    EXPECT_EQ(r.statistic("hull_facets"),
      static_cast<double>(CelestialCoordinates(V, o).num_hull_facets()));
    EXPECT_EQ(r.statistic("newton_iterations"), static_cast<double>(r.total_iterations));
    EXPECT_EQ(r.statistic("mean_newton_iterations"), r.total_iterations / 20.0);
    EXPECT_EQ(r.statistic("max_newton_iterations"), r.iterations.maxCoeff());
    EXPECT_GE(r.statistic("max_newton_iterations"), 1.0);
    EXPECT_EQ(r.statistic("warm_starts"), static_cast<double>(r.warm_starts));
    EXPECT_EQ(r.statistic("cold_restarts"), static_cast<double>(r.cold_restarts));
    EXPECT_GT(r.statistic("max_residual"), 0.0);
    EXPECT_LE(r.statistic("max_residual"), o.tolerance);
    EXPECT_EQ(r.statistic("at_control"), 0.0);
    EXPECT_EQ(r.statistic("not_converged"), 0.0);
    EXPECT_EQ(r.statistic("solve_seconds"), r.seconds);
  }
}

TEST(Celestial, QueryAtOrNearAControl)
{
  const Points V = random_controls(2, 12, 61, true);
  Points X(3, 2);
  X.row(0) = V.row(7);
  X.row(1) = V.row(7) + Eigen::RowVector2d(1e-13, 0.0); // within the tolerance (3.4e-12)
  X.row(2) = V.row(7) + Eigen::RowVector2d(1e-9, 0.0);  // beyond it: solved, weight ~ 1
  for (CelestialScheme scheme : { CelestialScheme::T, CelestialScheme::S })
  {
    const CelestialResult r = celestial_coordinates(V, X, options_for(scheme));
    for (int p = 0; p < 2; ++p)
    {
      EXPECT_EQ(r.hull_location[static_cast<std::size_t>(p)], CelestialLocation::AtControl);
      for (Index i = 0; i < V.rows(); ++i)
        EXPECT_EQ(r.W(p, i), i == 7 ? 1.0 : 0.0);
      EXPECT_EQ(r.residual[p], 0.0);
    }
    EXPECT_EQ(r.hull_location[2], CelestialLocation::Inside);
    EXPECT_NEAR(r.W(2, 7), 1.0, 1e-7);
    EXPECT_LE(row_errors(r.W, V, X).repro, kReproTol);
  }
}

TEST(Celestial, EmptyQuery)
{
  const Points V = random_controls(3, 5, 1, true);
  const CelestialResult r = celestial_coordinates(V, Points(0, 3));
  EXPECT_EQ(r.W.rows(), 0);
  EXPECT_EQ(r.W.cols(), V.rows());
  EXPECT_TRUE(r.outside.empty());
  EXPECT_EQ(r.iterations.size(), 0);
}

// ------------------------------------------------------------------------------------------
// Validation.

TEST(CelestialValidation, Controls)
{
  EXPECT_TRUE(throws_error(
    [] { CelestialCoordinates(Points(0, 3)); }, ErrorCode::EmptyInput, { "no control points" }));
  EXPECT_TRUE(throws_error([] { CelestialCoordinates(Points::Zero(5, 4)); },
    ErrorCode::SizeMismatch, { "2 or 3 coordinates, got 4" }));
  Points V = random_controls(3, 6, 2, false);
  V(4, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(
    throws_error([&] { CelestialCoordinates c(V); }, ErrorCode::NonFinite, { "control point 4" }));
  V(4, 1) = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(
    throws_error([&] { CelestialCoordinates c(V); }, ErrorCode::NonFinite, { "control point 4" }));
  EXPECT_TRUE(throws_error([] { CelestialCoordinates c(random_controls(3, 3, 2, false)); },
    ErrorCode::InvalidArgument,
    { "3D celestial coordinates need at least 4 control points, got 3" }));
  EXPECT_TRUE(throws_error([] { CelestialCoordinates c(random_controls(2, 2, 2, false)); },
    ErrorCode::InvalidArgument, { "at least 3 control points, got 2" }));
}

TEST(CelestialValidation, CoincidentControls)
{
  Points V = random_controls(3, 8, 3, false);
  V.row(6) = V.row(2);
  EXPECT_TRUE(throws_error([&] { CelestialCoordinates c(V); }, ErrorCode::InvalidArgument,
    { "control points 2 and 6 coincide", "remove one" }));
  V.row(6) = V.row(2) + Eigen::RowVector3d(1e-14, 0, 0);
  EXPECT_TRUE(throws_error([&] { CelestialCoordinates c(V); }, ErrorCode::InvalidArgument,
    { "control points 2 and 6 coincide" }));
  V.row(6) = V.row(2) + Eigen::RowVector3d(1e-9, 0, 0); // distinct: accepted
  EXPECT_NO_THROW(CelestialCoordinates c(V));
}

TEST(CelestialValidation, DegenerateHull)
{
  Points L(5, 2); // collinear in 2D
  L << 0, 0, 1, 1, 2, 2, -1, -1, 0.5, 0.5;
  EXPECT_TRUE(throws_error([&] { CelestialCoordinates c(L); }, ErrorCode::InvalidArgument,
    { "collinear", "add a control point off that line" }));
  Points P(6, 3); // coplanar in 3D (z = x + y)
  P << 0, 0, 0, 1, 0, 1, 0, 1, 1, 1, 1, 2, 0.3, 0.2, 0.5, 2, -1, 1;
  EXPECT_TRUE(throws_error([&] { CelestialCoordinates c(P); }, ErrorCode::InvalidArgument,
    { "coplanar", "add a control point off that plane" }));
  Points C(4, 3); // collinear in 3D
  C << 0, 0, 0, 1, 2, 3, 2, 4, 6, -1, -2, -3;
  EXPECT_TRUE(
    throws_error([&] { CelestialCoordinates c(C); }, ErrorCode::InvalidArgument, { "collinear" }));
  // nearly coplanar beyond the tolerance: accepted, and works at the centroid, which is only
  // ~1e-7 of the diameter from the hull's faces: converged at the rounding floor (residual
  // 9e-11, see CelestialOptions::tolerance), reproduction within 1e-9
  P(5, 2) += 1e-6;
  const Points X = P.colwise().mean();
  for (CelestialScheme scheme : { CelestialScheme::T, CelestialScheme::S })
  {
    const CelestialResult r = CelestialCoordinates(P, options_for(scheme)).compute(X);
    EXPECT_EQ(r.hull_location[0], CelestialLocation::Inside);
    EXPECT_TRUE(r.not_converged.empty());
    const RowErrors e = row_errors(r.W, P, X);
    EXPECT_LE(e.sum, kSumTol);
    EXPECT_LE(e.repro, 1e-9);
    EXPECT_GT(e.min_w, 0.0);
  }
}

TEST(CelestialValidation, Options)
{
  const Points V = random_controls(3, 6, 4, true);
  auto with = [&](auto set) {
    CelestialOptions o;
    set(o);
    return [V, o] { CelestialCoordinates c(V, o); };
  };
  EXPECT_TRUE(throws_error(with([](CelestialOptions& o) { o.lambda = 1.0; }),
    ErrorCode::InvalidArgument, { "lambda must lie in (1, 1e6]" }));
  EXPECT_TRUE(throws_error(with([](CelestialOptions& o) { o.lambda = std::nan(""); }),
    ErrorCode::InvalidArgument, { "lambda" }));
  EXPECT_TRUE(throws_error(with([](CelestialOptions& o) { o.tolerance = 0.0; }),
    ErrorCode::InvalidArgument, { "tolerance must lie in [1e-15, 1e-3]" }));
  EXPECT_TRUE(throws_error(with([](CelestialOptions& o) { o.max_iterations = 0; }),
    ErrorCode::InvalidArgument, { "max_iterations" }));
  EXPECT_TRUE(throws_error(with([](CelestialOptions& o) { o.boundary_tolerance = 1e-3; }),
    ErrorCode::InvalidArgument, { "boundary_tolerance" }));
  EXPECT_TRUE(throws_error(with([](CelestialOptions& o) { o.threads = -1; }),
    ErrorCode::InvalidArgument, { "threads must be >= 0" }));
  EXPECT_TRUE(throws_error(with([&](CelestialOptions& o) {
    o.scheme = CelestialScheme::S;
    o.user_weights = Eigen::VectorXd::Ones(V.rows());
  }),
    ErrorCode::InvalidArgument, { "user_weights are the s_i of the T scheme" }));
  EXPECT_TRUE(throws_error(with([](CelestialOptions& o) {
    o.scheme = CelestialScheme::T;
    o.user_weights = Eigen::VectorXd::Ones(3);
  }),
    ErrorCode::SizeMismatch, { "user_weights has 3 entries but there are 14 control points" }));
  EXPECT_TRUE(throws_error(with([&](CelestialOptions& o) {
    o.scheme = CelestialScheme::T;
    o.user_weights = Eigen::VectorXd::Ones(V.rows());
    o.user_weights[5] = -1.0;
  }),
    ErrorCode::InvalidArgument, { "user weight 5 is -1" }));
  EXPECT_TRUE(throws_error(with([&](CelestialOptions& o) {
    o.scheme = CelestialScheme::T;
    o.user_weights = Eigen::VectorXd::Ones(V.rows());
    o.user_weights[2] = std::nan("");
  }),
    ErrorCode::NonFinite, { "user weight 2" }));
}

TEST(CelestialValidation, Queries)
{
  const Points V = random_controls(3, 6, 5, true);
  const CelestialCoordinates cc(V);
  EXPECT_TRUE(throws_error([&] { cc.compute(Points::Zero(3, 2)); }, ErrorCode::SizeMismatch,
    { "the points have 2 coordinates but the control points have 3" }));
  Points X = random_inside(V, 10, 6);
  X(8, 2) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(throws_error([&] { cc.compute(X); }, ErrorCode::NonFinite, { "point 8" }));
  X(8, 2) = 0.0;
  Eigen::MatrixXi bad(2, 2);
  bad << 0, 1, 3, 10;
  EXPECT_TRUE(throws_error([&] { cc.compute(X, bad); }, ErrorCode::InvalidArgument,
    { "edge 1 refers to point 10 but there are 10 points" }));
  EXPECT_TRUE(throws_error(
    [&] { cc.compute(X, Eigen::MatrixXi::Zero(2, 3)); }, ErrorCode::SizeMismatch, { "#E by 2" }));
}

// ------------------------------------------------------------------------------------------
// Warm starts over mesh edges, non-convergence, progress and cancellation.

TEST(Celestial, WarmStartsOverMeshEdges)
{
  // a 40 x 40 grid in the box, points ordered row by row, edges between grid neighbours,
  // shuffled so that the index order is useless for warm starts
  const Points V = random_controls(2, 15, 71, true);
  const int g = 40;
  std::vector<int> perm(g * g);
  std::iota(perm.begin(), perm.end(), 0);
  std::shuffle(perm.begin(), perm.end(), std::mt19937(3));
  Points X(g * g, 2);
  std::vector<Eigen::Vector2i> E;
  for (int i = 0; i < g; ++i)
    for (int j = 0; j < g; ++j)
    {
      X.row(perm[i * g + j]) << -1.1 + 2.2 * i / (g - 1), -1.1 + 2.2 * j / (g - 1);
      if (i + 1 < g)
        E.emplace_back(perm[i * g + j], perm[(i + 1) * g + j]);
      if (j + 1 < g)
        E.emplace_back(perm[i * g + j], perm[i * g + j + 1]);
    }
  Eigen::MatrixXi edges(static_cast<Index>(E.size()), 2);
  for (std::size_t e = 0; e < E.size(); ++e)
    edges.row(static_cast<Index>(e)) = E[e].transpose();
  for (CelestialScheme scheme : { CelestialScheme::T, CelestialScheme::S })
  {
    CelestialOptions o = options_for(scheme);
    const CelestialCoordinates cc(V, o);
    const CelestialResult by_edges = cc.compute(X, edges);
    const CelestialResult by_curve = cc.compute(X);
    o.warm_start = false;
    const CelestialResult cold = CelestialCoordinates(V, o).compute(X);
    EXPECT_LE((by_edges.W - cold.W).cwiseAbs().maxCoeff(), kWarmColdTol);
    EXPECT_LE((by_curve.W - cold.W).cwiseAbs().maxCoeff(), kWarmColdTol);
    EXPECT_LT(by_edges.total_iterations, cold.total_iterations);
    std::printf("[ measured ] %s, iterations per point: edges %.2f, Hilbert %.2f, cold %.2f\n",
      scheme == CelestialScheme::T ? "TCC" : "SCC", double(by_edges.total_iterations) / X.rows(),
      double(by_curve.total_iterations) / X.rows(), double(cold.total_iterations) / X.rows());
    // thread independence with edges too
    CelestialOptions o1 = options_for(scheme);
    o1.threads = 1;
    const CelestialResult one = CelestialCoordinates(V, o1).compute(X, edges);
    EXPECT_EQ(std::memcmp(one.W.data(), by_edges.W.data(), sizeof(double) * one.W.size()), 0);
  }
}

TEST(Celestial, NotConverged)
{
  const Points V = random_controls(3, 10, 81, true);
  const Points X = random_inside(V, 50, 82);
  CelestialOptions o;
  o.max_iterations = 1;
  o.warm_start = false;
  EXPECT_TRUE(throws_error([&] { celestial_coordinates(V, X, o); }, ErrorCode::NotConverged,
    { "of 50 points did not converge in 1 Newton iterations", "(residual ", " more. ",
      "require_convergence = false" }));
  o.require_convergence = false;
  const CelestialResult r = celestial_coordinates(V, X, o);
  EXPECT_FALSE(r.not_converged.empty());
  for (Index p : r.not_converged)
  {
    EXPECT_TRUE(r.W.row(p).array().isNaN().all());
    EXPECT_GT(r.residual[p], o.tolerance);
  }
  EXPECT_TRUE(std::is_sorted(r.not_converged.begin(), r.not_converged.end()));
  // The shared result shape: the non-converged rows are the undefined ones.
  EXPECT_EQ(r.undefined, r.not_converged);
  EXPECT_FALSE(r.converged);
  EXPECT_EQ(r.statistic("not_converged"), static_cast<double>(r.not_converged.size()));
}

TEST(Celestial, ProgressAndCancel)
{
  const Points V = random_controls(3, 10, 91, true);
  const Points X = random_inside(V, 5000, 92);
  const CelestialCoordinates cc(V);
  std::vector<double> seen;
  cc.compute(X, [&](double f) {
    seen.push_back(f);
    return true;
  });
  ASSERT_GE(seen.size(), 2u);
  EXPECT_TRUE(std::is_sorted(seen.begin(), seen.end()));
  EXPECT_EQ(seen.back(), 1.0);
  int calls = 0;
  EXPECT_TRUE(throws_error([&] { cc.compute(X, [&](double) { return ++calls < 2; }); },
    ErrorCode::Cancelled, { "celestial coordinates was cancelled" }));
}

TEST(Celestial, MoveAndAccessors)
{
  const Points V = random_controls(2, 7, 3, false);
  CelestialOptions o;
  o.lambda = 3.0;
  CelestialCoordinates a(V, o);
  CelestialCoordinates b = std::move(a);
  EXPECT_EQ(b.num_controls(), 7);
  EXPECT_EQ(b.dimension(), 2);
  EXPECT_EQ(b.controls(), V);
  EXPECT_EQ(b.options().lambda, 3.0);
  EXPECT_GE(b.num_hull_facets(), 3);
}

// ------------------------------------------------------------------------------------------
// Hull points (CelestialHullPoints::Auto, §6) and warm starts from a given solution.

/// Checks, independently of the library's construction, that H (2^dim rows) are the corners of
/// a box (corner k = H(0) + the edges of the set bits of k, the edges mutually orthogonal)
/// that holds every row of V and X at least pad from each face, with pad = margin times the
/// diagonal of the box without it, and that the box is tight: along every edge some point lies
/// exactly pad from each of its two faces. Returns an empty string or what failed.
std::string check_hull_box(const Points& V, const Points& X, const Points& H, double margin)
{
  const int dim = static_cast<int>(V.cols());
  if (H.rows() != (Index(1) << dim) || H.cols() != dim)
    return "H is not 2^dim by dim";
  const double scale = diameter(H);
  const double tol = 1e-12 * scale;
  Points E(dim, dim); // row j: the edge of bit j
  for (int j = 0; j < dim; ++j)
    E.row(j) = H.row(Index(1) << j) - H.row(0);
  for (Index k = 0; k < H.rows(); ++k)
  {
    Eigen::RowVectorXd corner = H.row(0);
    for (int j = 0; j < dim; ++j)
      if ((k >> j) & 1)
        corner += E.row(j);
    if ((corner - H.row(k)).norm() > tol)
      return "corner " + std::to_string(k) + " is not H(0) plus its edges";
  }
  for (int i = 0; i < dim; ++i)
    for (int j = i + 1; j < dim; ++j)
      if (std::abs(E.row(i).dot(E.row(j))) > 1e-12 * scale * scale)
        return "edges " + std::to_string(i) + " and " + std::to_string(j) + " are not orthogonal";
  Points P(V.rows() + X.rows(), dim);
  P << V, X;
  Eigen::VectorXd length(dim), low(dim), high(dim); // the edge lengths, the least slacks
  for (int j = 0; j < dim; ++j)
  {
    length[j] = E.row(j).norm();
    const Eigen::VectorXd t = (P.rowwise() - H.row(0)) * E.row(j).transpose() / length[j];
    low[j] = t.minCoeff();
    high[j] = length[j] - t.maxCoeff();
  }
  const double pad = margin * (length.array() - 2.0 * low[0]).matrix().norm();
  for (int j = 0; j < dim; ++j)
    if (std::abs(low[j] - pad) > tol || std::abs(high[j] - pad) > tol)
      return "axis " + std::to_string(j) + ": slacks " + std::to_string(low[j]) + ", " +
        std::to_string(high[j]) + " instead of " + std::to_string(pad);
  return "";
}

/// A random rotation (Gram-Schmidt of a Gaussian matrix, determinant +1).
Eigen::MatrixXd random_rotation(int dim, unsigned seed)
{
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> N(0.0, 1.0);
  Eigen::MatrixXd A(dim, dim);
  for (int i = 0; i < dim; ++i)
    for (int j = 0; j < dim; ++j)
      A(i, j) = N(rng);
  Eigen::MatrixXd Q = Eigen::HouseholderQR<Eigen::MatrixXd>(A).householderQ();
  if (Q.determinant() < 0.0)
    Q.col(0) *= -1.0;
  return Q;
}

// A model far outside a small control set: with Auto every point gets positive weights over the
// controls and the 2^dim corners (placed as documented, columns last), which sum to 1 and
// reproduce the point with [V; H] as the controls; None keeps the error naming the points.
TEST(CelestialHullPoints, ModelFarOutsideASmallControlSet)
{
  for (int dim : { 2, 3 })
    for (CelestialScheme scheme : { CelestialScheme::T, CelestialScheme::S })
    {
      const Points V = random_controls(dim, dim + 2, 71u + static_cast<unsigned>(dim), false);
      Points X = random_controls(dim, 60, 73u, false); // [-1, 1]^dim, then shifted far away
      X.array() += 8.0;
      X.row(0) = V.colwise().mean(); // one point inside the controls' own hull
      CelestialOptions o = options_for(scheme);
      EXPECT_TRUE(throws_error([&] { celestial_coordinates(V, X, o); },
        ErrorCode::PointsOutside, { "59 of 60 points lie outside", "points 1, 2, 3" }));
      o.hull_points = CelestialHullPoints::Auto;
      const CelestialResult r = celestial_coordinates(V, X, o);
      const Points H = r.added_controls;
      ASSERT_EQ(H.rows(), 1 << dim);
      EXPECT_EQ(check_hull_box(V, X, H, 0.1), "") << "dim " << dim;
      // the box's first edge points along the direction from the centroid of the controls and
      // the points to the one farthest from it (the documented frame)
      Points P(V.rows() + X.rows(), dim);
      P << V, X;
      const Points centred = P.rowwise() - P.colwise().mean();
      Index far = 0;
      centred.rowwise().squaredNorm().maxCoeff(&far);
      const Eigen::RowVectorXd e1 = (H.row(1) - H.row(0)).normalized();
      EXPECT_NEAR(e1.dot(centred.row(far).normalized()), 1.0, 1e-12);
      ASSERT_EQ(r.W.cols(), V.rows() + H.rows());
      EXPECT_EQ(r.statistic("hull_points_added"), static_cast<double>(H.rows()));
      EXPECT_TRUE(r.outside.empty());
      EXPECT_EQ(r.inside, X.rows());
      Points all(V.rows() + H.rows(), dim);
      all << V, H;
      const RowErrors e = row_errors(r.W, all, X);
      EXPECT_GT(e.min_w, 0.0) << "dim " << dim;
      EXPECT_LE(e.sum, kSumTol);
      EXPECT_LE(e.repro, kReproTol);
      // the point inside the controls' hull still depends on the user's controls
      EXPECT_GT(r.W.row(0).head(V.rows()).sum(), 0.1);
    }
}

// Auto adds nothing when every point is strictly inside (bitwise the same as None), and adds the
// corners for a point on the hull (within boundary_tolerance), where None gives face weights.
TEST(CelestialHullPoints, OnlyWhenAPointIsNotStrictlyInside)
{
  const Points V = random_controls(3, 10, 81, true);
  Points X = random_inside(V, 30, 82);
  CelestialOptions o;
  const CelestialResult none = celestial_coordinates(V, X, o);
  o.hull_points = CelestialHullPoints::Auto;
  const CelestialResult automatic = celestial_coordinates(V, X, o);
  EXPECT_EQ(automatic.added_controls.rows(), 0);
  EXPECT_EQ(automatic.statistic("hull_points_added"), 0.0);
  EXPECT_TRUE(none.W == automatic.W);
  // Always adds them anyway: other weights, the same reproduction
  o.hull_points = CelestialHullPoints::Always;
  const CelestialResult always = celestial_coordinates(V, X, o);
  ASSERT_EQ(always.added_controls.rows(), 8);
  EXPECT_EQ(check_hull_box(V, X, always.added_controls, 0.1), "");
  Points all(V.rows() + 8, 3);
  all << V, always.added_controls;
  EXPECT_LE(row_errors(always.W, all, X).repro, kReproTol);
  EXPECT_GT(row_errors(always.W, all, X).min_w, 0.0);
  o.hull_points = CelestialHullPoints::Auto;
  X.row(5) << 1.2, 0.3, -0.4; // on the face x = 1.2 of the controls' box
  const CelestialResult on_face = celestial_coordinates(V, X, o);
  EXPECT_EQ(on_face.added_controls.rows(), 8);
  EXPECT_EQ(on_face.hull_location[5], CelestialLocation::Inside);
  EXPECT_GT(on_face.W.row(5).minCoeff(), 0.0);
  X.row(5) << 1.2 - 1e-9, 0.3, -0.4; // 1e-9 inside: strictly inside, nothing added
  EXPECT_EQ(celestial_coordinates(V, X, o).added_controls.rows(), 0);
}

// The hull points rotate, translate and scale with the scene, so the weights do not change
// (to 1e-10; the coordinates themselves are similarity invariant, SimilarityInvariant): random
// controls and points partly outside, and a symmetric scene (a cube's corners around an
// octahedron of controls: every corner is equally far from the centroid, so the frame's ties
// must be broken the same way after the rotation), in 2D and 3D, both schemes.
TEST(CelestialHullPoints, RotationTranslationScaleInvariant)
{
  for (int dim : { 2, 3 })
    for (bool symmetric : { false, true })
    {
      Points V, X;
      if (symmetric)
      {
        V.setZero(2 * dim, dim); // the cross-polytope of radius 0.5
        for (int j = 0; j < dim; ++j)
        {
          V(2 * j, j) = 0.5;
          V(2 * j + 1, j) = -0.5;
        }
        X = random_controls(dim, 0, 1, true); // the corners of [-1.2, 1.2]^dim
      }
      else
      {
        V = random_controls(dim, dim + 4, 121u + static_cast<unsigned>(dim), false);
        X = random_controls(dim, 50, 123, false);
        X.col(0).array() *= 3.0; // partly outside
      }
      const Eigen::MatrixXd R = random_rotation(dim, 125u + static_cast<unsigned>(dim));
      const Eigen::RowVectorXd t = Eigen::RowVectorXd::LinSpaced(dim, 3.0, -2.0);
      const double scale = 2.5;
      const Points V2 = ((V * R.transpose()) * scale).rowwise() + t;
      const Points X2 = ((X * R.transpose()) * scale).rowwise() + t;
      for (CelestialScheme scheme : { CelestialScheme::T, CelestialScheme::S })
      {
        CelestialOptions o = options_for(scheme);
        o.hull_points = CelestialHullPoints::Auto;
        const CelestialResult a = celestial_coordinates(V, X, o);
        const CelestialResult b = celestial_coordinates(V2, X2, o);
        ASSERT_EQ(a.added_controls.rows(), 1 << dim);
        ASSERT_EQ(b.added_controls.rows(), 1 << dim);
        const Points H2 = ((a.added_controls * R.transpose()) * scale).rowwise() + t;
        EXPECT_LE((b.added_controls - H2).cwiseAbs().maxCoeff(), 1e-12 * diameter(H2))
          << "dim " << dim << (symmetric ? " symmetric" : "");
        EXPECT_LE((a.W - b.W).cwiseAbs().maxCoeff(), 1e-10)
          << "dim " << dim << (symmetric ? " symmetric" : "");
        EXPECT_GT(a.W.minCoeff(), 0.0);
      }
    }
}

// The margin: every point and control lies at least hull_margin times the box's diagonal from
// each face of the added box, and the nearest exactly that (check_hull_box, for several
// margins); the weights are then positive. A margin <= 0, NaN or > 10 is refused.
TEST(CelestialHullPoints, MarginRespected)
{
  const Points V = random_controls(2, 5, 91, false);
  Points X = random_controls(2, 40, 92, false);
  X.col(0).array() *= 4.0; // wider than the controls
  for (double margin : { 1e-6, 0.05, 0.1, 1.0 })
  {
    CelestialOptions o;
    o.hull_points = CelestialHullPoints::Auto;
    o.hull_margin = margin;
    const CelestialResult r = celestial_coordinates(V, X, o);
    ASSERT_EQ(r.added_controls.rows(), 4);
    EXPECT_EQ(check_hull_box(V, X, r.added_controls, margin), "") << "margin " << margin;
    Points all(9, 2);
    all << V, r.added_controls;
    const RowErrors e = row_errors(r.W, all, X);
    EXPECT_LE(e.sum, kSumTol);
    EXPECT_LE(e.repro, kReproTol);
    EXPECT_GT(e.min_w, 0.0);
    EXPECT_EQ(r.boundary, 0);
  }
  for (double margin : { 0.0, -0.1, std::numeric_limits<double>::quiet_NaN(), 11.0 })
  {
    CelestialOptions bad;
    bad.hull_margin = margin;
    EXPECT_TRUE(throws_error([&] { CelestialCoordinates c(V, bad); }, ErrorCode::InvalidArgument,
      { "hull_margin must lie in [1e-6, 10]" }))
      << margin;
  }
}

// With Auto, controls that span no interior (one point, two, on a line or a plane) are accepted:
// the corners give the interior. The TCC user weights get s = 0 for the corners.
TEST(CelestialHullPoints, FewOrFlatControls)
{
  Points one(1, 3);
  one << 0.2, 0.1, -0.3;
  Points line(3, 2);
  line << 0, 0, 1, 1, 2, 2;
  Points plane(4, 3);
  plane << 0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0;
  for (const Points* V : { &one, &line, &plane })
  {
    CelestialOptions o;
    o.scheme = CelestialScheme::T;
    o.user_weights = Eigen::VectorXd::Constant(V->rows(), 0.5);
    EXPECT_THROW(CelestialCoordinates c(*V, o), Error);
    o.hull_points = CelestialHullPoints::Auto;
    const CelestialCoordinates cc(*V, o);
    EXPECT_EQ(cc.num_hull_facets(), 0);
    Points X = random_controls(static_cast<int>(V->cols()), 20, 95, false);
    const CelestialResult r = cc.compute(X);
    ASSERT_EQ(r.added_controls.rows(), Index(1) << V->cols());
    Points all(V->rows() + r.added_controls.rows(), V->cols());
    all << *V, r.added_controls;
    const RowErrors e = row_errors(r.W, all, X);
    EXPECT_GT(e.min_w, 0.0);
    EXPECT_LE(e.sum, kSumTol);
    EXPECT_LE(e.repro, kReproTol);
    EXPECT_TRUE(cc.hull_points_for(X) == r.added_controls);
  }
}

// Deforming with the user's controls moved and the corners where they are: the identity pose
// reproduces the points, and a translation of the user's controls moves the points near them
// more than the points far from them (the corners hold the far points).
TEST(CelestialHullPoints, DeformationKeepsTheCornersFixed)
{
  const Points V = random_controls(3, 6, 101, false);
  Points X = random_controls(3, 30, 102, false);
  X.array() *= 3.0;
  CelestialOptions o;
  o.hull_points = CelestialHullPoints::Auto;
  const CelestialResult r = celestial_coordinates(V, X, o);
  const Index nc = V.rows(), na = r.added_controls.rows();
  Points moved(nc + na, 3);
  moved << V, r.added_controls;
  const double diam = diameter(moved);
  EXPECT_LE(((r.W * moved) - X).cwiseAbs().maxCoeff(), kReproTol * diam);
  moved.topRows(nc).col(0).array() += 1.0; // the user's controls, not the corners
  const Points Y = r.W * moved;
  for (Index p = 0; p < X.rows(); ++p)
  {
    const double user_share = r.W.row(p).head(nc).sum();
    // the displacement is exactly the user controls' share of the translation
    EXPECT_NEAR(Y(p, 0) - X(p, 0), user_share, kReproTol * diam);
    EXPECT_NEAR((Y.row(p).tail(2) - X.row(p).tail(2)).norm(), 0.0, kReproTol * diam);
    EXPECT_LT(user_share, 1.0);
  }
}

// compute_from: started from the solution of the points before an edit (a control added, one
// removed), the weights equal a cold computation's within the tolerance; every inside point is
// started from the given row, and rows of NaN fall back to the neighbours.
TEST(Celestial, WarmStartFromAGivenSolution)
{
  for (CelestialScheme scheme : { CelestialScheme::T, CelestialScheme::S })
  {
    const Points V = random_controls(3, 12, 111, true);
    const Points X = random_inside(V, 300, 112);
    const CelestialOptions o = options_for(scheme);
    const CelestialResult before = celestial_coordinates(V, X, o);
    Points added(V.rows() + 1, 3);
    added << V, Eigen::RowVector3d(0.1, -0.2, 0.3);
    Points removed = V.topRows(V.rows() - 1);
    for (const Points* edited : std::vector<const Points*>{ &added, &removed, &V })
    {
      const CelestialCoordinates cc(*edited, o);
      const CelestialResult cold = cc.compute(X);
      const CelestialResult warm = cc.compute_from(X, before.solution);
      EXPECT_LE((warm.W - cold.W).cwiseAbs().maxCoeff(), kWarmColdTol);
      EXPECT_EQ(warm.warm_starts, warm.inside);
      EXPECT_TRUE(warm.converged);
      RecordProperty(std::string(scheme == CelestialScheme::T ? "T" : "S") + "_iterations_" +
          std::to_string(edited->rows()),
        sci(static_cast<double>(warm.total_iterations)) + " warm vs " +
          sci(static_cast<double>(cold.total_iterations)) + " neighbour-started");
      if (edited == &V) // started at the solution itself: no Newton step needed beyond a check
      {
        EXPECT_LE(warm.total_iterations, cold.total_iterations);
      }
    }
    Points partial = before.solution;
    partial.topRows(100).setConstant(std::numeric_limits<double>::quiet_NaN());
    const CelestialResult mixed = CelestialCoordinates(V, o).compute_from(X, partial);
    EXPECT_LE((mixed.W - before.W).cwiseAbs().maxCoeff(), kWarmColdTol);
    EXPECT_TRUE(throws_error([&] { CelestialCoordinates(V, o).compute_from(X, Points(3, 3)); },
      ErrorCode::SizeMismatch, { "initial solutions are 3 by 3 but there are 300 points" }));
  }
}

/// Every field of two results, bit for bit (NaN equal to NaN), but the wall-clock time.
void expect_same_result(const CelestialResult& a, const CelestialResult& b)
{
  const auto same_bits = [](const auto& x, const auto& y) {
    // empty: data() may be null, which memcmp must not be given
    const std::size_t bytes = sizeof(*x.data()) * static_cast<std::size_t>(x.size());
    return x.rows() == y.rows() && x.cols() == y.cols() &&
      (bytes == 0 || std::memcmp(x.data(), y.data(), bytes) == 0);
  };
  EXPECT_TRUE(same_bits(a.W, b.W));
  EXPECT_TRUE(same_bits(a.iterations, b.iterations));
  EXPECT_TRUE(same_bits(a.residual, b.residual));
  EXPECT_TRUE(same_bits(a.solution, b.solution));
  EXPECT_TRUE(same_bits(a.added_controls, b.added_controls));
  EXPECT_EQ(a.hull_location, b.hull_location);
  EXPECT_EQ(a.outside, b.outside);
  EXPECT_EQ(a.not_converged, b.not_converged);
  EXPECT_EQ(a.location, b.location);
  EXPECT_EQ(a.undefined, b.undefined);
  EXPECT_EQ(a.converged, b.converged);
  EXPECT_EQ(a.inside, b.inside);
  EXPECT_EQ(a.boundary, b.boundary);
  EXPECT_EQ(a.at_control, b.at_control);
  EXPECT_EQ(a.total_iterations, b.total_iterations);
  EXPECT_EQ(a.warm_starts, b.warm_starts);
  EXPECT_EQ(a.cold_restarts, b.cold_restarts);
  ASSERT_EQ(a.statistics.size(), b.statistics.size());
  for (std::size_t k = 0; k < a.statistics.size(); ++k)
  {
    EXPECT_EQ(a.statistics[k].first, b.statistics[k].first);
    if (a.statistics[k].first != "solve_seconds")
    {
      EXPECT_EQ(a.statistics[k].second, b.statistics[k].second) << a.statistics[k].first;
    }
  }
}

// compute(X, result) reuses result's storage: the same result as compute(X) whatever result
// held before (another run's fields, NaN everywhere, another shape), with points outside, on
// the hull and at a control, and with the hull points added (Auto).
TEST(Celestial, ReusedResultEqualsAFreshOne)
{
  for (int dim : { 2, 3 })
    for (CelestialScheme scheme : { CelestialScheme::T, CelestialScheme::S })
      for (bool auto_hull : { false, true })
      {
        SCOPED_TRACE(std::to_string(dim) + "D, " + (scheme == CelestialScheme::S ? "S" : "T") +
          (auto_hull ? ", hull points" : ""));
        const Points V = random_controls(dim, 14, 131, true);
        Points X = random_inside(V, 700, 132);
        X.row(5) = V.row(3);                   // at a control
        X.row(9) = 0.5 * (V.row(0) + V.row(1)); // on an edge of the box's hull
        X.row(11).setConstant(7.0);             // outside
        CelestialOptions o = options_for(scheme);
        o.outside = CelestialOutsidePolicy::Flag;
        o.hull_points = auto_hull ? CelestialHullPoints::Auto : CelestialHullPoints::None;
        const CelestialCoordinates cc(V, o);
        const CelestialResult fresh = cc.compute(X);
        ASSERT_EQ(fresh.added_controls.rows() > 0, auto_hull);
        CelestialResult reused = cc.compute(random_inside(V, 333, 133)); // another shape
        cc.compute(X, reused);
        expect_same_result(fresh, reused);
        // the same shape, full of NaN and of another run's lists
        reused.W.setConstant(std::numeric_limits<double>::quiet_NaN());
        reused.residual.setConstant(std::numeric_limits<double>::quiet_NaN());
        reused.solution.setConstant(std::numeric_limits<double>::quiet_NaN());
        reused.iterations.setConstant(-1);
        std::fill(reused.hull_location.begin(), reused.hull_location.end(),
          CelestialLocation::Outside);
        reused.outside = { 1, 2, 3 };
        reused.not_converged = { 4 };
        reused.added_controls = Points::Ones(2, dim);
        const double* storage = reused.W.data();
        cc.compute(X, reused);
        expect_same_result(fresh, reused);
        if (!auto_hull)
        {
          EXPECT_EQ(reused.W.data(), storage) << "W's storage was not reused";
        }
      }
}

TEST(Celestial, ReusingComputeRejectsBadPointsAndKeepsTheResult)
{
  const Points V = random_controls(3, 10, 141, true);
  const CelestialCoordinates cc(V);
  const Points X = random_inside(V, 50, 142);
  CelestialResult r = cc.compute(X);
  const CelestialResult before = r;
  Points bad = X;
  bad(7, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(throws_error([&] { cc.compute(bad, r); }, ErrorCode::NonFinite, { "7" }));
  expect_same_result(before, r);
  EXPECT_TRUE(throws_error(
    [&] { cc.compute(Points(4, 2), r); }, ErrorCode::SizeMismatch, { "2 coordinates" }));
  expect_same_result(before, r);
  cc.compute(Points(0, 3), r);
  EXPECT_EQ(r.W.rows(), 0);
  EXPECT_EQ(r.W.cols(), V.rows());
  EXPECT_EQ(r.iterations.size(), 0);
  EXPECT_TRUE(r.hull_location.empty());
}

} // namespace
