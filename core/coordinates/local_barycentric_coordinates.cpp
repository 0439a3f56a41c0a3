#include "core/coordinates/local_barycentric_coordinates.h"

#include "core/detail/anderson.h"
#include "core/detail/parallel_for.h"
#include "core/detail/row_cholesky.h"
#include "core/detail/simd.h"
#include "core/detail/format.h"
#include "core/detail/timing.h"
#include "core/common/error.h"
#include "core/solvers/fem_operators.h"
#include "core/coordinates/harmonic_coordinates.h"

#include <Eigen/Dense>
#include <Eigen/OrderingMethods>
#include <Eigen/SparseCholesky>

#if BARY_HAVE_AVX2_DISPATCH
#include <immintrin.h>
#endif

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <type_traits>
#include <string>
#include <utility>
#include <vector>

namespace bary
{
namespace
{

using RowMatrix = DenseWeights;
using Csr = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;
using Clock = std::chrono::steady_clock;

using detail::Anderson;
using detail::RowCholesky;
using detail::thread_count;

/// LBCResult::statistics (see its comment) from its fields; @p threads, the threads used.
void fill_statistics(LBCResult& result, int threads)
{
  Statistics& st = result.statistics;
  st.clear();
  st.emplace_back("iterations", static_cast<double>(result.iterations));
  st.emplace_back("primal_residual", result.primal_residual);
  st.emplace_back("dual_residual", result.dual_residual);
  st.emplace_back("primal_threshold", result.primal_threshold);
  st.emplace_back("dual_threshold", result.dual_threshold);
  st.emplace_back("objective", result.objective);
  st.emplace_back("converged", result.converged ? 1.0 : 0.0);
  st.emplace_back("partition_error", result.partition_error);
  st.emplace_back("reproduction_error", result.reproduction_error);
  st.emplace_back("min_weight", result.min_weight);
  st.emplace_back("threads", static_cast<double>(threads));
  st.emplace_back("geodesic_seconds", result.geodesic_seconds);
  st.emplace_back("factor_seconds", result.factor_seconds);
  st.emplace_back("admm_seconds", result.admm_seconds);
  st.emplace_back("solve_seconds", result.seconds);
}

[[noreturn]] void invalid(const std::string& message)
{
  throw Error(ErrorCode::InvalidArgument, message);
}

/// out = A X (+ add) for a row-major sparse A and row-major dense X, rows in parallel.
void csr_times(const Csr& A, const RowMatrix& X, RowMatrix& out, int threads)
{
  const Index rows = A.rows(), k = X.cols();
  out.resize(rows, k);
  const int* outer = A.outerIndexPtr();
  const int* inner = A.innerIndexPtr();
  const double* values = A.valuePtr();
#pragma omp parallel for num_threads(threads) schedule(static)
  for (Index r = 0; r < rows; ++r)
  {
    double* o = out.data() + r * k;
    for (Index c = 0; c < k; ++c)
      o[c] = 0.0;
    for (int p = outer[r]; p < outer[r + 1]; ++p)
    {
      const double a = values[p];
      const double* x = X.data() + static_cast<Index>(inner[p]) * k;
      for (Index c = 0; c < k; ++c)
        o[c] += a * x[c];
    }
  }
}

// --- the proximal map of the (relaxed) total variation: relaxed_tv_prox_radius below ---------
inline double prox_radius(double r, double kappa, double eps)
{
  if (eps <= 0.0)
    return r > kappa ? r - kappa : 0.0;
  if (r >= eps + kappa)
    return r - kappa;
  // rho < eps: rho - r + kappa (2 rho / eps - rho^2 / eps^2) = 0, the smaller root of
  // (kappa / eps^2) rho^2 - (1 + 2 kappa / eps) rho + r = 0 without cancellation
  const double c = 1.0 + 2.0 * kappa / eps;
  return 2.0 * r / (c + std::sqrt(std::max(0.0, c * c - 4.0 * kappa * r / (eps * eps))));
}

inline double relaxed_norm(double r, double eps)
{
  if (eps <= 0.0 || r >= eps)
    return r;
  return -r * r * r / (3.0 * eps * eps) + r * r / eps + eps / 3.0;
}

// --- polishing: projection onto {w >= 0, w K = b} ------------------------------------------------
/// Euclidean projection of @p z (n) onto {w >= 0, K^T w = b} by a semismooth Newton method on
/// the dual: w(l) = max(0, z + K l), maximise psi(l) = -1/2 |w(l)|^2 + b.l (concave, C^1),
/// Newton steps with the generalised Hessian K^T diag(z + K l > 0) K (+ a tiny ridge), a step
/// being accepted when it increases psi enough (Armijo) or reduces the gradient b - K^T w(l)
/// (near the solution the change of psi drowns in rounding). Entries with z = -infinity stay 0.
/// Returns false if it does not reach |K^T w - b|_inf <= tol within the iteration cap (w then
/// holds max(z, 0)).
bool project_feasible(const Eigen::MatrixXd& K, const Eigen::VectorXd& b, const double* z,
  double* w, Index n, double tol)
{
  const Index d = K.cols();
  Eigen::VectorXd lambda = Eigen::VectorXd::Zero(d);
  Eigen::Map<const Eigen::VectorXd> zv(z, n);
  Eigen::VectorXd x(n), wl(n), trial_x(n), trial_w(n);
  auto dual = [&](const Eigen::VectorXd& l, Eigen::VectorXd& xout, Eigen::VectorXd& wout) {
    xout.noalias() = zv + K * l;
    wout = xout.cwiseMax(0.0);
    return -0.5 * wout.squaredNorm() + b.dot(l);
  };
  double value = dual(lambda, x, wl);
  Eigen::VectorXd grad = b - K.transpose() * wl;
  double gmax = grad.cwiseAbs().maxCoeff();
  for (int iteration = 0; iteration < 100 && gmax > tol; ++iteration)
  {
    Eigen::MatrixXd Hm = Eigen::MatrixXd::Zero(d, d);
    for (Index i = 0; i < n; ++i)
      if (x(i) > 0.0)
        Hm.noalias() += K.row(i).transpose() * K.row(i);
    Hm.diagonal().array() += 1e-12 * (1.0 + Hm.diagonal().maxCoeff());
    const Eigen::VectorXd step = Hm.ldlt().solve(grad);
    if (!step.allFinite())
      break;
    const double slope = grad.dot(step);
    double t = 1.0;
    bool accepted = false;
    for (int ls = 0; ls < 60 && !accepted; ++ls, t *= 0.5)
    {
      const Eigen::VectorXd trial = lambda + t * step;
      const double v = dual(trial, trial_x, trial_w);
      const Eigen::VectorXd trial_grad = b - K.transpose() * trial_w;
      const double trial_gmax = trial_grad.cwiseAbs().maxCoeff();
      if (v >= value + 1e-4 * t * slope || trial_gmax < 0.5 * gmax)
      {
        lambda = trial;
        value = v;
        x.swap(trial_x);
        wl.swap(trial_w);
        grad = trial_grad;
        gmax = trial_gmax;
        accepted = true;
      }
    }
    if (!accepted)
      break;
  }
  if (gmax <= tol)
  {
    for (Index i = 0; i < n; ++i)
      w[i] = wl(i);
    return true;
  }
  for (Index i = 0; i < n; ++i)
    w[i] = std::max(0.0, z[i]);
  return false;
}

/// Mean number of entries above 10^-3 / #C per row of W (the locality statistics' threshold).
double mean_support(const RowMatrix& W)
{
  if (W.rows() == 0 || W.cols() == 0)
    return 0.0;
  const double threshold = 1e-3 / static_cast<double>(W.cols());
  Index count = 0;
  const double* w = W.data();
  for (Index k = 0, size = W.size(); k < size; ++k)
    count += w[k] > threshold;
  return static_cast<double>(count) / static_cast<double>(W.rows());
}

/// LBCStopping::Converged (docs/local-barycentric-coordinates.md, "Stopping rule", has the
/// study that chose it). On top of the paper's test, with rms = |r|_F / sqrt(N) (the residuals'
/// root mean square per entry, which does not loosen as the mesh grows: Boyd et al. 2011,
/// §3.3.1) and the targets e_p = 10^3 primal_tolerance / #C, e_d = 10^3 dual_tolerance / #C (at
/// the defaults 10^-3 / #C and 10^-2 / #C: the weights' RMS error is brought below the
/// threshold at which a weight counts as significant):
///  (A) rms_p <= e_p and rms_d <= e_d, or
///  (B) rms_p <= 10 e_p, rms_d <= 10 e_d and the support has settled: the mean number of
///      weights above 10^-3 / #C per vertex differs by at most 1% from its value at the check
///      half as many iterations ago (a window that grows with the run, so a slow drift late in
///      the run is seen as well as a fast one early; the residual gate keeps the early plateau,
///      where almost every weight is still significant, from passing).
constexpr double kSupportSettled = 0.01;
constexpr double kSettledResidualFactor = 10.0;
bool support_settled(const std::vector<double>& history)
{
  const std::size_t c = history.size();
  if (c < 2)
    return false;
  const double now = history[c - 1], then = history[c / 2 - 1];
  return std::abs(now - then) <= kSupportSettled * now;
}

/// Throws Error(InvalidArgument) naming the first LBCOptions field out of its documented range.
void validate_options(const LBCOptions& o)
{
  if (!(o.penalty > 0.0) || !std::isfinite(o.penalty))
    invalid("LBCOptions::penalty must be > 0, got " + detail::format_number(o.penalty));
  if (!(o.scaled_penalty > 0.0) || !std::isfinite(o.scaled_penalty))
    invalid("LBCOptions::scaled_penalty must be > 0, got " + detail::format_number(o.scaled_penalty));
  if (!(o.relaxation > 0.0 && o.relaxation < 2.0))
    invalid("LBCOptions::relaxation must be in (0, 2), got " + detail::format_number(o.relaxation));
  if (!(o.primal_tolerance > 0.0 && o.primal_tolerance < 1.0))
    invalid("LBCOptions::primal_tolerance must be in (0, 1), got " + detail::format_number(o.primal_tolerance));
  if (!(o.dual_tolerance > 0.0 && o.dual_tolerance < 1.0))
    invalid("LBCOptions::dual_tolerance must be in (0, 1), got " + detail::format_number(o.dual_tolerance));
  if (o.max_iterations < 1)
    invalid("LBCOptions::max_iterations must be >= 1, got " + std::to_string(o.max_iterations));
  if (o.check_interval < 1)
    invalid("LBCOptions::check_interval must be >= 1, got " + std::to_string(o.check_interval));
  if (o.locality == LocalityFunction::Custom && !o.custom_locality)
    invalid("LBCOptions::locality is Custom but custom_locality is empty");
  if (!(o.relaxed_tv_epsilon >= 0.0) || !std::isfinite(o.relaxed_tv_epsilon))
    invalid("LBCOptions::relaxed_tv_epsilon must be >= 0, got " + detail::format_number(o.relaxed_tv_epsilon));
  if (o.threads < 0)
    invalid("LBCOptions::threads must be >= 0 (0 = OpenMP's default), got " +
      std::to_string(o.threads));
  if (!(o.constraint_balance > 0.0) || !std::isfinite(o.constraint_balance))
    invalid("LBCOptions::constraint_balance must be > 0, got " + detail::format_number(o.constraint_balance));
  if (o.anderson_history < 1 || o.anderson_history > 50)
    invalid("LBCOptions::anderson_history must be in [1, 50], got " +
      std::to_string(o.anderson_history));
}

} // namespace

// =================================================================================================

struct LocalBarycentricCoordinates::Impl
{
  LBCOptions o;
  int D = 0;
  Index nv = 0, nc = 0, nt = 0, m = 0;
  double scale = 1.0;         ///< bounding-box diagonal of the input mesh
  Eigen::RowVectorXd center;  ///< bounding-box center
  Eigen::MatrixXd Vs;         ///< rescaled vertices (diameter 1)
  Eigen::MatrixXi T;
  Eigen::VectorXi control_vertex;
  std::vector<int> free_vertices;  ///< m mesh vertices that are optimised
  RowMatrix W_fixed;               ///< #V by n: boundary rows set, free rows 0

