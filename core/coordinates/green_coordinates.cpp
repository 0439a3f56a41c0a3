#include "core/coordinates/green_coordinates.h"

#include "core/common/error.h"
#include "core/detail/closest_point.h"
#include "core/detail/parallel_for.h"
#include "core/detail/constants.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace bary
{
namespace
{


// ---------------------------------------------------------------------------------------------
// 2D. Edge from v1 to v2 = v1 + a, seen from x; b = v1 - x, r(t)^2 = |b + t a|^2 = Q t^2 + R t + S
// (Q = |a|^2, R = 2 a.b, S = |b|^2), outward normal n = (a_y, -a_x) / |a| (counter-clockwise),
// c = cross(b, a) = |a| b.n = |a| (xi - x).n for every xi on the edge. With G = log(r) / (2 pi):
//   dG/dn = c / (2 pi |a| r^2),   integral_0^1 dt / r^2 = theta / |c|,
// theta the (unsigned) angle the edge subtends at x; Theta = sign(c) theta = atan2(c, b.(a+b))
// is the signed angle, accurate for every angle (the paper's arctangents of R / sqrt(4SQ - R^2)
// overflow on the edge's line). With L10 = log(|a+b|^2 / |b|^2) = integral_0^1 (2Qt + R) / r^2:
//   phi_2 += c/(2 pi) int t / r^2    = (c L10 / (2Q) - Theta R / (2Q)) / (2 pi)
//   phi_1 += c/(2 pi) int (1-t) / r^2 = (Theta - c L10 / (2Q) + Theta R / (2Q)) / (2 pi)
//   psi    = -|a| / (4 pi) int_0^1 log(r^2) dt
//          = -|a| / (4 pi) (2 c Theta / Q + R L10 / (2Q) + L1 - 2),   L1 = log |a+b|^2
// (int log(r^2) = L1 - 2 + int (R t + 2S) / r^2, and 4SQ - R^2 = 4 c^2): the paper's
// (4S - R^2/Q) A10 term is 2 c Theta / Q, finite everywhere.
// ---------------------------------------------------------------------------------------------

inline double cross2(double ax, double ay, double bx, double by)
{
  return ax * by - ay * bx;
}

// ---------------------------------------------------------------------------------------------
// 3D. Triangle (V0, V1, V2) with unit normal n (right-hand rule), area A, in-plane outward edge
// normals m_l (edge l from V_l to V_{l+1}); v_k = V_k - x, h = v_0.n (x's depth behind the
// plane). With G = -1 / (4 pi r):
//  - dG/dn = h / (4 pi r^3); the solid angle Omega = integral h / r^3 (signed; van Oosterom &
//    Strackee's arctangent, accurate for every angle);
//  - w = integral (xi - x) / r^3 = n Omega - sum_l m_l J_l, J_l = integral over edge l of 1/r
//    (the in-plane part is minus the tangential gradient of 1/r, integrated by the divergence
//    theorem in the plane);
//  - with Gamma_k the hat functions, sum_k Gamma_k(xi) v_k = xi - x, so g_k = int Gamma_k / r^3
//    solve [v0 v1 v2] g = w, and phi_k = h g_k / (4 pi) = (v_{k+1} x v_{k+2}).w / (8 pi A)
//    since det[v0 v1 v2] = 2 A h: no division by h (the paper's Algorithm 1 divides by
//    N_{k+1}.v_k instead, which is the same ratio);
//  - psi = integral 1 / (4 pi r) (the paper's GCTriInt): in the plane, div F = 1 / r for
//    F(rho) = rho (r - |h|) / |rho|^2 (rho the in-plane offset from x's projection p), so
//    integral_T 1/r = sum_l d_l integral_l (r - |h|) / rho^2 with d_l = (V_l - p).m_l, and per
//    edge (s the coordinate along it from p's foot, R0^2 = d^2 + h^2):
//      d integral (r - |h|) / (d^2 + s^2) ds = d J_l - |h| [atan(s d (r - |h|) / (d^2 r + |h| s^2))]
//    (the difference of atan(s / d) and atan(|h| s / (d r)) in one arctangent: no 0/0 when p
//    lies on the edge's line; the bracket's two ends are then one atan2).
// ---------------------------------------------------------------------------------------------

/// integral over the segment [A, B] (relative to x) of 1 / r, from asinh(s_B / R0) -
/// asinh(s_A / R0) written without cancellation. s_A < s_B are the ends' coordinates along the
/// segment, r_A, r_B their distances, R0sq the squared distance from x to the segment's line.
inline double edge_integral(double sA, double sB, double rA, double rB, double R0sq)
{
  if (sA >= 0.0)
    return std::log((rB + sB) / (rA + sA));
  if (sB <= 0.0)
    return std::log((rA - sA) / (rB - sB));
  return std::log((rB + sB) * (rA - sA) / R0sq);
}

/// One triangle's single-layer integral (times 4 pi: integral of 1/r) and, unless @p phi_out is
/// null, its double-layer terms: the solid angle is returned in @p omega and
/// (v_{k+1} x v_{k+2}).w / (8 pi A) added to phi_out[k].
struct TriangleTerms
{
  double single_layer = 0.0; // integral over the triangle of 1 / r
  double omega = 0.0;        // signed solid angle
  double phi[3] = { 0.0, 0.0, 0.0 };
};

TriangleTerms triangle_terms(const Eigen::Vector3d v[3], const double* n, double twice_area,
  const double* edge_normals, const double* edge_tangents, bool with_phi)
{
  TriangleTerms out;
  const Eigen::Vector3d N(n[0], n[1], n[2]);
  const double h = v[0].dot(N);
  const double ah = std::abs(h);
  const double r[3] = { v[0].norm(), v[1].norm(), v[2].norm() };
  Eigen::Vector3d w = Eigen::Vector3d::Zero();
  for (int l = 0; l < 3; ++l)
  {
    const Eigen::Vector3d& A = v[l];
    const Eigen::Vector3d& B = v[(l + 1) % 3];
    const Eigen::Vector3d t(edge_tangents[3 * l], edge_tangents[3 * l + 1], edge_tangents[3 * l + 2]);
    const Eigen::Vector3d m(edge_normals[3 * l], edge_normals[3 * l + 1], edge_normals[3 * l + 2]);
    const double sA = A.dot(t), sB = B.dot(t), rA = r[l], rB = r[(l + 1) % 3];
    const double d = A.dot(m);
    const double R0sq = d * d + h * h;
    if (R0sq == 0.0 || rA == 0.0 || rB == 0.0)
      continue; // x on the edge's line or at its end: only on the cage, where the caller takes
                // the limit (the edge's d J and arctangents vanish there)
    const double J = edge_integral(sA, sB, rA, rB, R0sq);
    w -= m * J;
    if (d != 0.0)
    {
      // atan(pB / qB) - atan(pA / qA) with q > 0 (d != 0, r > 0) in one atan2: both arctangents
      // lie in (-pi/2, pi/2), so their difference is the angle of (qA, pA)^* (qB, pB)
      const double pA = sA * d * (d * d + sA * sA) / (rA + ah); // s d (r - |h|), no cancellation
      const double pB = sB * d * (d * d + sB * sB) / (rB + ah);
      const double qA = d * d * rA + ah * sA * sA, qB = d * d * rB + ah * sB * sB;
      out.single_layer += d * J - ah * std::atan2(pB * qA - pA * qB, qA * qB + pA * pB);
    }
  }
  if (!with_phi)
    return out;
  const double det = v[0].dot(v[1].cross(v[2]));
  const double denom =
    r[0] * r[1] * r[2] + v[0].dot(v[1]) * r[2] + v[0].dot(v[2]) * r[1] + v[1].dot(v[2]) * r[0];
  out.omega = 2.0 * std::atan2(det, denom);
  w += N * out.omega;
  const double scale = 1.0 / (4.0 * kPi * twice_area);
  for (int k = 0; k < 3; ++k)
    out.phi[k] = v[(k + 1) % 3].cross(v[(k + 2) % 3]).dot(w) * scale;
  return out;
}

} // namespace

GreenCoordinates::GreenCoordinates(Cage cage, const GreenOptions& options)
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
  else
  {
    if (cage_.V.rows() == 0)
      throw Error(ErrorCode::EmptyInput, "the cage has no vertices");
    if (cage_.dimension() != 2 && cage_.dimension() != 3)
      throw Error(ErrorCode::SizeMismatch, "cage vertices must have 2 or 3 coordinates");
    if (!cage_.V.allFinite())
      throw Error(ErrorCode::NonFinite, "the cage has a non-finite coordinate");
    if (cage_.dimension() == 3 &&
      (cage_.F.cols() != 3 || cage_.F.rows() == 0 || cage_.F.minCoeff() < 0 ||
        cage_.F.maxCoeff() >= cage_.V.rows()))
      throw Error(ErrorCode::InvalidCage, "a 3D cage needs triangles whose indices are vertices");
  }
  tolerance_ = options.boundary_tolerance * cage_.diameter();
  sigma_ = is_positively_oriented(cage_) ? 1.0 : -1.0;
  if (cage_.dimension() == 3)
  {
    const Index nf = cage_.F.rows();
    normal_.resize(static_cast<std::size_t>(3 * nf));
    twice_area_.resize(static_cast<std::size_t>(nf));
    edge_normal_.resize(static_cast<std::size_t>(9 * nf));
    edge_tangent_.resize(static_cast<std::size_t>(9 * nf));
    for (Index f = 0; f < nf; ++f)
    {
      Eigen::Vector3d V[3];
      for (int k = 0; k < 3; ++k)
        V[k] = cage_.V.row(cage_.F(f, k)).transpose();
      const Eigen::Vector3d c = (V[1] - V[0]).cross(V[2] - V[0]);
      const double twice = c.norm();
      if (!(twice > 0.0))
        throw Error(ErrorCode::InvalidCage, "face " + std::to_string(f) + " of the cage has zero area");
      const Eigen::Vector3d n = c / twice;
      twice_area_[static_cast<std::size_t>(f)] = twice;
      for (int i = 0; i < 3; ++i)
        normal_[static_cast<std::size_t>(3 * f + i)] = n(i);
      for (int l = 0; l < 3; ++l)
      {
        const Eigen::Vector3d t = (V[(l + 1) % 3] - V[l]).normalized();
        const Eigen::Vector3d m = t.cross(n).normalized();
        for (int i = 0; i < 3; ++i)
        {
          edge_normal_[static_cast<std::size_t>(9 * f + 3 * l + i)] = m(i);
          edge_tangent_[static_cast<std::size_t>(9 * f + 3 * l + i)] = t(i);
        }
      }
    }
  }
}

