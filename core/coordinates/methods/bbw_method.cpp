/// @file bbw_method.cpp
/// Bounded biharmonic weights (Jacobson et al. 2011) as a weight method, for cage handles (the
/// cage's interior meshed, values linear on the cage's faces: Eq. 4) or mixed handles (a
/// Skeleton: points, bones, cage faces, regions; plus region vertex lists of a given mesh,
/// mixed_bbw_handles) in a given domain: a simplicial mesh used as is, or a closed surface /
/// polygon meshed with the joints and samples of the bones, cage faces and regions inserted.
/// A shape-preservation brush per vertex of a given mesh becomes the per-element brush of
/// Eq. 9. Meshing 0-0.1 of the progress, the solve 0.1-0.95, interpolation at the points
/// 0.95-1.

#include "core/coordinates/bbw.h"
#include "core/coordinates/bbw_handles.h"
#include "core/common/error.h"
#include "core/coordinates/weight_method.h"

#include <cmath>

namespace bary
{
namespace
{
class BBWMethod final : public WeightMethod
{
public:
  WeightsResult compute(const WeightsInput& input, const WeightsSettings& settings,
    const ProgressCallback& progress) const override
  {
    const double start = detail::seconds_now();
    const Eigen::MatrixXd& points = *input.points;
    if (!input.skeleton)
    {
      // Cage handles: one handle per cage vertex, fixed on the mesh boundary.
      const DomainMesh mesh =
        cage_domain_mesh(input, settings, detail::progress_slice(progress, 0.0, 0.1));
      BBWHandles handles;
      handles.extra_handles = input.cage->num_controls();
      handles.fixed_vertices = Eigen::Map<const Eigen::VectorXi>(
        mesh.boundary_vertices.data(), static_cast<Eigen::Index>(mesh.boundary_vertices.size()));
      handles.fixed_values = DenseWeights(mesh.boundary_weights);
      if (input.region_vertices)
        throw Error(ErrorCode::InvalidArgument,
          "region handles combine with a cage only as mixed handles (cage faces in the handles)");
      Eigen::VectorXd brush;
      if (input.shape_preservation)
      {
        // The brush is per vertex of the given mesh: only meaningful when the mesh is used as is.
        if (!input.domain_V || mesh.V.rows() != input.domain_V->rows() ||
          mesh.V != *input.domain_V)
          throw Error(ErrorCode::InvalidArgument,
            "a shape-preservation brush per vertex needs the domain mesh given (and used as is)");
        brush = shape_preservation_per_element(mesh.T, *input.shape_preservation, mesh.V.rows());
      }
      return solve(mesh.V, mesh.T, handles, points, settings, progress,
        input.domain_V ? -1.0 : start, brush);
    }
    const Skeleton& skeleton = *input.skeleton;
    if (input.domain_V && input.domain_T)
    {
      if (skeleton.handle_count() > 0 && skeleton.dimension() != input.domain_V->cols())
        throw_dimension_mismatch(skeleton.dimension(), static_cast<int>(input.domain_V->cols()));
      const BBWHandles handles = mixed_bbw_handles(*input.domain_V, skeleton,
        input.region_vertices ? *input.region_vertices : std::vector<std::vector<int>>());
      Eigen::VectorXd brush;
      if (input.shape_preservation)
        brush = shape_preservation_per_element(
          *input.domain_T, *input.shape_preservation, input.domain_V->rows());
      return solve(
        *input.domain_V, *input.domain_T, handles, points, settings, progress, -1.0, brush);
    }
    if (input.region_vertices || input.shape_preservation)
      throw Error(ErrorCode::InvalidArgument,
        "region vertex lists and a shape-preservation brush per vertex refer to the vertices of "
        "a given domain mesh, but the domain is a surface / polygon to be meshed",
        "give a triangle / tetrahedral mesh of the domain");
    if (!input.domain_boundary)
      throw Error(ErrorCode::InvalidArgument,
        "bounded biharmonic weights of a skeleton need a domain: a simplicial mesh, or a closed "
        "surface / polygon to mesh");
    const Cage& boundary = *input.domain_boundary;
    const int dim = boundary.dimension();
    if (skeleton.dimension() != dim)
      throw_dimension_mismatch(skeleton.dimension(), dim);
    validate_skeleton(skeleton);
    // Bone samples about one cell size apart, so the bones are resolved by the mesh.
    const int target = settings.target_cells > 0 ? settings.target_cells : default_target_cells(dim);
    const double cell = settings.max_cell_size > 0 ? settings.max_cell_size
                                                   : enclosed_measure(boundary) / target;
    const Eigen::MatrixXd samples = skeleton_samples(skeleton, bone_sample_spacing(dim, cell));
    Eigen::MatrixXd steiner = samples;
    if (settings.insert_points)
    {
      steiner.resize(samples.rows() + points.rows(), dim);
      steiner << samples, points;
    }
    WeightsSettings meshing = settings;
    meshing.insert_points = false;
    DomainMesh mesh;
    if (dim == 2)
    {
      PolygonMeshOptions options = polygon_mesh_options(meshing, points);
      options.steiner_points = steiner;
      mesh = mesh_polygon(boundary, options, detail::progress_slice(progress, 0.0, 0.1));
    }
    else
    {
      SurfaceMeshOptions options = surface_mesh_options(meshing, points);
      options.steiner_points = steiner;
      mesh = mesh_closed_surface(boundary, options, detail::progress_slice(progress, 0.0, 0.1));
    }
    const BBWHandles handles = mixed_bbw_handles(mesh.V, skeleton);
    return solve(mesh.V, mesh.T, handles, points, settings, progress, start);
  }

private:
  [[noreturn]] static void throw_dimension_mismatch(int handles, int domain)
  {
    throw Error(ErrorCode::SizeMismatch,
      "the handles are " + std::to_string(handles) + "D but the domain is " +
        std::to_string(domain) + "D");
  }

  /// BBW on (V, T), interpolated at the points. @p start: when the mesh was made here, the
  /// time meshing began (reported as mesh_seconds); negative for a given mesh. @p brush: the
  /// per-element shape-preservation brush (empty: none).
  static WeightsResult solve(const Eigen::MatrixXd& V, const Eigen::MatrixXi& T,
    const BBWHandles& handles, const Eigen::MatrixXd& points, const WeightsSettings& settings,
    const ProgressCallback& progress, double start, const Eigen::VectorXd& brush = {})
  {
    WeightsResult result;
    if (start >= 0)
      result.statistics.emplace_back("mesh_seconds", detail::seconds_now() - start);
    BBWOptions options;
    options.mode = settings.bbw_fast ? BBWMode::Fast : BBWMode::Coupled;
    options.threads = settings.threads;
    options.mass_lumping = settings.bbw_mass_lumping;
    options.bounded = !settings.bbw_unbounded;
    options.compare_with_fast = settings.bbw_compare_fast;
    options.shape_preservation = brush;
    const BBWResult solved = bounded_biharmonic_weights(
      V, T, handles, options, detail::progress_slice(progress, 0.1, 0.95));
    detail::interpolate_on_mesh(V, T, solved.W, points, settings, progress, result);
    result.converged = solved.converged;
    result.statistics.insert(
      result.statistics.end(), solved.statistics.begin(), solved.statistics.end());
    return result;
  }
};
} // namespace

const WeightMethod& bbw_method()
{
  static const BBWMethod method;
  return method;
}
} // namespace bary
