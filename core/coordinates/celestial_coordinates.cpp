#include "core/coordinates/celestial_coordinates.h"

#include "core/detail/constants.h"
#include "core/detail/format.h"
#include "core/detail/parallel_for.h"
#include "core/detail/simd.h"
#include "core/detail/cgal_convex_hull.h"
#include "core/detail/huge_pages.h"
#include "core/common/error.h"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <limits>
#include <map>
#include <numeric>
#include <string>
#include <utility>

#if BARY_HAVE_AVX2_DISPATCH
#include <immintrin.h>
#endif

// Notation: p the query point, v_i the controls, d_i = |v_i - p|, q_i = (v_i - p) / d_i.
//
// Both schemes solve F(x) = sum_i beta_i(x . q_i) q_i = 0 for x in R^dim with an increasing,
// positive beta(a); then alpha_i = (beta_i / d_i) / sum_j (beta_j / d_j) (Eq. 3).
//  - TCC (Eq. 8/9): beta(a) = s_i + exp(a), x = psi. F is the gradient of the strictly convex
//    Phi(psi) = sum_i exp(psi . q_i) + psi . sum_i s_i q_i; J = sum_i exp(a_i) q_i q_i^T is the
//    Jacobian of Appendix A (A.1), symmetric, so the paper's (J^-1)^T = J^-1.
//  - SCC (Eq. 11/15/18): mu_i = q_i . c + sqrt((q_i . c)^2 + K), K = lambda^2 + 2 lambda |c|.
//    Dividing by sqrt(K) gives mu_i = sqrt(K) m(q_i . y), y = c / sqrt(K), m(a) = a + sqrt(a^2+1)
//    (= exp(asinh a)). c -> y is a bijection of R^dim (|y| increases with |c| from 0 to
//    infinity) with inverse c = lambda m(|y|) y, because K = lambda^2 m(|y|)^2. So Eq. (11) is
//    sum_i m(q_i . y)^2 q_i = 0 with beta_i = m_i^2 up to the common factor K, which cancels in
//    Eq. (3): lambda has no effect on the coordinates. In y, F is the gradient of the strictly
//    convex Phi(y) = sum_i (m_i^3 / 6 + m_i / 2) (d/da of m^3/6 + m/2 is m^2: m' = m / r with
//    r = sqrt(a^2 + 1)), and J = sum_i (2 m_i^2 / r_i) q_i q_i^T. In c (the paper's Sect. 5.3)
//    the Jacobian has the extra term (2 lambda sum_i mu_i / S_i q_i) (c / |c|)^T: it is not
//    symmetric, not defined at c = 0, and it is singular on surfaces where |F(c)| = K |G(y)|
//    has local minima that are not solutions (the factor K shrinks with |c|). Newton in c with
//    J^-1 and a residual line search stalled there on 19.5% of 10,000 random interior points
//    (30 controls) and on all points 1e-8..1e-4 from a face; with the printed (J^-1)^T on
//    74% (docs/celestial-coordinates.md). In y: none. m(a) for a < 0 is evaluated as
//    1 / (r - a), which does not cancel.
// Newton is safeguarded by Armijo backtracking on Phi; Phi's decrease is below its rounding
// once the residual is ~1e-8 of sum beta, so a step is also accepted when the relative residual
// is below 1e-6 and the residual norm decreases.

namespace bary
{
namespace
{

constexpr double kRoundoff = std::numeric_limits<double>::epsilon() / 2; // u = 2^-53
constexpr Index kChunk = 256;      // points per warm-start chunk (independent of the threads)
constexpr int kMaxBacktracks = 50; // halvings of the Newton step before giving up
constexpr double kArmijo = 1e-4;
constexpr double kResidualSwitch = 1e-6; // below: also accept residual-norm decrease
// Above this relative residual a predicted start is compared with the plain one (Newton::solve).
// Interior predictions have residuals of 1e-5 .. 1e-2 and are better than the plain start;
// with 1e-3, 45% of 1e6 points paid an extra evaluation for nothing, with 0.1 0.2%; the far-off
// predictions near the hull (residual ~1 and more) are still caught.
constexpr double kPredictedResidual = 0.1;

/// m(a) = a + sqrt(a^2 + 1) without cancellation; r = sqrt(a^2 + 1).
inline double m_of(double a, double r)
{
  return a >= 0.0 ? a + r : 1.0 / (r - a);
}

/// Prefetches [data, data + bytes) into the cache (for writing if @p write).
inline void prefetch(const void* data, std::size_t bytes, bool write)
{
#if defined(__GNUC__)
  const char* c = static_cast<const char*>(data);
  for (std::size_t b = 0; b < bytes + 63; b += 64)
    if (write)
      __builtin_prefetch(c + std::min(b, bytes - 1), 1);
    else
      __builtin_prefetch(c + std::min(b, bytes - 1), 0);
#else
  (void)data;
  (void)bytes;
  (void)write;
#endif
}

/// Stride of the per-control arrays (q's components, betas, 1 / d_i): #C rounded up to a
/// multiple of 4, the lanes past #C zero (q) or finite, so that a kernel runs whole vectors.
inline Index padded(Index n)
{
  return (n + 3) / 4 * 4;
}

// ------------------------------------------------------------------------------------------
// AVX2 + FMA kernels of the per-point work (runtime dispatch, core/detail/simd.h): the control
// directions q_i and 1 / d_i, the S scheme's F, J, Phi and sum beta (Newton::eval) and the
// weights of Eq. (3). Four controls per vector; the same formulas as the portable code below
// them, with a * b + c fused and the sums over controls in four lanes (added in a fixed order):
// the results agree with the portable ones to rounding, and Newton's converged solutions to
// the tolerance (tested). On other machines, and with BARYLAB_SIMD=portable, the portable code.
#if BARY_HAVE_AVX2_DISPATCH
using detail::v4d;

BARY_TARGET_AVX2 BARY_ALWAYS_INLINE double lane_sum(const v4d& v)
{
  return (v[0] + v[1]) + (v[2] + v[3]);
}

/// Lanes i .. i + 3 that are controls (< n): all ones, else zero.
BARY_TARGET_AVX2 BARY_ALWAYS_INLINE void lane_mask(Index i, Index n, v4d& valid)
{
  const v4d lane = { 0.0, 1.0, 2.0, 3.0 };
  const v4d one = { 1.0, 1.0, 1.0, 1.0 }, zero = { 0.0, 0.0, 0.0, 0.0 };
  valid = BARY_SELECT(lane + static_cast<double>(i) < static_cast<double>(n), one, zero);
}

/// q_i = (v_i - p) / d_i and 1 / d_i (zero in the padding lanes). @p v: the controls as D
/// padded rows (v[k * ld + i]).
template<int D>
BARY_TARGET_AVX2 BARY_NOINLINE void directions_avx2(
  const double* v, Index n, Index ld, const double* p, double* q, double* inv_d)
{
  const v4d zero = { 0.0, 0.0, 0.0, 0.0 };
  for (Index i = 0; i < ld; i += 4)
  {
    v4d e[D], d2 = zero;
    for (int k = 0; k < D; ++k)
    {
      e[k] = BARY_LOAD4(v + k * ld + i) - p[k];
      d2 += e[k] * e[k];
    }
    v4d inv = 1.0 / v4d(_mm256_sqrt_pd(d2));
    if (i + 4 > n)
    {
      v4d valid;
      lane_mask(i, n, valid);
      inv = BARY_SELECT(valid > zero, inv, zero);
    }
    BARY_STORE4(inv_d + i, inv);
    for (int k = 0; k < D; ++k)
      BARY_STORE4(q + k * ld + i, e[k] * inv);
  }
}

/// The accumulators of scc_eval_avx2, one lane per control of each vector (named variables:
/// an array of them was zeroed through memory and spilled).
struct SccSums
{
  v4d phi, sb, f0, f1, f2, j00, j01, j02, j11, j12, j22;
};

/// One vector of controls of scc_eval_avx2; @p valid masks Phi and sum beta (the padding lanes
/// have q = 0, so their F and J terms vanish by themselves). J's terms without the factor 2
/// (applied to the sums: exact).
template<int D, bool Tail>
BARY_TARGET_AVX2 BARY_ALWAYS_INLINE void scc_terms(const double* q, Index ld, Index i,
  const v4d (&x)[D], const v4d& valid, double* beta, double* slope, SccSums& acc)
{
  v4d qk[D];
  qk[0] = BARY_LOAD4(q + i);
  v4d a = x[0] * qk[0];
  for (int k = 1; k < D; ++k)
  {
    qk[k] = BARY_LOAD4(q + k * ld + i);
    a += x[k] * qk[k];
  }
  const v4d zero = { 0.0, 0.0, 0.0, 0.0 };
  const v4d t = _mm256_sqrt_pd(a * a + 1.0); // r
  const v4d tma = t - a;
  const v4d inv = 1.0 / (t * tma); // 1 / (r (r - a))
  const v4d m = BARY_SELECT(a >= zero, a + t, t * inv);
  v4d b = m * m;
  const v4d w = b * tma * inv; // m^2 / r
  BARY_STORE4(beta + i, b);
  BARY_STORE4(slope + i, w);
  v4d e = m * (b * (1.0 / 6.0) + 0.5);
  if constexpr (Tail)
  {
    e *= valid;
    b *= valid;
  }
  acc.phi += e;
  acc.sb += b;
  const v4d w0 = w * qk[0];
  acc.f0 += b * qk[0];
  acc.j00 += w0 * qk[0];
  if constexpr (D > 1)
  {
    const v4d w1 = w * qk[1];
    acc.f1 += b * qk[1];
    acc.j01 += w0 * qk[1];
    acc.j11 += w1 * qk[1];
    if constexpr (D > 2)
    {
      acc.f2 += b * qk[2];
      acc.j02 += w0 * qk[2];
      acc.j12 += w1 * qk[2];
      acc.j22 += w * qk[2] * qk[2];
    }
  }
}

/// The lane sums of four vectors, each (l0 + l1) + (l2 + l3), into out[0..3].
BARY_TARGET_AVX2 BARY_ALWAYS_INLINE void lane_sums4(
  const v4d& a, const v4d& b, const v4d& c, const v4d& d, double* out)
{
  const __m256d ab = _mm256_hadd_pd(a, b), cd = _mm256_hadd_pd(c, d); // a0+a1 b0+b1 a2+a3 b2+b3
  const __m256d lo = _mm256_permute2f128_pd(ab, cd, 0x20), hi = _mm256_permute2f128_pd(ab, cd, 0x31);
  _mm256_storeu_pd(out, _mm256_add_pd(lo, hi));
}

/// The S scheme at y = x (Newton::eval): beta_i = m(q_i . y)^2 into beta and m_i^2 / r_i
/// (half of d beta_i / d a_i) into slope (ld entries each), and out = { Phi, sum beta,
/// F_0..F_2, J_00, J_01, J_02, J_11, J_12, J_22 } (12 entries; the last is scratch).
template<int D>
BARY_TARGET_AVX2 BARY_NOINLINE void scc_eval_avx2(
  const double* q, Index n, Index ld, const double* x, double* beta, double* slope, double* out)
{
  const v4d zero = { 0.0, 0.0, 0.0, 0.0 };
  SccSums acc{ zero, zero, zero, zero, zero, zero, zero, zero, zero, zero, zero };
  v4d xk[D];
  for (int k = 0; k < D; ++k)
    xk[k] = zero + x[k];
  const Index full = n / 4 * 4;
  const v4d valid = { 1.0, 1.0, 1.0, 1.0 };
  for (Index i = 0; i < full; i += 4)
    scc_terms<D, false>(q, ld, i, xk, valid, beta, slope, acc);
  if (full < n)
  {
    v4d tail;
    lane_mask(full, n, tail);
    scc_terms<D, true>(q, ld, full, xk, tail, beta, slope, acc);
  }
  lane_sums4(acc.phi, acc.sb, acc.f0, acc.f1, out);
  lane_sums4(acc.f2, acc.j00 + acc.j00, acc.j01 + acc.j01, acc.j02 + acc.j02, out + 4);
  lane_sums4(acc.j11 + acc.j11, acc.j12 + acc.j12, acc.j22 + acc.j22, zero, out + 8);
}

/// w_i = (beta_i / d_i) / sum_j (beta_j / d_j), Eq. (3), into w (n entries).
BARY_TARGET_AVX2 BARY_NOINLINE void weights_avx2(
  const double* beta, const double* inv_d, Index n, Index ld, double* w)
{
  v4d sum = { 0.0, 0.0, 0.0, 0.0 };
  for (Index i = 0; i < ld; i += 4) // padding: inv_d = 0, beta finite
    sum += BARY_LOAD4(beta + i) * BARY_LOAD4(inv_d + i);
  const double inv = 1.0 / lane_sum(sum);
  Index i = 0;
  for (; i + 4 <= n; i += 4)
    BARY_STORE4(w + i, BARY_LOAD4(beta + i) * BARY_LOAD4(inv_d + i) * inv);
  for (; i < n; ++i)
    w[i] = beta[i] * inv_d[i] * inv;
}

/// The weights as weights_avx2 (the same operations: the same bits) and, in the same pass, the
/// sums of the warm-start predictor (Predictor) at the converged y = x:
/// out = { s, g_0..g_2, M_00, M_01, M_02, M_11, M_12, M_22 } (12 entries; the last is scratch)
/// with s = sum_i beta_i / d_i, g = sum_i (beta'_i / d_i) q_i, M = sum_i c_i q_i q_i^T,
/// c_i = (beta'_i a_i + beta_i) / d_i, beta'_i = 2 slope_i, a_i = q_i . y.
template<int D>
BARY_TARGET_AVX2 BARY_NOINLINE void scc_finish_avx2(const double* q, Index n, Index ld,
  const double* x, const double* beta, const double* slope, const double* inv_d, double* w,
  double* out)
{
  const v4d zero = { 0.0, 0.0, 0.0, 0.0 };
  v4d xk[D];
  for (int k = 0; k < D; ++k)
    xk[k] = zero + x[k];
  v4d sum = zero, g0 = zero, g1 = zero, g2 = zero, m00 = zero, m01 = zero, m02 = zero,
      m11 = zero, m12 = zero, m22 = zero;
  for (Index i = 0; i < ld; i += 4) // padding: inv_d = 0, beta and slope finite
  {
    const v4d b = BARY_LOAD4(beta + i), id = BARY_LOAD4(inv_d + i);
    sum += b * id;
    v4d qk[D];
    qk[0] = BARY_LOAD4(q + i);
    v4d a = xk[0] * qk[0];
    for (int k = 1; k < D; ++k)
    {
      qk[k] = BARY_LOAD4(q + k * ld + i);
      a += xk[k] * qk[k];
    }
    const v4d ds = BARY_LOAD4(slope + i) * id; // beta' / (2 d)
    const v4d c = ((ds + ds) * a + b * id);
    const v4d c0 = c * qk[0];
    g0 += ds * qk[0];
    m00 += c0 * qk[0];
    if constexpr (D > 1)
    {
      const v4d c1 = c * qk[1];
      g1 += ds * qk[1];
      m01 += c0 * qk[1];
      m11 += c1 * qk[1];
      if constexpr (D > 2)
      {
        g2 += ds * qk[2];
        m02 += c0 * qk[2];
        m12 += c1 * qk[2];
        m22 += c * qk[2] * qk[2];
      }
    }
  }
  lane_sums4(sum, g0 + g0, g1 + g1, g2 + g2, out);
  lane_sums4(m00, m01, m02, m11, out + 4);
  lane_sums4(m12, m22, zero, zero, out + 8);
  const double inv = 1.0 / out[0];
  Index i = 0;
  for (; i + 4 <= n; i += 4)
    BARY_STORE4(w + i, BARY_LOAD4(beta + i) * BARY_LOAD4(inv_d + i) * inv);
  for (; i < n; ++i)
    w[i] = beta[i] * inv_d[i] * inv;
}
#endif

/// Whether the kernels above run (AVX2 and FMA available and not switched off).
inline bool use_avx2()
{
#if BARY_HAVE_AVX2_DISPATCH
  return detail::simd_level() == detail::SimdLevel::AVX2;
#else
  return false;
#endif
}

// ------------------------------------------------------------------------------------------
// Newton for one point, fixed dimension D. q is stored as D arrays of n (structure of arrays).

/// Solves the symmetric positive definite D x D system A x = b (NaN if it is singular).
template<int D>
Eigen::Matrix<double, D, 1> solve_spd(
  const Eigen::Matrix<double, D, D>& A, const Eigen::Matrix<double, D, 1>& b)
{
  // Cholesky A = L L^T by hand (a quarter of Eigen's pivoting LDLT in the profile); a
  // non-positive pivot gives NaN, which the caller treats as a failed step.
  Eigen::Matrix<double, D, 1> x;
  if constexpr (D == 1)
    x[0] = b[0] / A(0, 0);
  else if constexpr (D == 2)
  {
    const double l00 = std::sqrt(A(0, 0)), l10 = A(1, 0) / l00;
    const double l11 = std::sqrt(A(1, 1) - l10 * l10);
    const double y0 = b[0] / l00, y1 = (b[1] - l10 * y0) / l11;
    x[1] = y1 / l11;
    x[0] = (y0 - l10 * x[1]) / l00;
  }
  else
  {
    const double l00 = std::sqrt(A(0, 0)), l10 = A(1, 0) / l00, l20 = A(2, 0) / l00;
    const double l11 = std::sqrt(A(1, 1) - l10 * l10);
    const double l21 = (A(2, 1) - l20 * l10) / l11;
    const double l22 = std::sqrt(A(2, 2) - l20 * l20 - l21 * l21);
    const double y0 = b[0] / l00, y1 = (b[1] - l10 * y0) / l11,
                 y2 = (b[2] - l20 * y0 - l21 * y1) / l22;
    x[2] = y2 / l22;
    x[1] = (y1 - l21 * x[2]) / l11;
    x[0] = (y0 - l10 * x[1] - l20 * x[2]) / l00;
  }
  return x;
}

/// The same system by A = L diag(d) L^T: no square roots and three divisions instead of three
/// square roots and nine (the kernels' path, where the Cholesky's chain of them was a tenth of
/// the time). NaN if a pivot is not positive.
template<int D>
Eigen::Matrix<double, D, 1> solve_spd_ldlt(
  const Eigen::Matrix<double, D, D>& A, const Eigen::Matrix<double, D, 1>& b)
{
  Eigen::Matrix<double, D, 1> x;
  const double d0 = A(0, 0);
  if constexpr (D == 1)
  {
    x[0] = d0 > 0.0 ? b[0] / d0 : kNaN;
    return x;
  }
  else if constexpr (D == 2)
  {
    const double r0 = 1.0 / d0, l10 = A(1, 0) * r0;
    const double d1 = A(1, 1) - l10 * A(1, 0);
    if (!(d0 > 0.0 && d1 > 0.0))
      return Eigen::Matrix<double, D, 1>::Constant(kNaN);
    const double z1 = b[1] - l10 * b[0];
    x[1] = z1 / d1;
    x[0] = b[0] * r0 - l10 * x[1];
  }
  else
  {
    const double r0 = 1.0 / d0, l10 = A(1, 0) * r0, l20 = A(2, 0) * r0;
    const double d1 = A(1, 1) - l10 * A(1, 0);
    const double e21 = A(2, 1) - l20 * A(1, 0); // l21 d1
    const double r1 = 1.0 / d1, l21 = e21 * r1;
    const double d2 = A(2, 2) - l20 * A(2, 0) - l21 * e21;
    if (!(d0 > 0.0 && d1 > 0.0 && d2 > 0.0))
      return Eigen::Matrix<double, D, 1>::Constant(kNaN);
    const double z1 = b[1] - l10 * b[0];
    const double z2 = b[2] - l20 * b[0] - l21 * z1;
    x[2] = z2 / d2;
    x[1] = z1 * r1 - l21 * x[2];
    x[0] = b[0] * r0 - l10 * x[1] - l20 * x[2];
  }
  return x;
}

struct SolveStats
{
  int iterations = 0;
  double residual = kNaN;
  bool converged = false;
};

template<int D>
class Newton
{
public:
  using Vec = Eigen::Matrix<double, D, 1>;
  using Mat = Eigen::Matrix<double, D, D>;

