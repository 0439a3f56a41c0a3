#include "core/imaging/image_grid.h"

#include "core/common/error.h"
#include "core/detail/format.h"

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <string>

namespace bary
{

Eigen::Matrix3d ImageGrid::index_to_physical() const
{
  return direction * spacing.asDiagonal();
}

Eigen::Vector3d ImageGrid::point(const Eigen::Vector3d& index) const
{
  return origin + direction * spacing.cwiseProduct(index);
}

Eigen::Vector3d ImageGrid::point(Index i, Index j, Index k) const
{
  return point(Eigen::Vector3d(double(i), double(j), double(k)));
}

Eigen::Vector3d ImageGrid::continuous_index(const Eigen::Vector3d& p) const
{
  return index_to_physical().inverse() * (p - origin);
}

void validate_image_grid(const ImageGrid& grid, const char* what)
{
  const std::string name = what;
  for (int a = 0; a < 3; ++a)
    if (grid.size[a] < 1)
      throw Error(ErrorCode::InvalidArgument,
        name + " has " + std::to_string(grid.size[a]) + " voxels along axis " + std::to_string(a) +
          " (each axis needs at least one)");
  if (grid.size[0] > (Index(1) << 40) / grid.size[1] / grid.size[2])
    throw Error(ErrorCode::InvalidArgument, name + " has too many voxels (more than 2^40)");
  if (!grid.origin.allFinite())
    throw Error(ErrorCode::NonFinite, name + "'s origin contains NaN or infinity");
  if (!grid.spacing.allFinite())
    throw Error(ErrorCode::NonFinite, name + "'s spacing contains NaN or infinity");
  if (!(grid.spacing.minCoeff() > 0.0))
    throw Error(ErrorCode::InvalidArgument,
      name + "'s spacing " + detail::format_point(grid.spacing.data(), 3) +
        " is not positive along every axis");
  if (!grid.direction.allFinite())
    throw Error(ErrorCode::NonFinite, name + "'s direction matrix contains NaN or infinity");
  for (int a = 0; a < 3; ++a)
    if (std::abs(grid.direction.col(a).norm() - 1.0) > 1e-6)
      throw Error(ErrorCode::InvalidArgument,
        name + "'s direction matrix has a column of length " +
          detail::format_number(grid.direction.col(a).norm()) + " (axis " + std::to_string(a) +
          "); its columns must be unit vectors");
  const double det = grid.direction.determinant();
  if (!(std::abs(det) >= 1e-6))
    throw Error(ErrorCode::InvalidArgument,
      name + "'s direction matrix is singular (determinant " + detail::format_number(det) + ")");
}

ImageGrid grid_from_bounds(
  const Eigen::Vector3d& lower, const Eigen::Vector3d& upper, const Eigen::Vector3d& spacing)
{
  if (!lower.allFinite() || !upper.allFinite())
    throw Error(ErrorCode::NonFinite, "the grid's bounds contain NaN or infinity");
  if (!spacing.allFinite())
    throw Error(ErrorCode::NonFinite, "the grid's spacing contains NaN or infinity");
  if (!(spacing.minCoeff() > 0.0))
    throw Error(ErrorCode::InvalidArgument,
      "the grid's spacing " + detail::format_point(spacing.data(), 3) + " must be positive");
  ImageGrid grid;
  grid.origin = lower;
  grid.spacing = spacing;
  double count = 1.0;
  for (int a = 0; a < 3; ++a)
  {
    if (!(upper(a) >= lower(a)))
      throw Error(ErrorCode::InvalidArgument,
        "the grid's bounds are inverted along axis " + std::to_string(a) + " (" +
          detail::format_number(lower(a)) + " > " + detail::format_number(upper(a)) + ")");
    // the last centre at or beyond upper; 1e-9 forgives a bound that is a multiple of the
    // spacing up to rounding
    const double steps = std::ceil((upper(a) - lower(a)) / spacing(a) - 1e-9);
    const double n = std::max(0.0, steps) + 1.0;
    count *= n;
    if (!(count <= 2147483648.0))
      throw Error(ErrorCode::InvalidArgument,
        "a grid of spacing " + detail::format_point(spacing.data(), 3) + " over the bounds " +
          detail::format_point(lower.data(), 3) + " - " + detail::format_point(upper.data(), 3) +
          " would have more than 2^31 voxels",
        "choose a larger spacing");
    grid.size[a] = Index(n);
  }
  return grid;
}

Points grid_points(const ImageGrid& grid)
{
  Points P(grid.voxel_count(), 3);
  const Eigen::Matrix3d M = grid.index_to_physical();
  for (Index k = 0; k < grid.size[2]; ++k)
    for (Index j = 0; j < grid.size[1]; ++j)
      for (Index i = 0; i < grid.size[0]; ++i)
        P.row(grid.voxel(i, j, k)) =
          (grid.origin + M * Eigen::Vector3d(double(i), double(j), double(k))).transpose();
  return P;
}

bool same_grid(const ImageGrid& a, const ImageGrid& b, double tolerance)
{
  if (a.size != b.size)
    return false;
  const double h = std::min(a.spacing.minCoeff(), b.spacing.minCoeff());
  return (a.origin - b.origin).lpNorm<Eigen::Infinity>() <= tolerance * h &&
    (a.spacing - b.spacing).lpNorm<Eigen::Infinity>() <= tolerance * h &&
    (a.direction - b.direction).lpNorm<Eigen::Infinity>() <= tolerance;
}

} // namespace bary
