#pragma once
/// @file image_resampling.h
/// Resampling a scalar image through a map y -> x(y) from the output grid's points to the
/// moving image's physical space: out(y) = moving(x(y)). To warp an image by a transform T
/// (rest -> deformed), the map is T^-1, e.g. y + v(y) with v the inverse displacement field
/// (invert_displacement_field): the moving image is pulled back, as itk::ResampleImageFilter
/// does with a transform from the output space to the input space. Interpolation and the
/// inside test follow ITK 5.2 (core/imaging/trilinear.h); points outside the moving image get
/// the default value.

#include "core/common/progress.h"
#include "core/common/types.h"
#include "core/imaging/displacement_field.h"
#include "core/imaging/image_grid.h"

#include <Eigen/Core>

#include <functional>
#include <vector>

namespace bary
{

/// A scalar image: one value per voxel of the grid, voxel order (i fastest). Label maps of any
/// integer type up to 32 bits are held exactly by doubles.
struct ScalarImage
{
  ImageGrid grid;
  std::vector<double> values;
};

enum class Interpolation
{
  Nearest, ///< the nearest voxel's value (label maps: values preserved exactly)
  Linear   ///< trilinear (intensities)
};

struct ResampleOptions
{
  Interpolation interpolation = Interpolation::Linear;
  double default_value = 0.0; ///< the value of output voxels whose x(y) is outside the image
  int threads = 0;            ///< 0: all cores
};

struct ResampleResult
{
  std::vector<double> values; ///< one per output voxel, voxel order
  Index outside = 0;          ///< output voxels that got the default value
};

/// x(y) for an output point y.
using PointMap = std::function<Eigen::Vector3d(const Eigen::Vector3d&)>;

/// out(y) = moving(map(y)) at every voxel y of @p output_grid. An empty map is the identity.
/// @throws Error(InvalidArgument) for an invalid grid, Error(SizeMismatch) if the moving image
/// does not have one value per voxel, Error(NonFinite) for a NaN/inf value in the moving image,
/// the default value or a mapped point, Error(Cancelled) when @p progress asks to stop.
ResampleResult resample_image(const ScalarImage& moving, const ImageGrid& output_grid,
  const PointMap& map, const ResampleOptions& options = {}, const ProgressCallback& progress = {});

/// Warping by a pull-back displacement field: out(y) = moving(y + v(y)), v sampled as
/// FieldSampler does (zero outside its grid). With v the inverse field of a forward field u,
/// this is the moving image carried to the deformed space by T(x) = x + u(x).
/// @throws the errors above and those of validate_displacement_field.
ResampleResult warp_image(const ScalarImage& moving, const ImageGrid& output_grid,
  const DisplacementField& pullback, const ResampleOptions& options = {},
  const ProgressCallback& progress = {});

} // namespace bary