  /// @param q D * ld doubles, q[k * ld + i] = component k of q_i, ld = padded(n), zero for
  /// i >= n; @param s n user weights or nullptr (TCC only); @param scratch 6 ld doubles, finite
  /// (the betas of the current and the trial iterate, and four work arrays). Not thread-safe:
  /// one per thread.
  Newton(CelestialScheme scheme, const double* q, const double* s, Index n, double* scratch)
    : scheme_(scheme)
    , q_(q)
    , s_(s)
    , n_(n)
    , ld_(padded(n))
    , a_(scratch + 2 * ld_)
    , t_(scratch + 3 * ld_)
    , m_(scratch + 4 * ld_)
    , w_(scratch + 5 * ld_)
    , avx2_(use_avx2())
  {
    cur_.beta = scratch;
    next_.beta = scratch + ld_;
    cur_.slope = a_; // the S kernel's; a_ and t_ serve the other evals only
    next_.slope = t_;
    rs_.setZero();
    s_sum_ = 0.0;
    if (scheme_ == CelestialScheme::T && s_ != nullptr)
      for (Index i = 0; i < n_; ++i)
      {
        rs_ += s_[i] * qi(i);
        s_sum_ += s_[i];
      }
  }

  /// TCC: the linearised system of Sect. 4.2, sum_i (s_i + 1 + psi . q_i) q_i = 0.
  /// SCC: c0 = -l, l = the centre of mass of the segments cut by the sphere of radius lambda
  /// around p (Sect. 5.3): l = (lambda / 2n) sum_i q_i; returned as y0 = c0 / sqrt(K(c0)).
  Vec cold_start(double lambda) const
  {
    Vec sum = Vec::Zero();
    for (Index i = 0; i < n_; ++i)
      sum += qi(i);
    if (scheme_ == CelestialScheme::T)
    {
      Mat A = Mat::Zero();
      for (Index i = 0; i < n_; ++i)
        A.noalias() += qi(i) * qi(i).transpose();
      const Vec x = solve_spd<D>(A, -(sum + rs_));
      return x.allFinite() ? x : Vec::Zero();
    }
    const Vec c0 = -(lambda / (2.0 * static_cast<double>(n_))) * sum;
    return c0 / std::sqrt(lambda * lambda + 2.0 * lambda * c0.norm());
  }

  /// Newton from x (updated in place). After it, beta() holds the betas at x. With @p fallback
  /// (x is then a prediction), Newton starts from whichever of x and *fallback has the smaller
  /// relative residual when x's exceeds kPredictedResidual (a prediction far off, e.g. across
  /// a fold of the solution near the hull).
  SolveStats solve(Vec& x, double tol, int max_iterations, const Vec* fallback = nullptr)
  {
    SolveStats stats;
    eval(x, cur_);
    if (fallback != nullptr)
    {
      const double rho = cur_.finite ? cur_.F.norm() / cur_.sb : kNaN;
      if (!(rho <= kPredictedResidual))
      {
        eval(*fallback, next_);
        if (next_.finite && !(next_.F.norm() / next_.sb >= rho))
        {
          x = *fallback;
          std::swap(cur_, next_);
        }
      }
    }
    if (!cur_.finite)
      return stats;
    for (;;)
    {
      const double fnorm = cur_.F.norm();
      stats.residual = fnorm / cur_.sb;
      // The rounding floor: a_i = x . q_i carries an error ~ u |x|_1, which moves beta_i by
      // ~ 2 u |x|_1 beta_i (both schemes), so F by 2 u |x|_1 sum beta, plus the n-term sums.
      // It exceeds the default tolerance only where |x| is large: within ~1e-9 of the hull.
      const double floor = 4.0 * kRoundoff * (x.template lpNorm<1>() + static_cast<double>(n_));
      if (stats.residual <= std::max(tol, floor))
      {
        stats.converged = true;
        return stats;
      }
      if (stats.iterations >= max_iterations)
        return stats;
      Vec d = avx2_ ? Vec(-solve_spd_ldlt<D>(cur_.J, cur_.F)) : Vec(-solve_spd<D>(cur_.J, cur_.F));
      if constexpr (D > 1)
        if (!d.allFinite()) // a rounded pivot <= 0 (J nearly singular, very near the hull)
          d = -cur_.J.ldlt().solve(cur_.F);
      if (!d.allFinite() || !(cur_.F.dot(d) < 0.0))
        d = -cur_.F / cur_.J.trace(); // steepest descent, scaled
      if (!d.allFinite())
        return stats;
      const double slope = cur_.F.dot(d);
      double t = 1.0;
      bool accepted = false;
      Vec xn;
      for (int k = 0; k < kMaxBacktracks && !accepted; ++k, t *= 0.5)
      {
        xn = x + t * d;
        eval(xn, next_);
        if (!next_.finite)
          continue;
        accepted = next_.phi <= cur_.phi + kArmijo * t * slope ||
          (stats.residual < kResidualSwitch && next_.F.norm() <= (1.0 - kArmijo * t) * fnorm);
      }
      if (!accepted)
      {
        eval(x, cur_); // restore the betas of x
        return stats;  // stagnation: no step reduces the merit functions
      }
      x = xn;
      std::swap(cur_, next_);
      ++stats.iterations;
    }
  }

