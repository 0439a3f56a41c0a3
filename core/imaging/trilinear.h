#pragma once
/// @file trilinear.h
/// Interpolation on an ImageGrid with ITK's rules (itk::LinearInterpolateImageFunction,
/// itk::VectorLinearInterpolateImageFunction, itk::NearestNeighborInterpolateImageFunction as
/// used by itk::DisplacementFieldTransform and itk::ResampleImageFilter, ITK 5.2): a point is
/// inside when each continuous index c lies in [-0.5, n - 0.5); the linear stencil's neighbours
/// are clamped to [0, n - 1] (so the half voxel beyond the outer centres repeats the border
/// value); nearest rounds half up. Internal to core/imaging.

#include "core/imaging/image_grid.h"

#include <cmath>

namespace bary::detail
{

/// A trilinear stencil: the 2 x 2 x 2 neighbours lo/hi per axis and the weight t of hi.
struct TrilinearStencil
{
  Index lo[3], hi[3];
  double t[3];
};

/// Continuous indices within 1e-9 of an integer are taken as that integer, so that sampling at
/// the grid's own voxels (index -> point -> index, with rounding) returns the stored values
/// exactly.
inline double snap_index(double c)
{
  const double r = std::nearbyint(c);
  return std::abs(c - r) < 1e-9 ? r : c;
}

/// Fills @p s for the continuous index @p c; false (s untouched) when c is outside the grid
/// (or NaN).
inline bool trilinear_stencil(const Eigen::Vector3d& c, const std::array<Index, 3>& n,
  TrilinearStencil& s)
{
  for (int a = 0; a < 3; ++a)
  {
    const double ca = snap_index(c(a));
    if (!(ca >= -0.5 && ca < double(n[a]) - 0.5))
      return false;
    const double f = std::floor(ca);
    Index lo = Index(f), hi = lo + 1;
    s.t[a] = ca - f;
    if (lo < 0)
      lo = 0;
    if (hi > n[a] - 1)
      hi = n[a] - 1;
    s.lo[a] = lo;
    s.hi[a] = hi;
  }
  return true;
}

/// The nearest voxel of the continuous index @p c (rounding half up); false when outside.
inline bool nearest_voxel(
  const Eigen::Vector3d& c, const std::array<Index, 3>& n, Index& i, Index& j, Index& k)
{
  Index r[3];
  for (int a = 0; a < 3; ++a)
  {
    const double ca = snap_index(c(a));
    if (!(ca >= -0.5 && ca < double(n[a]) - 0.5))
      return false;
    r[a] = Index(std::floor(ca + 0.5));
    if (r[a] > n[a] - 1) // only by rounding at n - 0.5 - ulp
      r[a] = n[a] - 1;
  }
  i = r[0];
  j = r[1];
  k = r[2];
  return true;
}

/// sum over the 8 corners of weight * values[C * voxel + component], for C components at
/// @p values (voxel order i fastest), into out[0..C).
template<int C>
inline void trilinear_sum(
  const TrilinearStencil& s, const std::array<Index, 3>& n, const double* values, double* out)
{
  for (int c = 0; c < C; ++c)
    out[c] = 0.0;
  for (int corner = 0; corner < 8; ++corner)
  {
    const Index i = (corner & 1) ? s.hi[0] : s.lo[0];
    const Index j = (corner & 2) ? s.hi[1] : s.lo[1];
    const Index k = (corner & 4) ? s.hi[2] : s.lo[2];
    const double w = ((corner & 1) ? s.t[0] : 1.0 - s.t[0]) *
      ((corner & 2) ? s.t[1] : 1.0 - s.t[1]) * ((corner & 4) ? s.t[2] : 1.0 - s.t[2]);
    if (w == 0.0)
      continue;
    const double* v = values + C * (i + n[0] * (j + n[1] * k));
    for (int c = 0; c < C; ++c)
      out[c] += w * v[c];
  }
}

} // namespace bary::detail
