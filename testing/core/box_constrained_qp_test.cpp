// Tests for core/solvers/box_constrained_qp.h: agreement with a brute-force enumeration of all active
// sets on tiny problems, KKT and exact bounds on random sparse problems of ~2000 variables
// (M-matrix-like and bi-Laplacian-like), warm starts, the safeguard, and every error branch.
#include "core/solvers/box_constrained_qp.h"
#include "core/common/error.h"
#include "error_matchers.h"

#include <Eigen/Cholesky>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace
{
using namespace bary;
using bary::test::throws_error;
using SparseMatrix = Eigen::SparseMatrix<double>;

constexpr double kInf = std::numeric_limits<double>::infinity();

/// Independent KKT check of x for min 1/2 x'Ax + b'x, l <= x <= u: the largest violation of
/// stationarity (interior variables) or of the multiplier's sign (variables on a bound), relative
/// to max_i sum_j |A_ij x_j| (as in the header), and whether l <= x <= u holds exactly.
struct Kkt
{
  double residual = 0;
  bool within_bounds = true;
};
Kkt check_kkt(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, const Eigen::VectorXd& l,
  const Eigen::VectorXd& u, const Eigen::VectorXd& x)
{
  const Eigen::VectorXd y = A * x + b;
  const double scale = std::max(
    { 1e-300, (A.cwiseAbs() * x.cwiseAbs()).maxCoeff(), b.cwiseAbs().maxCoeff() });
  Kkt k;
  for (Eigen::Index i = 0; i < x.size(); ++i)
  {
    if (!(x(i) >= l(i) && x(i) <= u(i)))
      k.within_bounds = false;
    if (l(i) == u(i))
      continue;
    double v = 0;
    if (x(i) == l(i))
      v = std::max(0.0, -y(i));
    else if (x(i) == u(i))
      v = std::max(0.0, y(i));
    else
      v = std::abs(y(i));
    k.residual = std::max(k.residual, v / scale);
  }
  return k;
}

/// Brute force: try all 3^n assignments (lower / free / upper, fixed variables fixed), solve the
/// equality-constrained problem densely and keep the one that satisfies the KKT conditions.
Eigen::VectorXd brute_force(const Eigen::MatrixXd& A, const Eigen::VectorXd& b,
  const Eigen::VectorXd& l, const Eigen::VectorXd& u)
{
  const int n = static_cast<int>(b.size());
  int total = 1;
  for (int i = 0; i < n; ++i)
    total *= 3;
  Eigen::VectorXd best;
  double best_residual = kInf;
  for (int code = 0; code < total; ++code)
  {
    Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
    std::vector<int> free;
    bool possible = true;
    for (int i = 0, c = code; i < n; ++i, c /= 3)
    {
      const int s = c % 3; // 0 lower, 1 free, 2 upper
      if (l(i) == u(i))
      {
        if (s != 0)
          possible = false;
        x(i) = l(i);
      }
      else if (s == 0)
        x(i) = l(i);
      else if (s == 2)
        x(i) = u(i);
      else
        free.push_back(i);
      if (!std::isfinite(x(i)) && s != 1)
        possible = false;
    }
    if (!possible)
      continue;
    const int nf = static_cast<int>(free.size());
    if (nf > 0)
    {
      Eigen::MatrixXd Aff(nf, nf);
      Eigen::VectorXd rhs(nf);
      Eigen::VectorXd xn = x;
      for (int a = 0; a < nf; ++a)
        xn(free[a]) = 0;
      const Eigen::VectorXd r = A * xn + b;
      for (int a = 0; a < nf; ++a)
      {
        rhs(a) = -r(free[a]);
        for (int c = 0; c < nf; ++c)
          Aff(a, c) = A(free[a], free[c]);
      }
      const Eigen::VectorXd xf = Aff.llt().solve(rhs);
      for (int a = 0; a < nf; ++a)
        x(free[a]) = xf(a);
    }
    // KKT with small slack (the assignment's free variables must be inside their bounds).
    const Eigen::VectorXd y = A * x + b;
    double residual = 0;
    for (int i = 0; i < n; ++i)
    {
      if (l(i) == u(i))
        continue;
      const bool is_free = std::find(free.begin(), free.end(), i) != free.end();
      if (is_free)
        residual = std::max({ residual, l(i) - x(i), x(i) - u(i) });
      else if (x(i) == l(i))
        residual = std::max(residual, -y(i));
      else
        residual = std::max(residual, y(i));
    }
    if (residual < best_residual)
    {
      best_residual = residual;
      best = x;
    }
  }
  EXPECT_LT(best_residual, 1e-9) << "brute force found no KKT point";
  return best;
}

/// Random SPD matrix R'R + 0.1 I of size n.
Eigen::MatrixXd random_spd(int n, std::mt19937& rng)
{
  std::normal_distribution<double> normal;
  Eigen::MatrixXd R(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      R(i, j) = normal(rng);
  return R.transpose() * R + 0.1 * Eigen::MatrixXd::Identity(n, n);
}

TEST(BoxConstrainedQP, MatchesBruteForceOnTinyProblems)
{
  // 200 problems of 1..8 variables with finite, one-sided and fixed bounds. Tolerance: the
  // solution is unique, so the two must agree to rounding (1e-9 relative to |x|).
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::uniform_int_distribution<int> kind(0, 5);
  for (int trial = 0; trial < 200; ++trial)
  {
    const int n = 1 + trial % 8;
    const Eigen::MatrixXd A = random_spd(n, rng);
    Eigen::VectorXd b(n), l(n), u(n);
    for (int i = 0; i < n; ++i)
    {
      b(i) = 3.0 * uniform(rng);
      const double a = uniform(rng), c = uniform(rng);
      l(i) = std::min(a, c);
      u(i) = std::max(a, c);
      switch (kind(rng))
      {
        case 0: l(i) = -kInf; break;
        case 1: u(i) = kInf; break;
        case 2: u(i) = l(i); break; // fixed
        default: break;
      }
    }
    const Eigen::VectorXd expected = brute_force(A, b, l, u);
    const BoxQPResult r = box_constrained_qp(A.sparseView(), b, l, u);
    ASSERT_TRUE(r.converged) << "trial " << trial;
    EXPECT_LE((r.x - expected).cwiseAbs().maxCoeff(), 1e-9 * std::max(1.0, expected.cwiseAbs().maxCoeff()))
      << "trial " << trial;
    EXPECT_EQ(r.max_bound_violation, 0.0);
    EXPECT_TRUE(check_kkt(A, b, l, u, r.x).within_bounds);
  }
}

/// 2D grid graph Laplacian plus a diagonal shift: an M-matrix (n = side^2).
SparseMatrix grid_laplacian(int side, double shift)
{
  std::vector<Eigen::Triplet<double>> t;
  auto id = [side](int i, int j) { return i * side + j; };
  for (int i = 0; i < side; ++i)
    for (int j = 0; j < side; ++j)
    {
      double degree = shift;
      for (const auto& d : { std::pair{ 1, 0 }, std::pair{ -1, 0 }, std::pair{ 0, 1 }, std::pair{ 0, -1 } })
      {
        const int a = i + d.first, c = j + d.second;
        if (a < 0 || a >= side || c < 0 || c >= side)
          continue;
        t.emplace_back(id(i, j), id(a, c), -1.0);
        degree += 1.0;
      }
      t.emplace_back(id(i, j), id(i, j), degree);
    }
  SparseMatrix L(side * side, side * side);
  L.setFromTriplets(t.begin(), t.end());
  return L;
}

struct RandomProblem
{
  SparseMatrix A;
  Eigen::VectorXd b, l, u;
};

/// A ~ 2025 variables: an M-matrix (shifted Laplacian) or a bi-Laplacian L*L + shift (not an
/// M-matrix, like BBW's Q), random b and bounds [-0.5, 0.5] with some fixed and some infinite.
RandomProblem random_problem(bool bilaplacian, unsigned seed)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  const SparseMatrix L = grid_laplacian(45, bilaplacian ? 0.0 : 0.05);
  RandomProblem p;
  if (bilaplacian)
  {
    p.A = L * L;
    for (int i = 0; i < p.A.rows(); ++i)
      p.A.coeffRef(i, i) += 1e-3;
  }
  else
    p.A = L;
  const Eigen::Index n = p.A.rows();
  p.b.resize(n);
  p.l.resize(n);
  p.u.resize(n);
  for (Eigen::Index i = 0; i < n; ++i)
  {
    p.b(i) = uniform(rng);
    p.l(i) = -0.5;
    p.u(i) = 0.5;
    const double r = uniform(rng);
    if (r > 0.95)
      p.l(i) = p.u(i) = 0.25 * uniform(rng);
    else if (r > 0.9)
      p.u(i) = kInf;
    else if (r < -0.9)
      p.l(i) = -kInf;
  }
  return p;
}

class BoxQPRandom : public ::testing::TestWithParam<std::tuple<bool, unsigned>>
{
};

TEST_P(BoxQPRandom, ConvergesWithKktBelow1e10AndExactBounds)
{
  const auto [bilaplacian, seed] = GetParam();
  const RandomProblem p = random_problem(bilaplacian, seed);
  const BoxQPResult r = box_constrained_qp(p.A, p.b, p.l, p.u);
  ASSERT_TRUE(r.converged);
  EXPECT_LE(r.kkt_residual, 1e-10);
  EXPECT_EQ(r.max_bound_violation, 0.0);
  EXPECT_EQ(r.violators, 0);
  const Kkt k = check_kkt(Eigen::MatrixXd(p.A), p.b, p.l, p.u, r.x);
  EXPECT_TRUE(k.within_bounds);
  EXPECT_LE(k.residual, 1e-10);
  // Both bounds are active somewhere, so the test exercises all three sets.
  EXPECT_GT(r.lower, 0);
  EXPECT_GT(r.upper, 0);
  EXPECT_GT(r.free, 0);
  EXPECT_EQ(r.fixed + r.lower + r.upper + r.free, p.A.rows());
  // The objective is reported and consistent.
  EXPECT_NEAR(r.objective, 0.5 * r.x.dot(p.A * r.x) + p.b.dot(r.x),
    1e-12 * std::max(1.0, std::abs(r.objective)));
}

INSTANTIATE_TEST_SUITE_P(MMatrixAndBiLaplacian, BoxQPRandom,
  ::testing::Combine(::testing::Bool(), ::testing::Values(1u, 2u, 3u)));

TEST(BoxConstrainedQP, FactorizationStrategiesAndBackendsAgree)
{
  // The same bi-Laplacian problems with every backend, with and without the reused ordering and
  // the row modifications of the factorization: the solution is unique, so all must agree to
  // rounding (1e-9 relative), satisfy the KKT conditions, and the supernodal backend with
  // modifications must actually have modified factorizations (else this tests nothing).
  using Backend = SparseCholesky::Backend;
  for (const unsigned seed : { 1u, 2u })
  {
    const RandomProblem p = random_problem(true, seed);
    BoxQPOptions reference_options;
    reference_options.backend = Backend::Eigen;
    reference_options.reuse_ordering = false;
    reference_options.modify_factorizations = false;
    const BoxQPResult reference = box_constrained_qp(p.A, p.b, p.l, p.u, reference_options);
    ASSERT_TRUE(reference.converged);
    EXPECT_EQ(reference.modifications, 0);
    std::vector<Backend> backends = { Backend::Eigen, Backend::Supernodal };
    if (SparseCholesky::cholmod_available())
      backends.push_back(Backend::Cholmod);
    for (const Backend backend : backends)
      for (const bool reuse : { false, true })
        for (const bool modify : { false, true })
        {
          BoxQPOptions options;
          options.backend = backend;
          options.reuse_ordering = reuse;
          options.modify_factorizations = modify;
          const BoxQPResult r = box_constrained_qp(p.A, p.b, p.l, p.u, options);
          const std::string what = std::string(to_string(backend)) + (reuse ? " reuse" : "") +
            (modify ? " modify" : "") + ", seed " + std::to_string(seed);
          ASSERT_TRUE(r.converged) << what;
          EXPECT_LE(r.kkt_residual, 1e-10) << what;
          EXPECT_EQ(r.max_bound_violation, 0.0) << what;
          EXPECT_LE((r.x - reference.x).cwiseAbs().maxCoeff(),
            1e-9 * std::max(1.0, reference.x.cwiseAbs().maxCoeff())) << what;
          // At most one factorization or modification per iteration.
          EXPECT_LE(r.factorizations + r.modifications, r.iterations) << what;
          const bool can_modify = modify && backend == Backend::Supernodal && SparseCholesky::cholmod_available();
          if (can_modify)
          {
            EXPECT_GT(r.modifications, 0) << what;
            EXPECT_GE(r.modified_rows, r.modifications) << what;
          }
          else
          {
            EXPECT_EQ(r.modifications, 0) << what;
          }
        }
  }
}

TEST(BoxConstrainedQP, InfiniteBoundsGiveTheLinearSolve)
{
  const SparseMatrix A = grid_laplacian(10, 0.5);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(100, -1.0, 1.0);
  const Eigen::VectorXd l = Eigen::VectorXd::Constant(100, -kInf);
  const Eigen::VectorXd u = Eigen::VectorXd::Constant(100, kInf);
  const BoxQPResult r = box_constrained_qp(A, b, l, u);
  ASSERT_TRUE(r.converged);
  EXPECT_EQ(r.iterations, 1);
  const Eigen::VectorXd expected = Eigen::MatrixXd(A).llt().solve(-b);
  EXPECT_LE((r.x - expected).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(BoxConstrainedQP, FixedVariablesKeepTheirValuesExactly)
{
  const RandomProblem p = random_problem(true, 7);
  const BoxQPResult r = box_constrained_qp(p.A, p.b, p.l, p.u);
  ASSERT_TRUE(r.converged);
  Eigen::Index fixed = 0;
  for (Eigen::Index i = 0; i < p.l.size(); ++i)
    if (p.l(i) == p.u(i))
    {
      ++fixed;
      EXPECT_EQ(r.x(i), p.l(i));
      EXPECT_EQ(r.state(i), BoxQPState::Fixed);
    }
  EXPECT_EQ(r.fixed, fixed);
  EXPECT_GT(fixed, 0);
}

TEST(BoxConstrainedQP, WarmStartFromTheSolutionTakesOneIterationAndReusesTheFactor)
{
  const RandomProblem p = random_problem(true, 4);
  const BoxConstrainedQP qp(p.A);
  BoxQPWarmStart warm;
  const BoxQPResult first = qp.solve(p.b, p.l, p.u, {}, &warm);
  ASSERT_TRUE(first.converged);
  EXPECT_GT(first.iterations, 1);
  const BoxQPResult second = qp.solve(p.b, p.l, p.u, {}, &warm);
  ASSERT_TRUE(second.converged);
  EXPECT_EQ(second.iterations, 1);
  EXPECT_EQ(second.factorizations, 0); // the cached factor of the same free set
  EXPECT_LE((second.x - first.x).cwiseAbs().maxCoeff(), 1e-14);
  // A warm start from another matrix does not reuse its factor.
  const BoxConstrainedQP other(p.A * 2.0);
  const BoxQPResult third = other.solve(p.b, p.l, p.u, {}, &warm);
  ASSERT_TRUE(third.converged);
  EXPECT_EQ(third.factorizations, third.iterations);
}

TEST(BoxConstrainedQP, GuessedActiveSet)
{
  const Eigen::VectorXd x0 = (Eigen::VectorXd(4) << -1.0, 0.5, 2.0, 0.3).finished();
  const Eigen::VectorXd l = (Eigen::VectorXd(4) << 0.0, 0.0, 0.0, 0.3).finished();
  const Eigen::VectorXd u = (Eigen::VectorXd(4) << 1.0, 1.0, 1.0, 0.3).finished();
  const auto s = active_set_from_guess(x0, l, u);
  EXPECT_EQ(s(0), BoxQPState::Lower);
  EXPECT_EQ(s(1), BoxQPState::Free);
  EXPECT_EQ(s(2), BoxQPState::Upper);
  EXPECT_EQ(s(3), BoxQPState::Fixed);
  EXPECT_TRUE(throws_error([&] { active_set_from_guess(x0, l, Eigen::VectorXd(3)); },
    ErrorCode::SizeMismatch));
}

TEST(BoxConstrainedQP, SafeguardSingleStepsReachTheSameSolution)
{
  // block_attempts = 0 takes a single-index step whenever the violator count does not improve.
  const RandomProblem p = random_problem(true, 5);
  BoxQPOptions options;
  const BoxQPResult reference = box_constrained_qp(p.A, p.b, p.l, p.u, options);
  options.block_attempts = 0;
  const BoxQPResult guarded = box_constrained_qp(p.A, p.b, p.l, p.u, options);
  ASSERT_TRUE(guarded.converged);
  EXPECT_LE((guarded.x - reference.x).cwiseAbs().maxCoeff(), 1e-8);
  EXPECT_LE(guarded.kkt_residual, 1e-10);
}

TEST(BoxConstrainedQP, IterationCapIsReportedNotSilent)
{
  const RandomProblem p = random_problem(true, 6);
  BoxQPOptions options;
  options.max_iterations = 1;
  const BoxQPResult r = box_constrained_qp(p.A, p.b, p.l, p.u, options);
  EXPECT_FALSE(r.converged);
  EXPECT_EQ(r.iterations, 1);
  EXPECT_GT(r.violators, 0);
  EXPECT_GT(r.kkt_residual, 1e-10);
  EXPECT_EQ(r.max_bound_violation, 0.0); // still clamped into the box
}

TEST(BoxConstrainedQP, CancelStopsTheSolver)
{
  const RandomProblem p = random_problem(false, 1);
  BoxQPOptions options;
  options.keep_going = [] { return false; };
  EXPECT_TRUE(throws_error([&] { box_constrained_qp(p.A, p.b, p.l, p.u, options); },
    ErrorCode::Cancelled, { "cancelled" }));
}

TEST(BoxConstrainedQP, GradientScaleOverride)
{
  const RandomProblem p = random_problem(false, 2);
  BoxQPOptions options;
  options.gradient_scale = 1e6; // a larger scale loosens the relative measures
  const BoxQPResult loose = box_constrained_qp(p.A, p.b, p.l, p.u, options);
  const BoxQPResult plain = box_constrained_qp(p.A, p.b, p.l, p.u);
  ASSERT_TRUE(loose.converged);
  EXPECT_LE(loose.kkt_residual, plain.kkt_residual + 1e-12);
  options.gradient_scale = -1.0;
  EXPECT_TRUE(throws_error([&] { box_constrained_qp(p.A, p.b, p.l, p.u, options); },
    ErrorCode::InvalidArgument, { "gradient_scale" }));
}

TEST(BoxConstrainedQP, Errors)
{
  const SparseMatrix A = grid_laplacian(3, 0.1);
  const Eigen::VectorXd b = Eigen::VectorXd::Zero(9), l = Eigen::VectorXd::Zero(9),
                        u = Eigen::VectorXd::Ones(9);
  // Empty bounds (infeasible), named.
  Eigen::VectorXd bad_l = l;
  bad_l(4) = 2.0;
  EXPECT_TRUE(throws_error([&] { box_constrained_qp(A, b, bad_l, u); }, ErrorCode::InvalidArgument,
    { "variable 4", "infeasible" }));
  // NaN bound, NaN or infinite b.
  Eigen::VectorXd nan_u = u;
  nan_u(2) = std::nan("");
  EXPECT_TRUE(throws_error([&] { box_constrained_qp(A, b, l, nan_u); }, ErrorCode::NonFinite,
    { "variable 2" }));
  Eigen::VectorXd inf_b = b;
  inf_b(0) = kInf;
  EXPECT_TRUE(throws_error([&] { box_constrained_qp(A, inf_b, l, u); }, ErrorCode::NonFinite));
  // Fixed at infinity.
  Eigen::VectorXd inf_l = l, inf_u2 = u;
  inf_l(1) = inf_u2(1) = kInf;
  EXPECT_TRUE(throws_error([&] { box_constrained_qp(A, b, inf_l, inf_u2); },
    ErrorCode::InvalidArgument, { "variable 1" }));
  // Sizes.
  EXPECT_TRUE(throws_error([&] { box_constrained_qp(A, Eigen::VectorXd::Zero(8), l, u); },
    ErrorCode::SizeMismatch, { "linear term" }));
  EXPECT_TRUE(throws_error([&] { box_constrained_qp(SparseMatrix(3, 4), b, l, u); },
    ErrorCode::SizeMismatch, { "square" }));
  EXPECT_TRUE(throws_error([&] { box_constrained_qp(SparseMatrix(0, 0), b, l, u); },
    ErrorCode::EmptyInput));
  // Not positive definite: a non-positive diagonal (precompute), an indefinite matrix with a
  // positive diagonal (found when its free block is factored), an unbounded problem.
  SparseMatrix negative = A;
  negative.coeffRef(5, 5) = -1.0;
  EXPECT_TRUE(throws_error([&] { BoxConstrainedQP qp(negative); }, ErrorCode::InvalidArgument,
    { "(5, 5)", "positive definite" }));
  const SparseMatrix indefinite =
    (Eigen::MatrixXd(2, 2) << 1.0, 2.0, 2.0, 1.0).finished().sparseView();
  EXPECT_TRUE(throws_error(
    [&] {
      box_constrained_qp(indefinite, Eigen::VectorXd::Ones(2), Eigen::VectorXd::Constant(2, -1.0),
        Eigen::VectorXd::Constant(2, 1.0));
    },
    ErrorCode::InvalidArgument, { "positive definite" }));
  const SparseMatrix singular =
    (Eigen::MatrixXd(2, 2) << 1.0, 1.0, 1.0, 1.0).finished().sparseView();
  EXPECT_TRUE(throws_error(
    [&] {
      box_constrained_qp(singular, (Eigen::VectorXd(2) << 1.0, -1.0).finished(),
        Eigen::VectorXd::Constant(2, -kInf), Eigen::VectorXd::Constant(2, kInf));
    },
    ErrorCode::InvalidArgument, { "unbounded" }));
  // Asymmetric, non-finite matrices.
  SparseMatrix asymmetric = A;
  asymmetric.coeffRef(0, 1) = -0.5;
  EXPECT_TRUE(throws_error([&] { BoxConstrainedQP qp(asymmetric); }, ErrorCode::InvalidArgument,
    { "not symmetric" }));
  SparseMatrix nan_matrix = A;
  nan_matrix.coeffRef(3, 3) = std::nan("");
  EXPECT_TRUE(throws_error([&] { BoxConstrainedQP qp(nan_matrix); }, ErrorCode::NonFinite));
  // Solve before precompute; options out of range; warm start of the wrong size.
  EXPECT_TRUE(throws_error([&] { BoxConstrainedQP().solve(b, l, u); }, ErrorCode::InvalidArgument,
    { "before precompute" }));
  BoxQPOptions options;
  options.tolerance = 0.0;
  EXPECT_TRUE(throws_error([&] { box_constrained_qp(A, b, l, u, options); },
    ErrorCode::InvalidArgument, { "tolerance" }));
  options = {};
  options.max_iterations = 0;
  EXPECT_TRUE(throws_error([&] { box_constrained_qp(A, b, l, u, options); },
    ErrorCode::InvalidArgument, { "max_iterations" }));
  options = {};
  options.block_attempts = -1;
  EXPECT_TRUE(throws_error([&] { box_constrained_qp(A, b, l, u, options); },
    ErrorCode::InvalidArgument, { "block_attempts" }));
  BoxQPWarmStart warm;
  warm.state.resize(3);
  EXPECT_TRUE(throws_error([&] { BoxConstrainedQP(A).solve(b, l, u, {}, &warm); },
    ErrorCode::SizeMismatch, { "warm start" }));
}

} // namespace
