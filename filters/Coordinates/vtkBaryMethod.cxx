#include "vtkBaryMethod.h"

#include "vtkBaryCoordinates.h"

#include "core/bbw.h"
#include "core/celestial_coordinates.h"
#include "core/error.h"
#include "core/harmonic_coordinates.h"
#include "core/local_barycentric_coordinates.h"
#include "core/mean_value_coordinates.h"
#include "core/mesh_point_locator.h"

#include "vtkCellType.h"
#include "vtkDataSet.h"
#include "vtkObjectFactory.h"
#include "vtkPolyData.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>

vtkStandardNewMacro(vtkBaryMethod);

namespace
{
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start)
{
  return std::chrono::duration<double>(Clock::now() - start).count();
}

bary::OutsidePolicy outside_policy(const vtkBaryMethodParameters& parameters)
{
  static const bary::OutsidePolicy policies[] = { bary::OutsidePolicy::Error,
    bary::OutsidePolicy::Nearest, bary::OutsidePolicy::NaN };
  return policies[std::clamp(parameters.OutsidePolicy, 0, 2)];
}

/// A progress callback for the slice [begin, end] of @p progress.
bary::ProgressCallback slice(const bary::ProgressCallback& progress, double begin, double end)
{
  return [&progress, begin, end](double f) { return !progress || progress(begin + (end - begin) * f); };
}

/// Location and undefined points of a mesh-based method from the locator's outside list.
void report_outside(vtkBaryMethodReport* report, vtkIdType np, const std::vector<bary::Index>& outside,
  bary::OutsidePolicy policy)
{
  if (!report)
    return;
  report->Outside = static_cast<vtkIdType>(outside.size());
  report->Inside = np - report->Outside;
  report->Boundary = 0;
  report->Location.assign(static_cast<std::size_t>(np), 0);
  for (auto id : outside)
    report->Location[static_cast<std::size_t>(id)] = 1;
  report->Undefined.clear();
  if (policy == bary::OutsidePolicy::NaN)
    report->Undefined.assign(outside.begin(), outside.end());
}

bary::BBWOptions bbw_options(const vtkBaryMethodParameters& parameters)
{
  bary::BBWOptions options;
  options.mode = parameters.BBWMode == vtkBaryCoordinates::BBW_FAST ? bary::BBWMode::Fast
                                                                     : bary::BBWMode::Coupled;
  options.threads = parameters.NumberOfThreads;
  return options;
}

/// Mesh-vertex weights @p W on (V, T) interpolated at @p points (the outside policy of
/// @p parameters; progress 0.95-1); fills the report's locations.
bary::DenseWeights interpolate_at_points(const Eigen::MatrixXd& V, const Eigen::MatrixXi& T,
  const bary::DenseWeights& W, const Eigen::MatrixXd& points,
  const vtkBaryMethodParameters& parameters, const bary::ProgressCallback& progress,
  vtkBaryMethodReport* report)
{
  const bary::MeshPointLocator locator(V, T);
  const bary::OutsidePolicy policy = outside_policy(parameters);
  bary::MeshPointLocator::Result at_points =
    locator.interpolate(W, points, policy, slice(progress, 0.95, 1.0));
  report_outside(report, points.rows(), at_points.outside, policy);
  return std::move(at_points.W);
}

