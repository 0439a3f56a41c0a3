#include "core/coordinates/mean_value_coordinates.h"

#include "core/detail/parallel_for.h"
#include "core/common/error.h"
#include "core/detail/constants.h"
#include "core/detail/huge_pages.h"
#include "core/detail/simd.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <string>
#include <vector>

#if defined(__GNUC__) && (defined(__x86_64__) || defined(__i386__))
#include <immintrin.h>
#endif

namespace bary
{
namespace
{


/// Scratch space reused by the per-point kernels of one thread.
std::vector<double>& scratch(std::size_t size)
{
  thread_local std::vector<double> buffer;
  if (buffer.size() < size)
    buffer.resize(size);
  return buffer;
}

/// Normalises raw weights; returns false (and fills NaN) if their sum is too small to divide by.
bool normalize(double* w, Index n)
{
  double sum = 0.0, abs_sum = 0.0;
  for (Index i = 0; i < n; ++i)
  {
    sum += w[i];
    abs_sum += std::abs(w[i]);
  }
  if (!(std::abs(sum) > 1e-14 * abs_sum) || !std::isfinite(sum))
  {
    std::fill(w, w + n, kNaN);
    return false;
  }
  const double inv = 1.0 / sum;
  for (Index i = 0; i < n; ++i)
    w[i] *= inv;
  return true;
}

/// Closest point to p on triangle (a, b, c), returned as barycentric coordinates (Ericson,
/// Real-Time Collision Detection, Sect. 5.1.5). Also returns the squared distance.
double closest_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
  const Eigen::Vector3d& b, const Eigen::Vector3d& c, double bary[3])
{
  auto finish = [&](double u, double v, double w) {
    bary[0] = u;
    bary[1] = v;
    bary[2] = w;
    return (u * a + v * b + w * c - p).squaredNorm();
  };
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0)
    return finish(1, 0, 0);
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3)
    return finish(0, 1, 0);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0)
  {
    const double v = d1 / (d1 - d3);
    return finish(1 - v, v, 0);
  }
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6)
    return finish(0, 0, 1);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0)
  {
    const double w = d2 / (d2 - d6);
    return finish(1 - w, 0, w);
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
  {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return finish(0, 1 - w, w);
  }
  const double denom = 1.0 / (va + vb + vc);
  const double v = vb * denom, w = vc * denom;
  return finish(1 - v - w, v, w);
}

// ---------------------------------------------------------------------------------------------
// 3D batch kernel: four points at once (one per lane of a four-double vector), the same
// operations in the same order as evaluate_3d, lane by lane. Compiled twice (detail/simd.h):
// for AVX2 + FMA (a * b + c fused) and portable (SSE2 on x86-64); simd_level() picks one.
// The only other difference from evaluate_3d is asin (vector_asin below, < 0.67 ulp, against
// glibc's < 1 ulp). A lane that meets any special case of evaluate_3d (within the tolerance of
// a vertex or of a face's plane, det = 0, x on the line of an edge) is flagged and recomputed
// by evaluate_3d, so every special case is handled exactly as for a single point.
// ---------------------------------------------------------------------------------------------
#if defined(__GNUC__)
#define BARY_MVC_VECTOR_KERNEL 1

using detail::v4d;
typedef long long MvcLanes __attribute__((vector_size(32)));

/// What the 3D kernel reads of the evaluator: cage (column-major), edges, faces.
struct Mvc3dCage
{
  const double* V;          // n x 3, column-major
  Index n;
  Index nf;
  const std::array<int, 2>* edges;
  std::size_t ne;
  const struct Mvc3dFace* faces; // nf
  double tolerance;
};

/// A face as the kernel reads it (built per batch call from F, face_edges_ and
/// inv_twice_area_): offsets of its vertices' and edges' scratch records, and the signs of
/// evaluate_3d as factors (s[k] = +-1 of edge k; t[k] = -s[k] s[k+2]), so that the face loop
/// has no data-dependent branch.
struct Mvc3dFace
{
  std::uint32_t vertex[3], edge[3];
  double s[3], t[3];
  double inv_twice_area;
};

// asin(z) = z + z s P(s), s = z^2, for 0 <= z <= sqrt(1/2) (the half chords' range): P of
// degree 18 interpolating (asin(sqrt(s)) / sqrt(s) - 1) / s at the 19 Chebyshev nodes of
// [0, 1/2], solved in 60-digit arithmetic and rounded to double by tools/mvc_asin_coefficients.py,
// which also checks the evaluation below (even and odd parts in s^2) against 60-digit asin at
// 33,000 points: error < 0.67 ulp (the unit tests compare the weights with the per-point call's).
constexpr double kAsinP[19] = { 0.16666666666666669, 0.07499999999998412, 0.04464285714665563,
  0.030381944084994415, 0.0223721770065477, 0.017352221539201188, 0.013975730180211136,
  0.01139924601483468, 0.011310924828955462, -0.0032941927380090922, 0.07377343868679113,
  -0.2809947932275328, 0.952265420570822, -2.3535297860232123, 4.3847119392409954,
  -5.883233416999023, 5.436384462318588, -3.0948547605199717, 0.8387674099544927 };

