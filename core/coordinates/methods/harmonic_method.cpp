/// @file harmonic_method.cpp
/// Harmonic coordinates (Joshi et al. 2007) as a weight method: linear finite elements on a
/// mesh of the cage's interior, made here or given (0-0.9 of the progress), interpolated at the
/// points (0.9-1).

#include "core/coordinates/harmonic_coordinates.h"
#include "core/coordinates/weight_method.h"

namespace bary
{
namespace
{
class HarmonicMethod final : public WeightMethod
{
public:
  WeightsResult compute(const WeightsInput& input, const WeightsSettings& settings,
    const ProgressCallback& progress) const override
  {
    const Eigen::MatrixXd& points = *input.points;
    HarmonicOptions options;
    options.validate = settings.validate_cage;
    options.polygon_mesh = polygon_mesh_options(settings, points);
    options.surface_mesh = surface_mesh_options(settings, points);
    const HarmonicCoordinates harmonic = input.domain_V && input.domain_T
      ? HarmonicCoordinates(*input.cage,
          cage_domain_mesh(input, settings, detail::progress_slice(progress, 0.0, 0.1)), options,
          detail::progress_slice(progress, 0.1, 0.9))
      : HarmonicCoordinates(*input.cage, options, detail::progress_slice(progress, 0.0, 0.9));
    std::vector<Index> outside;
    WeightsResult result;
    result.W = harmonic.evaluate(
      points, settings.outside, &outside, detail::progress_slice(progress, 0.9, 1.0));
    result.location.assign(static_cast<std::size_t>(points.rows()), PointLocation::Inside);
    for (Index id : outside)
      result.location[static_cast<std::size_t>(id)] = PointLocation::Outside;
    if (settings.outside == OutsidePolicy::NaN)
      result.undefined = outside;
    result.statistics.emplace_back("mesh_vertices", harmonic.mesh().num_vertices());
    result.statistics.emplace_back("mesh_cells", harmonic.mesh().num_elements());
    result.mesh_weights = std::make_shared<MeshWeights>(
      MeshWeights{ harmonic.mesh().V, harmonic.mesh().T, harmonic.mesh_weights(), {} });
    return result;
  }
};
} // namespace

const WeightMethod& harmonic_method()
{
  static const HarmonicMethod method;
  return method;
}
} // namespace bary
