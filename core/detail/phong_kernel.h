#pragma once
/// @file detail/phong_kernel.h
/// The per-query kernels of Phong projection (core/surface/phong_projection.h): the projection
/// onto one triangle and the interpolated tangent basis Psi, shared by PhongProjection and the
/// forward and inverse problems (core/surface/weighted_averages.cpp), which inline them into
/// their portable and AVX2 functions (detail/simd.h). No allocation, never throws.
///
/// Every coefficient matrix of Psi on a triangle (v1, v2, v3) is a 2 by 2 matrix times a vertex
/// frame: A1 = M1 T1, A2 = M2 T2, A3 = M3 T2, A4 = M4 T3, A5 = M5 T3, A6 = M6 T1 with
/// M1 = E12 R12, M2 = E12, M3 = E23 R23, M4 = E23, M5 = E31 R31, M6 = E31 (Eq. 11-12), and
/// B = (A1 + ... + A6) / 2. So the R^D work of a query on a triangle is eight dot products
/// (the three frames' rows and the edges e1 = v1 - v3, e2 = v2 - v3 with y - v3), and a triangle
/// stores kPhongData numbers (PhongData); the frames are stored once per vertex (#V by 2 D,
/// row-major: t1 then t2).
///
/// With the rows r = 2 m + i (m = 0..5: A1..A6, i: the row of the matrix) and
/// mu_m = mono_m + mono_6 / 2 (B's monomial a b c shared out), the residual of Eq. (7) before
/// the blend is G = sum_r mu_m(r) C_r (x - y), x the point of the triangle: twelve rows, not
/// fourteen. With w = y - v3 and x - v3 = a e1 + b e2, C_r (x - y) = a C_r e1 + b C_r e2 - C_r w.