/// r = asin(z) lane by lane, 0 <= z <= sqrt(1/2).
BARY_ALWAYS_INLINE void vector_asin(const v4d& z, v4d& r)
{
  const v4d s = z * z, s2 = s * s;
  v4d even = s2 * kAsinP[18] + kAsinP[16];
  v4d odd = s2 * kAsinP[17] + kAsinP[15];
  even = even * s2 + kAsinP[14];
  odd = odd * s2 + kAsinP[13];
  even = even * s2 + kAsinP[12];
  odd = odd * s2 + kAsinP[11];
  even = even * s2 + kAsinP[10];
  odd = odd * s2 + kAsinP[9];
  even = even * s2 + kAsinP[8];
  odd = odd * s2 + kAsinP[7];
  even = even * s2 + kAsinP[6];
  odd = odd * s2 + kAsinP[5];
  even = even * s2 + kAsinP[4];
  odd = odd * s2 + kAsinP[3];
  even = even * s2 + kAsinP[2];
  odd = odd * s2 + kAsinP[1];
  even = even * s2 + kAsinP[0];
  const v4d p = even + s * odd;
  r = z + (z * s) * p;
}

/// r = sqrt(x) lane by lane (correctly rounded, as std::sqrt, so both forms give the same bits).
/// In the AVX2 instantiation AVX's four-lane square root: the template is only ever inlined into
/// mvc3d_group_avx2, compiled for AVX2 (an AMD EPYC takes four lanes at once: 247 -> 215 ms for
/// the 1,280-face benchmark, one thread; the Intel Xeon measured before took 128 bits at a time
/// either way). Elsewhere, and with clang (which checks the builtin's target in the template
/// itself), SSE2's two-lane square root on each half, part of x86-64's baseline.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi" // the AVX builtin's return outside an AVX function:
                                         // inlined into one, never called through the ABI
#endif
template<bool Avx2>
BARY_ALWAYS_INLINE void vector_sqrt(const v4d& x, v4d& r)
{
#if defined(__x86_64__) || defined(__i386__)
#if !defined(__clang__) // clang checks the builtin's target in the template itself
  if constexpr (Avx2)
    r = reinterpret_cast<v4d>(__builtin_ia32_sqrtpd256(reinterpret_cast<__m256d>(x)));
  else
#endif
  {
    const __m128d lo = _mm_sqrt_pd(_mm_set_pd(x[1], x[0]));
    const __m128d hi = _mm_sqrt_pd(_mm_set_pd(x[3], x[2]));
    r = v4d{ lo[0], lo[1], hi[0], hi[1] };
  }
#else
  r = v4d{ std::sqrt(x[0]), std::sqrt(x[1]), std::sqrt(x[2]), std::sqrt(x[3]) };
#endif
}
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

// Scratch layout (doubles, 4 lanes per quantity): per vertex ux, uy, uz, d, 1/d and the raw
// weight; per edge (u_a x u_b) x, y, z, sin(theta) = |u_a x u_b|, its inverse, theta,
// r . (u_a x u_b).
constexpr std::size_t kVertexStride = 24, kEdgeStride = 28;