PointLocation GreenCoordinates::evaluate(const double* x, double* phi, double* psi) const
{
  return dimension() == 2 ? evaluate_2d(x, phi, psi) : evaluate_3d(x, phi, psi);
}

PointLocation GreenCoordinates::evaluate_2d(const double* x, double* phi, double* psi) const
{
  const Eigen::MatrixXd& V = cage_.V;
  const Index n = V.rows();
  std::fill(phi, phi + n, 0.0);
  std::fill(psi, psi + n, 0.0);

  // On the cage? (a vertex first, then an edge; the nearest within the tolerance)
  Index at_vertex = -1, on_edge = -1;
  double t0 = 0.0, best = tolerance_;
  for (Index i = 0; i < n; ++i)
  {
    const double r = std::hypot(V(i, 0) - x[0], V(i, 1) - x[1]);
    if (r <= best)
    {
      best = r;
      at_vertex = i;
    }
  }
  if (at_vertex < 0)
    for (Index j = 0; j < n; ++j)
    {
      const Index k = j + 1 == n ? 0 : j + 1;
      const double ax = V(k, 0) - V(j, 0), ay = V(k, 1) - V(j, 1);
      const double bx = V(j, 0) - x[0], by = V(j, 1) - x[1];
      const double len = std::hypot(ax, ay);
      const double dist = std::abs(cross2(bx, by, ax, ay)) / len;
      const double t = -(ax * bx + ay * by) / (len * len);
      if (t > 0.0 && t < 1.0 && dist <= best)
      {
        best = dist;
        on_edge = j;
        t0 = t;
      }
    }
  double y[2] = { x[0], x[1] };
  if (at_vertex >= 0)
  {
    y[0] = V(at_vertex, 0);
    y[1] = V(at_vertex, 1);
  }
  else if (on_edge >= 0)
  {
    const Index k = on_edge + 1 == n ? 0 : on_edge + 1;
    y[0] = V(on_edge, 0) + t0 * (V(k, 0) - V(on_edge, 0));
    y[1] = V(on_edge, 1) + t0 * (V(k, 1) - V(on_edge, 1));
  }

  constexpr double inv2pi = 1.0 / (2.0 * kPi), inv4pi = 1.0 / (4.0 * kPi);
  double theta_sum = 0.0; // angles subtended by the edges not incident to y
  for (Index j = 0; j < n; ++j)
  {
    const Index k = j + 1 == n ? 0 : j + 1;
    const double ax = V(k, 0) - V(j, 0), ay = V(k, 1) - V(j, 1);
    const double bx = V(j, 0) - y[0], by = V(j, 1) - y[1];
    const double Q = ax * ax + ay * ay, len = std::sqrt(Q);
    const double S = bx * bx + by * by;
    const double ab = ax * bx + ay * by, R = 2.0 * ab;
    const double cx = ax + bx, cy = ay + by; // v2 - y
    const double S1 = cx * cx + cy * cy;
    if (at_vertex == j || at_vertex == k)
    { // y at an end of the edge: int_0^1 log(Q t^2) dt = log Q - 2
      psi[j] = -len * inv4pi * (std::log(Q) - 2.0);
      continue;
    }
    const double L1 = std::log(S1), L10 = std::log(S1 / S);
    if (on_edge == j)
    { // y on the edge: c = 0
      psi[j] = -len * inv4pi * (R * L10 / (2.0 * Q) + L1 - 2.0);
      continue;
    }
    const double c = cross2(bx, by, ax, ay);
    const double theta = std::atan2(c, S + ab);
    theta_sum += theta;
    phi[j] += (theta - c * L10 / (2.0 * Q) + theta * R / (2.0 * Q)) * inv2pi;
    phi[k] += (c * L10 / (2.0 * Q) - theta * R / (2.0 * Q)) * inv2pi;
    psi[j] = -len * inv4pi * (2.0 * c * theta / Q + R * L10 / (2.0 * Q) + L1 - 2.0);
  }

  PointLocation where;
  if (at_vertex >= 0 || on_edge >= 0)
  { // the interior limit: the incident edges subtend 2 pi sigma minus the others' angles
    const double rest = (2.0 * kPi * sigma_ - theta_sum) * inv2pi;
    if (at_vertex >= 0)
      phi[at_vertex] += rest;
    else
    {
      const Index k = on_edge + 1 == n ? 0 : on_edge + 1;
      phi[on_edge] += rest * (1.0 - t0);
      phi[k] += rest * t0;
    }
    where = PointLocation::Boundary;
  }
  else
    where = std::abs(theta_sum) > kPi ? PointLocation::Inside : PointLocation::Outside;

  for (Index i = 0; i < n; ++i)
  {
    phi[i] *= sigma_;
    psi[i] *= sigma_;
  }
  if (where == PointLocation::Outside && options_.extend_outside)
    extend_2d(x, phi, psi);
  return where;
}

