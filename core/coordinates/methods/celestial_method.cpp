/// @file celestial_method.cpp
/// T- and S-celestial coordinates (Cerveró et al.) as weight methods: free control points, the
/// domain is their convex hull; Newton per point, warm-started along the input's edges.

#include "core/coordinates/celestial_coordinates.h"
#include "core/common/error.h"
#include "core/coordinates/weight_method.h"

namespace bary
{
namespace
{
class CelestialMethod final : public WeightMethod
{
public:
  explicit CelestialMethod(CelestialScheme scheme)
    : scheme_(scheme)
  {
  }

  WeightsResult compute(const WeightsInput& input, const WeightsSettings& settings,
    const ProgressCallback& progress) const override
  {
    CelestialOptions options;
    options.scheme = scheme_;
    options.lambda = settings.lambda;
    options.hull_points = settings.celestial_hull_points;
    options.hull_margin = settings.celestial_hull_margin;
    options.hull_reference = input.hull_reference_points;
    if (!settings.user_weights.empty())
    {
      if (scheme_ == CelestialScheme::S)
        throw Error(ErrorCode::InvalidArgument,
          "user weights s_i belong to T-celestial coordinates (Eq. 8); S-celestial coordinates "
          "take none");
      options.user_weights = Eigen::Map<const Eigen::VectorXd>(
        settings.user_weights.data(), static_cast<Eigen::Index>(settings.user_weights.size()));
    }
    if (settings.outside == OutsidePolicy::Nearest)
      throw Error(ErrorCode::InvalidArgument,
        "celestial coordinates are defined inside the control points' convex hull only; the "
        "outside policy must be 'error' or 'nan' (not 'nearest')");
    options.outside = settings.outside == OutsidePolicy::NaN ? CelestialOutsidePolicy::Flag
                                                             : CelestialOutsidePolicy::Error;
    options.threads = settings.threads;
    const CelestialCoordinates celestial(input.cage->V, options);
    return input.edges && input.edges->rows() > 0
      ? celestial.compute(*input.points, *input.edges, progress)
      : celestial.compute(*input.points, progress);
  }

private:
  CelestialScheme scheme_;
};
} // namespace

const WeightMethod& t_celestial_method()
{
  static const CelestialMethod method(CelestialScheme::T);
  return method;
}

const WeightMethod& s_celestial_method()
{
  static const CelestialMethod method(CelestialScheme::S);
  return method;
}
} // namespace bary