/// Raw (unnormalised) weights of the four points @p xyz (x of the 4 lanes, then y, then z)
/// into rows[l][0..n) for each lane l, the signed count of ray crossings into winding[l], and
/// bit l of the return value set for a lane that evaluate_3d must recompute.
template<bool Avx2>
BARY_ALWAYS_INLINE unsigned mvc3d_group(
  const Mvc3dCage& c, const double* xyz, double* buf, double* const* rows, long long* winding)
{
  const Index n = c.n;
  const v4d X = BARY_LOAD4(xyz), Y = BARY_LOAD4(xyz + 4), Z = BARY_LOAD4(xyz + 8);
  const v4d zero = { 0.0, 0.0, 0.0, 0.0 }, one = { 1.0, 1.0, 1.0, 1.0 };
  const v4d tol = { c.tolerance, c.tolerance, c.tolerance, c.tolerance };
  const MvcLanes sign_off = { ~(1LL << 63), ~(1LL << 63), ~(1LL << 63), ~(1LL << 63) };
  MvcLanes bad = { 0, 0, 0, 0 };
  double* vert = buf;
  double* edge = vert + kVertexStride * static_cast<std::size_t>(n);

  for (Index i = 0; i < n; ++i)
  {
    double* q = vert + kVertexStride * static_cast<std::size_t>(i);
    const v4d ux = c.V[i] - X, uy = c.V[n + i] - Y, uz = c.V[2 * n + i] - Z;
    v4d d;
    vector_sqrt<Avx2>(ux * ux + uy * uy + uz * uz, d);
    bad |= d <= tol;
    const v4d inv = one / d;
    BARY_STORE4(q, ux * inv);
    BARY_STORE4(q + 4, uy * inv);
    BARY_STORE4(q + 8, uz * inv);
    BARY_STORE4(q + 12, d);
    BARY_STORE4(q + 16, inv);
    BARY_STORE4(q + 20, zero);
  }

  constexpr double r0 = 0.5373804163292384, r1 = 0.8116219853018327, r2 = 0.2290948120937462;
  for (std::size_t e = 0; e < c.ne; ++e)
  {
    const double* a = vert + kVertexStride * static_cast<std::size_t>(c.edges[e][0]);
    const double* b = vert + kVertexStride * static_cast<std::size_t>(c.edges[e][1]);
    double* q = edge + kEdgeStride * e;
    const v4d ax = BARY_LOAD4(a), ay = BARY_LOAD4(a + 4), az = BARY_LOAD4(a + 8);
    const v4d bx = BARY_LOAD4(b), by = BARY_LOAD4(b + 4), bz = BARY_LOAD4(b + 8);
    const v4d cx = ay * bz - az * by, cy = az * bx - ax * bz, cz = ax * by - ay * bx;
    v4d len;
    vector_sqrt<Avx2>(cx * cx + cy * cy + cz * cz, len);
    bad |= len == zero; // x on the line of an edge
    // theta = 2 asin(l / 2) or pi - 2 asin(m / 2) with the half chords l = |u_a - u_b| and
    // m = |u_a + u_b|, whichever is smaller (compared squared: one square root)
    const v4d dx = ax - bx, dy = ay - by, dz = az - bz;
    const v4d sx = ax + bx, sy = ay + by, sz = az + bz;
    const v4d ll = dx * dx + dy * dy + dz * dz, mm = sx * sx + sy * sy + sz * sz;
    // the chosen squared half chord, negated (sign bit set) where it is m: the second pass
    // takes the square roots and arc sines (two short loops keep more iterations in flight
    // than one long one, whose chain of dependent operations was the bottleneck)
    const v4d chord = BARY_SELECT(ll <= mm, ll, -mm);
    BARY_STORE4(q, cx);
    BARY_STORE4(q + 4, cy);
    BARY_STORE4(q + 8, cz);
    BARY_STORE4(q + 12, len);
    BARY_STORE4(q + 20, chord);
    BARY_STORE4(q + 24, r0 * cx + r1 * cy + r2 * cz);
  }
  for (std::size_t e = 0; e < c.ne; ++e)
  {
    double* q = edge + kEdgeStride * e;
    const v4d chord = BARY_LOAD4(q + 20);
    const MvcLanes use_m = reinterpret_cast<MvcLanes>(chord) < MvcLanes{ 0, 0, 0, 0 };
    v4d h, as;
    vector_sqrt<Avx2>(reinterpret_cast<v4d>(reinterpret_cast<MvcLanes>(chord) & sign_off), h);
    vector_asin(0.5 * h, as);
    BARY_STORE4(q + 16, one / BARY_LOAD4(q + 12));
    BARY_STORE4(q + 20, BARY_SELECT(use_m, kPi - 2.0 * as, 2.0 * as));
  }

  // faces, first pass: det, the special cases, the ray crossings, 1 / det
  double* inverse_det = edge + kEdgeStride * c.ne;
  MvcLanes wind = { 0, 0, 0, 0 };
  for (Index f = 0; f < c.nf; ++f)
  {
    const Mvc3dFace& face = c.faces[f];
    const double* E[3] = { edge + face.edge[0], edge + face.edge[1], edge + face.edge[2] };
    const double* const s = face.s;
    const double* u0 = vert + face.vertex[0];
    const v4d det = s[1] *
      (BARY_LOAD4(u0) * BARY_LOAD4(E[1]) + BARY_LOAD4(u0 + 4) * BARY_LOAD4(E[1] + 4) +
        BARY_LOAD4(u0 + 8) * BARY_LOAD4(E[1] + 8));
    const double* v1 = vert + face.vertex[1];
    const double* v2 = vert + face.vertex[2];
    const v4d abs_det = reinterpret_cast<v4d>(reinterpret_cast<MvcLanes>(det) & sign_off);
    const v4d plane_distance = BARY_LOAD4(u0 + 12) * BARY_LOAD4(v1 + 12) * BARY_LOAD4(v2 + 12) *
      abs_det * face.inv_twice_area;
    bad |= (plane_distance <= tol) | (det == zero);

    const v4d q0 = s[0] * BARY_LOAD4(E[0] + 24), q1 = s[1] * BARY_LOAD4(E[1] + 24),
              q2 = s[2] * BARY_LOAD4(E[2] + 24);
    // mask lanes are -1: crossings counted negatively, which keeps 0 and != 0 apart
    wind += ((det > zero) & (q0 > zero) & (q1 > zero) & (q2 > zero)) -
      ((det < zero) & (q0 < zero) & (q1 < zero) & (q2 < zero));
    BARY_STORE4(inverse_det + 4 * f, one / det);
  }
  // second pass: the weights
  for (Index f = 0; f < c.nf; ++f)
  {
    const Mvc3dFace& face = c.faces[f];
    const double* E[3] = { edge + face.edge[0], edge + face.edge[1], edge + face.edge[2] };
    v4d theta[3], sin_t[3], cosA[3];
    for (int k = 0; k < 3; ++k)
    {
      const int k1 = (k + 1) % 3, k2 = (k + 2) % 3;
      theta[k] = BARY_LOAD4(E[k1] + 20);
      sin_t[k] = BARY_LOAD4(E[k1] + 12);
      const double* ca = E[k];
      const double* cb = E[k2];
      cosA[k] = face.t[k] *
        (BARY_LOAD4(ca) * BARY_LOAD4(cb) + BARY_LOAD4(ca + 4) * BARY_LOAD4(cb + 4) +
          BARY_LOAD4(ca + 8) * BARY_LOAD4(cb + 8)) *
        BARY_LOAD4(ca + 16) * BARY_LOAD4(cb + 16);
    }
    const v4d inv_det = BARY_LOAD4(inverse_det + 4 * f);
    for (int k = 0; k < 3; ++k)
    {
      const int k1 = (k + 1) % 3, k2 = (k + 2) % 3;
      const std::uint32_t vertex = face.vertex[k];
      double* wk = vert + vertex + 20;
      const double* vk = vert + vertex;
      BARY_STORE4(wk,
        BARY_LOAD4(wk) +
          sin_t[k] * (theta[k] - cosA[k1] * theta[k2] - cosA[k2] * theta[k1]) * inv_det *
            BARY_LOAD4(vk + 16));
    }
  }

  for (Index i = 0; i < n; ++i)
    for (int l = 0; l < 4; ++l)
      rows[l][i] = vert[kVertexStride * static_cast<std::size_t>(i) + 20 + static_cast<std::size_t>(l)];
  unsigned special = 0;
  for (int l = 0; l < 4; ++l)
  {
    winding[l] = wind[l];
    if (bad[l])
      special |= 1u << l;
  }
  return special;
}

