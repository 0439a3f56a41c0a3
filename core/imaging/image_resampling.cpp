#include "core/imaging/image_resampling.h"

#include "core/common/error.h"
#include "core/detail/format.h"
#include "core/detail/parallel_for.h"
#include "core/imaging/trilinear.h"

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <string>

namespace bary
{
namespace
{
constexpr Index kResampleChunk = 4096; // output voxels per parallel chunk

void check_resample_input(
  const ScalarImage& moving, const ImageGrid& output_grid, const ResampleOptions& options)
{
  validate_image_grid(moving.grid, "the moving image");
  validate_image_grid(output_grid, "the output grid");
  if (Index(moving.values.size()) != moving.grid.voxel_count())
    throw Error(ErrorCode::SizeMismatch,
      "the moving image has " + std::to_string(moving.values.size()) + " values for " +
        std::to_string(moving.grid.voxel_count()) + " voxels");
  for (size_t v = 0; v < moving.values.size(); ++v)
    if (!std::isfinite(moving.values[v]))
      throw Error(ErrorCode::NonFinite,
        "the moving image has a NaN or infinite value at voxel " + std::to_string(v));
  if (!std::isfinite(options.default_value))
    throw Error(ErrorCode::NonFinite, "the default value must be finite");
}

/// out(y) = moving(map(y)); map(y, x) returns false when x is not finite.
template<class Map>
ResampleResult resample_with(const ScalarImage& moving, const ImageGrid& output_grid, Map&& map,
  const ResampleOptions& options, const ProgressCallback& progress)
{
  const Index n = output_grid.voxel_count();
  ResampleResult result;
  result.values.resize(size_t(n));
  const Eigen::Matrix3d M = output_grid.index_to_physical();
  const Eigen::Matrix3d to_index = moving.grid.index_to_physical().inverse();
  const ImageGrid& g = moving.grid;
  const Index nchunks = (n + kResampleChunk - 1) / kResampleChunk;
  std::vector<Index> outside(static_cast<size_t>(nchunks), 0);
  ProgressReporter reporter(progress, std::max<Index>(1, n));
  detail::parallel_for(n, kResampleChunk, options.threads, reporter, "resampling the image",
    [&](Index begin, Index end) {
      Index out_count = 0;
      for (Index v = begin; v < end; ++v)
      {
        const Eigen::Vector3d index(double(v % output_grid.size[0]),
          double((v / output_grid.size[0]) % output_grid.size[1]),
          double(v / (output_grid.size[0] * output_grid.size[1])));
        const Eigen::Vector3d y = output_grid.origin + M * index;
        const Eigen::Vector3d x = map(y);
        if (!x.allFinite())
          throw Error(ErrorCode::NonFinite,
            "the map sends the output point " + detail::format_point(y.data(), 3) +
              " to NaN or infinity");
        const Eigen::Vector3d c = to_index * (x - g.origin);
        double value = options.default_value;
        bool in = false;
        if (options.interpolation == Interpolation::Nearest)
        {
          Index i, j, k;
          if ((in = detail::nearest_voxel(c, g.size, i, j, k)))
            value = moving.values[size_t(g.voxel(i, j, k))];
        }
        else
        {
          detail::TrilinearStencil s;
          if ((in = detail::trilinear_stencil(c, g.size, s)))
            detail::trilinear_sum<1>(s, g.size, moving.values.data(), &value);
        }
        if (!in)
          ++out_count;
        result.values[size_t(v)] = value;
      }
      outside[size_t(begin / kResampleChunk)] = out_count;
    });
  for (Index c : outside)
    result.outside += c;
  return result;
}
} // namespace

ResampleResult resample_image(const ScalarImage& moving, const ImageGrid& output_grid,
  const PointMap& map, const ResampleOptions& options, const ProgressCallback& progress)
{
  check_resample_input(moving, output_grid, options);
  if (!map)
    return resample_with(
      moving, output_grid, [](const Eigen::Vector3d& y) { return y; }, options, progress);
  return resample_with(moving, output_grid, map, options, progress);
}

ResampleResult warp_image(const ScalarImage& moving, const ImageGrid& output_grid,
  const DisplacementField& pullback, const ResampleOptions& options,
  const ProgressCallback& progress)
{
  check_resample_input(moving, output_grid, options);
  const FieldSampler sampler(pullback);
  return resample_with(
    moving, output_grid,
    [&sampler](const Eigen::Vector3d& y) { return Eigen::Vector3d(y + sampler.displacement(y)); },
    options, progress);
}

} // namespace bary
