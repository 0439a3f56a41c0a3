#pragma once
/// @file barylabPipeline.h
/// The pipeline builder shared by the command line, the viewer and the tests: reading inputs,
/// running the coordinate and deformation filters with errors turned into exceptions, and
/// summarising results. No algorithm code: everything numerical is in core/ and filters/.

#include "core/common/error.h"
#include "core/coordinates/weight_methods.h"

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "vtkSmartPointer.h"

#include <functional>
#include <string>
#include <vector>

class vtkAlgorithm;
class vtkDataSet;
class vtkPointSet;
class vtkPolyData;
class vtkUnstructuredGrid;

namespace barylab
{

/// Callbacks for long runs; both optional.
struct RunCallbacks
{
  std::function<void(double)> progress;               ///< fraction in [0, 1]
  std::function<void(const std::string&)> warning;    ///< a filter's warning message
  std::function<bool()> cancel;                       ///< return true to abort
};

/// Updates @p algorithm; an error event becomes bary::Error with the filter's message (code
/// @p code), warnings go to callbacks.warning, progress to callbacks.progress.
void RunAlgorithm(vtkAlgorithm* algorithm, const RunCallbacks& callbacks,
  bary::ErrorCode code = bary::ErrorCode::InvalidArgument);

/// The parameter object of a weights computation (what the CLI flags and the viewer's panel
/// edit): the method and every setting of BaryLab's one settings table (bary::WeightsSettings,
/// core/coordinates/weight_methods.h: defaults, ranges and documentation), plus the name of the array.
struct WeightsParameters : bary::WeightsSettings
{
  std::string weights_name = "Weights";
};

/// The command-line name of @p parameters' method ("mvc").
std::string MethodName(const WeightsParameters& parameters);

/// True for methods whose controls are free points (tcc, scc): they take --control-points.
bool IsPointBasedMethod(bary::MethodId method);

/// Parameters of `barylab mesh` / vtkBaryCageMesher.
struct MeshParameters
{
  int cage_dimension = 0;
  int target_cells = 3000;
  double max_cell_size = 0.0;
  double min_angle = 20.0;           ///< 2D, degrees
  double radius_edge_ratio = 1.414;  ///< 3D, TetGen 'q'
  bool preserve_boundary = false;    ///< 3D, TetGen 'Y'
};

/// Meshes the interior of @p cage, inserting the points of @p points (may be null).
vtkSmartPointer<vtkUnstructuredGrid> MeshCage(vtkPolyData* cage, vtkPointSet* points,
  const MeshParameters& parameters, const RunCallbacks& callbacks = {},
  nlohmann::json* summary = nullptr);

/// Weights of the points of @p points w.r.t. @p cage: a copy of @p points with the weights
/// array (and the CageLocation array). Fills @p summary (if given) with counts and timings,
/// and with the method's solver figures under "solver". For BBW, @p cage may instead be a
/// skeleton (points and lines) with @p domain the mesh or closed surface it lives in (see
/// vtkBaryCoordinates).
vtkSmartPointer<vtkDataSet> ComputeWeights(vtkDataSet* points, vtkPolyData* cage,
  const WeightsParameters& parameters, const RunCallbacks& callbacks = {},
  nlohmann::json* summary = nullptr, vtkDataSet* domain = nullptr);

/// Deforms @p weighted (carrying the weights array parameters.weights_name, one component per
/// handle) by linear blend skinning with one 3 x 4 transform [A | t] per handle
/// (vtkBaryLinearBlendSkinning).
vtkSmartPointer<vtkPointSet> Skin(vtkPointSet* weighted, const std::vector<Eigen::MatrixXd>& pose,
  const WeightsParameters& parameters, const RunCallbacks& callbacks = {},
  nlohmann::json* summary = nullptr);

/// Deforms @p model by moving @p rest_cage to @p posed_cage. If @p model carries the weights
/// array (e.g. read from a file written by ComputeWeights), it is used as is. Control points
/// the weights method added (celestial hull points: the field data "AddedControlPoints" of
/// vtkBaryCoordinates, whose columns follow the controls') stay where they are: @p posed_cage
/// holds the given controls only. Free control points without weights on @p model get them
/// computed here first (so that hull points can be added).
vtkSmartPointer<vtkPointSet> Deform(vtkPointSet* model, vtkPolyData* rest_cage,
  vtkPointSet* posed_cage, const WeightsParameters& parameters,
  const RunCallbacks& callbacks = {}, nlohmann::json* summary = nullptr);

/// A time series: @p weighted (a model carrying the weights array) deformed by each of
/// @p frames (moved control points / cages, same points as @p rest_cage), written as
/// <prefix>_NNN.vtp files in @p output_dir plus <prefix>.pvd (ParaView's collection of the frames,
/// time = frame / #frames * @p period). Weights are computed once (by the caller) and reused.
/// Returns the .pvd path; fills @p summary with the frames written and the time per frame.
/// Writes @p frames as <prefix>_NNN.vtp in @p output_dir plus <prefix>.pvd (ParaView's
/// collection, time = frame / #frames * @p period); returns the .pvd path.
/// A null frame is another process's (a distributed run): listed in the .pvd, not written
/// here; @p write_collection false leaves the .pvd to another process.
std::string WriteTimeSeries(const std::vector<vtkSmartPointer<vtkDataSet>>& frames,
  const std::string& output_dir, const std::string& prefix, double period = 1.0,
  bool write_collection = true);

/// As WriteTimeSeries, a null frame is another process's and @p write_collection says whether
/// this process writes the .pvd.
std::string WriteAnimation(vtkPointSet* weighted, vtkPolyData* rest_cage,
  const std::vector<vtkSmartPointer<vtkPointSet>>& frames, const WeightsParameters& parameters,
  const std::string& output_dir, const std::string& prefix, double period = 1.0,
  nlohmann::json* summary = nullptr, bool write_collection = true);

/// Property statistics of the weights array @p array_name of @p data (partition of unity,
/// min/max, negative entries, significant weights per point above @p threshold, where a
/// negative threshold means 1e-3 / #C). With @p cage, also the reproduction error.
nlohmann::json WeightStatisticsJson(vtkDataSet* data, const std::string& array_name,
  vtkPolyData* cage, double threshold = -1.0, int cage_dimension = 0);

/// Locality statistics (Zhang et al. 2014, §5; vtkBaryLocalityStatistics) of the weights array
/// @p array_name of @p data: {"array", "points", "controls", "threshold", "measure" ("uniform",
/// "area", "volume"), "mean_support", "max_support", "t", "P", "k", "Q", "influence_fraction"}.
/// A negative @p threshold means 1e-3 / #C; with @p use_mesh_measure, points of a 2D triangle
/// or tetrahedral mesh count with their lumped area/volume.
nlohmann::json LocalityStatisticsJson(vtkDataSet* data, const std::string& array_name,
  double threshold = -1.0, bool use_mesh_measure = true);

/// Parameters of `barylab reduce` / vtkBaryReduceWeights.
struct ReduceParameters
{
  std::string weights_name = "Weights";
  double threshold = -1.0;           ///< negative: 1e-3 / #C
  std::string renormalize = "rowsum"; ///< rowsum | affine | none
  bool keep_dense = false;           ///< keep the dense array beside the compact pair
};

/// Sparse weights (vtkBaryReduceWeights): a copy of @p weighted with the dense array replaced by
/// <name>Indices / <name>Values. @p cage (may be null) gives the reproduction error and is
/// required for "affine". Fills @p summary with K, errors and memory.
vtkSmartPointer<vtkDataSet> ReduceWeights(vtkDataSet* weighted, vtkPolyData* cage,
  const ReduceParameters& parameters, const RunCallbacks& callbacks = {},
  nlohmann::json* summary = nullptr);

/// |grad w_i| of every component of the weights array @p weights_name of @p weighted, by VTK's
/// vtkGradientFilter (per-cell gradients of the linear interpolant, averaged at the points): a
/// copy of @p weighted with the point-data array "<weights_name>GradientNorm" (one component
/// per weight). Fills @p summary with the max / mean norm per component.
/// @throws bary::Error(InvalidArgument) for a missing array or a dataset without cells of
///   dimension >= 2 (a point cloud has no gradient).
vtkSmartPointer<vtkDataSet> WeightGradientNorms(vtkDataSet* weighted,
  const std::string& weights_name = "Weights", nlohmann::json* summary = nullptr);

/// Level sets w_component = value for each of @p levels, by VTK's vtkContourFilter (lines on a
/// 2D or surface mesh, surfaces in a volume mesh), with cell data "level" (the value) and
/// point data "weight". An empty @p levels means the influence threshold 10^-3 / n.
/// @throws bary::Error(InvalidArgument) for a missing array or a component out of range.
vtkSmartPointer<vtkPolyData> WeightLevelSets(vtkDataSet* weighted, int component,
  std::vector<double> levels, const std::string& weights_name = "Weights");

/// Dimension (2 or 3) of @p cage as the filters interpret it.
int CageDimension(vtkPolyData* cage, int requested = 0);

/// Writes @p json to @p path (pretty, atomically). Throws bary::Error(Io).
void WriteJson(const nlohmann::json& json, const std::string& path);

} // namespace barylab