/// BBW on the mesh (V, T), then interpolated at @p points; fills the report.
bary::DenseWeights solve_bbw_and_interpolate(const Eigen::MatrixXd& V, const Eigen::MatrixXi& T,
  const bary::BBWHandles& handles, const Eigen::MatrixXd& points,
  const vtkBaryMethodParameters& parameters, const bary::ProgressCallback& progress,
  double begin, vtkBaryMethodReport* report)
{
  const bary::BBWResult result =
    bary::bounded_biharmonic_weights(V, T, handles, bbw_options(parameters), slice(progress, begin, 0.95));
  bary::DenseWeights at_points =
    interpolate_at_points(V, T, result.W, points, parameters, progress, report);
  if (report)
  {
    auto& st = report->Statistics;
    long long iterations = 0, factorizations = 0;
    int most = 0;
    for (std::size_t j = 0; j < result.iterations.size(); ++j)
    {
      iterations += result.iterations[j];
      factorizations += result.factorizations[j];
      most = std::max(most, result.iterations[j]);
    }
    st.emplace_back("mesh_vertices", static_cast<double>(V.rows()));
    st.emplace_back("mesh_cells", static_cast<double>(T.rows()));
    st.emplace_back("handles", static_cast<double>(handles.handle_count()));
    st.emplace_back("fixed_vertices", static_cast<double>(result.fixed_vertices));
    st.emplace_back("coupled", result.mode == bary::BBWMode::Coupled ? 1.0 : 0.0);
    st.emplace_back("fast_iterations", static_cast<double>(iterations));
    st.emplace_back("fast_factorizations", static_cast<double>(factorizations));
    st.emplace_back("max_fast_iterations_per_handle", static_cast<double>(most));
    if (result.mode == bary::BBWMode::Coupled)
    {
      st.emplace_back("outer_iterations", result.outer_iterations);
      st.emplace_back("coupled_iterations", result.coupled_iterations);
      st.emplace_back("coupled_factorizations", result.coupled_factorizations);
      st.emplace_back("coupled_kkt_residual", result.coupled_kkt_residual);
      st.emplace_back("fast_difference_mean", result.fast_difference_mean);
      st.emplace_back("fast_difference_max", result.fast_difference_max);
    }
    st.emplace_back("max_kkt_residual", result.max_kkt_residual);
    st.emplace_back("max_bound_violation", result.max_bound_violation);
    st.emplace_back("partition_error", result.partition_error);
    st.emplace_back("partition_error_before_normalization", result.partition_error_before_normalization);
    st.emplace_back("converged", result.converged ? 1.0 : 0.0);
    st.emplace_back("solve_seconds", result.seconds);
  }
  return at_points;
}

/// Enclosed area (2D) or volume (3D) of a cage, for size bounds before meshing.
double enclosed_measure(const bary::Cage& cage)
{
  double sum = 0.0;
  if (cage.dimension() == 2)
  {
    const bary::Index n = cage.V.rows();
    for (bary::Index i = 0; i < n; ++i)
    {
      const bary::Index j = (i + 1) % n;
      sum += cage.V(i, 0) * cage.V(j, 1) - cage.V(j, 0) * cage.V(i, 1);
    }
    return std::abs(sum) / 2.0;
  }
  for (bary::Index f = 0; f < cage.F.rows(); ++f)
  {
    const Eigen::Vector3d a = cage.V.row(cage.F(f, 0)), b = cage.V.row(cage.F(f, 1)),
                          c = cage.V.row(cage.F(f, 2));
    sum += a.dot(b.cross(c));
  }
  return std::abs(sum) / 6.0;
}

/// The options of local barycentric coordinates from the filter parameters.
bary::LBCOptions lbc_options(const vtkBaryMethodParameters& parameters)
{
  bary::LBCOptions options;
  static const bary::LocalityFunction localities[] = { bary::LocalityFunction::Squared,
    bary::LocalityFunction::Constant, bary::LocalityFunction::Linear };
  options.locality = localities[std::clamp(parameters.LBCLocality, 0, 2)];
  options.distance_normalization =
    parameters.LBCDistanceNormalization == vtkBaryCoordinates::LBC_NORMALIZE_GLOBAL
    ? bary::DistanceNormalization::Global
    : bary::DistanceNormalization::PerControlPoint;
  options.relaxed_tv_epsilon = parameters.LBCRelaxedEpsilon;
  options.primal_tolerance = parameters.LBCPrimalTolerance;
  options.dual_tolerance = parameters.LBCDualTolerance;
  options.max_iterations = parameters.LBCMaximumIterations;
  options.barycentric_constraints = parameters.LBCBarycentricConstraints;
  // 0 = one thread: the ADMM's short parallel loops spin-wait in libgomp and were several
  // times slower with two threads on a loaded machine (see vtkBaryCoordinates.h).
  options.threads = parameters.NumberOfThreads > 0 ? parameters.NumberOfThreads : 1;
  options.require_convergence = true;
  return options;
}