// The paper's extension beyond the cage, 2D: x = alpha_j v_j + alpha_k v_k + beta n_j over the
// nearest edge j (alpha: affine coordinates of x's projection onto its line).
void GreenCoordinates::extend_2d(const double* x, double* phi, double* psi) const
{
  const Eigen::MatrixXd& V = cage_.V;
  const Index n = V.rows();
  Index nearest = 0;
  double best = std::numeric_limits<double>::infinity(), best_height = 0.0;
  const double tie = 1e-12 * cage_.diameter();
  for (Index j = 0; j < n; ++j)
  {
    const Index k = j + 1 == n ? 0 : j + 1;
    const Eigen::Vector2d a(V(k, 0) - V(j, 0), V(k, 1) - V(j, 1));
    const Eigen::Vector2d p(x[0] - V(j, 0), x[1] - V(j, 1));
    const double t = std::clamp(p.dot(a) / a.squaredNorm(), 0.0, 1.0);
    const double dist = (p - t * a).norm();
    // outward height (sigma makes the normal outward): breaks ties at a convex corner towards
    // the edge the point is most in front of
    const double height = sigma_ * cross2(p.x(), p.y(), a.x(), a.y()) / a.norm();
    if (dist < best - tie || (dist <= best + tie && height > best_height))
    {
      best = dist;
      best_height = height;
      nearest = j;
    }
  }
  const Index j = nearest, k = j + 1 == n ? 0 : j + 1;
  const Eigen::Vector2d a(V(k, 0) - V(j, 0), V(k, 1) - V(j, 1));
  const Eigen::Vector2d p(x[0] - V(j, 0), x[1] - V(j, 1));
  const double t = p.dot(a) / a.squaredNorm();
  phi[j] += 1.0 - t;
  phi[k] += t;
  psi[j] += cross2(p.x(), p.y(), a.x(), a.y()) / a.norm(); // p . (a_y, -a_x) / |a|
}