  /// beta_i at the last x solve() was given or returned (SCC: up to the common factor K,
  /// which cancels in Eq. 3).
  const double* beta() const { return cur_.beta; }
  /// m_i^2 / r_i at that x (S scheme through scc_eval_avx2 only).
  const double* slope() const { return cur_.slope; }
  /// F's Jacobian at that x.
  const Mat& jacobian() const { return cur_.J; }

private:
  struct State
  {
    Vec F;
    Mat J;
    double phi = 0.0, sb = 0.0;
    bool finite = false;
    double* beta = nullptr;  // n
    double* slope = nullptr; // n: m_i^2 / r_i (scc_eval_avx2)
  };

  Vec qi(Index i) const
  {
    Vec v;
    for (int k = 0; k < D; ++k)
      v[k] = q_[k * ld_ + i];
    return v;
  }

  // F, J, Phi and sum beta at x, and the betas into st.beta. First a_i = x . q_i and the
  // transcendental part (exp or sqrt) as Eigen array expressions, which vectorize (std::sqrt
  // and std::exp in a loop do not: errno, no SIMD exp in libm), then one loop of products and
  // sums with scalar accumulators, vectorized by omp simd. Results do not depend on threads.
  void eval(const Vec& x, State& st) const
  {
#if BARY_HAVE_AVX2_DISPATCH
    if (scheme_ == CelestialScheme::S && avx2_)
    {
      double sums[12];
      scc_eval_avx2<D>(q_, n_, ld_, x.data(), st.beta, st.slope, sums);
      st.phi = sums[0];
      st.sb = sums[1];
      for (int k = 0; k < D; ++k)
        st.F[k] = sums[2 + k];
      st.J(0, 0) = sums[5];
      if constexpr (D > 1)
      {
        st.J(0, 1) = st.J(1, 0) = sums[6];
        st.J(1, 1) = sums[8];
      }
      if constexpr (D > 2)
      {
        st.J(0, 2) = st.J(2, 0) = sums[7];
        st.J(1, 2) = st.J(2, 1) = sums[9];
        st.J(2, 2) = sums[10];
      }
      st.finite =
        std::isfinite(st.phi) && std::isfinite(st.sb) && st.F.allFinite() && st.J.allFinite();
      return;
    }
#endif
    const Index n = n_;
    const double* q0 = q_;
    const double* q1 = q_ + (D > 1 ? ld_ : 0);
    const double* q2 = q_ + (D > 2 ? 2 * ld_ : 0);
    using Array = Eigen::Array<double, Eigen::Dynamic, 1>;
    Eigen::Map<Array> a(a_, n), t(t_, n);
    if constexpr (D == 1)
      a = x[0] * Eigen::Map<const Array>(q0, n);
    else if constexpr (D == 2)
      a = x[0] * Eigen::Map<const Array>(q0, n) + x[1] * Eigen::Map<const Array>(q1, n);
    else
      a = x[0] * Eigen::Map<const Array>(q0, n) + x[1] * Eigen::Map<const Array>(q1, n) +
        x[2] * Eigen::Map<const Array>(q2, n);
    const double* tp = t_;
    double* beta = st.beta;
    double f0 = 0, f1 = 0, f2 = 0, j00 = 0, j01 = 0, j02 = 0, j11 = 0, j12 = 0, j22 = 0;
    double phi = 0, sb = 0;
    if (scheme_ == CelestialScheme::T)
    {
      t = a.exp(); // e_i
      const double* s = s_;
#pragma omp simd reduction(+ : f0, f1, f2, j00, j01, j02, j11, j12, j22, phi)
      for (Index i = 0; i < n; ++i)
      {
        const double e = tp[i];
        beta[i] = s ? s[i] + e : e;
        phi += e;
        const double w0 = e * q0[i];
        f0 += w0;
        j00 += w0 * q0[i];
        if constexpr (D > 1)
        {
          const double w1 = e * q1[i];
          f1 += w1;
          j01 += w0 * q1[i];
          j11 += w1 * q1[i];
          if constexpr (D > 2)
          {
            const double w2 = e * q2[i];
            f2 += w2;
            j02 += w0 * q2[i];
            j12 += w1 * q2[i];
            j22 += w2 * q2[i];
          }
        }
      }
      sb = phi + s_sum_;
      phi += x.dot(rs_);
      f0 += rs_[0];
      if constexpr (D > 1)
        f1 += rs_[1];
      if constexpr (D > 2)
        f2 += rs_[2];
    }
    else
    {
      // r = sqrt(a^2 + 1); one division for 1 / r and, for a < 0, m = 1 / (r - a): with
      // D = r (r - a), 1 / r = (r - a) / D (the same rounded r - a above and below, so its
      // cancellation for a >> 0 does not matter) and 1 / (r - a) = r / D.
      Eigen::Map<Array> m(m_, n), w(w_, n), b(beta, n);
      t = (a.square() + 1.0).sqrt();
      w = 1.0 / (t * (t - a)); // 1 / D
      m = (a >= 0.0).select(a + t, t * w);
      b = m.square();
      w = 2.0 * b * (t - a) * w; // 2 m^2 / r
      const double* mp = m_;
      const double* wp = w_;
#pragma omp simd reduction(+ : f0, f1, f2, j00, j01, j02, j11, j12, j22, phi, sb)
      for (Index i = 0; i < n; ++i)
      {
        const double mi = mp[i], bi = beta[i], wi = wp[i];
        phi += mi * (bi * (1.0 / 6.0) + 0.5);
        sb += bi;
        f0 += bi * q0[i];
        const double w0 = wi * q0[i];
        j00 += w0 * q0[i];
        if constexpr (D > 1)
        {
          f1 += bi * q1[i];
          const double w1 = wi * q1[i];
          j01 += w0 * q1[i];
          j11 += w1 * q1[i];
          if constexpr (D > 2)
          {
            f2 += bi * q2[i];
            j02 += w0 * q2[i];
            j12 += w1 * q2[i];
            j22 += wi * q2[i] * q2[i];
          }
        }
      }
    }
    st.F[0] = f0;
    st.J(0, 0) = j00;
    if constexpr (D > 1)
    {
      st.F[1] = f1;
      st.J(0, 1) = st.J(1, 0) = j01;
      st.J(1, 1) = j11;
    }
    if constexpr (D > 2)
    {
      st.F[2] = f2;
      st.J(0, 2) = st.J(2, 0) = j02;
      st.J(1, 2) = st.J(2, 1) = j12;
      st.J(2, 2) = j22;
    }
    st.phi = phi;
    st.sb = sb;
    st.finite = std::isfinite(phi) && std::isfinite(sb) && st.F.allFinite() && st.J.allFinite();
  }