/// Mesh vertices on the boundary of the simplicial mesh T (facets used by one cell), sorted.
std::vector<int> boundary_vertices_of(const Eigen::MatrixXi& T)
{
  const int corners = static_cast<int>(T.cols());
  std::map<std::array<int, 3>, int> facets;
  for (Eigen::Index c = 0; c < T.rows(); ++c)
    for (int skip = 0; skip < corners; ++skip)
    {
      std::array<int, 3> f = { -1, -1, -1 };
      int k = 0;
      for (int j = 0; j < corners; ++j)
        if (j != skip)
          f[static_cast<std::size_t>(k++)] = T(c, j);
      std::sort(f.begin(), f.begin() + k);
      ++facets[f];
    }
  std::vector<int> vertices;
  for (const auto& entry : facets)
    if (entry.second == 1)
      for (int v : entry.first)
        if (v >= 0)
          vertices.push_back(v);
  std::sort(vertices.begin(), vertices.end());
  vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
  return vertices;
}
} // namespace

bary::PolygonMeshOptions vtkBaryMethod::PolygonMeshOptions(
  const vtkBaryMethodParameters& parameters, const Eigen::MatrixXd& points)
{
  bary::PolygonMeshOptions options;
  options.target_cells = parameters.TargetNumberOfCells > 0 ? parameters.TargetNumberOfCells
                                                            : vtkBaryDefaultTargetCells(2);
  options.max_area = parameters.MaximumCellSize;
  if (parameters.InsertPointsIntoMesh)
    options.steiner_points = points;
  return options;
}

bary::SurfaceMeshOptions vtkBaryMethod::SurfaceMeshOptions(
  const vtkBaryMethodParameters& parameters, const Eigen::MatrixXd& points)
{
  bary::SurfaceMeshOptions options;
  options.target_cells = parameters.TargetNumberOfCells > 0 ? parameters.TargetNumberOfCells
                                                            : vtkBaryDefaultTargetCells(3);
  options.max_volume = parameters.MaximumCellSize;
  if (parameters.InsertPointsIntoMesh)
    options.steiner_points = points;
  return options;
}

bool vtkBaryMethod::IsPointBased(int method)
{
  return method == vtkBaryCoordinates::T_CELESTIAL || method == vtkBaryCoordinates::S_CELESTIAL;
}

