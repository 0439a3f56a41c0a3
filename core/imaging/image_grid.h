#pragma once
/// @file image_grid.h
/// A regular 3D image grid as ITK, DICOM and VTK's vtkImageData (with a direction matrix)
/// describe it: the voxel (i, j, k) lies at the physical point
///   p = origin + direction * (spacing ∘ (i, j, k)),
/// i fastest in memory (voxel v = i + size0 (j + size1 k)). BaryLab's physical space is LPS in
/// millimetres (docs/organ-workflow.md); the grid does not care, it maps indices to points.

#include "core/common/types.h"

#include <Eigen/Core>

#include <array>

namespace bary
{

struct ImageGrid
{
  std::array<Index, 3> size{ { 0, 0, 0 } }; ///< voxels along i, j, k (each >= 1)
  Eigen::Vector3d origin = Eigen::Vector3d::Zero(); ///< the physical point of voxel (0, 0, 0)
  Eigen::Vector3d spacing = Eigen::Vector3d::Ones(); ///< voxel size along i, j, k (each > 0)
  /// Columns: the physical directions of the i, j, k axes (invertible; usually orthonormal).
  Eigen::Matrix3d direction = Eigen::Matrix3d::Identity();

  /// size0 * size1 * size2.
  Index voxel_count() const { return size[0] * size[1] * size[2]; }
  /// The linear voxel number of (i, j, k), i fastest.
  Index voxel(Index i, Index j, Index k) const { return i + size[0] * (j + size[1] * k); }
  /// direction * diag(spacing): physical offset = M * (continuous index offset).
  Eigen::Matrix3d index_to_physical() const;
  /// The physical point of the (continuous) index @p index.
  Eigen::Vector3d point(const Eigen::Vector3d& index) const;
  /// The physical point of voxel (i, j, k).
  Eigen::Vector3d point(Index i, Index j, Index k) const;
  /// The continuous index of the physical point @p p (the inverse of point()).
  Eigen::Vector3d continuous_index(const Eigen::Vector3d& p) const;
};

/// Checks a grid: every size >= 1, finite origin, spacing finite and > 0, direction finite and
/// invertible (|det| >= 1e-6 with unit columns; a direction whose columns are not of unit
/// length is refused too, since ITK and the file formats store unit axes), voxel count below
/// 2^40.
/// @param what how the message names the grid ("the reference image")
/// @throws Error(InvalidArgument) naming the faulty member, Error(NonFinite) for NaN/inf.
void validate_image_grid(const ImageGrid& grid, const char* what = "the image grid");

/// The smallest grid with spacing @p spacing (identity direction) whose voxel centres cover the
/// axis-aligned box [lower, upper] (the last voxel centre at or beyond upper).
/// @throws Error(InvalidArgument) if spacing <= 0, the box is empty or inverted, or the grid
/// would have more than 2^31 voxels; Error(NonFinite) for NaN/inf.
ImageGrid grid_from_bounds(
  const Eigen::Vector3d& lower, const Eigen::Vector3d& upper, const Eigen::Vector3d& spacing);

/// The physical points of every voxel of @p grid, voxel_count() by 3, in voxel order.
Points grid_points(const ImageGrid& grid);

/// True if two grids have the same size and, within @p tolerance (relative to the spacing), the
/// same origin, spacing and direction.
bool same_grid(const ImageGrid& a, const ImageGrid& b, double tolerance = 1e-6);

} // namespace bary