  CelestialScheme scheme_;
  const double* q_;
  const double* s_;
  Index n_;
  Index ld_;           // padded(n): stride of q and of the scratch arrays
  double* a_;          // n: a_i = x . q_i
  double* t_;          // n: exp(a_i) (TCC) or sqrt(a_i^2 + 1) (SCC)
  double* m_;          // n: m(a_i) (SCC)
  double* w_;          // n: 2 m_i^2 / r_i (SCC)
  Vec rs_;             // sum_i s_i q_i (TCC)
  double s_sum_ = 0.0; // sum_i s_i (TCC)
  bool avx2_;          // the S scheme's eval runs scc_eval_avx2
  State cur_, next_;
};

// ------------------------------------------------------------------------------------------
// Hilbert curve order (Skilling, "Programming the Hilbert curve", AIP Conf. Proc. 707, 2004).

/// Bit b of x (b < 16) moved to bit D b.
template<int D>
BARY_ALWAYS_INLINE std::uint64_t spread_bits(std::uint32_t x)
{
  std::uint64_t v = x & 0xffffu;
  if constexpr (D == 2)
  {
    v = (v | (v << 8)) & 0x00ff00ffULL;
    v = (v | (v << 4)) & 0x0f0f0f0fULL;
    v = (v | (v << 2)) & 0x33333333ULL;
    v = (v | (v << 1)) & 0x55555555ULL;
  }
  else
  {
    v = (v | (v << 16)) & 0x0000ff0000ffULL;
    v = (v | (v << 8)) & 0x00f00f00f00fULL;
    v = (v | (v << 4)) & 0x0c30c30c30c3ULL;
    v = (v | (v << 2)) & 0x249249249249ULL;
  }
  return v;
}

/// The Hilbert keys of L points at once (Skilling's transpose algorithm; X[i][j] is coordinate
/// i of point j, overwritten): the lanes' loops are innermost, so the compiler vectorises them.
template<int D, int L>
BARY_ALWAYS_INLINE void hilbert_keys(
  std::array<std::array<std::uint32_t, L>, D>& X, int bits, std::uint64_t* key)
{
  // Without branches on the bits (they are data: a branch would be mispredicted half the time).
  for (int q = bits - 1; q > 0; --q)
  {
    const std::uint32_t P = (1u << q) - 1u;
    // i = 0: bit q of X[0] set: X[0] ^= P (else nothing)
    for (int j = 0; j < L; ++j)
      X[0][j] ^= P & (0u - ((X[0][j] >> q) & 1u));
    for (int i = 1; i < D; ++i)
    {
      // bit q of X[i] set: X[0] ^= P; else exchange the low bits of X[0] and X[i]. Through
      // copies, so that the compiler sees that the two rows do not overlap.
      std::array<std::uint32_t, L> a = X[0], b = X[static_cast<std::size_t>(i)];
      for (int j = 0; j < L; ++j)
      {
        const std::uint32_t set = 0u - ((b[j] >> q) & 1u);
        const std::uint32_t t = (a[j] ^ b[j]) & P & ~set;
        a[j] ^= (P & set) | t;
        b[j] ^= t;
      }
      X[0] = a;
      X[static_cast<std::size_t>(i)] = b;
    }
  }
  for (int i = 1; i < D; ++i)
    for (int j = 0; j < L; ++j)
      X[i][j] ^= X[i - 1][j];
  std::array<std::uint32_t, L> t{};
  for (int q = bits - 1; q > 0; --q)
    for (int j = 0; j < L; ++j)
      t[j] ^= ((1u << q) - 1u) & (0u - ((X[D - 1][j] >> q) & 1u));
  // Interleave, most significant bit first, X[0]'s bit before X[1]'s: bit b of X[i] goes to
  // bit b D + D - 1 - i of the key.
  for (int j = 0; j < L; ++j)
  {
    std::uint64_t k = 0;
    for (int i = 0; i < D; ++i)
      k |= spread_bits<D>(X[i][j] ^ t[j]) << (D - 1 - i);
    key[j] = k;
  }
}

/// The (key, index) pairs of points [first, first + n), n <= 8, into keys: the cell of each
/// coordinate in [0, cells] on the box [lo, hi], then hilbert_keys (lanes past n padded).
template<int D>
BARY_ALWAYS_INLINE void hilbert_block(const Eigen::MatrixXd& X, const double* lo, const double* hi,
  double cells, int bits, Index first, Index n, std::pair<std::uint64_t, Index>* keys)
{
  constexpr int L = 8;
  std::array<std::array<std::uint32_t, L>, D> c{};
  for (int k = 0; k < D; ++k)
  {
    const double ext = hi[k] - lo[k];
    for (Index j = 0; j < n; ++j)
    {
      const double u = ext > 0.0 ? (X(first + j, k) - lo[k]) / ext : 0.0;
      c[static_cast<std::size_t>(k)][static_cast<std::size_t>(j)] =
        static_cast<std::uint32_t>(std::clamp(u * cells, 0.0, cells));
    }
  }
  std::array<std::uint64_t, L> key;
  hilbert_keys<D, L>(c, bits, key.data());
  for (Index j = 0; j < n; ++j)
    keys[first + j] = { key[static_cast<std::size_t>(j)], first + j };
}

/// hilbert_block over the points [begin, end) eight at a time; the same bits compiled for AVX2
/// (eight lanes of 32 bits where SSE2 has four) and for the portable target.
template<int D>
void hilbert_blocks(const Eigen::MatrixXd& X, const double* lo, const double* hi, double cells,
  int bits, Index begin, Index end, std::pair<std::uint64_t, Index>* keys)
{
  for (Index first = begin; first < end; first += 8)
    hilbert_block<D>(X, lo, hi, cells, bits, first, std::min<Index>(8, end - first), keys);
}
#if BARY_HAVE_AVX2_DISPATCH
template<int D>
BARY_TARGET_AVX2 BARY_NOINLINE void hilbert_blocks_avx2(const Eigen::MatrixXd& X, const double* lo,
  const double* hi, double cells, int bits, Index begin, Index end,
  std::pair<std::uint64_t, Index>* keys)
{
  for (Index first = begin; first < end; first += 8)
    hilbert_block<D>(X, lo, hi, cells, bits, first, std::min<Index>(8, end - first), keys);
}
#endif

/// Indices 0..#P-1 sorted along a Hilbert curve through the bounding box of X (ties by index).
std::vector<Index> hilbert_order(const Eigen::MatrixXd& X, int threads)
{
  const Index np = X.rows();
  const int dim = static_cast<int>(X.cols());
  const int bits = 16; // 65536 cells per axis: ample for warm starts, and cheap
  const Eigen::RowVectorXd lo = X.colwise().minCoeff(), hi = X.colwise().maxCoeff();
  const double cells = std::ldexp(1.0, bits) - 1.0;
  std::vector<std::pair<std::uint64_t, Index>> keys;
  detail::assign_huge(keys, static_cast<std::size_t>(np));
  // Blocks of 8 Ki points (a multiple of the kernels' eight), in parallel.
  constexpr Index kBlock = 8192;
  const Index blocks = (np + kBlock - 1) / kBlock;
  [[maybe_unused]] const bool avx2 = use_avx2();
#pragma omp parallel for schedule(static) num_threads(threads) if (np >= 4096)
  for (Index b = 0; b < blocks; ++b)
  {
    const Index begin = b * kBlock, end = std::min(np, begin + kBlock);
    auto* out = keys.data();
#if BARY_HAVE_AVX2_DISPATCH
    if (avx2)
    {
      if (dim == 2)
        hilbert_blocks_avx2<2>(X, lo.data(), hi.data(), cells, bits, begin, end, out);
      else
        hilbert_blocks_avx2<3>(X, lo.data(), hi.data(), cells, bits, begin, end, out);
      continue;
    }
#endif
    if (dim == 2)
      hilbert_blocks<2>(X, lo.data(), hi.data(), cells, bits, begin, end, out);
    else
      hilbert_blocks<3>(X, lo.data(), hi.data(), cells, bits, begin, end, out);
  }
  // Sorted by (key, index): a stable least-significant-digit radix sort on the key (16 bits a
  // pass; the indices come ascending), the order std::sort of the pairs gives. Each thread
  // counts and scatters its own contiguous block, its buckets placed after those of the blocks
  // before it: the same stable order for any number of threads.
  std::vector<std::pair<std::uint64_t, Index>> other;
  detail::assign_huge(other, keys.size());
  const std::size_t buckets = std::size_t(1) << 16;
  const int parts = np >= 65536 ? std::clamp(threads, 1, 16) : 1;
  std::vector<std::size_t> count(buckets * static_cast<std::size_t>(parts));
  for (int shift = 0; shift < dim * bits; shift += 16)
  {
#pragma omp parallel num_threads(parts) if (parts > 1)
    {
      const std::size_t n = keys.size();
      const auto block = [&](int u) {
        return std::make_pair(n * static_cast<std::size_t>(u) / static_cast<std::size_t>(parts),
          n * (static_cast<std::size_t>(u) + 1) / static_cast<std::size_t>(parts));
      };
#pragma omp for schedule(static)
      for (int u = 0; u < parts; ++u)
      {
        std::size_t* c = count.data() + buckets * static_cast<std::size_t>(u);
        std::fill(c, c + buckets, 0);
        const auto [begin, end] = block(u);
        for (std::size_t i = begin; i < end; ++i)
          ++c[(keys[i].first >> shift) & 0xffffu];
      }
#pragma omp single
      {
        std::size_t sum = 0;
        for (std::size_t b = 0; b < buckets; ++b)
          for (int u = 0; u < parts; ++u)
            sum += std::exchange(count[buckets * static_cast<std::size_t>(u) + b], sum);
      }
#pragma omp for schedule(static)
      for (int u = 0; u < parts; ++u)
      {
        std::size_t* c = count.data() + buckets * static_cast<std::size_t>(u);
        const auto [begin, end] = block(u);
        for (std::size_t i = begin; i < end; ++i)
          other[c[(keys[i].first >> shift) & 0xffffu]++] = keys[i];
      }
    }
    keys.swap(other);
  }
  std::vector<Index> order;
  detail::assign_huge(order, static_cast<std::size_t>(np));
#pragma omp parallel for schedule(static) num_threads(threads) if (np >= 65536)
  for (Index p = 0; p < np; ++p)
    order[static_cast<std::size_t>(p)] = keys[static_cast<std::size_t>(p)].second;
  return order;
}

// ------------------------------------------------------------------------------------------
// Convex hull, recursively: a node is a face of the hull (the hull itself, a facet, an edge of
// a facet, a vertex) in its own orthonormal coordinates, with the planes bounding it there and
// the node of the face on each plane.

struct HullNode
{
  int dim = 0;
  std::vector<Index> ids;    // controls on this face (global ids)
  Eigen::VectorXd origin;    // global coordinates of the local origin
  Eigen::MatrixXd basis;     // global dim x dim, orthonormal columns
  Eigen::MatrixXd local;     // dim x #ids, the controls in local coordinates
  Eigen::MatrixXd normals;   // dim x #planes, outward unit normals (local coordinates)
  Eigen::VectorXd offsets;   // #planes: x is inside plane k iff normals.col(k) . x <= offsets[k]
  std::vector<int> children; // node of the face on each plane
};

} // namespace

struct CelestialCoordinates::Impl
{
  Points V;
  CelestialOptions options;
  int dim = 0;
  double diameter = 0.0;
  double tol = 0.0;            // absolute boundary tolerance
  std::vector<HullNode> nodes; // nodes[0] is the hull (empty when flat)
  std::vector<double> s;       // TCC user weights (empty: zero)
  /// The controls span no interior (fewer than dim + 1, on a line or a plane): allowed with
  /// CelestialHullPoints::Auto or Always only, which then always add the hull points.
  bool flat = false;

  /// @p storage: a result whose arrays' storage is reused (or null).
  CelestialResult compute(const Points& X, const Eigen::MatrixXi& edges, const Points* initial,
    const ProgressCallback& progress, CelestialResult* storage = nullptr) const;
  Points hull_points_for(const Points& X) const;
  Index facets() const { return nodes.empty() ? 0 : nodes.front().normals.cols(); }

  void validate();
  void build_hull();
  int add_node(
    int dim, std::vector<Index> ids, const Eigen::VectorXd& origin, const Eigen::MatrixXd& basis);
  void build_planes(int node);

  Eigen::VectorXd to_local(const HullNode& node, const double* p) const
  {
    Eigen::VectorXd x(node.dim);
    const Eigen::Map<const Eigen::VectorXd> pg(p, dim);
    x.noalias() = node.basis.transpose() * (pg - node.origin);
    return x;
  }
  /// max_k (normals_k . x - offsets_k) and its argmax.
  static double max_plane_distance(const HullNode& node, const Eigen::VectorXd& x, int* arg)
  {
    double best = -std::numeric_limits<double>::infinity();
    *arg = -1;
    for (Index k = 0; k < node.normals.cols(); ++k)
    {
      const double s = node.normals.col(k).dot(x) - node.offsets[k];
      if (s > best)
      {
        best = s;
        *arg = static_cast<int>(k);
      }
    }
    return best;
  }

