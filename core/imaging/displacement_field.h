#pragma once
/// @file displacement_field.h
/// Displacement fields on a regular grid, as ITK's itk::DisplacementFieldTransform and 3D
/// Slicer's grid transforms use them: the transform is T(x) = x + u(x), with u sampled at the
/// grid's voxels and interpolated trilinearly in between. Sampling follows ITK 5.2 exactly
/// (core/imaging/trilinear.h): a point whose continuous index lies in [-0.5, n - 0.5) on every
/// axis is inside, the stencil's neighbours are clamped to the grid (the half voxel beyond the
/// outer voxel centres repeats the border value), and a point outside gets zero displacement
/// (itk::DisplacementFieldTransform::TransformPoint returns the point itself). Also: the
/// Jacobian determinant of T (folds) and the inverse field by a relaxed fixed-point iteration.

#include "core/common/progress.h"
#include "core/common/types.h"
#include "core/imaging/image_grid.h"

#include <Eigen/Core>

namespace bary
{

struct DisplacementField
{
  ImageGrid grid;
  /// 3 by voxel_count(): column v is the displacement of voxel v (i fastest). Column-major, so
  /// the memory is x y z of voxel 0, x y z of voxel 1, ...: the layout of a 3-component
  /// vtkDataArray and of an ITK image of itk::Vector<double, 3>.
  Eigen::Matrix3Xd values;
};

/// Checks the grid (validate_image_grid), that values has 3 rows and one column per voxel,
/// and that every value is finite.
/// @throws Error(InvalidArgument), Error(SizeMismatch) or Error(NonFinite) naming the problem
/// (for NaN: the first voxel that has one).
void validate_displacement_field(const DisplacementField& field, const char* what = "the displacement field");

/// The field u = deformed - rest of the grid's voxels: @p deformed holds T(p) for each voxel's
/// point p (grid_points(grid)), voxel_count() by 3.
/// @throws Error(SizeMismatch) if deformed is not voxel_count() by 3, Error(NonFinite) for
/// NaN/inf (naming the first voxel and its point).
DisplacementField displacement_field_from_points(const ImageGrid& grid, const Points& deformed);

/// Trilinear sampling of a validated field at physical points (ITK's rules, see the file's
/// comment). Cheap to copy around threads: it only reads the field, which must outlive it.
class FieldSampler
{
public:
  /// Validates @p field (validate_displacement_field).
  explicit FieldSampler(const DisplacementField& field);
  /// u(p): trilinear inside the grid, zero outside.
  Eigen::Vector3d displacement(const Eigen::Vector3d& p) const;
  /// True when @p p is inside the grid (its continuous index in [-0.5, n - 0.5) on every axis).
  bool inside(const Eigen::Vector3d& p) const;
  const DisplacementField& field() const { return *field_; }

private:
  const DisplacementField* field_;
  Eigen::Matrix3d to_index_; ///< (direction diag(spacing))^-1
};

/// T(p) = p + u(p) for every row of @p points (#P by 3), on @p threads threads (0: all).
/// @throws Error(SizeMismatch) unless points has 3 columns, Error(NonFinite) for NaN/inf points.
Points transform_points(const DisplacementField& field, const Points& points, int threads = 0);

/// The Jacobian determinant det(I + du/dx) of T at the voxels: du/dx from central differences
/// of the stored values in index space (one-sided at the grid's faces, zero along an axis of
/// one voxel), mapped to physical space by (direction diag(spacing))^-1.
struct JacobianStatistics
{
  double minimum = 0.0;    ///< smallest determinant
  double maximum = 0.0;    ///< largest determinant
  Index folded = 0;        ///< voxels with determinant <= 0 (T folds there: no inverse)
  Index first_folded = -1; ///< the first such voxel (voxel order), -1 if none
  Index voxels = 0;
};
/// @param determinants if given, receives the determinant of every voxel (voxel order)
JacobianStatistics jacobian_statistics(const DisplacementField& field, int threads = 0,
  Eigen::VectorXd* determinants = nullptr);

struct InverseFieldOptions
{
  /// A voxel y has converged when its residual |x + u(x) - y| is at most this (physical units);
  /// 0: 1e-4 times the smallest spacing of the forward field's grid.
  double tolerance = 0.0;
  /// Iterations per voxel at most (>= 1).
  int max_iterations = 200;
  int threads = 0; ///< 0: all cores
};

struct InverseFieldResult
{
  /// v on the requested grid: T^-1(y) ≈ y + v(y) at its voxels.
  DisplacementField inverse;
  double tolerance = 0.0;     ///< the tolerance used
  double max_residual = 0.0;  ///< largest |x + u(x) - y| over the voxels
  double mean_residual = 0.0; ///< their mean
  Index not_converged = 0;    ///< voxels whose residual stayed above the tolerance
  Index first_not_converged = -1; ///< the first of them (voxel order), -1 if none
  /// Of not_converged, those whose best iterate x lies beyond the forward grid's outer voxel
  /// centres (a continuous index outside [0, n - 1]), where u is clamped and then cut to zero:
  /// T has no preimage of y inside the grid there (the field does not vanish at the grid's
  /// border; a larger grid or margin removes them). The others (not_converged -
  /// not_converged_at_border) are inside: a fold or a deformation too large to invert.
  Index not_converged_at_border = 0;
  int max_iterations_used = 0; ///< the most iterations one voxel took
  Index voxels = 0;
};

/// The inverse of T(x) = x + u(x) at the voxels y of @p grid: x solving x + u(x) = y, by the
/// fixed-point iteration x <- y - u(x) from x = y - u(y), relaxed where it does not contract:
/// the step is x <- x - a (x + u(x) - y), a = 1 (the plain iteration) halved while the residual
/// does not decrease and doubled back towards 1 after a decrease. Each voxel stops when its
/// residual is at most the tolerance, after max_iterations, when a falls below 1e-6, or when 20
/// iterations reduced the residual by less than the tolerance or 1% (stalled: no preimage, e.g.
/// at the grid's border or in a fold; a contraction of any rate below 0.9995 gains more); it
/// keeps its best iterate. The iteration converges where T is a contraction-close-to-identity and
/// invertible (Jacobian determinant > 0, |du/dx| < 1 everywhere it passes); where T folds
/// (jacobian_statistics) there is no inverse and voxels may not converge: they are counted in
/// not_converged, never hidden. Voxels y whose preimage is outside the forward grid get v = 0
/// (u is zero there). Results do not depend on the number of threads.
/// @throws Error(InvalidArgument) for options out of range or an invalid grid, the errors of
/// validate_displacement_field, Error(Cancelled) when @p progress asks to stop.
InverseFieldResult invert_displacement_field(const DisplacementField& forward,
  const ImageGrid& grid, const InverseFieldOptions& options = {},
  const ProgressCallback& progress = {});
/// Same on the forward field's own grid.
InverseFieldResult invert_displacement_field(const DisplacementField& forward,
  const InverseFieldOptions& options = {}, const ProgressCallback& progress = {});

} // namespace bary
