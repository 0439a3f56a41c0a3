/// @file green_method.cpp
/// Green coordinates (Lipman, Levin & Cohen-Or 2008) as a weight method: closed form, defined at
/// every point; W = phi (the vertices' coordinates) and face_weights = psi (the faces' normal
/// coefficients), which a deformation needs both of (deform_points_green).

#include "core/coordinates/green_coordinates.h"
#include "core/coordinates/weight_method.h"

namespace bary
{
namespace
{
class GreenMethod final : public WeightMethod
{
public:
  WeightsResult compute(const WeightsInput& input, const WeightsSettings& settings,
    const ProgressCallback& progress) const override
  {
    GreenOptions options;
    options.boundary_tolerance = settings.boundary_tolerance;
    options.validate = settings.validate_cage;
    options.threads = settings.threads;
    const GreenCoordinates green(*input.cage, options);
    return green.evaluate(*input.points, progress);
  }
};
} // namespace

const WeightMethod& green_method()
{
  static const GreenMethod method;
  return method;
}
} // namespace bary
