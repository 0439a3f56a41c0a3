#include "core/coordinates/weight_method.h"

#include "core/common/error.h"
#include "core/meshing/mesh_point_locator.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

namespace bary
{

namespace
{

/// The scale_exponent (cage.h) of the geometry that defines the weights: cage or control points,
/// skeleton, domain mesh, domain boundary (not the evaluation points: they may lie anywhere).
int input_scale_exponent(const WeightsInput& input)
{
  double extent = 0.0;
  const auto add = [&extent](const Eigen::MatrixXd& V) {
    const double e = bounding_box_extent(V);
    if (!std::isfinite(e))
      extent = e;
    else if (std::isfinite(extent))
      extent = std::max(extent, e);
  };
  if (input.cage)
    add(input.cage->V);
  if (input.skeleton)
    add(input.skeleton->C);
  if (input.domain_V)
    add(*input.domain_V);
  if (input.domain_boundary)
    add(input.domain_boundary->V);
  return scale_exponent(extent);
}

/// Runs settings.method; the advice of points outside the method's domain names the setting
/// (its filter property and command-line flag) instead of the algorithms' C++ option.
WeightsResult compute_in_settings_words(
  const WeightsInput& input, const WeightsSettings& settings, const ProgressCallback& progress)
{
  try
  {
    if (input.mesh_weights)
    { // solved elsewhere (another process): interpolate as the solving run did
      if (!method_info(settings.method).domain_mesh)
        throw Error(ErrorCode::InvalidArgument,
          "weights solved on a mesh were given to " + method_info(settings.method).title +
            ", which is not a mesh-based method");
      const MeshWeights& m = *input.mesh_weights;
      if (m.V.cols() != input.points->cols() || m.W.rows() != m.V.rows())
        throw Error(ErrorCode::SizeMismatch,
          "the mesh weights (" + std::to_string(m.W.rows()) + " rows for " +
            std::to_string(m.V.rows()) + " vertices in " + std::to_string(m.V.cols()) +
            "D) do not fit the " + std::to_string(input.points->cols()) + "D points");
      WeightsResult result;
      detail::interpolate_on_mesh(m.V, m.T, m.W, *input.points, settings, progress, result);
      result.statistics = m.statistics;
      return result;
    }
    WeightsResult result = method_info(settings.method).instance().compute(input, settings, progress);
    if (result.mesh_weights)
      result.mesh_weights->statistics = result.statistics;
    return result;
  }
  catch (const Error& e)
  {
    if (e.code() != ErrorCode::PointsOutside)
      throw;
    const SettingField& outside = setting_field("outside");
    const std::string set = "set " + outside.property + " (" + outside.primary_flag() + ") to ";
    const bool hull = settings.method == MethodId::TCelestial || settings.method == MethodId::SCelestial;
    const SettingField& hull_points = setting_field("celestial_hull_points");
    throw Error(e.code(), e.message(),
      hull ? "add control points around the model (the paper adds the corners of a box): set " +
          hull_points.property + " (" + hull_points.primary_flag() + ") to auto (the default) to add them, or " +
          set + "nan to get NaN rows for them"
           : set + "nearest to clamp them to the mesh or nan to mark them");
  }
}

} // namespace

WeightsResult compute_weights(
  const WeightsInput& input, const WeightsSettings& settings, const ProgressCallback& progress)
{
  validate_settings(settings);
  if (!input.points)
    throw Error(ErrorCode::InvalidArgument, "no evaluation points were given");
  const int k = input_scale_exponent(input);
  if (k == 0)
    return compute_in_settings_words(input, settings, progress);

  // Extreme scales: the same computation on the geometry times 2^k (exact; see scale_exponent).
  const double s = std::ldexp(1.0, k);
  WeightsInput scaled = input;
  Cage cage, boundary;
  Skeleton skeleton;
  Eigen::MatrixXd domain_V, points = *input.points * s;
  scaled.points = &points;
  if (input.cage)
  {
    cage = *input.cage;
    cage.V *= s;
    scaled.cage = &cage;
  }
  if (input.skeleton)
  {
    skeleton = *input.skeleton;
    skeleton.C *= s;
    scaled.skeleton = &skeleton;
  }
  if (input.domain_V)
  {
    domain_V = *input.domain_V * s;
    scaled.domain_V = &domain_V;
  }
  if (input.domain_boundary)
  {
    boundary = *input.domain_boundary;
    boundary.V *= s;
    scaled.domain_boundary = &boundary;
  }
  MeshWeights mesh_weights;
  if (input.mesh_weights)
  {
    mesh_weights = *input.mesh_weights;
    mesh_weights.V *= s;
    scaled.mesh_weights = &mesh_weights;
  }
  Eigen::MatrixXd hull_reference;
  if (input.hull_reference_points)
  {
    hull_reference = *input.hull_reference_points * s;
    scaled.hull_reference_points = &hull_reference;
  }
  WeightsSettings scaled_settings = settings;
  if (settings.max_cell_size > 0.0)
  {
    int dim = 0;
    for (const Eigen::MatrixXd* V : { input.cage ? &input.cage->V : nullptr,
           input.skeleton ? &input.skeleton->C : nullptr, input.domain_V,
           input.domain_boundary ? &input.domain_boundary->V : nullptr })
      if (V && dim == 0)
        dim = static_cast<int>(V->cols());
    scaled_settings.max_cell_size = std::clamp(std::ldexp(settings.max_cell_size, dim * k),
      std::numeric_limits<double>::min(), std::numeric_limits<double>::max());
  }
  WeightsResult result = compute_in_settings_words(scaled, scaled_settings, progress);
  if (result.mesh_weights)
    result.mesh_weights->V /= s; // exact: s is a power of 2
  if (result.face_weights.size() > 0 && input.cage)
  { // Green coordinates' psi: x = phi V + psi N at both scales, phi unchanged, so psi scales
    // with 1 / s; in 2D psi_j also carries -log(s) |e_j| / (2 pi) from log r (a multiple of
    // |e_j| that sum_j |e_j| n_j = 0 leaves out of every deformation), taken back out here.
    result.face_weights /= s;
    if (input.cage->dimension() == 2)
    {
      const Eigen::MatrixXd& V = input.cage->V;
      const Index n = V.rows();
      const double log_s = k * std::log(2.0) / (2.0 * 3.14159265358979323846);
      for (Index j = 0; j < n && j < result.face_weights.cols(); ++j)
        result.face_weights.col(j).array() += log_s * (V.row((j + 1) % n) - V.row(j)).stableNorm();
    }
  }
  return result;
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
  result.mesh_weights = std::make_shared<MeshWeights>(MeshWeights{ V, T, W, {} });
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