PointLocation GreenCoordinates::evaluate_3d(const double* x, double* phi, double* psi) const
{
  const Eigen::MatrixXd& V = cage_.V;
  const Eigen::MatrixXi& F = cage_.F;
  const Index n = V.rows(), nf = F.rows();
  std::fill(phi, phi + n, 0.0);
  std::fill(psi, psi + nf, 0.0);
  const Eigen::Vector3d X(x[0], x[1], x[2]);

  auto vertex = [&](Index f, int k) -> Eigen::Vector3d { return V.row(F(f, k)).transpose(); };
  auto normal = [&](Index f) {
    const double* m = normal_.data() + 3 * f;
    return Eigen::Vector3d(m[0], m[1], m[2]);
  };

  // On the cage? The nearest face point within the tolerance (planes first: cheap).
  Eigen::Vector3d y = X;
  bool on_cage = false;
  {
    double best = tolerance_;
    for (Index f = 0; f < nf; ++f)
    {
      if (std::abs((vertex(f, 0) - X).dot(normal(f))) > best)
        continue;
      const Eigen::Vector3d a = vertex(f, 0), b = vertex(f, 1), c = vertex(f, 2);
      const Eigen::Vector3d l = detail::closest_on_triangle(X, a, b, c);
      const Eigen::Vector3d q = l(0) * a + l(1) * b + l(2) * c;
      const double dist = (q - X).norm();
      if (dist <= best)
      {
        best = dist;
        y = q;
        on_cage = true;
      }
    }
  }

  constexpr double inv4pi = 1.0 / (4.0 * kPi);
  double omega_sum = 0.0; // solid angles of the faces not incident to y
  // incident faces (y on them within the tolerance) and y's barycentric coordinates there
  thread_local std::vector<std::pair<Index, Eigen::Vector3d>> incident;
  incident.clear();
  for (Index f = 0; f < nf; ++f)
  {
    Eigen::Vector3d v[3];
    for (int k = 0; k < 3; ++k)
      v[k] = vertex(f, k) - y;
    if (on_cage && std::abs(v[0].dot(normal(f))) <= tolerance_)
    {
      const Eigen::Vector3d a = vertex(f, 0), b = vertex(f, 1), c = vertex(f, 2);
      const Eigen::Vector3d l = detail::closest_on_triangle(y, a, b, c);
      if ((l(0) * a + l(1) * b + l(2) * c - y).norm() <= tolerance_)
      {
        incident.emplace_back(f, l);
        psi[f] = triangle_terms(v, normal_.data() + 3 * f, twice_area_[static_cast<std::size_t>(f)],
                   edge_normal_.data() + 9 * f, edge_tangent_.data() + 9 * f, false)
                   .single_layer *
          inv4pi;
        continue;
      }
    }
    const TriangleTerms t = triangle_terms(v, normal_.data() + 3 * f,
      twice_area_[static_cast<std::size_t>(f)], edge_normal_.data() + 9 * f,
      edge_tangent_.data() + 9 * f, true);
    psi[f] = t.single_layer * inv4pi;
    omega_sum += t.omega;
    for (int k = 0; k < 3; ++k)
      phi[F(f, k)] += t.phi[k];
  }

  PointLocation where;
  if (on_cage && !incident.empty())
  { // the interior limit: the incident faces subtend 4 pi sigma minus the others' solid angles,
    // shared among them with y's barycentric coordinates (equal on their common vertices)
    const double rest = (4.0 * kPi * sigma_ - omega_sum) * inv4pi / static_cast<double>(incident.size());
    for (const auto& [f, l] : incident)
      for (int k = 0; k < 3; ++k)
        phi[F(f, k)] += rest * l(k);
    where = PointLocation::Boundary;
  }
  else
    where = std::abs(omega_sum) > 2.0 * kPi ? PointLocation::Inside : PointLocation::Outside;

  for (Index i = 0; i < n; ++i)
    phi[i] *= sigma_;
  for (Index f = 0; f < nf; ++f)
    psi[f] *= sigma_;
  if (where == PointLocation::Outside && options_.extend_outside)
    extend_3d(x, phi, psi);
  return where;
}

