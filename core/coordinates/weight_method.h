#pragma once
/// @file weight_method.h
/// One class per weight method: it turns WeightsSettings into its algorithm's options, runs the
/// algorithm (meshing the domain and interpolating at the points where the method works on a
/// mesh) and returns the common WeightsResult. compute_weights() dispatches on the method
/// table (weight_methods.h); the VTK filters call nothing else.

#include "core/common/cage.h"
#include "core/meshing/domain_mesh.h"
#include "core/common/progress.h"
#include "core/deformation/skeleton.h"
#include "core/common/types.h"
#include "core/coordinates/weight_methods.h"
#include "core/common/weights_result.h"

namespace bary
{

/// What a weight method is computed from. Pointers are non-owning; only what the method uses
/// must be set (MethodInfo says which).
struct WeightsInput
{
  /// The cage (cage methods), or the control points in V (free-point methods, F empty).
  const Cage* cage = nullptr;
  /// BBW with skeleton handles (then cage is null and a domain is required).
  const Skeleton* skeleton = nullptr;
  /// A given simplicial domain mesh (#V by dim vertices, #T by dim+1 simplices): LBC uses it
  /// instead of meshing the cage, BBW with a skeleton as is.
  const Eigen::MatrixXd* domain_V = nullptr;
  const Eigen::MatrixXi* domain_T = nullptr;
  /// A closed surface / polygon whose interior is meshed (BBW with a skeleton).
  const Cage* domain_boundary = nullptr;
  /// BBW with a given domain mesh: region handles as lists of domain_V rows, numbered after the
  /// skeleton's handles (mixed_bbw_handles, bbw_handles.h). Optional.
  const std::vector<std::vector<int>>* region_vertices = nullptr;
  /// BBW with a given domain mesh: the shape-preservation brush rho >= 0 per domain_V row
  /// (§3.3, Eq. 7; shape_preservation_per_element). Optional.
  const Eigen::VectorXd* shape_preservation = nullptr;
  /// #P by dim evaluation points (required).
  const Eigen::MatrixXd* points = nullptr;
  /// #E by 2 point ids: the input's mesh edges, for warm starts along neighbours (optional).
  const Eigen::MatrixXi* edges = nullptr;
  /// Mesh-based methods: weights already solved on the domain mesh (the mesh_weights of a run
  /// on the same inputs and settings, e.g. on another process of a distributed run). The
  /// method is not run: the points are only interpolated, exactly as that run interpolated its
  /// own. Optional.
  const MeshWeights* mesh_weights = nullptr;
  /// Celestial coordinates: all the points of which input.points is a part (a distributed
  /// run's piece). The hull points' decision and box (CelestialOptions::hull_points) are made
  /// from them, so that every piece gets the same columns as the whole. Optional.
  const Eigen::MatrixXd* hull_reference_points = nullptr;
};

/// A weight method: stateless, thread-safe, one instance per method (MethodInfo::instance).
class WeightMethod
{
public:
  virtual ~WeightMethod() = default;
  /// Weights of input.points; W's columns in the controls' order (a 2D cage's polygon order;
  /// BBW: point handles, then bones). Progress covers the whole computation.
  /// @throws Error (invalid input, settings that do not fit the method, non-convergence with
  ///   advice naming the settings, cancellation)
  virtual WeightsResult compute(const WeightsInput& input, const WeightsSettings& settings,
    const ProgressCallback& progress) const = 0;
};

/// Checks the settings and runs settings.method.
WeightsResult compute_weights(
  const WeightsInput& input, const WeightsSettings& settings, const ProgressCallback& progress = {});

/// Domain-mesh options of @p settings for a cage (size bound; the points as Steiner points
/// when insert_points). Shared by the mesh-based methods and the cage mesher.
PolygonMeshOptions polygon_mesh_options(const WeightsSettings& settings, const Eigen::MatrixXd& points);
SurfaceMeshOptions surface_mesh_options(const WeightsSettings& settings, const Eigen::MatrixXd& points);
/// The interior of @p cage meshed with the options above (2D or 3D by the cage).
DomainMesh mesh_cage_interior(const Cage& cage, const WeightsSettings& settings,
  const Eigen::MatrixXd& points, const ProgressCallback& progress);

/// The domain mesh of a mesh-based cage method: the given one (input.domain_V / domain_T, each
/// cage vertex matched to its boundary vertex: domain_mesh_for_cage; the cage validated first
/// unless settings.validate_cage is off), else the cage's interior meshed (mesh_cage_interior).
DomainMesh cage_domain_mesh(const WeightsInput& input, const WeightsSettings& settings,
  const ProgressCallback& progress);

/// The "advice" of an error, naming settings by their command-line flag and filter property:
/// "raise LBCMaximumIterations (--max-iterations)". @p verb_keys: pairs of a verb and keys.
std::string settings_advice(const std::vector<std::pair<std::string, std::vector<std::string>>>& verb_keys);

/// The methods' instances (their MethodInfo::instance).
const WeightMethod& mean_value_method();
const WeightMethod& harmonic_method();
const WeightMethod& bbw_method();
const WeightMethod& t_celestial_method();
const WeightMethod& s_celestial_method();
const WeightMethod& lbc_method();
const WeightMethod& green_method();

namespace detail
{
/// A progress callback for the slice [begin, end] of @p progress.
ProgressCallback progress_slice(const ProgressCallback& progress, double begin, double end);
/// Weights @p W at the vertices of the mesh (V, T) interpolated at @p points with the outside
/// policy of @p settings (progress 0.95 to 1 of @p progress): W, location and undefined of
/// @p result are set.
void interpolate_on_mesh(const Eigen::MatrixXd& V, const Eigen::MatrixXi& T, const DenseWeights& W,
  const Eigen::MatrixXd& points, const WeightsSettings& settings,
  const ProgressCallback& progress, WeightsResult& result);
/// Seconds since @p start (a steady-clock time in seconds from seconds_now()).
double seconds_now();
} // namespace detail

} // namespace bary
