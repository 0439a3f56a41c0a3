/// @file lbc_method.cpp
/// Local barycentric coordinates (Zhang et al. 2014) as a weight method: on a mesh of the
/// cage's interior, made here or given (0-0.1 of the progress), the ADMM (0.1-0.95), then
/// interpolated at the points (0.95-1).

#include "core/common/error.h"
#include "core/coordinates/local_barycentric_coordinates.h"
#include "core/coordinates/weight_method.h"

namespace bary
{
namespace
{
LBCOptions lbc_options(const WeightsSettings& settings)
{
  LBCOptions options;
  options.locality = settings.lbc_locality;
  options.distance_normalization = settings.lbc_distance_normalization;
  options.relaxed_tv_epsilon = settings.lbc_relaxed_epsilon;
  options.primal_tolerance = settings.lbc_primal_tolerance;
  options.dual_tolerance = settings.lbc_dual_tolerance;
  options.max_iterations = settings.lbc_max_iterations;
  options.barycentric_constraints = !settings.lbc_unconstrained;
  options.stopping = settings.lbc_stopping;
  // 0 = one thread: the ADMM's short parallel loops spin-wait in libgomp and were several
  // times slower with two threads on a loaded machine (docs/local-barycentric-coordinates.md).
  options.threads = settings.threads > 0 ? settings.threads : 1;
  options.require_convergence = true;
  return options;
}

class LBCMethod final : public WeightMethod
{
public:
  WeightsResult compute(const WeightsInput& input, const WeightsSettings& settings,
    const ProgressCallback& progress) const override
  {
    const double start = detail::seconds_now();
    const DomainMesh mesh =
      cage_domain_mesh(input, settings, detail::progress_slice(progress, 0.0, 0.1));
    const double mesh_seconds = detail::seconds_now() - start;
    LBCResult solved;
    try
    {
      solved = local_barycentric_coordinates(
        mesh, lbc_options(settings), detail::progress_slice(progress, 0.1, 0.95));
    }
    catch (const Error& e)
    {
      if (e.code() != ErrorCode::NotConverged)
        throw;
      // the core's advice names LBCOptions' fields; name the settings
      // the paper's rule is the looser one: suggest it only when the converged rule was asked
      std::vector<std::pair<std::string, std::vector<std::string>>> advice = {
        { "raise", { "lbc_max_iterations" } },
        { "loosen", { "lbc_primal_tolerance", "lbc_dual_tolerance" } }
      };
      if (settings.lbc_stopping == LBCStopping::Converged)
        advice.push_back({ "choose paper for", { "lbc_stopping" } });
      throw Error(ErrorCode::NotConverged, e.message(), settings_advice(advice));
    }
    WeightsResult result;
    detail::interpolate_on_mesh(mesh.V, mesh.T, solved.W, *input.points, settings, progress, result);
    result.converged = solved.converged;
    result.statistics = { { "mesh_vertices", static_cast<double>(mesh.num_vertices()) },
      { "mesh_cells", static_cast<double>(mesh.num_elements()) },
      { "mesh_seconds", mesh_seconds } }; // meshing, or matching a given mesh
    result.statistics.insert(
      result.statistics.end(), solved.statistics.begin(), solved.statistics.end());
    return result;
  }
};
} // namespace

const WeightMethod& lbc_method()
{
  static const LBCMethod method;
  return method;
}
} // namespace bary
