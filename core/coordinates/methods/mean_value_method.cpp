/// @file mean_value_method.cpp
/// Mean value coordinates (Hormann & Floater 2006; Ju, Schaefer & Warren 2005) as a weight
/// method: closed form, defined at every point.

#include "core/coordinates/mean_value_coordinates.h"
#include "core/coordinates/weight_method.h"

namespace bary
{
namespace
{
class MeanValueMethod final : public WeightMethod
{
public:
  WeightsResult compute(const WeightsInput& input, const WeightsSettings& settings,
    const ProgressCallback& progress) const override
  {
    MeanValueOptions options;
    options.boundary_tolerance = settings.boundary_tolerance;
    options.validate = settings.validate_cage;
    options.threads = settings.threads;
    const MeanValueCoordinates mvc(*input.cage, options);
    return mvc.evaluate(*input.points, progress);
  }
};
} // namespace

const WeightMethod& mean_value_method()
{
  static const MeanValueMethod method;
  return method;
}
} // namespace bary