  CelestialLocation classify(const double* p) const;
  SolveStats solve_on_face(int node, const double* p, double* w) const;
};

namespace
{

/// Orthonormal basis (columns) of the orthogonal complement of the unit vector n in R^3.
Eigen::Matrix<double, 3, 2> complement_basis(const Eigen::Vector3d& n)
{
  Eigen::Index k;
  n.cwiseAbs().minCoeff(&k);
  Eigen::Vector3d e = Eigen::Vector3d::Zero();
  e[k] = 1.0;
  const Eigen::Vector3d u = n.cross(e).normalized();
  Eigen::Matrix<double, 3, 2> B;
  B.col(0) = u;
  B.col(1) = n.cross(u);
  return B;
}

} // namespace

int CelestialCoordinates::Impl::add_node(
  int node_dim, std::vector<Index> ids, const Eigen::VectorXd& origin, const Eigen::MatrixXd& basis)
{
  HullNode node;
  node.dim = node_dim;
  node.ids = std::move(ids);
  node.origin = origin;
  node.basis = basis;
  node.local.resize(node_dim, static_cast<Index>(node.ids.size()));
  for (std::size_t j = 0; j < node.ids.size(); ++j)
    node.local.col(static_cast<Index>(j)) =
      basis.transpose() * (V.row(node.ids[j]).transpose() - origin);
  nodes.push_back(std::move(node));
  const int index = static_cast<int>(nodes.size()) - 1;
  build_planes(index);
  return index;
}

// The planes of a node and, recursively, their faces. The combinatorial hull comes from CGAL
// (exact predicates); each face's control set is every control within tol of its plane, and
// the plane is refitted through the best-conditioned triple of that set, so slivers of nearly
// coplanar controls neither give inaccurate normals nor duplicate faces.
void CelestialCoordinates::Impl::build_planes(int index)
{
  const int k = nodes[static_cast<std::size_t>(index)].dim;
  if (k == 0)
    return;
  const Eigen::MatrixXd L = nodes[static_cast<std::size_t>(index)].local; // copy: nodes grows
  const std::vector<Index> ids = nodes[static_cast<std::size_t>(index)].ids;
  const Eigen::VectorXd origin = nodes[static_cast<std::size_t>(index)].origin;
  const Eigen::MatrixXd basis = nodes[static_cast<std::size_t>(index)].basis;
  const Index m = L.cols();

  std::vector<Eigen::VectorXd> normals;
  std::vector<double> offsets;
  std::vector<std::vector<Index>> face_ids; // positions into ids
  auto on_plane = [&](const Eigen::VectorXd& n, double o) {
    std::vector<Index> on;
    for (Index j = 0; j < m; ++j)
      if (std::abs(n.dot(L.col(j)) - o) <= tol)
        on.push_back(j);
    return on;
  };
  auto add_plane = [&](Eigen::VectorXd n, double o, std::vector<Index> on) {
    for (const auto& f : face_ids)
      if (f == on)
        return;
    normals.push_back(std::move(n));
    offsets.push_back(o);
    face_ids.push_back(std::move(on));
  };

  if (k == 1)
  {
    Index lo = 0, hi = 0;
    for (Index j = 1; j < m; ++j)
    {
      if (L(0, j) < L(0, lo))
        lo = j;
      if (L(0, j) > L(0, hi))
        hi = j;
    }
    add_plane(Eigen::VectorXd::Constant(1, 1.0), L(0, hi), { hi });
    add_plane(Eigen::VectorXd::Constant(1, -1.0), -L(0, lo), { lo });
  }
  else if (k == 2)
  {
    std::vector<std::array<double, 2>> pts;
    for (Index j = 0; j < m; ++j)
      pts.push_back({ L(0, j), L(1, j) });
    const std::vector<int> hull = detail::convex_hull_2d(pts); // counterclockwise
    for (std::size_t e = 0; e < hull.size(); ++e)
    {
      const Eigen::Vector2d a = L.col(hull[e]);
      const Eigen::Vector2d b = L.col(hull[(e + 1) % hull.size()]);
      Eigen::VectorXd n(2);
      n << b.y() - a.y(), a.x() - b.x(); // outward for a counterclockwise polygon
      n.normalize();
      const double o = n[0] * a.x() + n[1] * a.y();
      add_plane(n, o, on_plane(n, o));
    }
  }
  else
  {
    std::vector<std::array<double, 3>> pts;
    for (Index j = 0; j < m; ++j)
      pts.push_back({ L(0, j), L(1, j), L(2, j) });
    const std::vector<std::array<int, 3>> hull = detail::convex_hull_3d(pts);
    const Eigen::Vector3d centroid = L.rowwise().mean();
    for (const std::array<int, 3>& t : hull)
    {
      const Eigen::Vector3d a = L.col(t[0]), b = L.col(t[1]), cc = L.col(t[2]);
      Eigen::Vector3d n = (b - a).cross(cc - a).normalized();
      std::vector<Index> on = on_plane(n, n.dot(a));
      // refit: a far pair of the set (the farthest from its first control), then the control
      // farthest from their line
      Index i0 = on.front(), i1 = on.front(), i2 = on.front();
      double best = -1.0;
      for (Index j : on)
        if ((L.col(j) - L.col(i0)).squaredNorm() > best)
        {
          best = (L.col(j) - L.col(i0)).squaredNorm();
          i1 = j;
        }
      const Eigen::Vector3d u = (L.col(i1) - L.col(i0)).normalized();
      best = -1.0;
      for (Index j : on)
      {
        const Eigen::Vector3d w = L.col(j) - L.col(i0);
        const double dist2 = (w - w.dot(u) * u).squaredNorm();
        if (dist2 > best)
        {
          best = dist2;
          i2 = j;
        }
      }
      if (best <= tol * tol)
        continue; // a sliver of nearly collinear controls: its neighbours bound the hull there
      const Eigen::Vector3d p0 = L.col(i0), p1 = L.col(i1), p2 = L.col(i2);
      Eigen::Vector3d nf = (p1 - p0).cross(p2 - p0).normalized();
      if (nf.dot(centroid - p0) > 0.0)
        nf = -nf;
      const double o = nf.dot(p0);
      add_plane(Eigen::VectorXd(nf), o, on_plane(nf, o));
    }
  }

  // Faces: one node each, coordinates orthonormal within the plane.
  std::vector<int> children;
  for (std::size_t f = 0; f < normals.size(); ++f)
  {
    std::vector<Index> child_ids;
    for (Index j : face_ids[f])
      child_ids.push_back(ids[static_cast<std::size_t>(j)]);
    const Eigen::VectorXd x0 = L.col(face_ids[f].front());
    const Eigen::VectorXd child_origin = origin + basis * x0;
    Eigen::MatrixXd local_basis(k, k - 1); // within this node's coordinates
    if (k == 2)
      local_basis << -normals[f][1], normals[f][0];
    else if (k == 3)
      local_basis = complement_basis(Eigen::Vector3d(normals[f]));
    children.push_back(add_node(k - 1, std::move(child_ids), child_origin, basis * local_basis));
  }
  HullNode& node = nodes[static_cast<std::size_t>(index)];
  node.normals.resize(k, static_cast<Index>(normals.size()));
  node.offsets.resize(static_cast<Index>(normals.size()));
  for (std::size_t f = 0; f < normals.size(); ++f)
  {
    node.normals.col(static_cast<Index>(f)) = normals[f];
    node.offsets[static_cast<Index>(f)] = offsets[f];
  }
  node.children = std::move(children);
}

void CelestialCoordinates::Impl::validate()
{
  const CelestialOptions& o = options;
  auto bad = [](const std::string& what) { throw Error(ErrorCode::InvalidArgument, what); };
  if (!(o.lambda > 1.0 && o.lambda <= 1e6))
    bad("lambda must lie in (1, 1e6] (the wrapping sphere must contain the unit sphere, "
        "Sect. 5), got " +
      detail::format_number(o.lambda, 3));
  if (!(o.tolerance >= 1e-15 && o.tolerance <= 1e-3))
    bad("tolerance must lie in [1e-15, 1e-3], got " + detail::format_number(o.tolerance, 3));
  if (o.max_iterations < 1 || o.max_iterations > 10000)
    bad("max_iterations must lie in [1, 10000], got " + std::to_string(o.max_iterations));
  if (!(o.boundary_tolerance >= 1e-15 && o.boundary_tolerance <= 1e-6))
    bad("boundary_tolerance must lie in [1e-15, 1e-6], got " + detail::format_number(o.boundary_tolerance, 3));
  if (o.threads < 0)
    bad("threads must be >= 0 (0 = OpenMP's default), got " + std::to_string(o.threads));

  const Index n = V.rows();
  if (n == 0)
    throw Error(ErrorCode::EmptyInput, "there are no control points");
  if (V.cols() != 2 && V.cols() != 3)
    throw Error(ErrorCode::SizeMismatch,
      "control points must have 2 or 3 coordinates, got " + std::to_string(V.cols()));
  dim = static_cast<int>(V.cols());
  for (Index i = 0; i < n; ++i)
    if (!V.row(i).allFinite())
      throw Error(ErrorCode::NonFinite,
        "control point " + std::to_string(i) + " has a non-finite coordinate " + detail::format_row(V, i));

  if (o.hull_points != CelestialHullPoints::None && o.hull_points != CelestialHullPoints::Auto &&
    o.hull_points != CelestialHullPoints::Always)
    bad("CelestialOptions::hull_points must be None, Auto or Always");
  if (!(o.hull_margin >= 1e-6 && o.hull_margin <= 10.0))
    bad("hull_margin must lie in [1e-6, 10] (relative to the diagonal of the box around the "
        "points and the controls; > 0 so that every point is strictly inside the added hull "
        "points), got " + detail::format_number(o.hull_margin, 3));
  const bool auto_hull = o.hull_points != CelestialHullPoints::None;
  if (o.user_weights.size() != 0)
  {
    if (o.scheme != CelestialScheme::T)
      bad("user_weights are the s_i of the T scheme (Eq. 8); the S scheme has none: leave "
          "user_weights empty or choose CelestialScheme::T");
    if (o.user_weights.size() != n)
      throw Error(ErrorCode::SizeMismatch,
        "user_weights has " + std::to_string(o.user_weights.size()) + " entries but there are " +
          std::to_string(n) + " control points (one each)");
    for (Index i = 0; i < n; ++i)
      if (!std::isfinite(o.user_weights[i]))
        throw Error(ErrorCode::NonFinite, "user weight " + std::to_string(i) + " is not finite");
      else if (o.user_weights[i] < 0.0)
        bad("user weight " + std::to_string(i) + " is " + detail::format_number(o.user_weights[i], 3) +
          "; the s_i of Eq. (8) must be >= 0");
    if (o.user_weights.cwiseAbs().maxCoeff() > 0.0)
      s.assign(o.user_weights.data(), o.user_weights.data() + n);
  }

  if (n < dim + 1 && !auto_hull)
    bad(std::to_string(dim) + "D celestial coordinates need at least " + std::to_string(dim + 1) +
      " control points, got " + std::to_string(n) + " (their convex hull must have an interior)");

  diameter = (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm();
  tol = o.boundary_tolerance * diameter;

  // Coincident controls: sweep in x, report the lexicographically smallest pair.
  {
    std::vector<Index> by_x(static_cast<std::size_t>(n));
    std::iota(by_x.begin(), by_x.end(), Index(0));
    std::sort(by_x.begin(), by_x.end(),
      [&](Index a, Index b) { return V(a, 0) < V(b, 0) || (V(a, 0) == V(b, 0) && a < b); });
    std::pair<Index, Index> first{ -1, -1 };
    for (std::size_t a = 0; a < by_x.size(); ++a)
      for (std::size_t b = a + 1; b < by_x.size() && V(by_x[b], 0) - V(by_x[a], 0) <= tol; ++b)
        if ((V.row(by_x[a]) - V.row(by_x[b])).norm() <= tol)
        {
          const std::pair<Index, Index> pr{ std::min(by_x[a], by_x[b]),
            std::max(by_x[a], by_x[b]) };
          if (first.first < 0 || pr < first)
            first = pr;
        }
    if (first.first >= 0)
      bad("control points " + std::to_string(first.first) + " and " + std::to_string(first.second) +
        " coincide at " + detail::format_row(V, first.first) + " (distance " +
        detail::format_number((V.row(first.first) - V.row(first.second)).norm(), 3) +
        " <= boundary_tolerance * diagonal = " + detail::format_number(tol, 3) + "); remove one of them");
  }
  if (n < dim + 1)
  {
    flat = true; // auto_hull: the hull points give the interior
    return;
  }

  // Affine rank: control 0, the farthest from it, the farthest from their line (and from
  // their plane in 3D).
  {
    Index i1 = 0;
    (V.rowwise() - V.row(0)).rowwise().squaredNorm().maxCoeff(&i1);
    const Eigen::VectorXd u = (V.row(i1) - V.row(0)).transpose().normalized();
    Index i2 = 0;
    double d2 = -1.0;
    for (Index i = 0; i < n; ++i)
    {
      const Eigen::VectorXd w = (V.row(i) - V.row(0)).transpose();
      const double d = (w - w.dot(u) * u).norm();
      if (d > d2)
      {
        d2 = d;
        i2 = i;
      }
    }
    if (d2 <= tol && auto_hull)
    {
      flat = true;
      return;
    }
    if (d2 <= tol)
      bad("the control points are collinear (all within " + detail::format_number(d2, 3) +
        " of the line through control points 0 and " + std::to_string(i1) +
        "): their convex hull has no interior; add a control point off that line");
    if (dim == 3)
    {
      const Eigen::Vector3d a = V.row(0), b = V.row(i1), c = V.row(i2);
      const Eigen::Vector3d nrm = (b - a).cross(c - a).normalized();
      double d3 = 0.0;
      for (Index i = 0; i < n; ++i)
        d3 = std::max(d3, std::abs(nrm.dot(Eigen::Vector3d(V.row(i)) - a)));
      if (d3 <= tol && auto_hull)
      {
        flat = true;
        return;
      }
      if (d3 <= tol)
        bad("the control points are coplanar (all within " + detail::format_number(d3, 3) +
          " of the plane through control points 0, " + std::to_string(i1) + " and " +
          std::to_string(i2) +
          "): their convex hull has no interior; add a control point off "
          "that plane");
    }
  }
}

void CelestialCoordinates::Impl::build_hull()
{
  if (flat)
    return;
  std::vector<Index> ids(static_cast<std::size_t>(V.rows()));
  std::iota(ids.begin(), ids.end(), Index(0));
  // local origin at the bounding-box centre: plane offsets stay small, distances accurate
  const Eigen::VectorXd centre =
    0.5 * (V.colwise().maxCoeff() + V.colwise().minCoeff()).transpose();
  add_node(dim, std::move(ids), centre, Eigen::MatrixXd::Identity(dim, dim));
}

CelestialLocation CelestialCoordinates::Impl::classify(const double* p) const
{
  const Index n = V.rows();
  const double tol2 = tol * tol;
  // the nearest control's squared distance, without an early exit (so that it vectorizes)
  const double* v0 = V.col(0).data();
  const double* v1 = V.col(1).data();
  const double* v2 = V.col(dim > 2 ? 2 : 1).data();
  const double p2 = dim > 2 ? p[2] : 0.0;
  double nearest = std::numeric_limits<double>::infinity();
#pragma omp simd reduction(min : nearest)
  for (Index i = 0; i < n; ++i)
  {
    const double e0 = v0[i] - p[0], e1 = v1[i] - p[1], e2 = dim > 2 ? v2[i] - p2 : 0.0;
    nearest = std::min(nearest, e0 * e0 + e1 * e1 + e2 * e2);
  }
  if (nearest <= tol2)
    return CelestialLocation::AtControl;
  // the root's basis is the identity: local coordinates are p - origin
  const HullNode& root = nodes.front();
  double x[3] = { 0.0, 0.0, 0.0 };
  for (int k = 0; k < dim; ++k)
    x[k] = p[k] - root.origin[k];
  double s = -std::numeric_limits<double>::infinity();
  const double* nrm = root.normals.data();
  for (Index f = 0, nf = root.normals.cols(); f < nf; ++f, nrm += dim)
  {
    double d = -root.offsets[f];
    for (int k = 0; k < dim; ++k)
      d += nrm[k] * x[k];
    s = std::max(s, d);
  }
  if (s > tol)
    return CelestialLocation::Outside;
  return s >= -tol ? CelestialLocation::Boundary : CelestialLocation::Inside;
}

// The coordinates of a point within tol of the boundary of node `index`'s face, or in it:
// descend to the face p lies on (preferring one whose own bounds contain p's projection), then
// solve the same scheme with that face's controls in its own coordinates. Writes the weights
// of the face's controls into w (the others are left untouched: the caller zeroes the row).
SolveStats CelestialCoordinates::Impl::solve_on_face(int index, const double* p, double* w) const
{
  const HullNode* node = &nodes[static_cast<std::size_t>(index)];
  Eigen::VectorXd x = to_local(*node, p);
  for (;;)
  {
    if (node->dim == 0)
    {
      w[node->ids.front()] = 1.0;
      return { 0, 0.0, true };
    }
    for (std::size_t j = 0; j < node->ids.size(); ++j)
      if ((node->local.col(static_cast<Index>(j)) - x).norm() <= tol)
      {
        w[node->ids[j]] = 1.0;
        return { 0, 0.0, true };
      }
    int arg;
    const double smax = max_plane_distance(*node, x, &arg);
    if (smax < -tol)
      break; // interior of this face
    int next = node->children[static_cast<std::size_t>(arg)];
    for (Index k = 0; k < node->normals.cols(); ++k)
    {
      if (node->normals.col(k).dot(x) - node->offsets[k] < -tol)
        continue;
      const HullNode& child =
        nodes[static_cast<std::size_t>(node->children[static_cast<std::size_t>(k)])];
      int a2;
      if (child.dim == 0 || max_plane_distance(child, to_local(child, p), &a2) <= tol)
      {
        next = node->children[static_cast<std::size_t>(k)];
        break;
      }
    }
    node = &nodes[static_cast<std::size_t>(next)];
    x = to_local(*node, p);
  }

  // Solve in the face.
  const int k = node->dim;
  const Index m = static_cast<Index>(node->ids.size()), ld = padded(m);
  std::vector<double> q(static_cast<std::size_t>(k * ld)), inv_d(static_cast<std::size_t>(m)), sf,
    beta(static_cast<std::size_t>(m)), scratch(static_cast<std::size_t>(6 * ld));
  for (Index j = 0; j < m; ++j)
  {
    const Eigen::VectorXd e = node->local.col(j) - x;
    const double d = e.norm();
    inv_d[static_cast<std::size_t>(j)] = 1.0 / d;
    for (int c = 0; c < k; ++c)
      q[static_cast<std::size_t>(c * ld + j)] = e[c] / d;
  }
  if (!s.empty())
    for (Index id : node->ids)
      sf.push_back(s[static_cast<std::size_t>(id)]);
  const double* sp = sf.empty() ? nullptr : sf.data();
  SolveStats stats;
  auto run = [&](auto tag) {
    constexpr int K = decltype(tag)::value;
    Newton<K> newton(options.scheme, q.data(), sp, m, scratch.data());
    typename Newton<K>::Vec y = newton.cold_start(options.lambda);
    stats = newton.solve(y, options.tolerance, options.max_iterations);
    std::copy(newton.beta(), newton.beta() + m, beta.begin());
  };
  if (k == 1)
    run(std::integral_constant<int, 1>{});
  else if (k == 2)
    run(std::integral_constant<int, 2>{});
  else
    run(std::integral_constant<int, 3>{});
  double sum = 0.0;
  for (Index j = 0; j < m; ++j)
    sum += beta[static_cast<std::size_t>(j)] * inv_d[static_cast<std::size_t>(j)];
  for (Index j = 0; j < m; ++j)
    w[node->ids[static_cast<std::size_t>(j)]] =
      beta[static_cast<std::size_t>(j)] * inv_d[static_cast<std::size_t>(j)] / sum;
  return stats;
}

// ------------------------------------------------------------------------------------------

CelestialCoordinates::CelestialCoordinates(Points controls, const CelestialOptions& options)
  : impl_(std::make_unique<Impl>())
{
  impl_->V = std::move(controls);
  impl_->options = options;
  impl_->validate();
  impl_->build_hull();
}

CelestialCoordinates::~CelestialCoordinates() = default;
CelestialCoordinates::CelestialCoordinates(CelestialCoordinates&&) noexcept = default;
CelestialCoordinates& CelestialCoordinates::operator=(CelestialCoordinates&&) noexcept = default;

Index CelestialCoordinates::num_controls() const noexcept
{
  return impl_->V.rows();
}
int CelestialCoordinates::dimension() const noexcept
{
  return impl_->dim;
}
const Points& CelestialCoordinates::controls() const noexcept
{
  return impl_->V;
}
const CelestialOptions& CelestialCoordinates::options() const noexcept
{
  return impl_->options;
}
Index CelestialCoordinates::num_hull_facets() const noexcept
{
  return impl_->nodes.empty() ? 0 : impl_->nodes.front().normals.cols();
}

Points CelestialCoordinates::hull_points_for(const Points& X) const
{
  if (X.cols() != impl_->dim)
    throw Error(ErrorCode::SizeMismatch,
      "the points have " + std::to_string(X.cols()) + " coordinates but the control points have " +
        std::to_string(impl_->dim));
  if (!X.allFinite())
    throw Error(ErrorCode::NonFinite, "the points have a non-finite coordinate");
  return impl_->hull_points_for(X);
}

Points CelestialCoordinates::Impl::hull_points_for(const Points& X) const
{
  // A frame from the points alone (the controls, then X), so that the corners rotate,
  // translate and scale with them: see the header.
  const Index nv = V.rows(), n = nv + X.rows();
  const auto point = [&](Index i) -> Eigen::RowVectorXd { return i < nv ? V.row(i) : X.row(i - nv); };
  Eigen::RowVectorXd c = V.colwise().sum();
  if (X.rows() > 0)
    c += X.colwise().sum();
  c /= static_cast<double>(n);
  Eigen::MatrixXd P(n, dim); // centred
  for (Index i = 0; i < n; ++i)
    P.row(i) = point(i) - c;
  // The lowest index whose squared residual is within a relative 1e-9 of the largest.
  const auto farthest = [&](const Eigen::VectorXd& r2, double* largest) {
    *largest = r2.maxCoeff();
    Index i = 0;
    while (r2[i] < (1.0 - 1e-9) * *largest)
      ++i;
    return i;
  };
  double r_max = 0.0;
  const Index i1 = farthest(P.rowwise().squaredNorm(), &r_max);
  if (!(r_max > 0.0))
    throw Error(ErrorCode::InvalidArgument,
      "the control points and the points all coincide at " + detail::format_row(V, 0) +
        ": no hull points can be placed around them");
  Eigen::MatrixXd E(dim, dim); // columns: the axes
  E.col(0) = P.row(i1).transpose() / std::sqrt(r_max);
  if (dim == 2)
    E.col(1) << -E(1, 0), E(0, 0);
  else
  {
    const Eigen::MatrixXd R = P - (P * E.col(0)) * E.col(0).transpose(); // off the line
    double d_max = 0.0;
    const Index i2 = farthest(R.rowwise().squaredNorm(), &d_max);
    Eigen::Vector3d e2;
    if (d_max > 1e-24 * r_max)
      e2 = R.row(i2).transpose();
    else
    {
      // all on one line: no direction off it to take from the points
      Eigen::Index axis = 0;
      E.col(0).cwiseAbs().minCoeff(&axis);
      e2 = Eigen::Vector3d::Unit(axis) - E(axis, 0) * Eigen::Vector3d(E.col(0));
    }
    E.col(1) = e2.normalized();
    E.col(2) = Eigen::Vector3d(E.col(0)).cross(Eigen::Vector3d(E.col(1)));
  }
  const Eigen::MatrixXd T = P * E; // coordinates in the frame
  Eigen::RowVectorXd lo = T.colwise().minCoeff(), hi = T.colwise().maxCoeff();
  const double pad = options.hull_margin * (hi - lo).norm();
  lo.array() -= pad;
  hi.array() += pad;
  const Index corners = Index(1) << dim;
  Points H(corners, dim);
  for (Index k = 0; k < corners; ++k)
  {
    Eigen::VectorXd t(dim);
    for (int j = 0; j < dim; ++j)
      t[j] = (k >> j) & 1 ? hi[j] : lo[j];
    H.row(k) = c + (E * t).transpose();
  }
  return H;
}

namespace
{

/// First-order prediction of a neighbour's solution (the kernels' path, S scheme): at a
/// solved point p with solution y, F(p, y) = 0 gives dy/dp = -J^-1 dF/dp, and with
/// dq_i/dp = -(I - q_i q_i^T) / d_i, -dF/dp = B = g y^T + s I - M (sums of scc_finish_avx2).
/// A neighbour p' starts from y + J^-1 B (p' - p) instead of y (the error of the start drops
/// from O(h) to O(h^2), h = |p' - p|): 2.47 Newton iterations a point instead of 3.38 on the
/// benchmark's 1e6 random points. The solution it converges to is the same (to the
/// tolerance): only the start moves.
template<int D>
struct Predictor
{
  Eigen::Matrix<double, D, D> B, J;
  Eigen::Matrix<double, D, 1> p; // where it was taken
  bool valid = false;
};

/// The solve of the Inside points of one chunk, for a fixed dimension.
template<int D>
struct ChunkSolver
{
  using Vec = typename Newton<D>::Vec;
  const Points& V;
  const CelestialOptions& options;
  const double* s; // user weights or nullptr
  const Index ld;   // padded(#C)
  const bool avx2;  // directions_avx2, weights_avx2 and (S scheme) scc_finish_avx2
  std::vector<double> v, q, inv_d, scratch; // v: the controls as D padded rows (AVX2)

  ChunkSolver(const Points& V_, const CelestialOptions& options_, const double* s_)
    : V(V_)
    , options(options_)
    , s(s_)
    , ld(padded(V_.rows()))
    , avx2(use_avx2())
    , v(static_cast<std::size_t>(D * ld), 0.0)
    , q(static_cast<std::size_t>(D * ld), 0.0)
    , inv_d(static_cast<std::size_t>(ld), 0.0)
    , scratch(static_cast<std::size_t>(6 * ld), 0.0)
  {
    for (int k = 0; k < D; ++k)
      for (Index i = 0; i < V.rows(); ++i)
        v[static_cast<std::size_t>(k * ld + i)] = V(i, k);
  }

  /// Solves the point x (D coordinates) from *warm (or cold if null), moved by *predict when
  /// that is given and valid; writes its row of W into w on success, y (the Newton unknown)
  /// and (S scheme, kernels' path) *made, the prediction from x's solution for its neighbours
  /// (else made->valid = false).
  /// Returns the stats of the last attempt; total counts every iteration.
  SolveStats solve(const double* x, const Vec* warm, Vec& y, double* w, long long& total,
    bool& restarted, const Predictor<D>* predict = nullptr, Predictor<D>* made = nullptr)
  {
    if (made != nullptr)
      made->valid = false;
    const Index n = V.rows();
    double* qd = q.data();
    double* id = inv_d.data();
#if BARY_HAVE_AVX2_DISPATCH
    if (avx2)
      directions_avx2<D>(v.data(), n, ld, x, qd, id);
    else
#endif
    {
      const double* vc[3] = { V.col(0).data(), V.col(D > 1 ? 1 : 0).data(),
        V.col(D > 2 ? 2 : 0).data() };
      const Index stride = ld;
#pragma omp simd
      for (Index i = 0; i < n; ++i)
      {
        double e[D], d2 = 0.0;
        for (int k = 0; k < D; ++k)
        {
          e[k] = vc[k][i] - x[k];
          d2 += e[k] * e[k];
        }
        const double inv = 1.0 / std::sqrt(d2);
        id[i] = inv;
        for (int k = 0; k < D; ++k)
          qd[k * stride + i] = e[k] * inv;
      }
    }
    Newton<D> newton(options.scheme, qd, s, n, scratch.data());
    restarted = false;
    SolveStats stats;
    if (warm != nullptr)
    {
      y = *warm;
      bool predicted = false;
      if (predict != nullptr && predict->valid)
      {
        Vec dp;
        for (int k = 0; k < D; ++k)
          dp[k] = x[k] - predict->p[k];
        const Vec dy = solve_spd_ldlt<D>(predict->J, Vec(predict->B * dp));
        predicted = dy.allFinite();
        if (predicted)
          y += dy;
      }
      stats = newton.solve(y, options.tolerance, options.max_iterations, predicted ? warm : nullptr);
      total += stats.iterations;
      restarted = !stats.converged;
    }
    if (warm == nullptr || restarted)
    {
      y = newton.cold_start(options.lambda);
      stats = newton.solve(y, options.tolerance, options.max_iterations);
      total += stats.iterations;
    }
    if (!stats.converged)
      return stats;
    const double* beta = newton.beta();
#if BARY_HAVE_AVX2_DISPATCH
    if (avx2 && made != nullptr && options.scheme == CelestialScheme::S)
    {
      double sums[12];
      scc_finish_avx2<D>(qd, n, ld, y.data(), beta, newton.slope(), id, w, sums);
      const Eigen::Map<const Vec> g(sums + 1);
      Eigen::Matrix<double, D, D> M; // sums: s, g_0..g_2, M_00, M_01, M_02, M_11, M_12, M_22
      M(0, 0) = sums[4];
      if constexpr (D > 1)
      {
        M(0, 1) = M(1, 0) = sums[5];
        M(1, 1) = sums[7];
      }
      if constexpr (D > 2)
      {
        M(0, 2) = M(2, 0) = sums[6];
        M(1, 2) = M(2, 1) = sums[8];
        M(2, 2) = sums[9];
      }
      made->B = g * y.transpose() - M;
      made->B.diagonal().array() += sums[0];
      made->J = newton.jacobian();
      for (int k = 0; k < D; ++k)
        made->p[k] = x[k];
      made->valid = made->B.allFinite() && made->J.allFinite();
      return stats;
    }
    if (avx2)
    {
      weights_avx2(beta, id, n, ld, w);
      return stats;
    }
#endif
    double sum = 0.0;
    for (Index i = 0; i < n; ++i)
      sum += beta[i] * id[i];
    const double inv = 1.0 / sum;
    for (Index i = 0; i < n; ++i)
      w[i] = beta[i] * id[i] * inv;
    return stats;
  }
};

} // namespace

namespace
{
/// Input checks of compute(): @p X is #P by @p dim and finite, @p edges #E by 2 within [0, #P).
void check_query(const Points& X, const Eigen::MatrixXi& edges, int dim)
{
  const Index np = X.rows();
  if (X.cols() != dim)
    throw Error(ErrorCode::SizeMismatch,
      "the points have " + std::to_string(X.cols()) +
        " coordinates but the control points have " + std::to_string(dim));
  for (Index p = 0; p < np; ++p)
    if (!X.row(p).allFinite())
      throw Error(ErrorCode::NonFinite,
        "point " + std::to_string(p) + " has a non-finite coordinate " + detail::format_row(X, p));
  if (edges.size() != 0)
  {
    if (edges.cols() != 2)
      throw Error(ErrorCode::SizeMismatch,
        "edges must be #E by 2 (vertex pairs), got " + std::to_string(edges.cols()) + " columns");
    for (Index e = 0; e < edges.rows(); ++e)
      for (int k = 0; k < 2; ++k)
        if (edges(e, k) < 0 || edges(e, k) >= np)
          throw Error(ErrorCode::InvalidArgument,
            "edge " + std::to_string(e) + " refers to point " + std::to_string(edges(e, k)) +
              " but there are " + std::to_string(np) + " points");
  }
}

/// The points' neighbours from the mesh @p edges (self-loops dropped), compressed: the
/// neighbours of p are adj[adj_start[p] .. adj_start[p + 1]).
void point_graph(
  const Eigen::MatrixXi& edges, Index np, std::vector<Index>& adj_start, std::vector<Index>& adj)
{
  adj_start.assign(static_cast<std::size_t>(np + 1), 0);
  for (Index e = 0; e < edges.rows(); ++e)
    if (edges(e, 0) != edges(e, 1))
    {
      ++adj_start[static_cast<std::size_t>(edges(e, 0)) + 1];
      ++adj_start[static_cast<std::size_t>(edges(e, 1)) + 1];
    }
  std::partial_sum(adj_start.begin(), adj_start.end(), adj_start.begin());
  adj.resize(static_cast<std::size_t>(adj_start.back()));
  std::vector<Index> fill(adj_start.begin(), adj_start.end() - 1);
  for (Index e = 0; e < edges.rows(); ++e)
    if (edges(e, 0) != edges(e, 1))
    {
      adj[static_cast<std::size_t>(fill[static_cast<std::size_t>(edges(e, 0))]++)] = edges(e, 1);
      adj[static_cast<std::size_t>(fill[static_cast<std::size_t>(edges(e, 1))]++)] = edges(e, 0);
    }
}

/// Breadth-first order over the graph (adj_start, adj), the neighbours of a point nearest first
/// (Sect. 4.2), a new search started from each not yet visited point of @p seeds in turn.
std::vector<Index> breadth_first_order(const std::vector<Index>& seeds,
  const std::vector<Index>& adj_start, const std::vector<Index>& adj,
  const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>& X)
{
  const Index np = X.rows();
  std::vector<char> seen(static_cast<std::size_t>(np), 0);
  std::vector<Index> bfs;
  bfs.reserve(static_cast<std::size_t>(np));
  std::vector<std::pair<double, Index>> next;
  for (Index seed : seeds)
  {
    if (seen[static_cast<std::size_t>(seed)])
      continue;
    seen[static_cast<std::size_t>(seed)] = 1;
    std::size_t head = bfs.size();
    bfs.push_back(seed);
    while (head < bfs.size())
    {
      const Index u = bfs[head++];
      next.clear();
      for (Index a = adj_start[static_cast<std::size_t>(u)];
           a < adj_start[static_cast<std::size_t>(u) + 1]; ++a)
      {
        const Index v = adj[static_cast<std::size_t>(a)];
        if (!seen[static_cast<std::size_t>(v)])
        {
          seen[static_cast<std::size_t>(v)] = 1;
          next.emplace_back((X.row(v) - X.row(u)).squaredNorm(), v);
        }
      }
      std::sort(next.begin(), next.end());
      for (const auto& [dist, v] : next)
        bfs.push_back(v);
    }
  }
  return bfs;
}

/// The fields CelestialResult shares with every method (see its comment), from its own.
void fill_weights_result(CelestialResult& result, Index hull_facets)
{
  const std::size_t np = result.hull_location.size();
  result.location.resize(np);
  for (std::size_t p = 0; p < np; ++p)
  {
    const CelestialLocation where = result.hull_location[p];
    result.location[p] = where == CelestialLocation::Inside ? PointLocation::Inside
      : where == CelestialLocation::Outside                 ? PointLocation::Outside
                                                            : PointLocation::Boundary;
  }
  result.undefined = result.outside;
  result.undefined.insert(
    result.undefined.end(), result.not_converged.begin(), result.not_converged.end());
  std::sort(result.undefined.begin(), result.undefined.end());
  result.converged = result.not_converged.empty();
  double max_residual = 0.0;
  for (Index p = 0; p < result.residual.size(); ++p)
    if (std::isfinite(result.residual(p)))
      max_residual = std::max(max_residual, result.residual(p));
  Statistics& st = result.statistics;
  st.clear();
  st.emplace_back("hull_facets", static_cast<double>(hull_facets));
  st.emplace_back("newton_iterations", static_cast<double>(result.total_iterations));
  st.emplace_back("mean_newton_iterations",
    np > 0 ? static_cast<double>(result.total_iterations) / static_cast<double>(np) : 0.0);
  st.emplace_back(
    "max_newton_iterations", result.iterations.size() > 0 ? result.iterations.maxCoeff() : 0);
  st.emplace_back("warm_starts", static_cast<double>(result.warm_starts));
  st.emplace_back("cold_restarts", static_cast<double>(result.cold_restarts));
  st.emplace_back("max_residual", max_residual);
  st.emplace_back("at_control", static_cast<double>(result.at_control));
  st.emplace_back("not_converged", static_cast<double>(result.not_converged.size()));
  st.emplace_back("solve_seconds", result.seconds);
  st.emplace_back("hull_points_added", static_cast<double>(result.added_controls.rows())); // last
}
} // namespace

CelestialResult CelestialCoordinates::compute(
  const Points& X, const ProgressCallback& progress) const
{
  return impl_->compute(X, Eigen::MatrixXi(0, 2), nullptr, progress);
}

CelestialResult CelestialCoordinates::compute(
  const Points& X, const Eigen::MatrixXi& edges, const ProgressCallback& progress) const
{
  return impl_->compute(X, edges, nullptr, progress);
}

void CelestialCoordinates::compute(
  const Points& X, CelestialResult& result, const ProgressCallback& progress) const
{
  // (Impl::compute checks X before it takes result's storage)
  result = impl_->compute(X, Eigen::MatrixXi(0, 2), nullptr, progress, &result);
}

CelestialResult CelestialCoordinates::compute_from(
  const Points& X, const Points& initial, const ProgressCallback& progress) const
{
  if (initial.rows() != X.rows() || initial.cols() != impl_->dim)
    throw Error(ErrorCode::SizeMismatch,
      "the initial solutions are " + std::to_string(initial.rows()) + " by " +
        std::to_string(initial.cols()) + " but there are " + std::to_string(X.rows()) +
        " points in " + std::to_string(impl_->dim) + "D (one row each)");
  return impl_->compute(X, Eigen::MatrixXi(0, 2), &initial, progress);
}

CelestialResult CelestialCoordinates::Impl::compute(const Points& Xin,
  const Eigen::MatrixXi& edges, const Points* initial, const ProgressCallback& progress,
  CelestialResult* storage) const
{
  const auto start = std::chrono::steady_clock::now();
  const Impl& im = *this;
  const CelestialOptions& opt = im.options;
  const int dim = im.dim;
  const Index np = Xin.rows(), nc = im.V.rows();
  check_query(Xin, edges, dim);

  // Hull points (§6): the controls and the corners of the enlarged bounding box, solved as one
  // set of controls; the corners' columns last.
  const auto with_hull_points = [&](CelestialResult* from) {
    const Points H = hull_points_for(opt.hull_reference ? *opt.hull_reference : Xin);
    Points all(nc + H.rows(), dim);
    all << V, H;
    CelestialOptions o = opt;
    o.hull_points = CelestialHullPoints::None;
    if (o.user_weights.size() != 0)
    {
      o.user_weights.conservativeResize(all.rows());
      o.user_weights.tail(H.rows()).setZero();
    }
    const CelestialCoordinates augmented(std::move(all), o);
    CelestialResult r = augmented.impl_->compute(Xin, edges, initial, progress, from);
    r.added_controls = H;
    r.statistics.back().second = static_cast<double>(H.rows());
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return r;
  };
  const bool auto_hull = opt.hull_points == CelestialHullPoints::Auto;
  if ((auto_hull && flat) || opt.hull_points == CelestialHullPoints::Always)
    return with_hull_points(storage);

  CelestialResult result;
  if (storage != nullptr)
  { // its arrays' storage, kept where the sizes allow (resize keeps an equal size's storage)
    result.W.swap(storage->W);
    result.hull_location.swap(storage->hull_location);
    result.iterations.swap(storage->iterations);
    result.residual.swap(storage->residual);
    result.solution.swap(storage->solution);
  }
  result.W.resize(np, nc); // every row is written below (a zero fill is a pass over #P x #C)
  detail::advise_huge_pages(result.W.data(), static_cast<std::size_t>(result.W.size()) * sizeof(double));
  // The per-point arrays (60 MB at 10^6 points) in huge pages too: see detail/huge_pages.h.
  const auto advised = [](auto& m) {
    detail::advise_huge_pages(m.data(), static_cast<std::size_t>(m.size()) * sizeof(*m.data()));
  };
  detail::assign_huge(result.hull_location, static_cast<std::size_t>(np), CelestialLocation::Inside);
  // Every entry of these (and every row of W) is written by the solve below.
  result.iterations.resize(np);
  advised(result.iterations);
  result.residual.resize(np);
  advised(result.residual);
  result.solution.resize(np, dim);
  advised(result.solution);
  if (np == 0)
  {
    result.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    fill_weights_result(result, im.facets());
    return result;
  }
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> Xrows(np, dim);
  advised(Xrows);
  Xrows = Xin;
  const auto& X = Xrows;

  const int threads = detail::thread_count(opt.threads);

  // 1. Where each point lies (cheap; before any solve so that an outside point fails fast).
#pragma omp parallel for schedule(static) num_threads(threads) if (np >= 4096)
  for (Index p = 0; p < np; ++p)
    result.hull_location[static_cast<std::size_t>(p)] = im.classify(X.row(p).data());
  if (auto_hull && opt.hull_reference)
  { // the whole's decision (a distributed run's piece): the same columns on every piece
    const Points& R = *opt.hull_reference;
    check_query(R, Eigen::MatrixXi(), dim);
    for (Index p = 0; p < R.rows(); ++p)
    {
      const Eigen::Matrix<double, 1, Eigen::Dynamic> r = R.row(p);
      const CelestialLocation where = im.classify(r.data());
      if (where == CelestialLocation::Outside || where == CelestialLocation::Boundary)
        return with_hull_points(&result);
    }
  }
  else if (auto_hull)
    for (Index p = 0; p < np; ++p)
    {
      const CelestialLocation where = result.hull_location[static_cast<std::size_t>(p)];
      if (where == CelestialLocation::Outside || where == CelestialLocation::Boundary)
        return with_hull_points(&result);
    }
  for (Index p = 0; p < np; ++p)
    if (result.hull_location[static_cast<std::size_t>(p)] == CelestialLocation::Outside)
      result.outside.push_back(p);
  if (!result.outside.empty() && opt.outside == CelestialOutsidePolicy::Error)
  {
    std::string ids;
    for (std::size_t k = 0; k < std::min<std::size_t>(10, result.outside.size()); ++k)
      ids += (k ? ", " : "") + std::to_string(result.outside[k]);
    if (result.outside.size() > 10)
      ids += " and " + std::to_string(result.outside.size() - 10) + " more";
    int arg;
    const double dist = Impl::max_plane_distance(
      im.nodes.front(), im.to_local(im.nodes.front(), X.row(result.outside.front()).data()), &arg);
    throw Error(ErrorCode::PointsOutside,
      std::to_string(result.outside.size()) + " of " + std::to_string(np) +
        " points lie outside the convex hull of the " + std::to_string(nc) +
        " control points (points " + ids + "; point " + std::to_string(result.outside.front()) +
        " is at least " + detail::format_number(dist, 3) +
        " from the hull): celestial coordinates are defined only inside the hull",
      "add control points around the model (the paper adds the corners of a box), or set "
      "hull_points = CelestialHullPoints::Auto (command line: --hull-points auto) to add them, "
      "or outside = CelestialOutsidePolicy::Flag to get NaN rows for them");
  }

  // 2. The order of the warm starts.
  std::vector<Index> order;
  std::vector<Index> position; // position[p] = place of p in order (edges only)
  std::vector<Index> adj_start, adj;
  const bool use_edges = opt.warm_start && edges.rows() > 0;
  if (opt.warm_start)
    order = hilbert_order(Xin, threads);
  else
  {
    order.resize(static_cast<std::size_t>(np));
    std::iota(order.begin(), order.end(), Index(0));
  }
  if (use_edges)
  {
    point_graph(edges, np, adj_start, adj);
    order = breadth_first_order(order, adj_start, adj, X);
    position.resize(static_cast<std::size_t>(np));
    for (Index k = 0; k < np; ++k)
      position[static_cast<std::size_t>(order[static_cast<std::size_t>(k)])] = k;
  }

  // 3. Solve, chunk by chunk. Within a chunk the points are solved in order, each Inside point
  // warm-started from the nearest solved neighbour (edges) or the last solved point (Hilbert)
  // of the same chunk; chunks are independent, so nothing depends on the threads.
  const Index chunks = (np + kChunk - 1) / kChunk;
  ProgressReporter reporter(progress, np);
  long long total_iterations = 0;
  Index warm_starts = 0, cold_restarts = 0;
  const double* s = im.s.empty() ? nullptr : im.s.data();


  auto run = [&](auto tag) {
    constexpr int D = decltype(tag)::value;
    using Vec = typename Newton<D>::Vec;
    // Per thread: its solver, the chunk's solutions (warm starts) and its counts.
    struct ThreadState
    {
      ChunkSolver<D> solver;
      std::vector<Vec> ys;
      std::vector<char> solved;
      std::vector<Predictor<D>> predictors; // of the chunk's solved points (kernels' path)
      // The chunk's rows of W in curve order, copied to W's rows at the chunk's end: written
      // where they are computed, W's rows (in no order, far apart) stalled the kernels' stores.
      std::vector<double> rows;
      // The chunk's iterations, residuals and solutions in curve order (the same reason).
      std::vector<int> its;
      std::vector<double> residuals;
      std::vector<Vec> solutions;
      // The chunk's points and locations in curve order, gathered at its start.
      std::vector<Vec> xs;
      std::vector<CelestialLocation> locs;
      std::vector<Index> failed; // points solved without converging (NaN rows)
      long long iterations = 0;
      Index warm = 0, restarts = 0;
      Vec given = Vec::Zero(); // the start from `initial`
    };
    detail::parallel_for(
      np, kChunk, static_cast<int>(std::min<Index>(threads, chunks)), reporter,
      "celestial coordinates",
      [&] {
        return ThreadState{ ChunkSolver<D>(im.V, opt, s),
          std::vector<Vec>(static_cast<std::size_t>(kChunk)),
          std::vector<char>(static_cast<std::size_t>(kChunk)),
          std::vector<Predictor<D>>(static_cast<std::size_t>(kChunk)),
          std::vector<double>(static_cast<std::size_t>(kChunk * nc)),
          std::vector<int>(static_cast<std::size_t>(kChunk)),
          std::vector<double>(static_cast<std::size_t>(kChunk)),
          std::vector<Vec>(static_cast<std::size_t>(kChunk)),
          std::vector<Vec>(static_cast<std::size_t>(kChunk)),
          std::vector<CelestialLocation>(static_cast<std::size_t>(kChunk)), std::vector<Index>() };
      },
      [&](ThreadState& t, Index begin, Index end) {
        std::fill(t.solved.begin(), t.solved.end(), 0);
        Index last = -1; // last solved position in this chunk
        for (Index k = begin; k < end; ++k) // independent loads, many in flight
        {
          const Index p = order[static_cast<std::size_t>(k)];
          t.locs[static_cast<std::size_t>(k - begin)] = result.hull_location[static_cast<std::size_t>(p)];
          for (int d = 0; d < D; ++d)
            t.xs[static_cast<std::size_t>(k - begin)][d] = X(p, d);
        }
        for (Index k = begin; k < end; ++k)
        {
          const Index p = order[static_cast<std::size_t>(k)];
          const std::size_t at = static_cast<std::size_t>(k - begin);
          double* w = t.rows.data() + (k - begin) * nc;
          int& its = t.its[at];
          double& residual = t.residuals[at];
          Vec& solution = t.solutions[at];
          its = 0;
          residual = kNaN;
          solution.setConstant(kNaN);
          const CelestialLocation loc = t.locs[at];
          const double* x = t.xs[at].data();
          if (loc == CelestialLocation::Outside)
          {
            std::fill(w, w + nc, kNaN);
            continue;
          }
          if (loc != CelestialLocation::Inside)
          {
            std::fill(w, w + nc, 0.0);
            const SolveStats st = im.solve_on_face(0, x, w);
            t.iterations += st.iterations;
            its = st.iterations;
            residual = st.residual;
            if (!st.converged)
              std::fill(w, w + nc, kNaN);
            continue;
          }
          const Vec* warm = nullptr;
          const Predictor<D>* predict = nullptr;
          if (initial != nullptr && initial->row(p).allFinite())
          {
            // psi as given; for SCC y = c / sqrt(lambda^2 + 2 lambda |c|) (the inverse of
            // c = lambda m(|y|) y, see the top of this file)
            for (int d = 0; d < D; ++d)
              t.given[d] = (*initial)(p, d);
            if (opt.scheme == CelestialScheme::S)
              t.given /= std::sqrt(opt.lambda * opt.lambda + 2.0 * opt.lambda * t.given.norm());
            warm = &t.given;
            ++t.warm;
          }
          else if (opt.warm_start)
          {
            Index from = last;
            if (use_edges)
            {
              double best = std::numeric_limits<double>::infinity();
              for (Index a = adj_start[static_cast<std::size_t>(p)];
                   a < adj_start[static_cast<std::size_t>(p) + 1]; ++a)
              {
                const Index v = adj[static_cast<std::size_t>(a)];
                const Index pos = position[static_cast<std::size_t>(v)];
                if (pos < begin || pos >= k || !t.solved[static_cast<std::size_t>(pos - begin)])
                  continue;
                const double d2 = (X.row(v) - X.row(p)).squaredNorm();
                if (d2 < best || (d2 == best && pos < from))
                {
                  best = d2;
                  from = pos;
                }
              }
            }
            if (from >= 0)
            {
              warm = &t.ys[static_cast<std::size_t>(from - begin)];
              predict = &t.predictors[static_cast<std::size_t>(from - begin)];
              ++t.warm;
            }
          }
          Vec& y = t.ys[static_cast<std::size_t>(k - begin)];
          bool restarted = false;
          const SolveStats st = t.solver.solve(x, warm, y, w, t.iterations, restarted, predict,
            &t.predictors[static_cast<std::size_t>(k - begin)]);
          t.restarts += restarted ? 1 : 0;
          its = st.iterations;
          residual = st.residual;
          if (!st.converged)
          {
            std::fill(w, w + nc, kNaN);
            continue;
          }
          t.solved[static_cast<std::size_t>(k - begin)] = 1;
          last = k;
          if (opt.scheme == CelestialScheme::T)
            solution = y;
          else
          {
            // c = lambda m(|y|) y
            const double ny = y.norm();
            const double f = opt.lambda * m_of(ny, std::sqrt(ny * ny + 1.0));
            solution = f * y;
          }
        }
        // The rows to W and the rest to theirs, a few points ahead in flight.
        const auto prefetch_outputs = [&](Index a) {
          prefetch(result.W.row(a).data(), static_cast<std::size_t>(nc) * sizeof(double), true);
          prefetch(&result.iterations[a], sizeof(int), true);
          prefetch(&result.residual[a], sizeof(double), true);
          for (int d = 0; d < D; ++d)
            prefetch(&result.solution(a, d), sizeof(double), true);
        };
        constexpr Index ahead = 8;
        for (Index k = begin; k < std::min(end, begin + ahead); ++k)
          prefetch_outputs(order[static_cast<std::size_t>(k)]);
        for (Index k = begin; k < end; ++k)
        {
          if (k + ahead < end)
            prefetch_outputs(order[static_cast<std::size_t>(k + ahead)]);
          const Index p = order[static_cast<std::size_t>(k)];
          const std::size_t at = static_cast<std::size_t>(k - begin);
          const double* row = t.rows.data() + (k - begin) * nc;
          std::copy(row, row + nc, result.W.row(p).data());
          const CelestialLocation loc = t.locs[at];
          if (loc != CelestialLocation::Outside && std::isnan(row[0]))
            t.failed.push_back(p);
          result.iterations[p] = t.its[at];
          result.residual[p] = loc == CelestialLocation::AtControl ? 0.0 : t.residuals[at];
          for (int d = 0; d < D; ++d)
            result.solution(p, d) = t.solutions[at][d];
        }
      },
      [&](ThreadState& t) {
        total_iterations += t.iterations;
        warm_starts += t.warm;
        cold_restarts += t.restarts;
        result.not_converged.insert(result.not_converged.end(), t.failed.begin(), t.failed.end());
      });
  };
  if (dim == 2)
    run(std::integral_constant<int, 2>{});
  else
    run(std::integral_constant<int, 3>{});

  for (Index p = 0; p < np; ++p)
  {
    const CelestialLocation loc = result.hull_location[static_cast<std::size_t>(p)];
    switch (loc)
    {
      case CelestialLocation::Inside: ++result.inside; break;
      case CelestialLocation::Boundary: ++result.boundary; break;
      case CelestialLocation::AtControl: ++result.at_control; break;
      case CelestialLocation::Outside: break;
    }
  }
  std::sort(result.not_converged.begin(), result.not_converged.end());
  result.total_iterations = total_iterations;
  result.warm_starts = warm_starts;
  result.cold_restarts = cold_restarts;


  if (!result.not_converged.empty() && opt.require_convergence)
  {
    std::string list;
    for (std::size_t k = 0; k < std::min<std::size_t>(10, result.not_converged.size()); ++k)
    {
      const Index p = result.not_converged[k];
      list += (k ? ", " : "") + std::to_string(p) + " (residual " + detail::format_number(result.residual[p], 3) + ")";
    }
    if (result.not_converged.size() > 10)
      list += " and " + std::to_string(result.not_converged.size() - 10) + " more";
    throw Error(ErrorCode::NotConverged,
      std::to_string(result.not_converged.size()) + " of " + std::to_string(np) +
        " points did not converge in " + std::to_string(opt.max_iterations) +
        " Newton iterations to the tolerance " + detail::format_number(opt.tolerance, 3) + ": points " + list +
        ". Raise max_iterations or tolerance, or set require_convergence = false to get NaN "
        "rows and the list in CelestialResult::not_converged");
  }
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  fill_weights_result(result, im.facets());
  return result;
}

CelestialResult celestial_coordinates(const Points& controls, const Points& X,
  const CelestialOptions& options, const ProgressCallback& progress)
{
  return CelestialCoordinates(controls, options).compute(X, progress);
}

} // namespace bary