BARY_NOINLINE unsigned mvc3d_group_portable(
  const Mvc3dCage& c, const double* xyz, double* buf, double* const* rows, long long* winding)
{
  return mvc3d_group<false>(c, xyz, buf, rows, winding);
}

#if BARY_HAVE_AVX2_DISPATCH
BARY_TARGET_AVX2 BARY_NOINLINE unsigned mvc3d_group_avx2(
  const Mvc3dCage& c, const double* xyz, double* buf, double* const* rows, long long* winding)
{
  return mvc3d_group<true>(c, xyz, buf, rows, winding);
}
#endif

#endif // __GNUC__

} // namespace

MeanValueCoordinates::MeanValueCoordinates(Cage cage, const MeanValueOptions& options)
  : cage_(std::move(cage))
  , options_(options)
{
  if (!(options.boundary_tolerance >= 0.0 && options.boundary_tolerance <= 1e-3))
    throw Error(ErrorCode::InvalidArgument,
      "boundary_tolerance must lie in [0, 1e-3], got " + std::to_string(options.boundary_tolerance));
  if (options.threads < 0)
    throw Error(ErrorCode::InvalidArgument, "threads must be >= 0 (0 = default)");
  if (options.validate)
    validate_cage(cage_, options.validation);
  else if (cage_.V.rows() == 0)
    throw Error(ErrorCode::EmptyInput, "the cage has no vertices");
  else if (cage_.dimension() != 2 && cage_.dimension() != 3)
    throw Error(ErrorCode::SizeMismatch, "cage vertices must have 2 or 3 coordinates");
  tolerance_ = options.boundary_tolerance * cage_.diameter();
  if (cage_.dimension() == 3)
  {
    const Index nf = cage_.F.rows();
    inv_twice_area_.resize(static_cast<std::size_t>(nf));
    face_edges_.resize(static_cast<std::size_t>(3 * nf));
    std::map<std::pair<int, int>, unsigned> index;
    for (Index f = 0; f < nf; ++f)
    {
      const Eigen::Vector3d a = cage_.V.row(cage_.F(f, 0)), b = cage_.V.row(cage_.F(f, 1)),
                            c = cage_.V.row(cage_.F(f, 2));
      const double twice_area = (b - a).cross(c - a).norm();
      inv_twice_area_[static_cast<std::size_t>(f)] =
        twice_area > 0.0 ? 1.0 / twice_area : std::numeric_limits<double>::infinity();
      for (int k = 0; k < 3; ++k)
      {
        const int i = cage_.F(f, k), j = cage_.F(f, (k + 1) % 3);
        const auto key = std::make_pair(std::min(i, j), std::max(i, j));
        auto [it, added] = index.emplace(key, static_cast<unsigned>(edges_.size()));
        if (added)
          edges_.push_back({ key.first, key.second });
        // bit 0: the face walks the edge against its stored direction (cross product negated)
        face_edges_[static_cast<std::size_t>(3 * f + k)] = (it->second << 1) | (i > j ? 1u : 0u);
      }
    }
  }
}