bary::DenseWeights vtkBaryMethod::Compute(const vtkBaryCage& cage,
  const Eigen::MatrixXd& points, const vtkBaryMethodParameters& parameters,
  const bary::ProgressCallback& progress, vtkBaryMethodReport* report,
  const Eigen::MatrixXi& edges, vtkDataSet* domain)
{
  switch (parameters.Method)
  {
    case vtkBaryCoordinates::MEAN_VALUE:
    {
      bary::MeanValueOptions options;
      options.boundary_tolerance = parameters.BoundaryTolerance;
      options.validate = parameters.ValidateCage;
      options.threads = parameters.NumberOfThreads;
      bary::MeanValueCoordinates mvc(cage.Cage, options);
      bary::MeanValueResult result = mvc.evaluate(points, progress);
      if (report)
      {
        report->Inside = result.inside;
        report->Outside = result.outside;
        report->Boundary = result.boundary;
        report->Undefined.assign(result.undefined.begin(), result.undefined.end());
        report->Location.resize(result.location.size());
        for (std::size_t i = 0; i < result.location.size(); ++i)
          report->Location[i] = static_cast<unsigned char>(result.location[i]);
      }
      return std::move(result.W);
    }
    case vtkBaryCoordinates::HARMONIC:
    {
      bary::HarmonicOptions options;
      options.validate = parameters.ValidateCage;
      options.polygon_mesh = PolygonMeshOptions(parameters, points);
      options.surface_mesh = SurfaceMeshOptions(parameters, points);
      const bary::HarmonicCoordinates harmonic(cage.Cage, options,
        [&progress](double f) { return !progress || progress(0.9 * f); });
      const bary::OutsidePolicy policy = outside_policy(parameters);
      std::vector<bary::Index> outside;
      bary::DenseWeights W = harmonic.evaluate(points, policy, &outside,
        [&progress](double f) { return !progress || progress(0.9 + 0.1 * f); });
      report_outside(report, points.rows(), outside, policy);
      if (report)
      {
        report->Statistics.emplace_back("mesh_vertices", harmonic.mesh().num_vertices());
        report->Statistics.emplace_back("mesh_cells", harmonic.mesh().num_elements());
      }
      return W;
    }
    case vtkBaryCoordinates::BBW:
    {
      // Cage handles (Eq. 4): one handle per cage vertex, values linear on the cage's faces
      // (edges in 2D) fixed on the mesh boundary.
      const auto start = Clock::now();
      const bary::DomainMesh mesh = cage.Cage.dimension() == 2
        ? bary::mesh_polygon(cage.Cage, PolygonMeshOptions(parameters, points), slice(progress, 0, 0.1))
        : bary::mesh_closed_surface(cage.Cage, SurfaceMeshOptions(parameters, points), slice(progress, 0, 0.1));
      bary::BBWHandles handles;
      handles.extra_handles = cage.Cage.num_controls();
      handles.fixed_vertices = Eigen::Map<const Eigen::VectorXi>(
        mesh.boundary_vertices.data(), static_cast<Eigen::Index>(mesh.boundary_vertices.size()));
      handles.fixed_values = bary::DenseWeights(mesh.boundary_weights);
      if (report)
        report->Statistics.emplace_back("mesh_seconds", seconds_since(start));
      return solve_bbw_and_interpolate(mesh.V, mesh.T, handles, points, parameters, progress, 0.1, report);
    }
    case vtkBaryCoordinates::T_CELESTIAL:
    case vtkBaryCoordinates::S_CELESTIAL:
    {
      bary::CelestialOptions options;
      options.scheme = parameters.Method == vtkBaryCoordinates::T_CELESTIAL
        ? bary::CelestialScheme::T
        : bary::CelestialScheme::S;
      options.lambda = parameters.Lambda;
      if (!parameters.UserWeights.empty())
      {
        if (options.scheme == bary::CelestialScheme::S)
          throw bary::Error(bary::ErrorCode::InvalidArgument,
            "user weights s_i belong to T-celestial coordinates (Eq. 8); S-celestial coordinates "
            "take none");
        options.user_weights = Eigen::Map<const Eigen::VectorXd>(
          parameters.UserWeights.data(), static_cast<Eigen::Index>(parameters.UserWeights.size()));
      }
      if (parameters.OutsidePolicy == vtkBaryCoordinates::OUTSIDE_NEAREST)
        throw bary::Error(bary::ErrorCode::InvalidArgument,
          "celestial coordinates are defined inside the control points' convex hull only; the "
          "outside policy must be 'error' or 'nan' (not 'nearest')");
      options.outside = parameters.OutsidePolicy == vtkBaryCoordinates::OUTSIDE_NAN
        ? bary::CelestialOutsidePolicy::Flag
        : bary::CelestialOutsidePolicy::Error;
      options.threads = parameters.NumberOfThreads;
      const bary::CelestialCoordinates celestial(cage.Cage.V, options);
      bary::CelestialResult result = edges.rows() > 0 ? celestial.compute(points, edges, progress)
                                                      : celestial.compute(points, progress);
      if (report)
      {
        const std::size_t np = result.location.size();
        report->Location.resize(np);
        report->Inside = report->Outside = report->Boundary = 0;
        for (std::size_t p = 0; p < np; ++p)
        {
          const auto where = result.location[p];
          const unsigned char code = where == bary::CelestialLocation::Inside ? 0
            : where == bary::CelestialLocation::Outside                       ? 1
                                                                               : 2;
          report->Location[p] = code;
          (code == 0 ? report->Inside : code == 1 ? report->Outside : report->Boundary)++;
        }
        report->Undefined.clear();
        std::vector<bary::Index> undefined = result.outside;
        undefined.insert(undefined.end(), result.not_converged.begin(), result.not_converged.end());
        std::sort(undefined.begin(), undefined.end());
        report->Undefined.assign(undefined.begin(), undefined.end());
        auto& st = report->Statistics;
        double max_residual = 0.0;
        for (bary::Index p = 0; p < result.residual.size(); ++p)
          if (std::isfinite(result.residual(p)))
            max_residual = std::max(max_residual, result.residual(p));
        st.emplace_back("hull_facets", static_cast<double>(celestial.num_hull_facets()));
        st.emplace_back("newton_iterations", static_cast<double>(result.total_iterations));
        st.emplace_back("mean_newton_iterations",
          np > 0 ? static_cast<double>(result.total_iterations) / static_cast<double>(np) : 0.0);
        st.emplace_back("max_newton_iterations",
          result.iterations.size() > 0 ? result.iterations.maxCoeff() : 0);
        st.emplace_back("warm_starts", static_cast<double>(result.warm_starts));
        st.emplace_back("cold_restarts", static_cast<double>(result.cold_restarts));
        st.emplace_back("max_residual", max_residual);
        st.emplace_back("at_control", static_cast<double>(result.at_control));
        st.emplace_back("not_converged", static_cast<double>(result.not_converged.size()));
        st.emplace_back("solve_seconds", result.seconds);
      }
      return std::move(result.W);
    }
    case vtkBaryCoordinates::LBC:
    {
      // Zhang et al. 2014 on a mesh of the cage's interior: the given one or one made here
      // (0-0.1), the ADMM (0.1-0.95), interpolation at the points (0.95-1).
      const auto start = Clock::now();
      const bary::DomainMesh mesh =
        LBCDomainMesh(cage, domain, points, parameters, slice(progress, 0, 0.1));
      const double mesh_seconds = seconds_since(start);
      bary::LBCResult result;
      try
      {
        result = bary::local_barycentric_coordinates(
          mesh, lbc_options(parameters), slice(progress, 0.1, 0.95));
      }
      catch (const bary::Error& e)
      {
        if (e.code() != bary::ErrorCode::NotConverged)
          throw;
        // the core's advice names core options; name the filter's (and the command line's)
        std::string message = e.what();
        message = message.substr(0, message.find("; raise"));
        throw bary::Error(bary::ErrorCode::NotConverged,
          message + "; raise LBCMaximumIterations (--max-iterations) or loosen "
                    "LBCPrimalTolerance / LBCDualTolerance (--primal-tolerance, --dual-tolerance)");
      }
      bary::DenseWeights at_points =
        interpolate_at_points(mesh.V, mesh.T, result.W, points, parameters, progress, report);
      if (report)
      {
        auto& st = report->Statistics;
        st.emplace_back("mesh_vertices", static_cast<double>(mesh.num_vertices()));
        st.emplace_back("mesh_cells", static_cast<double>(mesh.num_elements()));
        st.emplace_back("mesh_seconds", mesh_seconds); // meshing, or matching a given mesh
        st.emplace_back("iterations", static_cast<double>(result.iterations));
        st.emplace_back("primal_residual", result.primal_residual);
        st.emplace_back("dual_residual", result.dual_residual);
        st.emplace_back("primal_threshold", result.primal_threshold);
        st.emplace_back("dual_threshold", result.dual_threshold);
        st.emplace_back("objective", result.objective);
        st.emplace_back("converged", result.converged ? 1.0 : 0.0);
        st.emplace_back("partition_error", result.partition_error);
        st.emplace_back("reproduction_error", result.reproduction_error);
        st.emplace_back("min_weight", result.min_weight);
        st.emplace_back("threads", static_cast<double>(lbc_options(parameters).threads));
        st.emplace_back("geodesic_seconds", result.geodesic_seconds);
        st.emplace_back("factor_seconds", result.factor_seconds);
        st.emplace_back("admm_seconds", result.admm_seconds);
        st.emplace_back("solve_seconds", result.seconds);
      }
      return at_points;
    }
    default:
      throw bary::Error(bary::ErrorCode::InvalidArgument,
        "unknown coordinate method " + std::to_string(parameters.Method));
  }
}