  Eigen::SparseMatrix<double> G;   ///< (#T D) by #V gradient (rescaled units)
  Eigen::VectorXd area;            ///< #T
  Eigen::MatrixXd distances;       ///< #V by n normalised distances
  Eigen::MatrixXd phi;             ///< #T by n
  RowMatrix weight;                ///< #T by n: phi A (the TV weights of Eq. 14)

  // scaled splitting (see the file comment of the header): constraint rows a_t (G_t Z + E_t) and
  // b_v Z_v; state s = (s_X: #T D rows, s_W: m rows) by n.
  double mu = 10.0;                ///< internal penalty
  Eigen::VectorXd a;               ///< #T cell row scale
  Eigen::VectorXd b;               ///< m vertex row scale
  Csr Ga;                          ///< (#T D) by m: diag(a) G_free
  Csr GtA;                         ///< m by (#T D): Ga^T
  std::vector<int> ea_row;         ///< #T: first row of cell t in ea, -1 if a (G E)_t = 0
  RowMatrix ea;                    ///< (cells with boundary data) D by n: rows of diag(a) E
  std::vector<int> c0_row;         ///< m: row of vertex v in c0, -1 if (Ga^T ea)_v = 0
  RowMatrix c0;                    ///< rows of Ga^T diag(a) E
  RowMatrix H;                     ///< m by n least-norm solution of H K = B
  Eigen::MatrixXd Ur;              ///< n by D+1 orthonormal basis of range(K)
  Eigen::MatrixXd Kmat;            ///< n by D+1, [c_i^T 1] (rescaled)
  RowCholesky chol;
  SparseCholesky sparse;           ///< used for the explicit backends
  bool use_row_cholesky = true;

  double geodesic_seconds = 0, factor_seconds = 0;

  Index rows_x() const { return nt * D; }
  Index state_rows() const { return nt * D + m; }

  void solve(RowMatrix& B, int threads) const
  {
    if (use_row_cholesky)
      chol.solve(B, threads);
    else
    {
      Eigen::MatrixXd cm = B;
      B = sparse.solve(cm);
    }
  }

  double tau(double x) const
  {
    switch (o.locality)
    {
      case LocalityFunction::Squared: return x * x;
      case LocalityFunction::Constant: return 1.0;
      case LocalityFunction::Linear: return x;
      case LocalityFunction::Custom: return o.custom_locality(x);
    }
    return 1.0;
  }

  /// Residuals (26)-(27) of a step and the ADMM iterates it produced.
  struct Check_
  {
    double primal = 0, dual = 0;
    double primal_scaled = 0, dual_scaled = 0; // the same in the scaled splitting, mu internal
    RowMatrix Z;  // Z^{k+1} = Y^{k+1} M + H
    RowMatrix W;  // W^{k+1} (>= 0, the projection (31))
  };
  /// Buffers of one computation.
  struct Work
  {
    RowMatrix r;   ///< #T D by n: r_X = 2 p_X - s_X (shrinkage (30) applied to s_X)
    RowMatrix B;   ///< m by n (2n on checks): right-hand sides, then Z' (and Z^k)
    std::vector<double> sums; ///< per-row partial sums for deterministic reductions
    double mu = 0.0; ///< the penalty of this computation (Impl::mu, changed by residual balancing)
  };
  /// r_X = 2 prox(s_X) - s_X: the shrinkage (30) per cell and control point.
  template <int N>
  void reflect_gradients(const RowMatrix& s, RowMatrix& r, double mu_now, int threads) const;
  /// The Y-update of Appendix B: w.B <- the feasible Z minimising
  /// |a (G Z + E) - r_X|^2 + |b Z - r_W|^2 for r = 2 p - s (columns 0..n-1) and, with
  /// @p with_state, for r = s itself (columns n..2n-1: Z^k of the state).
  template <int N, bool WithState>
  void y_update(const RowMatrix& s, Work& w, int threads) const;
  /// g = alpha (q - p), q = (a (G Z' + E), b Z'), the residuals on checks (see step()).
  template <int N, bool Check, bool StoreG>
  void finish_step(RowMatrix& s, RowMatrix* g, Work& w, Check_* check, const double* zk,
    Index zk_stride, int threads) const;
  /// One fixed-point evaluation of the relaxed Douglas-Rachford (= ADMM) map at s:
  /// g = alpha (q - p). In place (g == nullptr): s <- s + g. With @p check: the residuals
  /// (26)-(27), Z^{k+1}, W^{k+1}. Returns |g|^2.
  /// @p tracked: Z^k of the state s, kept up to date (Z^{k+1} = (1 - alpha/2) Z^k +
  /// (alpha/2) Z', exact for the plain iteration) so that checks need no projection of s; null:
  /// computed on checks (after Anderson steps, which mix states).
  double step(RowMatrix& s, RowMatrix* g, Work& w, Check_* check, RowMatrix* tracked,
    int threads) const;
  void polish(const RowMatrix& Z, const RowMatrix& W, RowMatrix& Wfree, LBCResult& result,
    int threads) const;
  double objective_of(const DenseWeights& W, int threads) const;
  double cage_edge_length(const DomainMesh& mesh) const;