PointLocation MeanValueCoordinates::evaluate(const double* x, double* w) const
{
  return dimension() == 2 ? evaluate_2d(x, w) : evaluate_3d(x, w);
}

// Hormann & Floater 2006, Eq. (7) with Sect. 4's treatment of the boundary.
PointLocation MeanValueCoordinates::evaluate_2d(const double* x, double* w) const
{
  const Eigen::MatrixXd& V = cage_.V;
  const Index n = V.rows();
  std::vector<double>& buf = scratch(static_cast<std::size_t>(5 * n));
  double* sx = buf.data();
  double* sy = sx + n;
  double* r = sy + n;
  double* t = r + n; // tan(alpha_i / 2) of the angle at x spanned by edge i

  for (Index i = 0; i < n; ++i)
  {
    sx[i] = V(i, 0) - x[0];
    sy[i] = V(i, 1) - x[1];
    r[i] = std::hypot(sx[i], sy[i]);
    if (r[i] <= tolerance_)
    { // at a vertex: Lagrange property
      std::fill(w, w + n, 0.0);
      w[i] = 1.0;
      return PointLocation::Boundary;
    }
  }
  double winding = 0.0;
  for (Index i = 0; i < n; ++i)
  {
    const Index j = (i + 1 == n) ? 0 : i + 1;
    const double det = sx[i] * sy[j] - sy[i] * sx[j]; // 2 A_i
    const double dot = sx[i] * sx[j] + sy[i] * sy[j]; // D_i
    const double edge = std::hypot(V(j, 0) - V(i, 0), V(j, 1) - V(i, 1));
    if (dot < 0.0 && std::abs(det) <= tolerance_ * edge)
    { // on edge i: the coordinates are linear along the edge
      std::fill(w, w + n, 0.0);
      w[i] = r[j] / (r[i] + r[j]);
      w[j] = r[i] / (r[i] + r[j]);
      return PointLocation::Boundary;
    }
    // tan(a/2) = sin(a) / (1 + cos(a)) = (1 - cos(a)) / sin(a): the first form cancels when
    // a ~ pi (x just off the edge, beyond the tolerance), the second when a ~ 0; pick by sign.
    t[i] = dot >= 0.0 ? det / (r[i] * r[j] + dot) : (r[i] * r[j] - dot) / det;
    winding += std::atan(t[i]);
  }
  for (Index i = 0; i < n; ++i)
  {
    const Index h = (i == 0) ? n - 1 : i - 1;
    w[i] = (t[h] + t[i]) / r[i];
  }
  normalize(w, n);
  // sum of the angles a_i = 2 atan(t_i) is 2 pi times the winding number
  return std::abs(winding) > 0.5 * kPi ? PointLocation::Inside : PointLocation::Outside;
}