bary::DenseWeights vtkBaryMethod::ComputeBBW(const bary::Skeleton& skeleton, vtkDataSet* domain,
  const Eigen::MatrixXd& points, const vtkBaryMethodParameters& parameters,
  const bary::ProgressCallback& progress, vtkBaryMethodReport* report)
{
  const int dim = vtkBaryConversion::DomainDimension(domain);
  if (skeleton.dimension() != dim)
    throw bary::Error(bary::ErrorCode::SizeMismatch,
      "the handles are " + std::to_string(skeleton.dimension()) + "D but the domain is " +
        std::to_string(dim) + "D");
  bary::validate_skeleton(skeleton);
  const auto start = Clock::now();
  Eigen::MatrixXd V;
  Eigen::MatrixXi T;
  bool meshed = false;
  // A simplicial mesh is used as is; a closed surface or a polygon is meshed with the skeleton.
  bool tets = false, triangles = false, polygons = false;
  for (vtkIdType c = 0; c < domain->GetNumberOfCells(); ++c)
  {
    const int type = domain->GetCellType(c);
    tets = tets || type == VTK_TETRA;
    triangles = triangles || type == VTK_TRIANGLE;
    polygons = polygons || type == VTK_POLYGON || type == VTK_POLY_LINE || type == VTK_QUAD;
  }
  const bool simplicial = tets || (dim == 2 && triangles && !polygons);
  if (simplicial)
    vtkBaryConversion::ToSimplices(domain, dim, V, T);
  else
  {
    vtkPolyData* surface = vtkPolyData::SafeDownCast(domain);
    if (!surface)
      throw bary::Error(bary::ErrorCode::InvalidArgument,
        "a domain to be meshed must be a vtkPolyData (a closed triangle surface or a polygon)");
    const vtkBaryCage boundary = vtkBaryConversion::ToCage(surface, dim);
    // Bone samples about one cell size apart, so the bones are resolved by the mesh.
    const int target = parameters.TargetNumberOfCells > 0 ? parameters.TargetNumberOfCells
                                                          : vtkBaryDefaultTargetCells(dim);
    const double cell = parameters.MaximumCellSize > 0 ? parameters.MaximumCellSize
                                                       : enclosed_measure(boundary.Cage) / target;
    const double spacing = dim == 2 ? std::sqrt(4.0 * cell / std::sqrt(3.0))
                                    : std::cbrt(6.0 * std::sqrt(2.0) * cell);
    const Eigen::MatrixXd samples = bary::skeleton_samples(skeleton, spacing);
    Eigen::MatrixXd steiner = samples;
    if (parameters.InsertPointsIntoMesh)
    {
      steiner.resize(samples.rows() + points.rows(), dim);
      steiner << samples, points;
    }
    vtkBaryMethodParameters meshing = parameters;
    meshing.InsertPointsIntoMesh = false;
    bary::DomainMesh mesh;
    if (dim == 2)
    {
      bary::PolygonMeshOptions options = PolygonMeshOptions(meshing, points);
      options.steiner_points = steiner;
      mesh = bary::mesh_polygon(boundary.Cage, options, slice(progress, 0, 0.1));
    }
    else
    {
      bary::SurfaceMeshOptions options = SurfaceMeshOptions(meshing, points);
      options.steiner_points = steiner;
      mesh = bary::mesh_closed_surface(boundary.Cage, options, slice(progress, 0, 0.1));
    }
    V = std::move(mesh.V);
    T = std::move(mesh.T);
    meshed = true;
  }
  const bary::BBWHandles handles =
    bary::handles_from_skeleton(V, skeleton.C, skeleton.P, skeleton.BE);
  if (report && meshed)
    report->Statistics.emplace_back("mesh_seconds", seconds_since(start));
  return solve_bbw_and_interpolate(V, T, handles, points, parameters, progress, 0.1, report);
}