  // Set-up steps, in the constructor's order.
  /// The mesh's sizes (D, nv, nc, nt), T and control_vertex, after checking their shapes.
  void take_mesh(const DomainMesh& mesh);
  /// W_fixed (the boundary rows: the cage's hat functions, the Lagrange and linearity
  /// properties), the free vertices and m, after checking the boundary and control vertices.
  void split_boundary(const DomainMesh& mesh);
  /// Vs: the vertices moved and scaled to bounding-box diameter 1 (Appendix B, "Parameters").
  void rescale(const Eigen::MatrixXd& V);
  /// G and area on Vs (gradient_operator validates the elements); every vertex in an element.
  void build_operators();
  /// distances (Eq. 12), phi (Eq. 11; all 1 with LocalityFunction::Constant) and the TV
  /// weights phi_i^s A_s of Eq. 14.
  void compute_locality_weights();
  /// #V by n geodesic distances g_i to the control points (heat method, §3.3).
  Eigen::MatrixXd geodesic_distances() const;
  /// distances = D_i = g_i / max g (Eq. 12, per control point or global; unreachable: 1).
  void normalize_distances(const Eigen::MatrixXd& g);
  /// phi_i^s = tau(D_i at the centroid of cell s) (Eq. 11).
  void locality_at_cells();
  /// Kmat = [c_i^T 1], Ur (orthonormal basis of range(K)) and H = B K^+, the least-norm
  /// solution of H K = B (Eq. 16, by SVD as Appendix B); Ur empty and H = 0 without
  /// barycentric constraints.
  void constraint_basis();
  /// The scaled splitting's row scales a (per cell) and b (per free vertex) and the internal
  /// penalty mu (ConstraintScaling; all 1 and the paper's penalty with Paper).
  void scale_constraints(const DomainMesh& mesh);
  /// Ga = diag(a) G restricted to the free columns, and GtA = Ga^T.
  void scaled_gradient();
  /// The boundary data's rows: ea = diag(a) G W_fixed and c0 = Ga^T ea, only the nonzero rows
  /// stored (ea_row, c0_row).
  void boundary_terms(int threads);
  /// Factors the Y-system Ga^T Ga + diag(b)^2 (K + beta^2 M with Lumped, G^T G + I with
  /// Paper), with RowCholesky (Automatic) or the chosen SparseCholesky backend.
  void factor_y_system();
};

double LocalBarycentricCoordinates::Impl::cage_edge_length(const DomainMesh& mesh) const
{
  // Pairs of control points that share a boundary row (a cage edge, or two corners of a cage
  // face), in rescaled units.
  std::vector<std::pair<int, int>> pairs;
  const SparseWeights& B = mesh.boundary_weights;
  for (Index r = 0; r < B.outerSize(); ++r)
  {
    std::vector<int> support;
    for (SparseWeights::InnerIterator it(B, r); it; ++it)
      if (it.value() != 0.0)
        support.push_back(static_cast<int>(it.col()));
    if (support.size() > 3)
      continue;
    for (std::size_t i = 0; i < support.size(); ++i)
      for (std::size_t j = i + 1; j < support.size(); ++j)
        pairs.emplace_back(std::min(support[i], support[j]), std::max(support[i], support[j]));
  }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  double sum = 0.0;
  for (const auto& [i, j] : pairs)
    sum += (Vs.row(control_vertex(i)) - Vs.row(control_vertex(j))).norm();
  if (!pairs.empty() && sum > 0.0)
    return sum / static_cast<double>(pairs.size());
  // nearest neighbours
  sum = 0.0;
  for (Index i = 0; i < nc; ++i)
  {
    double nearest = std::numeric_limits<double>::infinity();
    for (Index j = 0; j < nc; ++j)
      if (j != i)
        nearest = std::min(nearest, (Vs.row(control_vertex(i)) - Vs.row(control_vertex(j))).norm());
    sum += nearest;
  }
  return sum / static_cast<double>(nc);
}

// ------------------------------------------------------------------------------------------
// Row kernels of the ADMM step compiled for AVX2 without FMA (BARY_TARGET_AVX2_EXACT): plain
// loops over a row of n columns, the same IEEE operations in the same order as the Eigen
// expressions of the portable step (maximum as (x < y ? y : x), like Eigen's), so that the
// result is bitwise the portable one (test LBC.AVX2AndPortableStepsAreBitwiseEqual), with four
// doubles a vector where Eigen's packets are SSE2's two. The reflection's square root and
// division in intrinsics (a loop's std::sqrt keeps errno and stays scalar).
#if BARY_HAVE_AVX2_DISPATCH
namespace
{
/// reflect_gradients' cell without relaxation: |s| per control point over the dim rows,
/// f = 2 max(0, 1 - kappa / |s|) - 1 as (max(0, |s| - kappa) / max(|s|, 1e-300)) times 2 minus 1,
/// r = f s.
template <int Dim>
BARY_TARGET_AVX2_EXACT BARY_NOINLINE void reflect_cell_avx2(
  Index n, const double* st, const double* w, double inv_mu_a, double* rt)
{
  Index i = 0;
  const __m256d zero = _mm256_setzero_pd(), tiny = _mm256_set1_pd(1e-300),
                inv = _mm256_set1_pd(inv_mu_a), two = _mm256_set1_pd(2.0),
                one = _mm256_set1_pd(1.0);
  for (; i + 4 <= n; i += 4)
  {
    __m256d sk[Dim];
    sk[0] = _mm256_loadu_pd(st + i);
    __m256d q = _mm256_mul_pd(sk[0], sk[0]);
    for (int k = 1; k < Dim; ++k)
    {
      sk[k] = _mm256_loadu_pd(st + k * n + i);
      q = _mm256_add_pd(q, _mm256_mul_pd(sk[k], sk[k]));
    }
    q = _mm256_sqrt_pd(q);
    // max(x, y) as (x < y ? y : x): maxpd(y, x) returns x when they are equal or unordered
    const __m256d kappa = _mm256_mul_pd(_mm256_loadu_pd(w + i), inv);
    const __m256d num = _mm256_max_pd(zero, _mm256_sub_pd(q, kappa));
    const __m256d f = _mm256_div_pd(num, _mm256_max_pd(tiny, q));
    const __m256d g = _mm256_sub_pd(_mm256_mul_pd(two, f), one);
    for (int k = 0; k < Dim; ++k)
      _mm256_storeu_pd(rt + k * n + i, _mm256_mul_pd(g, sk[k]));
  }
  for (; i < n; ++i)
  {
    double q = st[i] * st[i];
    for (int k = 1; k < Dim; ++k)
      q += st[k * n + i] * st[k * n + i];
    q = std::sqrt(q);
    const double num = q - w[i] * inv_mu_a;
    const double f = (num < 0.0 ? 0.0 : num) / (q < 1e-300 ? 1e-300 : q);
    const double g = 2.0 * f - 1.0;
    for (int k = 0; k < Dim; ++k)
      rt[k * n + i] = g * st[k * n + i];
  }
}

/// q = e (or 0) + sum_p values[p] B[inner[p]] over a gradient row's entries, then the plain
/// step s += alpha (q - (r + s) / 2). @p q: n doubles of scratch.
BARY_TARGET_AVX2_EXACT BARY_NOINLINE void gradient_row_step_avx2(Index n, const double* e,
  int begin, int end, const int* inner, const double* values, const double* B, Index width,
  const double* rr, double* sr, double alpha, double* q)
{
  if (e != nullptr)
    for (Index i = 0; i < n; ++i)
      q[i] = e[i];
  else
    for (Index i = 0; i < n; ++i)
      q[i] = 0.0;
  for (int p = begin; p < end; ++p)
  {
    const double v = values[p];
    const double* b = B + static_cast<Index>(inner[p]) * width;
    for (Index i = 0; i < n; ++i)
      q[i] += v * b[i];
  }
  for (Index i = 0; i < n; ++i)
    sr[i] += alpha * (q[i] - 0.5 * (rr[i] + sr[i]));
}

/// A weight row's plain step: s += alpha (b z - max(s, 0)).
BARY_TARGET_AVX2_EXACT BARY_NOINLINE void weight_row_step_avx2(
  Index n, const double* z, double bv, double alpha, double* sw)
{
  for (Index i = 0; i < n; ++i)
    sw[i] += alpha * (bv * z[i] - (sw[i] < 0.0 ? 0.0 : sw[i]));
}

/// y_update's row before the projection: z = b |s_W| - c0 (when given) + sum_p values[p] r_X.
BARY_TARGET_AVX2_EXACT BARY_NOINLINE void y_row_avx2(Index n, const double* sw, double bv,
  const double* c0, int begin, int end, const int* inner, const double* values,
  const double* rx, double* z)
{
  for (Index i = 0; i < n; ++i)
    z[i] = bv * std::abs(sw[i]);
  if (c0 != nullptr)
    for (Index i = 0; i < n; ++i)
      z[i] -= c0[i];
  for (int p = begin; p < end; ++p)
  {
    const double v = values[p];
    const double* x = rx + static_cast<Index>(inner[p]) * n;
    for (Index i = 0; i < n; ++i)
      z[i] += v * x[i];
  }
}
} // namespace
#endif

/// Calls f(std::integral_constant<int, N>) with N = n for the small column counts the kernels
/// are unrolled for (the square, the octahedron and 6-vertex polygons, the cube: 4, 6, 8; each
/// value instantiates every kernel, which costs compile time), N = 0 (run-time count) otherwise.
template <typename F>
void dispatch_columns(Index n, F&& f)
{
  switch (n)
  {
    case 4: f(std::integral_constant<int, 4>()); break;
    case 6: f(std::integral_constant<int, 6>()); break;
    case 8: f(std::integral_constant<int, 8>()); break;
    default: f(std::integral_constant<int, 0>()); break;
  }
}

template <int N>
void LocalBarycentricCoordinates::Impl::reflect_gradients(
  const RowMatrix& s, RowMatrix& r, double mu_now, int threads) const
{
  const Index n = N > 0 ? N : nc;
  const int dim = D;
  const double eps = o.relaxed_tv_epsilon;
  using Array = Eigen::Array<double, N == 0 ? Eigen::Dynamic : N, 1>;
  r.resize(nt * dim, n);
  [[maybe_unused]] const bool avx2 = N == 0 && detail::simd_level() == detail::SimdLevel::AVX2;
#pragma omp parallel num_threads(threads)
  {
    Array q(n), f(n);
#pragma omp for schedule(static)
    for (Index t = 0; t < nt; ++t)
    {
      const double* st = s.data() + t * dim * n;
      double* rt = r.data() + t * dim * n;
#if BARY_HAVE_AVX2_DISPATCH
      if (avx2 && eps <= 0.0)
      {
        const double inv = 1.0 / (mu_now * a(t));
        if (dim == 2)
          reflect_cell_avx2<2>(n, st, weight.data() + t * n, inv, rt);
        else
          reflect_cell_avx2<3>(n, st, weight.data() + t * n, inv, rt);
        continue;
      }
#endif
      const Eigen::Map<const Array> w(weight.data() + t * n, n);
      q = Eigen::Map<const Array>(st, n).square();
      for (int k = 1; k < dim; ++k)
        q += Eigen::Map<const Array>(st + k * n, n).square();
      q = q.sqrt(); // Eigen's packet sqrt vectorises (std::sqrt keeps errno and does not)
      // s_X = a x~ with x~ = a x: the threshold of x~ is kappa~ = phi A / (mu a) (Eq. 30).
      const double inv_mu_a = 1.0 / (mu_now * a(t));
      if (eps <= 0.0)
        f = (q - w * inv_mu_a).max(0.0) / q.max(1e-300); // max(0, 1 - kappa / |s|)
      else
      {
        // f_eps: in x = x~ / a the threshold is kappa = phi A / (mu a^2) and the radius r / a.
        const double at = a(t);
        for (Index i = 0; i < n; ++i)
          f(i) = q(i) > 0.0 ? at * prox_radius(q(i) / at, w(i) * inv_mu_a / at, eps) / q(i) : 0.0;
      }
      f = 2.0 * f - 1.0;
      for (int k = 0; k < dim; ++k)
        Eigen::Map<Array>(rt + k * n, n) = f * Eigen::Map<const Array>(st + k * n, n);
    }
  }
}

template <int N, bool WithState>
void LocalBarycentricCoordinates::Impl::y_update(const RowMatrix& s, Work& w, int threads) const
{
  using Vec = Eigen::Matrix<double, N == 0 ? Eigen::Dynamic : N, 1>;
  using VecMap = Eigen::Map<Vec>;
  using ConstMap = Eigen::Map<const Vec>;
  const Index n = N > 0 ? N : nc, rx = rows_x();
  const Index width = WithState ? 2 * n : n;
  w.B.resize(m, width);
  const int* outer = GtA.outerIndexPtr();
  const int* inner = GtA.innerIndexPtr();
  const double* values = GtA.valuePtr();
  const Index d1 = Ur.cols();
  const double* rx_data = w.r.data();
  [[maybe_unused]] const bool avx2 = N == 0 && detail::simd_level() == detail::SimdLevel::AVX2;
#pragma omp parallel num_threads(threads)
  {
    std::vector<double> proj(static_cast<std::size_t>(d1));
#pragma omp for schedule(static)
    for (Index v = 0; v < m; ++v)
    {
      double* z = w.B.data() + v * width;
      const double* sw = s.data() + (rx + v) * n;
      const double bv = b(v);
      // r_W = 2 max(0, s_W) - s_W = |s_W|; - c0; + Ga^T r_X gathered from the incident cells
      const int crow = c0_row[static_cast<std::size_t>(v)];
#if BARY_HAVE_AVX2_DISPATCH
      if (avx2)
        y_row_avx2(n, sw, bv, crow >= 0 ? c0.data() + static_cast<Index>(crow) * n : nullptr,
          outer[v], outer[v + 1], inner, values, rx_data, z);
      else
#endif
      {
        VecMap zv(z, n);
        zv = bv * ConstMap(sw, n).cwiseAbs();
        if (crow >= 0)
          zv -= ConstMap(c0.data() + static_cast<Index>(crow) * n, n);
        for (int p = outer[v]; p < outer[v + 1]; ++p)
          zv += values[p] * ConstMap(rx_data + static_cast<Index>(inner[p]) * n, n);
      }
      if (WithState)
      {
        VecMap zs(z + n, n);
        zs = bv * ConstMap(sw, n);
        if (crow >= 0)
          zs -= ConstMap(c0.data() + static_cast<Index>(crow) * n, n);
        for (int p = outer[v]; p < outer[v + 1]; ++p)
          zs += values[p] * ConstMap(s.data() + static_cast<Index>(inner[p]) * n, n);
      }
      // times Pi = I - Ur Ur^T (the rows of M span null(K^T)): z <- z - (z Ur) Ur^T
      for (Index block = 0; block < width; block += n)
      {
        double* zb = z + block;
        for (Index j = 0; j < d1; ++j)
        {
          const double* u = Ur.data() + j * Ur.rows();
          double sum = 0.0;
          for (Index i = 0; i < n; ++i)
            sum += zb[i] * u[i];
          proj[static_cast<std::size_t>(j)] = sum;
        }
        for (Index j = 0; j < d1; ++j)
        {
          const double* u = Ur.data() + j * Ur.rows();
          const double c = proj[static_cast<std::size_t>(j)];
          for (Index i = 0; i < n; ++i)
            zb[i] -= c * u[i];
        }
      }
    }
  }
  solve(w.B, threads);
#pragma omp parallel for num_threads(threads) schedule(static)
  for (Index v = 0; v < m; ++v)
  {
    double* z = w.B.data() + v * width;
    const double* h = H.data() + v * n;
    for (Index i = 0; i < n; ++i)
      z[i] += h[i];
    if (WithState)
      for (Index i = 0; i < n; ++i)
        z[n + i] += h[i];
  }
}

template <int N, bool Check, bool StoreG>
void LocalBarycentricCoordinates::Impl::finish_step(RowMatrix& s, RowMatrix* g, Work& w,
  Check_* check, const double* zk, Index zk_stride, int threads) const
{
  using Vec = Eigen::Matrix<double, N == 0 ? Eigen::Dynamic : N, 1>;
  using VecMap = Eigen::Map<Vec>;
  using ConstMap = Eigen::Map<const Vec>;
  const Index n = N > 0 ? N : nc, rx = rows_x();
  const int dim = D;
  const double alpha = o.relaxation;
  const Index width = w.B.cols();
  const int* outer = Ga.outerIndexPtr();
  const int* inner = Ga.innerIndexPtr();
  const double* values = Ga.valuePtr();
  constexpr int sums = Check ? 5 : 1;
  double* partial = w.sums.data();
  [[maybe_unused]] const bool avx2 = N == 0 && detail::simd_level() == detail::SimdLevel::AVX2;
  // With l^k = (a (G Z^k + E), b Z^k) and q = p + g / alpha:
  //   r_p = (1 - alpha/2)(p - l^k) - g/2,  r_d = mu_paper ((alpha/2)(p - l^k) + g/2),
  // each row divided by its scale (a for gradient rows, b for weight rows).
#pragma omp parallel num_threads(threads)
  {
    std::vector<double> qbuf(static_cast<std::size_t>(n)), lbuf(static_cast<std::size_t>(n));
    double* q = qbuf.data();
    double* l = lbuf.data();
#pragma omp for schedule(static)
    for (Index t = 0; t < nt; ++t)
    {
      const int erow = ea_row[static_cast<std::size_t>(t)];
      double acc[5] = { 0, 0, 0, 0, 0 };
      const double inv = 1.0 / a(t);
      for (int k = 0; k < dim; ++k)
      {
        const Index row = t * dim + k;
        double* sr = s.data() + row * n;
        const double* rr = w.r.data() + row * n;
#if BARY_HAVE_AVX2_DISPATCH
        if (!Check && !StoreG && avx2)
        {
          const double* e = erow >= 0 ? ea.data() + (static_cast<Index>(erow) + k) * n : nullptr;
          gradient_row_step_avx2(
            n, e, outer[row], outer[row + 1], inner, values, w.B.data(), width, rr, sr, alpha, q);
          continue;
        }
#endif
        VecMap qm(q, n), lm(l, n);
        if (erow >= 0)
        {
          const ConstMap e(ea.data() + (static_cast<Index>(erow) + k) * n, n);
          qm = e;
          if (Check)
            lm = e;
        }
        else
        {
          qm.setZero();
          if (Check)
            lm.setZero();
        }
        for (int p = outer[row]; p < outer[row + 1]; ++p)
          qm += values[p] * ConstMap(w.B.data() + static_cast<Index>(inner[p]) * width, n);
        if (Check)
          for (int p = outer[row]; p < outer[row + 1]; ++p)
            lm += values[p] * ConstMap(zk + static_cast<Index>(inner[p]) * zk_stride, n);
        double a0 = 0.0;
        if (!Check && !StoreG)
        {
          // the plain step: s += alpha (q - (r + s) / 2)
          VecMap sv(sr, n);
          sv += alpha * (ConstMap(q, n) - 0.5 * (ConstMap(rr, n) + sv));
        }
        else
        {
          double* gr = StoreG ? g->data() + row * n : nullptr;
          for (Index i = 0; i < n; ++i)
          {
            const double pv = 0.5 * (rr[i] + sr[i]); // p = (r + s) / 2
            const double gv = alpha * (q[i] - pv);
            if (Check)
            {
              const double pl = pv - l[i];
              const double rp = (1.0 - 0.5 * alpha) * pl - 0.5 * gv;
              const double rd = 0.5 * alpha * pl + 0.5 * gv;
              acc[1] += rp * rp;
              acc[2] += rd * rd;
              acc[3] += rp * rp * inv * inv;
              acc[4] += rd * rd * inv * inv;
            }
            if (StoreG)
            {
              a0 += gv * gv;
              gr[i] = gv;
            }
            else
              sr[i] += gv;
          }
        }
        acc[0] += a0;
      }
      for (int c = 0; c < sums; ++c)
        partial[t * sums + c] = acc[c];
    }
#pragma omp for schedule(static)
    for (Index v = 0; v < m; ++v)
    {
      double* sw = s.data() + (rx + v) * n;
      const double* z = w.B.data() + v * width;
      double* gr = StoreG ? g->data() + (rx + v) * n : nullptr;
      const double bv = b(v), inv = 1.0 / b(v);
      double acc[5] = { 0, 0, 0, 0, 0 };
      double* wout = Check ? check->W.data() + v * n : nullptr;
      const double* zp = Check ? zk + v * zk_stride : nullptr;
      if (!Check && !StoreG)
      {
#if BARY_HAVE_AVX2_DISPATCH
        if (avx2)
        {
          weight_row_step_avx2(n, z, bv, alpha, sw);
          continue;
        }
#endif
        VecMap sv(sw, n);
        sv += alpha * (bv * ConstMap(z, n) - sv.cwiseMax(0.0));
        continue;
      }
      for (Index i = 0; i < n; ++i)
      {
        const double pv = std::max(0.0, sw[i]);
        const double gv = alpha * (bv * z[i] - pv);
        if (Check)
        {
          const double pl = pv - bv * zp[i];
          const double rp = (1.0 - 0.5 * alpha) * pl - 0.5 * gv;
          const double rd = 0.5 * alpha * pl + 0.5 * gv;
          acc[1] += rp * rp;
          acc[2] += rd * rd;
          acc[3] += rp * rp * inv * inv;
          acc[4] += rd * rd * inv * inv;
          wout[i] = pv * inv;
        }
        if (StoreG)
        {
          acc[0] += gv * gv;
          gr[i] = gv;
        }
        else
          sw[i] += gv;
      }
      for (int c = 0; c < sums; ++c)
        partial[(nt + v) * sums + c] = acc[c];
    }
  }
}

double LocalBarycentricCoordinates::Impl::step(RowMatrix& s, RowMatrix* g, Work& w, Check_* check,
  RowMatrix* tracked, int threads) const
{
  const Index n = nc;
  const double alpha = o.relaxation;
  if (check)
    check->W.resize(m, n);
  if (g)
    g->resize(s.rows(), n);
  const Index parts = nt + m;
  const int sums = check ? 5 : 1;
  w.sums.assign(static_cast<std::size_t>(parts * sums), 0.0);
  const bool project_state = check && !tracked;
  dispatch_columns(n, [&](auto columns) {
    constexpr int N = decltype(columns)::value;
    // 1. p = prox(s): shrinkage (30) per cell and control point, projection (31) per vertex;
    //    kept as r = 2 p - s.
    reflect_gradients<N>(s, w.r, w.mu, threads);
    // 2. Z' = Pi(2 p - s) (and Z^k = Pi(s) on checks without tracking): the Y-update
    if (project_state)
      y_update<N, true>(s, w, threads);
    else
      y_update<N, false>(s, w, threads);
    // 3. g = alpha (q - p); the residuals on checks
    const double* zk = project_state ? w.B.data() + n : tracked ? tracked->data() : nullptr;
    const Index stride = project_state ? 2 * n : n;
    if (check)
    {
      if (g)
        finish_step<N, true, true>(s, g, w, check, zk, stride, threads);
      else
        finish_step<N, true, false>(s, g, w, check, zk, stride, threads);
    }
    else
    {
      if (g)
        finish_step<N, false, true>(s, g, w, check, zk, stride, threads);
      else
        finish_step<N, false, false>(s, g, w, check, zk, stride, threads);
    }
  });
  double total[5] = { 0, 0, 0, 0, 0 };
  for (Index r = 0; r < parts; ++r)
    for (int c = 0; c < sums; ++c)
      total[c] += w.sums[static_cast<std::size_t>(r * sums + c)];
  if (check)
  {
    check->primal_scaled = std::sqrt(total[1]);
    check->dual_scaled = w.mu * std::sqrt(total[2]);
    check->primal = std::sqrt(total[3]);
    check->dual = o.penalty * std::sqrt(total[4]);
  }
  // Z^{k+1} = (1 - alpha/2) Z^k + (alpha/2) Z'
  const Index width = w.B.cols();
  if (tracked || check)
  {
    RowMatrix* out = tracked ? tracked : &check->Z;
    if (!tracked)
      out->resize(m, n);
#pragma omp parallel for num_threads(threads) schedule(static)
    for (Index v = 0; v < m; ++v)
    {
      const double* z = w.B.data() + v * width;
      double* zk = out->data() + v * n;
      const double* zold = tracked ? zk : z + n;
      for (Index i = 0; i < n; ++i)
        zk[i] = (1.0 - 0.5 * alpha) * zold[i] + 0.5 * alpha * z[i];
    }
    if (tracked && check)
      check->Z = *tracked;
  }
  return total[0];
}

void LocalBarycentricCoordinates::Impl::polish(const RowMatrix& Z, const RowMatrix& W,
  RowMatrix& Wfree, LBCResult& result, int threads) const
{
  const Index n = nc;
  Wfree.resize(m, n);
  Index failures = 0;
  double max_change = 0.0;
  constexpr double kOff = -1e300; // "not in the support": stays 0
#pragma omp parallel num_threads(threads) reduction(+ : failures) reduction(max : max_change)
  {
    Eigen::VectorXd bv(D + 1), z(n);
#pragma omp for schedule(static)
    for (Index v = 0; v < m; ++v)
    {
      const Index vertex = free_vertices[static_cast<std::size_t>(v)];
      bv.head(D) = Vs.row(vertex).transpose();
      bv(D) = 1.0;
      const double* zr = Z.data() + v * n;
      const double* wr = W.data() + v * n;
      double* out = Wfree.data() + v * n;
      if (!o.barycentric_constraints)
        for (Index i = 0; i < n; ++i)
          out[i] = std::max(0.0, zr[i]);
      else if (o.polish)
      {
        // The ADMM's W (>= 0, exact zeros) projected onto the constraints on its support; if
        // the support cannot satisfy them, Z projected onto the whole feasible set.
        for (Index i = 0; i < n; ++i)
          z(i) = wr[i] > 0.0 ? wr[i] : kOff;
        if (!project_feasible(Kmat, bv, z.data(), out, n, 1e-14) &&
          !project_feasible(Kmat, bv, zr, out, n, 1e-14))
          ++failures;
      }
      else
        for (Index i = 0; i < n; ++i)
          out[i] = zr[i];
      for (Index i = 0; i < n; ++i)
        max_change = std::max(max_change, std::abs(out[i] - zr[i]));
    }
  }
  result.polish_failures = failures;
  result.max_polish_change = max_change;
}

double LocalBarycentricCoordinates::Impl::objective_of(const DenseWeights& W, int threads) const
{
  const Eigen::MatrixXd grad = G * Eigen::MatrixXd(W);
  std::vector<double> cell(static_cast<std::size_t>(nt), 0.0);
  const double eps = o.relaxed_tv_epsilon;
#pragma omp parallel for num_threads(threads) schedule(static)
  for (Index t = 0; t < nt; ++t)
  {
    double sum = 0.0;
    for (Index i = 0; i < nc; ++i)
      sum += weight(t, i) * relaxed_norm(grad.col(i).segment(t * D, D).norm(), eps);
    cell[static_cast<std::size_t>(t)] = sum;
  }
  double sum = 0.0;
  for (double c : cell)
    sum += c;
  // Eq. 14 scales like length^(D-1).
  return sum * std::pow(scale, D - 1);
}

// --- set-up steps of the constructor ------------------------------------------------------------

void LocalBarycentricCoordinates::Impl::take_mesh(const DomainMesh& mesh)
{
  nv = mesh.V.rows();
  nc = mesh.control_vertex.size();
  D = static_cast<int>(mesh.V.cols());
  if (nv == 0 || mesh.T.rows() == 0)
    throw Error(ErrorCode::EmptyInput, "the domain mesh is empty");
  if (D != 2 && D != 3)
    throw Error(ErrorCode::SizeMismatch,
      "mesh vertices must have 2 or 3 coordinates, got " + std::to_string(D));
  if (mesh.T.cols() != D + 1)
    throw Error(ErrorCode::SizeMismatch,
      "a " + std::to_string(D) + "D domain needs " + (D == 2 ? "triangles" : "tetrahedra") +
        " (T with " + std::to_string(D + 1) + " columns), got " + std::to_string(mesh.T.cols()) +
        " columns");
  if (nc < D + 1)
    throw Error(ErrorCode::EmptyInput,
      "a " + std::to_string(D) + "D cage needs at least " + std::to_string(D + 1) +
        " control vertices, got " + std::to_string(nc));
  const Index nb = static_cast<Index>(mesh.boundary_vertices.size());
  if (mesh.boundary_weights.rows() != nb || mesh.boundary_weights.cols() != nc)
    throw Error(ErrorCode::SizeMismatch,
      "boundary_weights is " + std::to_string(mesh.boundary_weights.rows()) + " by " +
        std::to_string(mesh.boundary_weights.cols()) + " but there are " + std::to_string(nb) +
        " boundary vertices and " + std::to_string(nc) + " control vertices");
  nt = mesh.T.rows();
  T = mesh.T;
  control_vertex = mesh.control_vertex;
}

void LocalBarycentricCoordinates::Impl::split_boundary(const DomainMesh& mesh)
{
  const Index nb = static_cast<Index>(mesh.boundary_vertices.size());
  std::vector<int> fixed_row(static_cast<std::size_t>(nv), -1);
  for (Index k = 0; k < nb; ++k)
  {
    const int v = mesh.boundary_vertices[static_cast<std::size_t>(k)];
    if (v < 0 || v >= nv)
      invalid("boundary vertex " + std::to_string(v) + " is outside [0, " + std::to_string(nv) + ")");
    if (fixed_row[static_cast<std::size_t>(v)] >= 0)
      invalid("boundary vertex " + std::to_string(v) + " is listed twice");
    fixed_row[static_cast<std::size_t>(v)] = static_cast<int>(k);
  }
  for (Index i = 0; i < nc; ++i)
  {
    const int v = mesh.control_vertex(i);
    if (v < 0 || v >= nv)
      invalid("control vertex " + std::to_string(i) + " is mesh vertex " + std::to_string(v) +
        ", outside [0, " + std::to_string(nv) + ")");
    if (fixed_row[static_cast<std::size_t>(v)] < 0)
      invalid("control vertex " + std::to_string(i) + " (mesh vertex " + std::to_string(v) +
        ") is not a boundary vertex of the domain mesh");
  }
  W_fixed = RowMatrix::Zero(nv, nc);
  {
    const Eigen::MatrixXd bw = Eigen::MatrixXd(mesh.boundary_weights);
    if (!bw.allFinite())
      throw Error(ErrorCode::NonFinite, "boundary_weights holds NaN or infinity");
    for (Index k = 0; k < nb; ++k)
      W_fixed.row(mesh.boundary_vertices[static_cast<std::size_t>(k)]) = bw.row(k);
  }
  for (Index v = 0; v < nv; ++v)
    if (fixed_row[static_cast<std::size_t>(v)] < 0)
      free_vertices.push_back(static_cast<int>(v));
  m = static_cast<Index>(free_vertices.size());
}

void LocalBarycentricCoordinates::Impl::rescale(const Eigen::MatrixXd& V)
{
  if (!V.allFinite())
    throw Error(ErrorCode::NonFinite, "the mesh has a non-finite vertex coordinate");
  const Eigen::RowVectorXd lo = V.colwise().minCoeff(), hi = V.colwise().maxCoeff();
  scale = (hi - lo).norm();
  if (!(scale > 0.0))
    invalid("the mesh has zero extent");
  center = 0.5 * (lo + hi);
  Vs = (V.rowwise() - center) / scale;
}

void LocalBarycentricCoordinates::Impl::build_operators()
{
  G = gradient_operator(Vs, T);
  area = simplex_volumes(Vs, T);
  std::vector<char> used(static_cast<std::size_t>(nv), 0);
  for (Index t = 0; t < nt; ++t)
    for (Index k = 0; k <= D; ++k)
      used[static_cast<std::size_t>(T(t, k))] = 1;
  for (Index v = 0; v < nv; ++v)
    if (!used[static_cast<std::size_t>(v)])
      invalid("mesh vertex " + std::to_string(v) + " belongs to no element");
}

void LocalBarycentricCoordinates::Impl::compute_locality_weights()
{
  distances = Eigen::MatrixXd::Zero(nv, nc);
  phi = Eigen::MatrixXd::Ones(nt, nc);
  if (o.locality != LocalityFunction::Constant)
  {
    normalize_distances(geodesic_distances());
    locality_at_cells();
  }
  weight.resize(nt, nc);
  for (Index t = 0; t < nt; ++t)
    for (Index j = 0; j < nc; ++j)
      weight(t, j) = phi(t, j) * area(t);
}

Eigen::MatrixXd LocalBarycentricCoordinates::Impl::geodesic_distances() const
{
  GeodesicHeatOptions go = o.geodesic;
  go.threads = o.threads;
  // BaryLab's supernodal factorisation was the fastest here (LBCOptions::geodesic)
  if (go.backend == SparseCholesky::Backend::Automatic)
    go.backend = SparseCholesky::Backend::Supernodal;
  const GeodesicHeat heat(Vs, T, G, area, go);
  return heat.distances(control_vertex);
}

void LocalBarycentricCoordinates::Impl::normalize_distances(const Eigen::MatrixXd& g)
{
  // unreachable vertices (another component) count as farthest
  double global_max = 0.0;
  for (Index j = 0; j < nc; ++j)
    for (Index v = 0; v < nv; ++v)
      if (std::isfinite(g(v, j)))
        global_max = std::max(global_max, g(v, j));
  for (Index j = 0; j < nc; ++j)
  {
    double mx = global_max;
    if (o.distance_normalization == DistanceNormalization::PerControlPoint)
    {
      mx = 0.0;
      for (Index v = 0; v < nv; ++v)
        if (std::isfinite(g(v, j)))
          mx = std::max(mx, g(v, j));
    }
    for (Index v = 0; v < nv; ++v)
      distances(v, j) =
        std::isfinite(g(v, j)) && mx > 0.0 ? std::clamp(g(v, j) / mx, 0.0, 1.0) : 1.0;
  }
}

void LocalBarycentricCoordinates::Impl::locality_at_cells()
{
  for (Index t = 0; t < nt; ++t)
    for (Index j = 0; j < nc; ++j)
    {
      double d = 0.0;
      for (Index k = 0; k <= D; ++k)
        d += distances(T(t, k), j);
      const double value = tau(d / (D + 1));
      if (!std::isfinite(value) || value < 0.0)
        invalid("the locality function returned " + detail::format_number(value) + " for D = " +
          detail::format_number(d / (D + 1)) + "; it must be finite and >= 0");
      phi(t, j) = value;
    }
}

void LocalBarycentricCoordinates::Impl::constraint_basis()
{
  Kmat.resize(nc, D + 1);
  for (Index i = 0; i < nc; ++i)
  {
    Kmat.row(i).head(D) = Vs.row(control_vertex(i));
    Kmat(i, D) = 1.0;
  }
  if (!o.barycentric_constraints)
  {
    // each w_i on its own: no W K = B (Pi = I, H = 0)
    Ur.resize(nc, 0);
    H = RowMatrix::Zero(m, nc);
    return;
  }
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(Kmat, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::VectorXd sv = svd.singularValues();
  if (!(sv(D) > 1e-10 * sv(0)))
    invalid("the control points do not span the " + std::to_string(D) +
      "D space (collinear or coplanar): no barycentric coordinates exist");
  Ur = svd.matrixU();
  // K^+ = V S^-1 U^T; H = B K^+ for the free rows
  const Eigen::MatrixXd Kplus = svd.matrixV() * sv.cwiseInverse().asDiagonal() * Ur.transpose();
  H.resize(m, nc);
  for (Index v = 0; v < m; ++v)
  {
    Eigen::RowVectorXd bvec(D + 1);
    bvec.head(D) = Vs.row(free_vertices[static_cast<std::size_t>(v)]);
    bvec(D) = 1.0;
    H.row(v) = bvec * Kplus;
  }
}

void LocalBarycentricCoordinates::Impl::scale_constraints(const DomainMesh& mesh)
{
  a = Eigen::VectorXd::Ones(nt);
  b = Eigen::VectorXd::Ones(m);
  mu = o.penalty;
  if (o.scaling != ConstraintScaling::Lumped)
    return;
  const double hc = cage_edge_length(mesh);
  mu = o.scaled_penalty * hc;
  Eigen::VectorXd mass = Eigen::VectorXd::Zero(nv);
  for (Index t = 0; t < nt; ++t)
    for (Index k = 0; k <= D; ++k)
      mass(T(t, k)) += area(t) / (D + 1);
  a = area.cwiseSqrt();
  for (Index v = 0; v < m; ++v)
    b(v) = o.constraint_balance / hc *
      std::sqrt(mass(free_vertices[static_cast<std::size_t>(v)]));
}

void LocalBarycentricCoordinates::Impl::scaled_gradient()
{
  std::vector<int> free_index(static_cast<std::size_t>(nv), -1);
  for (Index v = 0; v < m; ++v)
    free_index[static_cast<std::size_t>(free_vertices[static_cast<std::size_t>(v)])] =
      static_cast<int>(v);
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(static_cast<std::size_t>(G.nonZeros()));
  for (Index j = 0; j < G.outerSize(); ++j)
    for (Eigen::SparseMatrix<double>::InnerIterator it(G, j); it; ++it)
    {
      const int f = free_index[static_cast<std::size_t>(it.col())];
      if (f >= 0)
        triplets.emplace_back(
          static_cast<int>(it.row()), f, a(it.row() / D) * it.value());
    }
  Ga.resize(nt * D, m);
  Ga.setFromTriplets(triplets.begin(), triplets.end());
  Ga.makeCompressed();
  GtA = Csr(Ga.transpose());
  GtA.makeCompressed();
}

void LocalBarycentricCoordinates::Impl::boundary_terms(int threads)
{
  // E = G W_fixed (free rows of W_fixed are 0), scaled by a; only the cells touching the
  // boundary have nonzero rows, only those are stored (and likewise for Ga^T diag(a) E).
  const Eigen::MatrixXd E = G * Eigen::MatrixXd(W_fixed);
  RowMatrix ea_full(nt * D, nc);
  for (Index r = 0; r < nt * D; ++r)
    ea_full.row(r) = a(r / D) * E.row(r);
  ea_row.assign(static_cast<std::size_t>(nt), -1);
  Index stored = 0;
  for (Index t = 0; t < nt; ++t)
    if (ea_full.middleRows(t * D, D).cwiseAbs().maxCoeff() > 0.0)
      ea_row[static_cast<std::size_t>(t)] = static_cast<int>(D * stored++);
  ea.resize(D * stored, nc);
  for (Index t = 0; t < nt; ++t)
    if (ea_row[static_cast<std::size_t>(t)] >= 0)
      ea.middleRows(ea_row[static_cast<std::size_t>(t)], D) = ea_full.middleRows(t * D, D);
  RowMatrix c0_full;
  csr_times(GtA, ea_full, c0_full, threads);
  c0_row.assign(static_cast<std::size_t>(m), -1);
  stored = 0;
  for (Index v = 0; v < m; ++v)
    if (c0_full.row(v).cwiseAbs().maxCoeff() > 0.0)
      c0_row[static_cast<std::size_t>(v)] = static_cast<int>(stored++);
  c0.resize(stored, nc);
  for (Index v = 0; v < m; ++v)
    if (c0_row[static_cast<std::size_t>(v)] >= 0)
      c0.row(c0_row[static_cast<std::size_t>(v)]) = c0_full.row(v);
}

void LocalBarycentricCoordinates::Impl::factor_y_system()
{
  if (m == 0)
    return;
  Eigen::SparseMatrix<double> S = Eigen::SparseMatrix<double>(GtA * Ga);
  for (Index v = 0; v < m; ++v)
    S.coeffRef(v, v) += b(v) * b(v);
  S.makeCompressed();
  if (o.backend == SparseCholesky::Backend::Automatic)
  {
    use_row_cholesky = true;
    chol.factor(S);
  }
  else
  {
    use_row_cholesky = false;
    sparse = SparseCholesky(o.backend);
    sparse.compute(S);
  }
}

// =================================================================================================

LocalBarycentricCoordinates::LocalBarycentricCoordinates(
  const DomainMesh& mesh, const LBCOptions& options, const ProgressCallback& progress)
  : impl_(std::make_unique<Impl>())
{
  Impl& s = *impl_;
  s.o = options;
  validate_options(s.o);
  const int threads = thread_count(s.o.threads);
  auto check_cancel = [&progress](double f) {
    if (progress && !progress(f))
      throw Error(ErrorCode::Cancelled, "local barycentric coordinates were cancelled");
  };
  check_cancel(0.0);

  // --- mesh: the fixed boundary rows and the free vertices
  s.take_mesh(mesh);
  s.split_boundary(mesh);

  // --- rescale to bounding-box diameter 1 (Appendix B, "Parameters"); operators
  const auto t_factor = Clock::now();
  s.rescale(mesh.V);
  s.build_operators();
  s.factor_seconds = seconds_since(t_factor);
  check_cancel(0.05);

  // --- locality weights phi_i^s = tau(D_i(centroid)) (§3.3)
  const auto t_geo = Clock::now();
  s.compute_locality_weights();
  s.geodesic_seconds = seconds_since(t_geo);
  check_cancel(0.5);

  // --- constraints W K = B, the scaled splitting and the factorisation of its Y-system
  const auto t_fac2 = Clock::now();
  s.constraint_basis();
  s.scale_constraints(mesh);
  s.scaled_gradient();
  s.boundary_terms(threads);
  check_cancel(0.6);
  s.factor_y_system();
  s.factor_seconds += seconds_since(t_fac2);
  check_cancel(1.0);
}

LocalBarycentricCoordinates::~LocalBarycentricCoordinates() = default;
LocalBarycentricCoordinates::LocalBarycentricCoordinates(LocalBarycentricCoordinates&&) noexcept =
  default;
LocalBarycentricCoordinates& LocalBarycentricCoordinates::operator=(
  LocalBarycentricCoordinates&&) noexcept = default;

const Eigen::MatrixXd& LocalBarycentricCoordinates::normalized_distances() const noexcept
{
  return impl_->distances;
}
const Eigen::MatrixXd& LocalBarycentricCoordinates::locality_weights() const noexcept
{
  return impl_->phi;
}
const LBCOptions& LocalBarycentricCoordinates::options() const noexcept
{
  return impl_->o;
}
Index LocalBarycentricCoordinates::free_vertex_count() const noexcept
{
  return impl_->m;
}

double LocalBarycentricCoordinates::objective(const DenseWeights& W) const
{
  const Impl& s = *impl_;
  if (W.rows() != s.nv || W.cols() != s.nc)
    throw Error(ErrorCode::SizeMismatch,
      "weights are " + std::to_string(W.rows()) + " by " + std::to_string(W.cols()) +
        " but the mesh has " + std::to_string(s.nv) + " vertices and " + std::to_string(s.nc) +
        " control vertices");
  return s.objective_of(W, thread_count(s.o.threads));
}

LBCResult LocalBarycentricCoordinates::compute(const ProgressCallback& progress) const
{
  const Impl& s = *impl_;
  const LBCOptions& o = s.o;
  const auto t0 = Clock::now();
  const int threads = thread_count(o.threads);
  const Index n = s.nc, m = s.m, rows = s.state_rows();
  LBCResult result;
  result.geodesic_seconds = s.geodesic_seconds;
  result.factor_seconds = s.factor_seconds;
  const double entries = static_cast<double>(rows) * static_cast<double>(n);
  result.primal_threshold = entries * o.primal_tolerance;
  result.dual_threshold = entries * o.dual_tolerance;
  auto report = [&progress](double f) {
    if (progress && !progress(std::clamp(f, 0.0, 1.0)))
      throw Error(ErrorCode::Cancelled, "local barycentric coordinates were cancelled");
  };
  report(0.0);

  RowMatrix Zout, Wout;
  const bool trivial = m == 0 || (o.barycentric_constraints && n == s.D + 1);
  if (trivial)
  {
    // No free vertex, or as many control points as a simplex: W = H is the only solution.
    Zout = s.H;
    Wout = s.H.cwiseMax(0.0);
    result.converged = true;
  }
  else
  {
    // s0 = l(Z0) with Z0 = H (Y = 0, lambda = 0: Appendix B's initial values)
    RowMatrix state(rows, n), g, trial, trial_g;
    {
      const Index rx = s.rows_x();
      RowMatrix GH;
      csr_times(s.Ga, s.H, GH, threads);
      for (Index t = 0; t < s.nt; ++t)
        for (int k = 0; k < s.D; ++k)
        {
          const Index r = t * s.D + k;
          state.row(r) = GH.row(r);
          if (s.ea_row[static_cast<std::size_t>(t)] >= 0)
            state.row(r) += s.ea.row(s.ea_row[static_cast<std::size_t>(t)] + k);
        }
      for (Index v = 0; v < m; ++v)
        state.row(rx + v) = s.b(v) * s.H.row(v);
    }
    Impl::Work work;
    work.mu = s.mu;
    Impl::Check_ check;
    std::unique_ptr<Anderson> anderson;
    if (o.anderson)
    {
      anderson = std::make_unique<Anderson>(rows * n, o.anderson_history, threads);
      trial.resize(rows, n);
    }
    int iterations = 0;
    double residual = 0.0;
    double progress_fraction = 0.0;
    double log_p0 = 0.0, log_d0 = 0.0;
    bool have_log0 = false;
    auto process_check = [&]() {
      result.primal_residual = check.primal;
      result.dual_residual = check.dual;
      result.primal_history.push_back(check.primal);
      result.dual_history.push_back(check.dual);
      result.support_history.push_back(mean_support(check.W));
      bool ok = check.primal <= result.primal_threshold && check.dual <= result.dual_threshold;
      if (ok && o.stopping == LBCStopping::Converged)
      {
        const double rp = check.primal / std::sqrt(entries) / (1e3 * o.primal_tolerance / n);
        const double rd = check.dual / std::sqrt(entries) / (1e3 * o.dual_tolerance / n);
        ok = (rp <= 1.0 && rd <= 1.0) ||
          (rp <= kSettledResidualFactor && rd <= kSettledResidualFactor &&
            support_settled(result.support_history));
      }
      // progress: fraction of the way (in log scale) from the first residuals to the thresholds
      const double lp = std::log(std::max(check.primal, 1e-300) / result.primal_threshold);
      const double ld = std::log(std::max(check.dual, 1e-300) / result.dual_threshold);
      if (!have_log0)
      {
        log_p0 = std::max(lp, 1e-3);
        log_d0 = std::max(ld, 1e-3);
        have_log0 = true;
      }
      const double f = std::clamp(std::min(1.0 - lp / log_p0, 1.0 - ld / log_d0), 0.0, 1.0);
      progress_fraction = std::max(progress_fraction,
        std::max(f, static_cast<double>(iterations) / o.max_iterations));
      report(0.98 * progress_fraction);
      return ok;
    };
    // One evaluation at x; in place (plain step) when gx is null. True when it was a check
    // and the stopping rule holds.
    RowMatrix tracked = s.H; // Z^0 = H
    auto evaluate = [&](RowMatrix& x, RowMatrix* gx, double* norm2) {
      ++iterations;
      const bool due = iterations % o.check_interval == 0 || iterations >= o.max_iterations;
      const double r2 =
        s.step(x, gx, work, due ? &check : nullptr, anderson ? nullptr : &tracked, threads);
      if (norm2)
        *norm2 = r2;
      return due && process_check();
    };
    // Residual balancing (LBCOptions::adaptive_penalty, with the converged rule only): after a
    // check, the residuals' root mean squares relative to the converged rule's targets; when
    // one exceeds the other by more than kBalanceBand, mu is doubled (primal too large) or
    // halved (dual too large). Band, factor and spacing chosen on the kidney and icosphere42
    // cases of the stopping study (band 5 / 3 / 2 / 1.5, spacing 2 / 3 / 5 checks, factor 2 / 4:
    // docs/local-barycentric-coordinates.md). The state
    // s = l(Z^k) - lambda / mu is rescaled to keep Z^k and the multipliers lambda: its part
    // orthogonal to the constraint subspace, s - l(Z^k) (Z^k = Pi(s), tracked), is multiplied by
    // mu_old / mu_new. The Y-system does not depend on mu (only the shrinkage threshold does), so
    // nothing is refactored. At most kMaxPenaltyUpdates changes, kPenaltyUpdateChecks checks
    // apart: mu is then fixed and convergence is that of ADMM with a fixed penalty.
    constexpr double kBalanceBand = 2.0, kFactor = 2.0;
    constexpr int kMaxPenaltyUpdates = 20, kPenaltyUpdateChecks = 3;
    const bool balance = o.adaptive_penalty && o.stopping == LBCStopping::Converged;
    int checks_since_update = 0;
    const double e_p = 1e3 * o.primal_tolerance / n, e_d = 1e3 * o.dual_tolerance / n;
    const double root_entries = std::sqrt(entries);
    RowMatrix lx;
    auto rebalance = [&]() {
      if (++checks_since_update < kPenaltyUpdateChecks ||
        result.penalty_updates >= kMaxPenaltyUpdates)
        return;
      const double rp = check.primal / root_entries / e_p, rd = check.dual / root_entries / e_d;
      double factor = 1.0;
      if (rp > kBalanceBand * rd)
        factor = kFactor;
      else if (rd > kBalanceBand * rp)
        factor = 1.0 / kFactor;
      else
        return;
      const double keep = 1.0 / factor; // mu_old / mu_new
      const Index rx = s.rows_x();
      csr_times(s.Ga, tracked, lx, threads);
#pragma omp parallel for num_threads(threads) schedule(static)
      for (Index t = 0; t < s.nt; ++t)
      {
        const int erow = s.ea_row[static_cast<std::size_t>(t)];
        for (int k = 0; k < s.D; ++k)
        {
          const Index r = t * s.D + k;
          for (Index i = 0; i < n; ++i)
          {
            const double l = lx(r, i) + (erow >= 0 ? s.ea(erow + k, i) : 0.0);
            state(r, i) = l + keep * (state(r, i) - l);
          }
        }
      }
#pragma omp parallel for num_threads(threads) schedule(static)
      for (Index v = 0; v < m; ++v)
        for (Index i = 0; i < n; ++i)
        {
          const double l = s.b(v) * tracked(v, i);
          state(rx + v, i) = l + keep * (state(rx + v, i) - l);
        }
      work.mu *= factor;
      ++result.penalty_updates;
      checks_since_update = 0;
    };
    bool converged = false;
    if (!anderson)
    {
      while (!converged && iterations < o.max_iterations)
      {
        converged = evaluate(state, nullptr, nullptr);
        if (!converged && balance && iterations % o.check_interval == 0)
          rebalance();
      }
    }
    else
    {
      // Safeguarded Anderson acceleration; the safeguard constants of Zhang, O'Donoghue & Boyd
      // 2020 (D = 1e6, eps = 1e-6).
      constexpr double kSafeD = 1e6, kSafeEps = 1e-6;
      double r2 = 0.0;
      converged = evaluate(state, &g, &r2);
      residual = std::sqrt(r2);
      const double residual0 = residual;
      while (!converged && iterations < o.max_iterations)
      {
        bool accepted = false;
        if (anderson->extrapolate(state.data(), g.data(), trial.data()))
        {
          converged = evaluate(trial, &trial_g, &r2);
          if (converged)
            break; // the trial point's own ADMM step met the stopping rule
          const double r = std::sqrt(r2);
          const double bound = kSafeD * residual0 *
            std::pow(static_cast<double>(result.anderson_accepted + 1), -(1.0 + kSafeEps));
          if (r < residual && r <= bound)
          {
            state.swap(trial);
            g.swap(trial_g);
            residual = r;
            ++result.anderson_accepted;
            accepted = true;
          }
          else
            ++result.anderson_rejected;
          if (iterations >= o.max_iterations)
            break;
        }
        if (!accepted)
        {
          // plain relaxed Douglas-Rachford (= ADMM) step
          state += g;
          converged = evaluate(state, &g, &r2);
          residual = std::sqrt(r2);
        }
      }
    }
    result.iterations = iterations;
    result.converged = converged;
    result.penalty_factor = work.mu / s.mu;
    if (!converged && result.primal_history.empty())
    {
      // never checked (max_iterations below check_interval): the residuals of one more step
      s.step(state, nullptr, work, &check, anderson ? nullptr : &tracked, threads);
      process_check();
    }
    Zout = std::move(check.Z);
    Wout = std::move(check.W);
  }
  result.admm_seconds = seconds_since(t0);
  if (!result.converged && o.require_convergence)
  {
    const bool residuals_met = result.primal_residual <= result.primal_threshold &&
      result.dual_residual <= result.dual_threshold;
    std::string why;
    if (residuals_met && o.stopping == LBCStopping::Converged && !result.support_history.empty())
    {
      const std::vector<double>& h = result.support_history;
      const double root = std::sqrt(static_cast<double>(s.state_rows()) * static_cast<double>(n));
      why = "the residuals meet the paper's thresholds but not the converged rule's: root mean "
            "square primal residual " + detail::format_number(result.primal_residual / root) +
        " (target " + detail::format_number(1e3 * o.primal_tolerance / n) + "), dual " +
        detail::format_number(result.dual_residual / root) + " (target " +
        detail::format_number(1e3 * o.dual_tolerance / n) + "); weights above 1e-3/" +
        std::to_string(n) + " per vertex: " + detail::format_number(h[h.size() > 1 ? h.size() / 2 - 1 : 0]) +
        " at half the iterations, " + detail::format_number(h.back()) + " at the end";
    }
    else
      why = "primal residual " + detail::format_number(result.primal_residual) + " > " +
        detail::format_number(result.primal_threshold) + " or dual residual " +
        detail::format_number(result.dual_residual) + " > " +
        detail::format_number(result.dual_threshold);
    throw Error(ErrorCode::NotConverged,
      "local barycentric coordinates did not converge in " + std::to_string(o.max_iterations) +
        " iterations (" + why + ")",
      o.stopping == LBCStopping::Converged
        ? "raise max_iterations, loosen the tolerances, set stopping = Paper or set "
          "require_convergence = false"
        : "raise max_iterations, loosen the tolerances or set require_convergence = false");
  }
  report(0.98);

  // --- polish and assemble
  const auto t_polish = Clock::now();
  RowMatrix Wfree;
  s.polish(Zout, Wout, Wfree, result, threads);
  result.W = s.W_fixed;
  for (Index v = 0; v < m; ++v)
    result.W.row(s.free_vertices[static_cast<std::size_t>(v)]) = Wfree.row(v);
  result.objective = s.objective_of(result.W, threads);
  // property errors in the input's units
  {
    double pe = 0.0, re = 0.0;
    for (Index v = 0; v < s.nv; ++v)
    {
      pe = std::max(pe, std::abs(result.W.row(v).sum() - 1.0));
      Eigen::RowVectorXd x = Eigen::RowVectorXd::Zero(s.D);
      for (Index i = 0; i < n; ++i)
        x += result.W(v, i) * s.Vs.row(s.control_vertex(i));
      re = std::max(re, (x - s.Vs.row(v)).norm());
    }
    result.partition_error = pe;
    result.reproduction_error = re;
    result.min_weight = result.W.minCoeff();
  }
  result.polish_seconds = seconds_since(t_polish);
  result.seconds = s.geodesic_seconds + s.factor_seconds + seconds_since(t0);
  fill_statistics(result, threads);
  report(1.0);
  return result;
}

double relaxed_tv_prox_radius(double r, double kappa, double eps)
{
  return prox_radius(r, kappa, eps);
}

double relaxed_tv(double r, double eps)
{
  return relaxed_norm(r, eps);
}

LBCResult local_barycentric_coordinates(
  const DomainMesh& mesh, const LBCOptions& options, const ProgressCallback& progress)
{
  const auto t0 = Clock::now();
  ProgressCallback setup, solve;
  if (progress)
  {
    setup = [&progress](double f) { return progress(0.1 * f); };
    solve = [&progress](double f) { return progress(0.1 + 0.9 * f); };
  }
  const LocalBarycentricCoordinates lbc(mesh, options, setup);
  LBCResult result = lbc.compute(solve);
  result.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  fill_statistics(result, thread_count(options.threads));
  return result;
}

} // namespace bary