// Ju, Schaefer & Warren 2005, Sect. 3.2 / Fig. 4, rearranged for accuracy and speed.
//
// Accuracy — the paper's pseudo-code cancels near the cage; here nothing does:
//  - for the arc between u_a and u_b (a cage edge seen from x): e = u_a x u_b, sin(theta) = |e|,
//    and theta = 2 asin(|u_a - u_b| / 2) or pi - 2 asin(|u_a + u_b| / 2), whichever argument is
//    smaller, accurate for every angle;
//  - the spherical angle at u_k of a face, c_k = cos(A_k) = -(e_k . e_{k-1}) / (|e_k| |e_{k-1}|),
//    from the normals of the two arcs through u_k (equal to the paper's half-angle expression);
//  - sin(A_k) = |det| / (sin(theta_{k+1}) sin(theta_{k-1})), so the paper's denominator
//    d_i sin(theta_{i+1}) s_{i-1}, with s = sign(det) sqrt(1 - c^2), equals d_i det / sin(theta_i).
//    The square root loses all accuracy as c -> -1, i.e. as x approaches a face (error
//    ~1e-16 / dist^2); det keeps its relative accuracy (error ~1e-16 / dist).
//  Hence, per face: w_i += sin(theta_i) (theta_i - c_{i+1} theta_{i-1} - c_{i-1} theta_{i+1})
//  / (d_i det), with theta_k the arc opposite vertex k.
// Speed — arc quantities depend on the edge only, and each edge has two faces: they are
// computed once per edge (1.5 #F asin per point instead of 3 #F asin plus trig per face). Inside/outside comes from a
// signed count of the faces crossed by a ray from x in a fixed generic direction r; the ray meets
// face (u0, u1, u2) iff r lies in the cone of the u's, i.e. r . e_k has the sign of det for all
// three edges. The two faces of an edge see r . e with opposite signs, so a ray grazing an edge
// is counted exactly once.
PointLocation MeanValueCoordinates::evaluate_3d(const double* x, double* w) const
{
  const Eigen::MatrixXd& V = cage_.V;
  const Eigen::MatrixXi& F = cage_.F;
  const Index n = V.rows();
  const std::size_t ne = edges_.size();
  std::vector<double>& buf = scratch(static_cast<std::size_t>(5 * n) + 7 * ne);
  double* d = buf.data();
  double* inv_d = d + n;
  double* u = inv_d + n;           // unit vectors, 3 per vertex
  double* ecross = u + 3 * n;      // u_a x u_b, 3 per edge
  double* elen = ecross + 3 * ne;  // |u_a x u_b| = sin(theta)
  double* einv = elen + ne;        // 1 / |u_a x u_b|
  double* etheta = einv + ne;      // theta
  double* eray = etheta + ne;      // r . (u_a x u_b)

  for (Index i = 0; i < n; ++i)
  {
    const double ux = V(i, 0) - x[0], uy = V(i, 1) - x[1], uz = V(i, 2) - x[2];
    d[i] = std::sqrt(ux * ux + uy * uy + uz * uz);
    if (d[i] <= tolerance_)
    { // at a vertex: Lagrange property
      std::fill(w, w + n, 0.0);
      w[i] = 1.0;
      return PointLocation::Boundary;
    }
    inv_d[i] = 1.0 / d[i];
    u[3 * i] = ux * inv_d[i];
    u[3 * i + 1] = uy * inv_d[i];
    u[3 * i + 2] = uz * inv_d[i];
  }
  // a fixed direction in no special position w.r.t. axis-aligned or symmetric cages
  constexpr double r[3] = { 0.5373804163292384, 0.8116219853018327, 0.2290948120937462 };
  for (std::size_t e = 0; e < ne; ++e)
  {
    const double* a = u + 3 * edges_[e][0];
    const double* b = u + 3 * edges_[e][1];
    double* c = ecross + 3 * e;
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
    elen[e] = std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    einv[e] = elen[e] > 0.0 ? 1.0 / elen[e] : 0.0;
    // theta from the half chords |u_a - u_b| / 2 = sin(theta/2) and |u_a + u_b| / 2 =
    // cos(theta/2), whichever is smaller: asin of at most sqrt(1/2), accurate for every angle
    // (atan2(|e|, u_a . u_b) is too, at twice the cost).
    const double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
    const double sx = a[0] + b[0], sy = a[1] + b[1], sz = a[2] + b[2];
    const double l = std::sqrt(dx * dx + dy * dy + dz * dz);
    const double m = std::sqrt(sx * sx + sy * sy + sz * sz);
    etheta[e] = l <= m ? 2.0 * std::asin(0.5 * l) : kPi - 2.0 * std::asin(0.5 * m);
    eray[e] = r[0] * c[0] + r[1] * c[1] + r[2] * c[2];
  }

  std::fill(w, w + n, 0.0);
  int winding = 0;
  for (Index f = 0, nf = F.rows(); f < nf; ++f)
  {
    const int p[3] = { F(f, 0), F(f, 1), F(f, 2) };
    // edge k of the face joins p[k] and p[k+1]; its arc cross product is s[k] * ecross[E[k]]
    std::size_t E[3];
    double s[3];
    for (int k = 0; k < 3; ++k)
    {
      const unsigned code = face_edges_[static_cast<std::size_t>(3 * f + k)];
      E[k] = code >> 1;
      s[k] = (code & 1u) ? -1.0 : 1.0;
    }
    // det[u0, u1, u2] = u0 . (u1 x u2): its sign tells which side of the face x is on
    const double* u0 = u + 3 * p[0];
    const double* c1 = ecross + 3 * E[1];
    const double det = s[1] * (u0[0] * c1[0] + u0[1] * c1[1] + u0[2] * c1[2]);

    // Distance from x to the face's plane is d0 d1 d2 |det| / (2 area).
    const double plane_distance = d[p[0]] * d[p[1]] * d[p[2]] * std::abs(det) *
      inv_twice_area_[static_cast<std::size_t>(f)];
    if (plane_distance <= tolerance_)
    {
      const Eigen::Vector3d a = V.row(p[0]), b = V.row(p[1]), c = V.row(p[2]);
      double lambda[3];
      const double dist2 = closest_on_triangle(Eigen::Vector3d(x[0], x[1], x[2]), a, b, c, lambda);
      if (dist2 <= tolerance_ * tolerance_)
      { // on this face (or its edges): barycentric interpolation
        std::fill(w, w + n, 0.0);
        for (int k = 0; k < 3; ++k)
          w[p[k]] = lambda[k];
        return PointLocation::Boundary;
      }
      continue; // in the face's plane but outside it: the face contributes nothing
    }
    if (elen[E[0]] == 0.0 || elen[E[1]] == 0.0 || elen[E[2]] == 0.0 || det == 0.0)
      continue; // x on the line of an edge, outside it: the face is seen edge-on

    const double q0 = s[0] * eray[E[0]], q1 = s[1] * eray[E[1]], q2 = s[2] * eray[E[2]];
    if (det > 0.0 ? (q0 > 0.0 && q1 > 0.0 && q2 > 0.0) : (q0 < 0.0 && q1 < 0.0 && q2 < 0.0))
      winding += det > 0.0 ? 1 : -1;

    double theta[3], sin_t[3], cosA[3];
    for (int k = 0; k < 3; ++k)
    {
      const int k1 = (k + 1) % 3, k2 = (k + 2) % 3;
      theta[k] = etheta[E[k1]]; // arc opposite vertex k: edge k+1
      sin_t[k] = elen[E[k1]];
      const double* ca = ecross + 3 * E[k];
      const double* cb = ecross + 3 * E[k2];
      cosA[k] = -s[k] * s[k2] * (ca[0] * cb[0] + ca[1] * cb[1] + ca[2] * cb[2]) * einv[E[k]] *
        einv[E[k2]];
    }
    const double inv_det = 1.0 / det;
    for (int k = 0; k < 3; ++k)
    {
      const int k1 = (k + 1) % 3, k2 = (k + 2) % 3;
      w[p[k]] += sin_t[k] * (theta[k] - cosA[k1] * theta[k2] - cosA[k2] * theta[k1]) * inv_det *
        inv_d[p[k]];
    }
  }
  normalize(w, n);
  return winding != 0 ? PointLocation::Inside : PointLocation::Outside;
}