#include "core/detail/simd.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace bary::detail
{

inline constexpr int kPhongRows = 12;
inline constexpr int kPhongData = 56;
inline constexpr int kPhongMaxIterations = 30;

/// Offsets into a triangle's kPhongData numbers.
struct PhongData
{
  static constexpr int q1 = 0;      ///< C_r e1, 12 rows
  static constexpr int q2 = 12;     ///< C_r e2
  static constexpr int col0 = 24;   ///< column 0 of M_m, rows 2 m + i: M_m(i, 0)
  static constexpr int col1 = 36;   ///< column 1: M_m(i, 1)
  static constexpr int gram = 48;   ///< G^-1 (00, 01, 11) of e1, e2
  static constexpr int scale = 51;  ///< the longest edge
};

/// Newton's stopping rule (barycentric units). The iteration stops when its last step is below
/// kPhongStepTolerance, or when the step it would take next, predicted from the last two
/// (|step_k|^2 / |step_{k-1}|: Newton's rate, also where convergence is only linear, near a corner
/// of the triangle), is below kPhongPredictedTolerance.
inline constexpr double kPhongStepTolerance = 1e-13;
inline constexpr double kPhongPredictedTolerance = 1e-8;

/// out[0..4) = the sums of the lanes of a, b, c, d: ((lane 0 + lane 1) + (lane 2 + lane 3)).
BARY_ALWAYS_INLINE void lane_sums(const v4d& a, const v4d& b, const v4d& c, const v4d& d, double* out)
{
#if defined(__clang__)
  const v4d ab = __builtin_shufflevector(a, b, 0, 4, 2, 6) + __builtin_shufflevector(a, b, 1, 5, 3, 7);
  const v4d cd = __builtin_shufflevector(c, d, 0, 4, 2, 6) + __builtin_shufflevector(c, d, 1, 5, 3, 7);
  BARY_STORE4(out, __builtin_shufflevector(ab, cd, 0, 1, 4, 5) + __builtin_shufflevector(ab, cd, 2, 3, 6, 7));
#elif defined(__GNUC__)
  typedef long long v4i __attribute__((vector_size(32)));
  const v4d ab = __builtin_shuffle(a, b, v4i{ 0, 4, 2, 6 }) + __builtin_shuffle(a, b, v4i{ 1, 5, 3, 7 });
  const v4d cd = __builtin_shuffle(c, d, v4i{ 0, 4, 2, 6 }) + __builtin_shuffle(c, d, v4i{ 1, 5, 3, 7 });
  BARY_STORE4(out, __builtin_shuffle(ab, cd, v4i{ 0, 1, 4, 5 }) + __builtin_shuffle(ab, cd, v4i{ 2, 3, 6, 7 }));
#else
  const v4d* v[4] = { &a, &b, &c, &d };
  for (int k = 0; k < 4; ++k)
    out[k] = ((*v[k])[0] + (*v[k])[1]) + ((*v[k])[2] + (*v[k])[3]);
#endif
}

/// out[k] = (p0[k], p1[k], p2[k], p3[k]) for k < 4: four rows of four doubles transposed.
BARY_ALWAYS_INLINE void transpose4(
  const double* p0, const double* p1, const double* p2, const double* p3, v4d* out)
{
  const v4d a = BARY_LOAD4(p0), b = BARY_LOAD4(p1), c = BARY_LOAD4(p2), d = BARY_LOAD4(p3);
#if defined(__clang__)
  const v4d t0 = __builtin_shufflevector(a, b, 0, 4, 2, 6), t1 = __builtin_shufflevector(a, b, 1, 5, 3, 7);
  const v4d t2 = __builtin_shufflevector(c, d, 0, 4, 2, 6), t3 = __builtin_shufflevector(c, d, 1, 5, 3, 7);
  out[0] = __builtin_shufflevector(t0, t2, 0, 1, 4, 5);
  out[1] = __builtin_shufflevector(t1, t3, 0, 1, 4, 5);
  out[2] = __builtin_shufflevector(t0, t2, 2, 3, 6, 7);
  out[3] = __builtin_shufflevector(t1, t3, 2, 3, 6, 7);
#elif defined(__GNUC__)
  typedef long long v4i __attribute__((vector_size(32)));
  const v4d t0 = __builtin_shuffle(a, b, v4i{ 0, 4, 2, 6 }), t1 = __builtin_shuffle(a, b, v4i{ 1, 5, 3, 7 });
  const v4d t2 = __builtin_shuffle(c, d, v4i{ 0, 4, 2, 6 }), t3 = __builtin_shuffle(c, d, v4i{ 1, 5, 3, 7 });
  out[0] = __builtin_shuffle(t0, t2, v4i{ 0, 1, 4, 5 });
  out[1] = __builtin_shuffle(t1, t3, v4i{ 0, 1, 4, 5 });
  out[2] = __builtin_shuffle(t0, t2, v4i{ 2, 3, 6, 7 });
  out[3] = __builtin_shuffle(t1, t3, v4i{ 2, 3, 6, 7 });
#else
  for (int k = 0; k < 4; ++k)
    out[k] = v4d{ { p0[k], p1[k], p2[k], p3[k] } };
#endif
}

/// The eight dot products of a query with a triangle: out = (T1 w, T2 w, T3 w, e1 w, e2 w) (2 +
/// 2 + 2 + 1 + 1 numbers) with w = y - v3, T_k the corners' frames (2 D numbers each), e1 =
/// v1 - v3, e2 = v2 - v3. For D a multiple of 4, four coordinates at a time, then lane_sums;
/// otherwise in order of d.
template<int kD>
BARY_ALWAYS_INLINE void phong_dots(const double* T1, const double* T2, const double* T3,
  const double* v1, const double* v2, const double* v3, int D, const double* y, double* out)
{
  const int n = kD > 0 ? kD : D;
  if (n % 4 == 0)
  {
    const v4d zero = { 0, 0, 0, 0 };
    v4d s[8] = { zero, zero, zero, zero, zero, zero, zero, zero };
    for (int d = 0; d < n; d += 4)
    {
      const v4d p3 = BARY_LOAD4(v3 + d);
      const v4d w = BARY_LOAD4(y + d) - p3;
      s[0] += BARY_LOAD4(T1 + d) * w;
      s[1] += BARY_LOAD4(T1 + n + d) * w;
      s[2] += BARY_LOAD4(T2 + d) * w;
      s[3] += BARY_LOAD4(T2 + n + d) * w;
      s[4] += BARY_LOAD4(T3 + d) * w;
      s[5] += BARY_LOAD4(T3 + n + d) * w;
      s[6] += (BARY_LOAD4(v1 + d) - p3) * w;
      s[7] += (BARY_LOAD4(v2 + d) - p3) * w;
    }
    lane_sums(s[0], s[1], s[2], s[3], out);
    lane_sums(s[4], s[5], s[6], s[7], out + 4);
    return;
  }
  for (int k = 0; k < 8; ++k)
    out[k] = 0.0;
  for (int d = 0; d < n; ++d)
  {
    const double w = y[d] - v3[d];
    out[0] += T1[d] * w;
    out[1] += T1[n + d] * w;
    out[2] += T2[d] * w;
    out[3] += T2[n + d] * w;
    out[4] += T3[d] * w;
    out[5] += T3[n + d] * w;
    out[6] += (v1[d] - v3[d]) * w;
    out[7] += (v2[d] - v3[d]) * w;
  }
}

/// Newton's start and the right-hand side of a triangle: the start (a, b) (the Euclidean
/// projection of y onto the triangle's plane when @p euclidean_start, else (a0, b0)), clamped
/// inside the triangle (the blend's denominator vanishes at the corners); the twelve rows
/// C_r w = M_m (T_k w) into @p pw (rows of A1 (T1), A2 (T2), A3 (T2), A4 (T3), A5 (T3),
/// A6 (T1)); the squared residual tolerance (1e-14 times the longest edge, squared).
BARY_ALWAYS_INLINE void phong_setup(const double* dots, const double* data, bool euclidean_start,
  double a0, double b0, double& a, double& b, double* pw, double& tolerance2)
{
  const double* gi = data + PhongData::gram;
  if (euclidean_start)
  {
    a0 = gi[0] * dots[6] + gi[1] * dots[7];
    b0 = gi[1] * dots[6] + gi[2] * dots[7];
  }
  const double* c0 = data + PhongData::col0;
  const double* c1 = data + PhongData::col1;
  const double t10 = dots[0], t11 = dots[1], t20 = dots[2], t21 = dots[3], t30 = dots[4],
               t31 = dots[5];
  BARY_STORE4(pw, BARY_LOAD4(c0) * v4d{ t10, t10, t20, t20 } + BARY_LOAD4(c1) * v4d{ t11, t11, t21, t21 });
  BARY_STORE4(pw + 4, BARY_LOAD4(c0 + 4) * v4d{ t20, t20, t30, t30 } +
      BARY_LOAD4(c1 + 4) * v4d{ t21, t21, t31, t31 });
  BARY_STORE4(pw + 8, BARY_LOAD4(c0 + 8) * v4d{ t30, t30, t10, t10 } +
      BARY_LOAD4(c1 + 8) * v4d{ t31, t31, t11, t11 });
  const double residual_tolerance = 1e-14 * data[PhongData::scale];
  tolerance2 = residual_tolerance * residual_tolerance;
  a = std::clamp(a0, 0.02, 0.96);
  b = std::clamp(b0, 0.02, 0.96);
  if (a + b > 0.98)
  {
    const double excess = (a + b - 0.98) / 2;
    a -= excess;
    b -= excess;
  }
}

/// The end of a converged iteration at (a, b): true and the coordinates in @p xi when the point
/// is in the triangle (each coordinate >= -1e-9; those in [-1e-9, 0) set to 0, then divided by
/// their sum), else false and (a, b, 1 - a - b).
BARY_ALWAYS_INLINE bool phong_finish(double a, double b, double* xi)
{
  double x[3] = { a, b, 1.0 - a - b };
  constexpr double tolerance = 1e-9;
  if (x[0] < -tolerance || x[1] < -tolerance || x[2] < -tolerance)
  {
    xi[0] = x[0];
    xi[1] = x[1];
    xi[2] = x[2];
    return false;
  }
  for (double& v : x)
    v = std::max(v, 0.0);
  const double sum = x[0] + x[1] + x[2];
  xi[0] = x[0] / sum;
  xi[1] = x[1] / sum;
  xi[2] = x[2] / sum;
  return true;
}

/// Newton converging to a point outside the triangle: the step has at least halved and the
/// iterate (a, b) is outside by more than twice the step and 1e-9 (where the steps keep halving
/// at least, it moves less than one more step), so Eq. (9) will fail: stop now.
BARY_ALWAYS_INLINE bool phong_leaving(double a, double b, double step, double last_step)
{
  const double c = 1.0 - a - b;
  return step < 0.5 * last_step && std::min(std::min(a, b), c) < -1e-9 - 2 * step;
}

/// Phong projection of y onto one triangle from its dot products (phong_dots) and its
/// kPhongData numbers. Newton starts at (a0, b0) (barycentric coordinates of v1 and v2), or at
/// the Euclidean projection of y onto the triangle's plane when @p euclidean_start. Returns true
/// and the barycentric coordinates in @p xi when Newton converges to a point of the triangle,
/// else false (xi: the last iterate). See phong_projection.h for the iteration; phong_newton4
/// runs the same operations for four triangles at once.
BARY_ALWAYS_INLINE bool phong_newton(
  const double* dots, const double* data, bool euclidean_start, double a0, double b0, double* xi)
{
  const v4d q1[3] = { BARY_LOAD4(data + PhongData::q1), BARY_LOAD4(data + PhongData::q1 + 4),
    BARY_LOAD4(data + PhongData::q1 + 8) };
  const v4d q2[3] = { BARY_LOAD4(data + PhongData::q2), BARY_LOAD4(data + PhongData::q2 + 4),
    BARY_LOAD4(data + PhongData::q2 + 8) };
  double rows[12], a, b, tolerance2;
  phong_setup(dots, data, euclidean_start, a0, b0, a, b, rows, tolerance2);
  const v4d pw[3] = { BARY_LOAD4(rows), BARY_LOAD4(rows + 4), BARY_LOAD4(rows + 8) };
  const double residual_tolerance = 1e-14 * data[PhongData::scale];
  double last_step = 0; // no prediction before the second step
  for (int it = 0; it < kPhongMaxIterations; ++it)
  {
    const double c = 1.0 - a - b;
    const double s = a * b + b * c + c * a;
    // g_r = C_r (x(a, b) - y): the residual rows before the blend.
    v4d g[3];
    for (int j = 0; j < 3; ++j)
      g[j] = (q1[j] * a + q2[j] * b) - pw[j];
    if (!(std::abs(s) > 1e-24))
    {
      // At (or within rounding of) a corner k, where Psi is the corner's basis: accept the
      // corner when y - v_k is orthogonal to it (Property 3). The corner's basis is A1 at v1,
      // A3 at v2, A5 at v3 (rows 4 k, 4 k + 1); its residual at the corner is
      // C (v_k - y) = C e_k - C w (e_3 = 0).
      const int k = a >= b && a >= c ? 0 : b >= c ? 1 : 2;
      double r[4];
      const v4d zero = { 0, 0, 0, 0 };
      const v4d corner = k == 0 ? q1[0] - pw[0] : k == 1 ? q2[1] - pw[1] : zero - pw[2];
      BARY_STORE4(r, corner);
      if (std::hypot(r[0], r[1]) > 1e3 * residual_tolerance)
        break;
      xi[0] = xi[1] = xi[2] = 0.0;
      xi[k] = 1.0;
      return true;
    }
    // Monomials (B's a b c shared out among A1..A6) and their derivatives along a and b with
    // c = 1 - a - b (d/da - d/dc, d/db - d/dc).
    const double ab = a * b, bc = b * c, ca = c * a, aa = a * a, bb = b * b, cc = c * c;
    const double h = 0.5 * (ab * c), ha = 0.5 * (bc - ab), hb = 0.5 * (ca - ab);
    const double m[6] = { aa * b + h, a * bb + h, bb * c + h, b * cc + h, cc * a + h, c * aa + h };
    const double ma[6] = { 2 * ab + ha, bb + ha, -bb + ha, -2 * bc + ha, (cc - 2 * ca) + ha,
      (2 * ca - aa) + ha };
    const double mb[6] = { aa + hb, 2 * ab + hb, (2 * bc - bb) + hb, (cc - 2 * bc) + hb,
      -2 * ca + hb, -aa + hb };
    v4d G0 = { 0, 0, 0, 0 }, Ga = G0, Gb = G0;
    for (int j = 0; j < 3; ++j)
    {
      const v4d mj = { m[2 * j], m[2 * j], m[2 * j + 1], m[2 * j + 1] };
      const v4d maj = { ma[2 * j], ma[2 * j], ma[2 * j + 1], ma[2 * j + 1] };
      const v4d mbj = { mb[2 * j], mb[2 * j], mb[2 * j + 1], mb[2 * j + 1] };
      G0 += mj * g[j];
      Ga += maj * g[j] + mj * q1[j];
      Gb += mbj * g[j] + mj * q2[j];
    }
    // Lanes (0, 2) hold row 0 of the blend, lanes (1, 3) row 1.
    double sums[3][4];
    BARY_STORE4(sums[0], G0);
    BARY_STORE4(sums[1], Ga);
    BARY_STORE4(sums[2], Gb);
    const double G[2] = { sums[0][0] + sums[0][2], sums[0][1] + sums[0][3] };
    const double GA[2] = { sums[1][0] + sums[1][2], sums[1][1] + sums[1][3] };
    const double GB[2] = { sums[2][0] + sums[2][2], sums[2][1] + sums[2][3] };
    // Newton on H = G / s (the same roots in the triangle, well scaled near its corners):
    // J_H = M / s^2 with M = s J_G - G grad(s)^T, so the step is -s M^-1 G.
    const double sa = c - a, sb = c - b;
    const double M00 = s * GA[0] - G[0] * sa, M01 = s * GB[0] - G[0] * sb;
    const double M10 = s * GA[1] - G[1] * sa, M11 = s * GB[1] - G[1] * sb;
    const double det = M00 * M11 - M01 * M10;
    if (!(std::abs(det) > 0) || !(std::abs(det) < std::numeric_limits<double>::infinity()))
      break;
    const double f = -s / det;
    const double da = f * (M11 * G[0] - M01 * G[1]);
    const double db = f * (M00 * G[1] - M10 * G[0]);
    if (!std::isfinite(da) || !std::isfinite(db))
      break;
    a += da;
    b += db;
    // Converged: the step is at rounding level, the next one is predicted to be, or the
    // residual |H| = |G| / s was (near a corner, where Psi's limit depends on the direction,
    // Newton converges only linearly).
    const double step = std::abs(da) + std::abs(db);
    if (step < kPhongStepTolerance || step * step < kPhongPredictedTolerance * last_step ||
      G[0] * G[0] + G[1] * G[1] <= tolerance2 * (s * s))
      return phong_finish(a, b, xi);
    // Far outside the triangle, or on the way to a point outside it: no projection here
    // (Eq. 9 cannot hold).
    if (phong_leaving(a, b, step, last_step) || std::abs(a) > 1e3 || std::abs(b) > 1e3)
      break;
    last_step = step;
  }
  xi[0] = a;
  xi[1] = b;
  xi[2] = 1.0 - a - b;
  return false;
}

/// Four Phong projections at once, one per lane of the vectors (each a triangle and a target:
/// @p dots[l], @p data[l], Newton from the Euclidean projection): phong_newton's iteration and
/// stopping rules, while the four iterations' latencies overlap. The residual's rows are summed
/// monomial by monomial in chains of fused steps (phong_newton sums them four rows at a time),
/// so a lane agrees with phong_newton to rounding, not to the bit. @p status[l] on return: 1 converged in the triangle (its
/// coordinates in @p xi[l]), 0 no projection, -1 a corner was reached (rare: run phong_newton
/// for that lane). Lanes with @p active[l] false are ignored (status 0).
BARY_ALWAYS_INLINE void phong_newton4(const double* const* dots, const double* const* data,
  const bool* active, int* status, double (*xi)[3])
{
  int first = -1;
  for (int l = 0; l < 4; ++l)
  {
    status[l] = 0;
    if (active[l] && first < 0)
      first = l;
  }
  if (first < 0)
    return;
  // Per lane: the start and the rows; then transposed (vector r holds row r of the four lanes).
  double start_a[4], start_b[4], tol[4], pw[4][12];
  const double* q[4];
  for (int l = 0; l < 4; ++l)
  {
    const int k = active[l] ? l : first; // an idle lane repeats an active one
    phong_setup(dots[k], data[k], true, 0.0, 0.0, start_a[l], start_b[l], pw[l], tol[l]);
    q[l] = data[k];
  }
  v4d Q1[12], Q2[12], PW[12];
  for (int j = 0; j < 3; ++j)
  {
    transpose4(q[0] + PhongData::q1 + 4 * j, q[1] + PhongData::q1 + 4 * j,
      q[2] + PhongData::q1 + 4 * j, q[3] + PhongData::q1 + 4 * j, Q1 + 4 * j);
    transpose4(q[0] + PhongData::q2 + 4 * j, q[1] + PhongData::q2 + 4 * j,
      q[2] + PhongData::q2 + 4 * j, q[3] + PhongData::q2 + 4 * j, Q2 + 4 * j);
    transpose4(pw[0] + 4 * j, pw[1] + 4 * j, pw[2] + 4 * j, pw[3] + 4 * j, PW + 4 * j);
  }
  const v4d zero = { 0, 0, 0, 0 }, one = { 1, 1, 1, 1 }, two = { 2, 2, 2, 2 };
  // The rows' right-hand sides negated once: g_r = Q1_r a + (Q2_r b - PW_r), two fused steps.
  for (int r = 0; r < 12; ++r)
    PW[r] = zero - PW[r];
  const v4d tolerance2 = { tol[0], tol[1], tol[2], tol[3] };
  v4d a = { start_a[0], start_a[1], start_a[2], start_a[3] };
  v4d b = { start_b[0], start_b[1], start_b[2], start_b[3] };
  v4d last_step = zero;
  bool running[4] = { active[0], active[1], active[2], active[3] };
  int left = static_cast<int>(running[0]) + running[1] + running[2] + running[3];
  for (int it = 0; it < kPhongMaxIterations && left > 0; ++it)
  {
    const v4d c = (one - a) - b;
    const v4d ab = a * b, bc = b * c, ca = c * a, aa = a * a, bb = b * b, cc = c * c;
    const v4d s = (ab + bc) + ca;
    const v4d h = (ab * c) * 0.5, ha = (bc - ab) * 0.5, hb = (ca - ab) * 0.5;
    // Monomial k (B's a b c shared out) and its derivatives along a and b weigh rows 2 k and
    // 2 k + 1 (row i of A_{k+1}); each monomial is made where its rows are summed, so few
    // vectors are live at once.
    // Each sum is a chain of fused steps (one product added at a time), started by monomial 0.
    v4d G0, G1, GA0, GA1, GB0, GB1;
#define BARY_PHONG_ROWS(k, m, ma, mb)                                                            \
  {                                                                                              \
    const v4d mk = (m), mak = (ma), mbk = (mb);                                                  \
    const v4d g0 = Q1[2 * (k)] * a + (Q2[2 * (k)] * b + PW[2 * (k)]);                            \
    const v4d g1 = Q1[2 * (k) + 1] * a + (Q2[2 * (k) + 1] * b + PW[2 * (k) + 1]);                \
    if ((k) == 0)                                                                                \
    {                                                                                            \
      G0 = mk * g0;                                                                              \
      G1 = mk * g1;                                                                              \
      GA0 = mak * g0;                                                                            \
      GA1 = mak * g1;                                                                            \
      GB0 = mbk * g0;                                                                            \
      GB1 = mbk * g1;                                                                            \
    }                                                                                            \
    else                                                                                         \
    {                                                                                            \
      G0 = G0 + mk * g0;                                                                         \
      G1 = G1 + mk * g1;                                                                         \
      GA0 = GA0 + mak * g0;                                                                      \
      GA1 = GA1 + mak * g1;                                                                      \
      GB0 = GB0 + mbk * g0;                                                                      \
      GB1 = GB1 + mbk * g1;                                                                      \
    }                                                                                            \
    GA0 = GA0 + mk * Q1[2 * (k)];                                                                \
    GA1 = GA1 + mk * Q1[2 * (k) + 1];                                                            \
    GB0 = GB0 + mk * Q2[2 * (k)];                                                                \
    GB1 = GB1 + mk * Q2[2 * (k) + 1];                                                            \
  }
    BARY_PHONG_ROWS(0, aa * b + h, two * ab + ha, aa + hb)
    BARY_PHONG_ROWS(1, a * bb + h, bb + ha, two * ab + hb)
    BARY_PHONG_ROWS(2, bb * c + h, ha - bb, (two * bc - bb) + hb)
    BARY_PHONG_ROWS(3, b * cc + h, ha - two * bc, (cc - two * bc) + hb)
    BARY_PHONG_ROWS(4, cc * a + h, (cc - two * ca) + ha, hb - two * ca)
    BARY_PHONG_ROWS(5, c * aa + h, (two * ca - aa) + ha, hb - aa)
#undef BARY_PHONG_ROWS
    const v4d sa = c - a, sb = c - b;
    const v4d M00 = s * GA0 - G0 * sa, M01 = s * GB0 - G0 * sb;
    const v4d M10 = s * GA1 - G1 * sa, M11 = s * GB1 - G1 * sb;
    const v4d det = M00 * M11 - M01 * M10;
    const v4d f = (zero - s) / det;
    const v4d da = f * (M11 * G0 - M01 * G1);
    const v4d db = f * (M00 * G1 - M10 * G0);
    const v4d an = a + da, bn = b + db;
#if defined(__GNUC__)
    {
      // Usually no lane stops: the tests of the loop below as masks first.
      typedef long long v4l __attribute__((vector_size(32)));
      const v4l sign = { ~(1LL << 63), ~(1LL << 63), ~(1LL << 63), ~(1LL << 63) };
#define BARY_VABS(x) reinterpret_cast<v4d>(reinterpret_cast<v4l>(x) & sign)
      const v4d abs_det = BARY_VABS(det), step = BARY_VABS(da) + BARY_VABS(db);
      const v4d tiny = { 1e-24, 1e-24, 1e-24, 1e-24 };
      const v4d huge = { 1e3, 1e3, 1e3, 1e3 };
      const v4d infinite = { std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
        std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity() };
      const v4d step_tolerance = { kPhongStepTolerance, kPhongStepTolerance, kPhongStepTolerance,
        kPhongStepTolerance };
      // phong_newton's tests of s, det, da and db, or stricter (a lane they stop goes to the
      // lane-by-lane tests below): with |s| > 0, det = 0 makes the step infinite or NaN, and a
      // finite step has finite da and db.
      const v4l valid = (BARY_VABS(s) > tiny) & (abs_det < infinite) & ((step - step) == zero);
      const v4l converged = (step < step_tolerance) | (step * step < last_step * kPhongPredictedTolerance) |
        (G0 * G0 + G1 * G1 <= tolerance2 * (s * s));
      const v4l far = (BARY_VABS(an) > huge) | (BARY_VABS(bn) > huge);
#undef BARY_VABS
      // phong_leaving, as a mask
      const v4d cn = (one - an) - bn;
      v4d lowest = BARY_SELECT(bn < an, bn, an);
      lowest = BARY_SELECT(cn < lowest, cn, lowest);
      const v4d margin = { -1e-9, -1e-9, -1e-9, -1e-9 };
      const v4l leaving = (step < last_step * 0.5) & (lowest < margin - step * 2.0);
      const v4l idle = { running[0] ? 0LL : -1LL, running[1] ? 0LL : -1LL, running[2] ? 0LL : -1LL,
        running[3] ? 0LL : -1LL };
      const v4l go_on = (valid & ~converged & ~far & ~leaving) | idle;
      if ((go_on[0] & go_on[1] & go_on[2] & go_on[3]) != 0)
      {
        a = an;
        b = bn;
        last_step = step;
        continue;
      }
      const v4l finish = (valid & converged) | idle;
      if ((finish[0] & finish[1] & finish[2] & finish[3]) != 0)
      {
        // Every running lane converged (the usual end): phong_finish, four at a time.
        const v4d x[3] = { an, bn, cn };
        const v4d low_bound = { -1e-9, -1e-9, -1e-9, -1e-9 };
        const v4l outside = (x[0] < low_bound) | (x[1] < low_bound) | (x[2] < low_bound);
        v4d y[3];
        for (int k = 0; k < 3; ++k)
          y[k] = BARY_SELECT(x[k] < zero, zero, x[k]);
        const v4d sum = (y[0] + y[1]) + y[2];
        double X[3][4], Y[3][4];
        for (int k = 0; k < 3; ++k)
        {
          BARY_STORE4(X[k], x[k]);
          BARY_STORE4(Y[k], y[k] / sum);
        }
        for (int l = 0; l < 4; ++l)
          if (running[l])
          {
            status[l] = outside[l] != 0 ? 0 : 1;
            for (int k = 0; k < 3; ++k)
              xi[l][k] = outside[l] != 0 ? X[k][l] : Y[k][l];
          }
        return;
      }
    }
#endif
    double S[4], DET[4], DA[4], DB[4], AN[4], BN[4], RES[4], TS[4], A[4], B[4];
    BARY_STORE4(A, a);
    BARY_STORE4(B, b);
    BARY_STORE4(S, s);
    BARY_STORE4(DET, det);
    BARY_STORE4(DA, da);
    BARY_STORE4(DB, db);
    BARY_STORE4(AN, an);
    BARY_STORE4(BN, bn);
    BARY_STORE4(RES, G0 * G0 + G1 * G1);
    BARY_STORE4(TS, tolerance2 * (s * s));
    double LAST[4];
    BARY_STORE4(LAST, last_step);
    for (int l = 0; l < 4; ++l)
    {
      if (!running[l])
        continue;
      bool stop = true;
      if (!(std::abs(S[l]) > 1e-24))
        status[l] = -1; // a corner: phong_newton decides
      else if (!(std::abs(DET[l]) > 0) || !(std::abs(DET[l]) < std::numeric_limits<double>::infinity()) ||
        !std::isfinite(DA[l]) || !std::isfinite(DB[l]))
      {
        status[l] = 0;
        xi[l][0] = A[l];
        xi[l][1] = B[l];
        xi[l][2] = 1.0 - A[l] - B[l];
      }
      else
      {
        const double step = std::abs(DA[l]) + std::abs(DB[l]);
        if (step < kPhongStepTolerance || step * step < kPhongPredictedTolerance * LAST[l] ||
          RES[l] <= TS[l])
          status[l] = phong_finish(AN[l], BN[l], xi[l]) ? 1 : 0;
        else if (phong_leaving(AN[l], BN[l], step, LAST[l]) || std::abs(AN[l]) > 1e3 ||
          std::abs(BN[l]) > 1e3)
        {
          status[l] = 0;
          xi[l][0] = AN[l];
          xi[l][1] = BN[l];
          xi[l][2] = 1.0 - AN[l] - BN[l];
        }
        else
        {
          LAST[l] = step;
          stop = false;
        }
      }
      if (stop)
      {
        running[l] = false;
        --left;
      }
    }
    a = an;
    b = bn;
    last_step = v4d{ LAST[0], LAST[1], LAST[2], LAST[3] };
  }
  // Lanes still running: no convergence in kPhongMaxIterations steps.
  double A[4], B[4];
  BARY_STORE4(A, a);
  BARY_STORE4(B, b);
  for (int l = 0; l < 4; ++l)
    if (running[l])
    {
      xi[l][0] = A[l];
      xi[l][1] = B[l];
      xi[l][2] = 1.0 - A[l] - B[l];
    }
}

/// Phong projection of @p y onto a triangle: its data, its corners' frames and positions;
/// Newton from (a0, b0) or from the Euclidean projection.
template<int kD>
BARY_ALWAYS_INLINE bool phong_project(const double* data, const double* T1, const double* T2,
  const double* T3, const double* v1, const double* v2, const double* v3, int D, const double* y,
  bool euclidean_start, double a0, double b0, double* xi)
{
  double dots[8];
  phong_dots<kD>(T1, T2, T3, v1, v2, v3, D, y, dots);
  return phong_newton(dots, data, euclidean_start, a0, b0, xi);
}

/// The interpolated tangent basis Psi(a, b, c) of a triangle (its data and corners' frames):
/// 2 D numbers into @p out (row 0, then row 1), N1 T1 + N2 T2 + N3 T3 with the 2 by 2 matrices
/// N1 = k1 M1 + k6 M6, N2 = k2 M2 + k3 M3, N3 = k4 M4 + k5 M5 (k_m = (mono_m + abc / 2) / s).
/// At a corner (the blend's denominator below 1e-300) the corner's basis (A1, A3 or A5).
template<int kD>
BARY_ALWAYS_INLINE void phong_psi(const double* data, const double* T1, const double* T2,
  const double* T3, int D, double a, double b, double c, double* out)
{
  const int n = kD > 0 ? kD : D;
  const double s = a * b + b * c + c * a;
  double k[6];
  if (!(s > 1e-300))
  {
    const int corner = a >= b && a >= c ? 0 : b >= c ? 2 : 4;
    for (int m = 0; m < 6; ++m)
      k[m] = m == corner ? 1.0 : 0.0;
  }
  else
  {
    const double inverse = 1.0 / s;
    const double h = 0.5 * (a * b * c * inverse);
    const double mono[6] = { a * a * b, a * b * b, b * b * c, b * c * c, c * c * a, c * a * a };
    for (int m = 0; m < 6; ++m)
      k[m] = mono[m] * inverse + h;
  }
  const double* c0 = data + PhongData::col0;
  const double* c1 = data + PhongData::col1;
  // N_k(i, j) for the frames T1 (A1, A6), T2 (A2, A3), T3 (A4, A5).
  double N[3][2][2];
  const int pairs[3][2] = { { 0, 5 }, { 1, 2 }, { 3, 4 } };
  for (int t = 0; t < 3; ++t)
    for (int i = 0; i < 2; ++i)
    {
      const int m0 = pairs[t][0], m1 = pairs[t][1];
      N[t][i][0] = k[m0] * c0[2 * m0 + i] + k[m1] * c0[2 * m1 + i];
      N[t][i][1] = k[m0] * c1[2 * m0 + i] + k[m1] * c1[2 * m1 + i];
    }
  const double* T[3] = { T1, T2, T3 };
  int d = 0;
  for (; d + 4 <= n; d += 4)
    for (int i = 0; i < 2; ++i)
    {
      v4d acc = BARY_LOAD4(T[0] + d) * N[0][i][0] + BARY_LOAD4(T[0] + n + d) * N[0][i][1];
      for (int t = 1; t < 3; ++t)
        acc += BARY_LOAD4(T[t] + d) * N[t][i][0] + BARY_LOAD4(T[t] + n + d) * N[t][i][1];
      BARY_STORE4(out + i * n + d, acc);
    }
  for (; d < n; ++d)
    for (int i = 0; i < 2; ++i)
    {
      double acc = T[0][d] * N[0][i][0] + T[0][n + d] * N[0][i][1];
      for (int t = 1; t < 3; ++t)
        acc += T[t][d] * N[t][i][0] + T[t][n + d] * N[t][i][1];
      out[i * n + d] = acc;
    }
}

} // namespace bary::detail