// The paper's extension beyond the cage, 3D: x = sum_k alpha_k v_k + beta n_j over the nearest
// face j (alpha: barycentric coordinates of x's projection onto its plane, beta x's height).
void GreenCoordinates::extend_3d(const double* x, double* phi, double* psi) const
{
  const Eigen::MatrixXd& V = cage_.V;
  const Eigen::MatrixXi& F = cage_.F;
  const Eigen::Vector3d X(x[0], x[1], x[2]);
  Index nearest = 0;
  double best = std::numeric_limits<double>::infinity(), best_height = 0.0;
  const double tie = 1e-12 * cage_.diameter();
  for (Index f = 0, nf = F.rows(); f < nf; ++f)
  {
    const Eigen::Vector3d a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    const Eigen::Vector3d l = detail::closest_on_triangle(X, a, b, c);
    const double dist = (l(0) * a + l(1) * b + l(2) * c - X).norm();
    const Eigen::Vector3d nrm(normal_[3 * f], normal_[3 * f + 1], normal_[3 * f + 2]);
    const double height = sigma_ * (X - a).dot(nrm);
    if (dist < best - tie || (dist <= best + tie && height > best_height))
    {
      best = dist;
      best_height = height;
      nearest = f;
    }
  }
  const Index f = nearest;
  const Eigen::Vector3d nrm(normal_[3 * f], normal_[3 * f + 1], normal_[3 * f + 2]);
  Eigen::Vector3d v[3];
  for (int k = 0; k < 3; ++k)
    v[k] = V.row(F(f, k)).transpose() - X;
  const double inv = 1.0 / twice_area_[static_cast<std::size_t>(f)];
  for (int k = 0; k < 3; ++k)
    phi[F(f, k)] += v[(k + 1) % 3].cross(v[(k + 2) % 3]).dot(nrm) * inv;
  psi[f] += -v[0].dot(nrm); // (x - V0) . n
}

