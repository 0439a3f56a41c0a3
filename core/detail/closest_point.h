#pragma once
/// @file detail/closest_point.h
/// Closest points on segments and triangles, with their barycentric coordinates, and distances
/// between segments. Used by domain meshing (feature-size and Steiner-point checks) and by
/// MeshPointLocator. Header-only, no allocation, re-entrant.

#include <Eigen/Core>

#include <algorithm>
#include <cmath>

namespace bary::detail
{

/// Closest point to @p p on the segment [a, b] (any dimension): returns t in [0, 1] with the
/// closest point a + t (b - a). A degenerate segment gives t = 0.
template<class Vec>
inline double closest_on_segment(const Vec& p, const Vec& a, const Vec& b)
{
  const Vec ab = b - a;
  const double len2 = ab.squaredNorm();
  if (!(len2 > 0.0))
    return 0.0;
  return std::clamp((p - a).dot(ab) / len2, 0.0, 1.0);
}

/// Closest point to @p p on the triangle (a, b, c) in 3D (Ericson, "Real-Time Collision
/// Detection", 2005, Sect. 5.1.5, by Voronoi regions). Returns the barycentric coordinates
/// (u, v, w) of the closest point u a + v b + w c: all >= 0, summing to 1. Degenerate triangles
/// are handled (the closest point of their edges).
inline Eigen::Vector3d closest_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
  const Eigen::Vector3d& b, const Eigen::Vector3d& c)
{
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0)
    return { 1.0, 0.0, 0.0 };
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3)
    return { 0.0, 1.0, 0.0 };
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 && d1 - d3 > 0.0)
  {
    const double v = d1 / (d1 - d3);
    return { 1.0 - v, v, 0.0 };
  }
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6)
    return { 0.0, 0.0, 1.0 };
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 && d2 - d6 > 0.0)
  {
    const double w = d2 / (d2 - d6);
    return { 1.0 - w, 0.0, w };
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 && (d4 - d3) + (d5 - d6) > 0.0)
  {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return { 0.0, 1.0 - w, w };
  }
  const double sum = va + vb + vc;
  if (sum > 0.0 && va >= 0.0 && vb >= 0.0 && vc >= 0.0)
  {
    const double v = vb / sum, w = vc / sum;
    return { 1.0 - v - w, v, w };
  }
  // Degenerate triangle (or rounding at a region boundary): best of the three edges.
  Eigen::Vector3d best(1.0, 0.0, 0.0);
  double best_d = (p - a).squaredNorm();
  const Eigen::Vector3d* P[3] = { &a, &b, &c };
  for (int k = 0; k < 3; ++k)
  {
    const Eigen::Vector3d& s = *P[k];
    const Eigen::Vector3d& e = *P[(k + 1) % 3];
    const double t = closest_on_segment(p, s, e);
    const double d = (s + t * (e - s) - p).squaredNorm();
    if (d < best_d)
    {
      best_d = d;
      best.setZero();
      best(k) = 1.0 - t;
      best((k + 1) % 3) = t;
    }
  }
  return best;
}

/// Distance from @p p to the triangle (a, b, c) in 3D.
inline double point_triangle_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
  const Eigen::Vector3d& b, const Eigen::Vector3d& c)
{
  const Eigen::Vector3d l = closest_on_triangle(p, a, b, c);
  return (l(0) * a + l(1) * b + l(2) * c - p).norm();
}

/// Distance between the segments [p1, q1] and [p2, q2] in 3D (Ericson 2005, Sect. 5.1.9).
inline double segment_segment_distance(const Eigen::Vector3d& p1, const Eigen::Vector3d& q1,
  const Eigen::Vector3d& p2, const Eigen::Vector3d& q2)
{
  const Eigen::Vector3d d1 = q1 - p1, d2 = q2 - p2, r = p1 - p2;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  double s = 0.0, t = 0.0;
  if (a <= 0.0 && e <= 0.0)
    return r.norm();
  if (a <= 0.0)
    t = std::clamp(f / e, 0.0, 1.0);
  else
  {
    const double c = d1.dot(r);
    if (e <= 0.0)
      s = std::clamp(-c / a, 0.0, 1.0);
    else
    {
      const double b = d1.dot(d2), denom = a * e - b * b;
      s = denom > 0.0 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0.0)
      {
        t = 0.0;
        s = std::clamp(-c / a, 0.0, 1.0);
      }
      else if (t > 1.0)
      {
        t = 1.0;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  return (p1 + s * d1 - (p2 + t * d2)).norm();
}

} // namespace bary::detail
