#include "core/coordinates/weight_method.h"

#include "core/common/error.h"
#include "core/meshing/mesh_point_locator.h"

#include <chrono>

namespace bary
{

WeightsResult compute_weights(
  const WeightsInput& input, const WeightsSettings& settings, const ProgressCallback& progress)
{
  validate_settings(settings);
  if (!input.points)
    throw Error(ErrorCode::InvalidArgument, "no evaluation points were given");
  return method_info(settings.method).instance().compute(input, settings, progress);
}

PolygonMeshOptions polygon_mesh_options(const WeightsSettings& settings, const Eigen::MatrixXd& points)
{
  PolygonMeshOptions options;
  options.target_cells = settings.target_cells > 0 ? settings.target_cells : default_target_cells(2);
  options.max_area = settings.max_cell_size;
  if (settings.insert_points)
    options.steiner_points = points;
  return options;
}

SurfaceMeshOptions surface_mesh_options(const WeightsSettings& settings, const Eigen::MatrixXd& points)
{
  SurfaceMeshOptions options;
  options.target_cells = settings.target_cells > 0 ? settings.target_cells : default_target_cells(3);
  options.max_volume = settings.max_cell_size;
  if (settings.insert_points)
    options.steiner_points = points;
  return options;
}

DomainMesh mesh_cage_interior(const Cage& cage, const WeightsSettings& settings,
  const Eigen::MatrixXd& points, const ProgressCallback& progress)
{
  return cage.dimension() == 2
    ? mesh_polygon(cage, polygon_mesh_options(settings, points), progress)
    : mesh_closed_surface(cage, surface_mesh_options(settings, points), progress);
}

DomainMesh cage_domain_mesh(const WeightsInput& input, const WeightsSettings& settings,
  const ProgressCallback& progress)
{
  if (!(input.domain_V && input.domain_T))
    return mesh_cage_interior(*input.cage, settings, *input.points, progress);
  if (settings.validate_cage)
    validate_cage(*input.cage);
  return domain_mesh_for_cage(*input.cage, *input.domain_V, *input.domain_T, progress);
}

std::string settings_advice(
  const std::vector<std::pair<std::string, std::vector<std::string>>>& verb_keys)
{
  std::string properties, flags;
  std::string advice;
  for (std::size_t i = 0; i < verb_keys.size(); ++i)
  {
    std::string names, options;
    for (std::size_t k = 0; k < verb_keys[i].second.size(); ++k)
    {
      const SettingField& f = setting_field(verb_keys[i].second[k]);
      names += (k ? " / " : "") + f.property;
      options += (k ? ", " : "") + f.primary_flag();
    }
    advice += (i ? " or " : "") + verb_keys[i].first + " " + names + " (" + options + ")";
  }
  return advice;
}

namespace detail
{
ProgressCallback progress_slice(const ProgressCallback& progress, double begin, double end)
{
  return [progress, begin, end](double f) { return !progress || progress(begin + (end - begin) * f); };
}

void interpolate_on_mesh(const Eigen::MatrixXd& V, const Eigen::MatrixXi& T, const DenseWeights& W,
  const Eigen::MatrixXd& points, const WeightsSettings& settings,
  const ProgressCallback& progress, WeightsResult& result)
{
  const MeshPointLocator locator(V, T);
  MeshPointLocator::Result at_points =
    locator.interpolate(W, points, settings.outside, progress_slice(progress, 0.95, 1.0));
  result.W = std::move(at_points.W);
  result.location.assign(static_cast<std::size_t>(points.rows()), PointLocation::Inside);
  for (Index id : at_points.outside)
    result.location[static_cast<std::size_t>(id)] = PointLocation::Outside;
  result.undefined.clear();
  if (settings.outside == OutsidePolicy::NaN)
    result.undefined.assign(at_points.outside.begin(), at_points.outside.end());
}

double seconds_now()
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
} // namespace detail

} // namespace bary