GreenResult GreenCoordinates::evaluate(const Points& P, const ProgressCallback& progress) const
{
  const Index dim = dimension();
  if (P.cols() != dim)
    throw Error(ErrorCode::SizeMismatch,
      "the points have " + std::to_string(P.cols()) + " coordinates but the cage is " +
        std::to_string(dim) + "D");
  for (Index p = 0; p < P.rows(); ++p)
    if (!P.row(p).allFinite())
      throw Error(ErrorCode::NonFinite, "point " + std::to_string(p) + " has a non-finite coordinate");

  const Index np = P.rows(), nc = num_controls(), nf = num_faces();
  GreenResult result;
  result.W.resize(np, nc);
  result.face_weights.resize(np, nf);
  result.location.assign(static_cast<std::size_t>(np), PointLocation::Inside);
  ProgressReporter reporter(progress, np);
  const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> X = P;
  constexpr Index chunk = 8;
  detail::parallel_for(np, chunk, options_.threads, reporter, "Green coordinates",
    [&](Index begin, Index end) {
      for (Index p = begin; p < end; ++p)
        result.location[static_cast<std::size_t>(p)] =
          evaluate(X.row(p).data(), result.W.row(p).data(), result.face_weights.row(p).data());
    });
  for (const PointLocation where : result.location)
    switch (where)
    {
      case PointLocation::Inside: ++result.inside; break;
      case PointLocation::Outside: ++result.outside; break;
      case PointLocation::Boundary: ++result.boundary; break;
    }
  return result;
}

GreenResult green_coordinates(const Cage& cage, const Points& P, const GreenOptions& options)
{
  return GreenCoordinates(cage, options).evaluate(P);
}

} // namespace bary