bary::DomainMesh vtkBaryMethod::LBCDomainMesh(const vtkBaryCage& cage, vtkDataSet* domain,
  const Eigen::MatrixXd& points, const vtkBaryMethodParameters& parameters,
  const bary::ProgressCallback& progress)
{
  const int dim = cage.Cage.dimension();
  if (!domain)
    return dim == 2
      ? bary::mesh_polygon(cage.Cage, PolygonMeshOptions(parameters, points), progress)
      : bary::mesh_closed_surface(cage.Cage, SurfaceMeshOptions(parameters, points), progress);
  if (parameters.ValidateCage)
    bary::validate_cage(cage.Cage);
  Eigen::MatrixXd V;
  Eigen::MatrixXi T;
  vtkBaryConversion::ToSimplices(domain, dim, V, T);
  if (T.cols() != dim + 1 || V.cols() != dim)
    throw bary::Error(bary::ErrorCode::InvalidArgument,
      std::string("the domain mesh is made of ") + (T.cols() == 4 ? "tetrahedra" : "triangles") +
        " but the cage is " + std::to_string(dim) + "D: give " +
        (dim == 2 ? "a triangulation of the cage's interior, in its plane"
                  : "a tetrahedralization of the cage's interior"));
  // Each cage vertex is the mesh's boundary vertex at its coordinates.
  constexpr double kMatchTolerance = 1e-6; // relative to the cage diameter
  const double diameter = cage.Cage.diameter();
  const double tolerance = kMatchTolerance * diameter;
  const std::vector<int> boundary = boundary_vertices_of(T);
  const bary::Index nc = cage.Cage.num_controls();
  Eigen::VectorXi control(nc);
  for (bary::Index i = 0; i < nc; ++i)
  {
    double best = std::numeric_limits<double>::infinity();
    int at = -1;
    for (int v : boundary)
    {
      const double d = (V.row(v) - cage.Cage.V.row(i)).norm();
      if (d < best)
      {
        best = d;
        at = v;
      }
    }
    if (!(best <= tolerance))
    {
      std::ostringstream where;
      where.precision(7);
      where << "(" << cage.Cage.V(i, 0);
      for (int k = 1; k < dim; ++k)
        where << ", " << cage.Cage.V(i, k);
      where << ")";
      std::ostringstream gap;
      gap.precision(3);
      gap << best / diameter;
      throw bary::Error(bary::ErrorCode::InvalidArgument,
        "the domain mesh does not fit the cage: cage vertex " + std::to_string(i) + " at " +
          where.str() + " is not a boundary vertex of the mesh (the nearest one is " +
          gap.str() + " x the cage diameter away, allowed 1e-6): give a mesh of this cage's "
          "interior that has the cage vertices as vertices");
    }
    control(i) = at;
    if (progress && !progress(0.5 * static_cast<double>(i + 1) / static_cast<double>(nc)))
      throw bary::Error(bary::ErrorCode::Cancelled, "matching the domain mesh to the cage was cancelled");
  }
  bary::DomainMesh mesh =
    bary::domain_mesh_from_simplices(cage.Cage, V, T, control, kMatchTolerance);
  if (progress && !progress(1.0))
    throw bary::Error(bary::ErrorCode::Cancelled, "matching the domain mesh to the cage was cancelled");
  return mesh;
}