MeanValueResult MeanValueCoordinates::evaluate(const Points& P, const ProgressCallback& progress) const
{
  MeanValueResult result;
  evaluate(P, result, progress);
  return result;
}

void MeanValueCoordinates::evaluate(
  const Points& P, MeanValueResult& out, const ProgressCallback& progress) const
{
  const Index dim = dimension();
  if (P.cols() != dim)
    throw Error(ErrorCode::SizeMismatch,
      "the points have " + std::to_string(P.cols()) + " coordinates but the cage is " +
        std::to_string(dim) + "D");
  for (Index p = 0; p < P.rows(); ++p)
    if (!P.row(p).allFinite())
      throw Error(ErrorCode::NonFinite,
        "point " + std::to_string(p) + " has a non-finite coordinate");

  const Index np = P.rows(), nc = num_controls();
  // every field starts afresh but W's and the locations' storage (each row of W is written
  // whole below, whatever it held)
  MeanValueResult result;
  result.W.swap(out.W);
  result.location.swap(out.location);
  out = MeanValueResult{};
  if (result.W.rows() != np || result.W.cols() != nc)
  {
    result.W.resize(np, nc);
    detail::advise_huge_pages(result.W.data(), sizeof(double) * static_cast<std::size_t>(result.W.size()));
  }
  result.location.assign(static_cast<std::size_t>(np), PointLocation::Inside);

  // Points are handed out in small chunks (load balance: a per-block region with coarse chunks
  // left one of two threads idle a third of the time); every point is computed independently
  // into its own row, so the result does not depend on the threads.
  ProgressReporter reporter(progress, np);
  const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> X = P;
  constexpr Index chunk = 8;
#if defined(BARY_MVC_VECTOR_KERNEL)
  // (the kernel addresses its scratch records with 32-bit offsets)
  if (dim == 3 && kEdgeStride * edges_.size() < (std::size_t{ 1 } << 31) &&
    kVertexStride * static_cast<std::size_t>(nc) < (std::size_t{ 1 } << 31))
  {
    // four points per call of the vector kernel (see mvc3d_group); its special lanes and the
    // unused lanes of a last, partial group are left to evaluate_3d / ignored
    const Index nf = cage_.F.rows();
    std::vector<Mvc3dFace> faces(static_cast<std::size_t>(nf));
    for (Index f = 0; f < nf; ++f)
    {
      Mvc3dFace& face = faces[static_cast<std::size_t>(f)];
      for (int k = 0; k < 3; ++k)
      {
        const unsigned code = face_edges_[static_cast<std::size_t>(3 * f + k)];
        face.vertex[k] = static_cast<std::uint32_t>(kVertexStride * static_cast<std::size_t>(cage_.F(f, k)));
        face.edge[k] = static_cast<std::uint32_t>(kEdgeStride * (code >> 1));
        face.s[k] = (code & 1u) ? -1.0 : 1.0;
      }
      for (int k = 0; k < 3; ++k)
        face.t[k] = -face.s[k] * face.s[(k + 2) % 3];
      face.inv_twice_area = inv_twice_area_[static_cast<std::size_t>(f)];
    }
    const Mvc3dCage c{ cage_.V.data(), nc, nf, edges_.data(), edges_.size(),
      faces.data(), tolerance_ };
    const bool avx2 = detail::simd_level() == detail::SimdLevel::AVX2;
    const std::size_t scratch_size = (kVertexStride + 1) * static_cast<std::size_t>(nc) +
      kEdgeStride * edges_.size() + 4 * static_cast<std::size_t>(nf);
    detail::parallel_for(np, chunk, options_.threads, reporter, "mean value coordinates",
      [&](Index begin, Index end) {
        thread_local std::vector<double, detail::AlignedAllocator<double>> buffer;
        if (buffer.size() < scratch_size)
          buffer.resize(scratch_size);
        double* spare = buffer.data() + scratch_size - static_cast<std::size_t>(nc);
        for (Index p = begin; p < end; p += 4)
        {
          const int lanes = static_cast<int>(std::min<Index>(4, end - p));
          alignas(32) double xyz[12];
          double* rows[4];
          for (int l = 0; l < 4; ++l)
          {
            const Index q = p + std::min(l, lanes - 1);
            for (int k = 0; k < 3; ++k)
              xyz[4 * k + l] = X(q, k);
            rows[l] = l < lanes ? result.W.row(p + l).data() : spare;
          }
          long long winding[4];
          unsigned special = 0;
#if BARY_HAVE_AVX2_DISPATCH
          if (avx2)
            special = mvc3d_group_avx2(c, xyz, buffer.data(), rows, winding);
          else
#endif
            special = mvc3d_group_portable(c, xyz, buffer.data(), rows, winding);
          for (int l = 0; l < lanes; ++l)
          {
            PointLocation& location = result.location[static_cast<std::size_t>(p + l)];
            if (special & (1u << l))
              location = evaluate_3d(X.row(p + l).data(), rows[l]);
            else
            {
              normalize(rows[l], nc);
              location = winding[l] != 0 ? PointLocation::Inside : PointLocation::Outside;
            }
          }
        }
      });
  }
  else
#endif
    detail::parallel_for(np, chunk, options_.threads, reporter, "mean value coordinates",
      [&](Index begin, Index end) {
        for (Index p = begin; p < end; ++p)
          result.location[static_cast<std::size_t>(p)] =
            evaluate(X.row(p).data(), result.W.row(p).data());
      });

  for (Index p = 0; p < np; ++p)
  {
    switch (result.location[static_cast<std::size_t>(p)])
    {
      case PointLocation::Inside: ++result.inside; break;
      case PointLocation::Outside: ++result.outside; break;
      case PointLocation::Boundary: ++result.boundary; break;
    }
    if (std::isnan(result.W(p, 0)))
      result.undefined.push_back(p);
  }
  out = std::move(result);
}

DenseWeights mean_value_coordinates(const Cage& cage, const Points& P, const MeanValueOptions& options)
{
  return MeanValueCoordinates(cage, options).evaluate(P).W;
}

} // namespace bary
