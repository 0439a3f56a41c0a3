/**
 * @class   vtkBaryCoordinates
 * @brief   Generalized barycentric coordinates of the points of a data set w.r.t. a cage.
 *
 * Input 0: any vtkDataSet whose points are evaluated (a mesh, a point cloud, an image).
 * The method and all its settings are the WeightMethod's (a vtkBaryWeightMethod, which a
 * vtkBaryCageDeformation may share): e.g. GetWeightMethod()->SetMethodToLBC().
 *
 * Input 1 (the cage): a vtkPolyData, interpreted by vtkBaryConversion::ToCage — a closed
 * triangle surface (3D), or one polygon in a plane z = const (2D: a polygon cell, a polyline, or
 * bare points in order as in an .obj with only `v` lines).
 *
 * Bounded biharmonic weights (Method BBW) take two kinds of handles on input 1:
 * - **cage handles**: a cage as above (3D: triangles; 2D: a polygon *cell* — bare points are
 *   point handles for BBW). One handle per cage point, weights linear on the cage's faces
 *   (Jacobson et al. Eq. 4); the cage's interior is meshed as for HARMONIC.
 * - **a skeleton**: points and lines (vtkBaryConversion::ToSkeleton; libigl's .tgf convention):
 *   every line segment is a bone, every point on no line a point handle; weights columns are the
 *   point handles (point order), then the bones (cell order). Needs input 2, the **domain**: a
 *   tetrahedral mesh or a triangle mesh in a plane z = const (used as is: it must contain the
 *   joints and vertices along the bones, as libigl's .mesh files do), or a closed triangle
 *   surface / one planar polygon, which is meshed with the joints and bone samples inserted.
 * - **mixed handles** (with a domain): points, bones, a cage (closed or open) and regions in one
 *   solve, told apart by a cell-data array "HandleType" (0 point, 1 bone, 2 cage, 3 region;
 *   default by cell type: polygons are cage faces), or regions as the domain's point array
 *   "HandleRegion"; a shape-preservation brush as the domain's point array "ShapePreservation"
 *   (rho >= 0 per vertex, §3.3). Columns: points, bones, cage vertices, regions
 *   (vtkBaryMixedHandles, which says when this path is taken).
 * Celestial coordinates (T_CELESTIAL, S_CELESTIAL) take free control points on input 1 (any
 * points; cells ignored; 2D when they lie in a plane z = const): the domain is their convex hull,
 * component i is control point i. When input 0 has cells, Newton's warm starts follow its edges.
 * With the method's CelestialHullPoints set to auto, when some point is outside the control
 * points' hull or on it, the corners of the enlarged bounding box of the points and the
 * controls (4 in 2D, 8 in 3D, CelestialHullMargin times its diagonal beyond it) are added as
 * controls: the weights array then has #C + #A components, the added ones last, and the output's
 * field data holds their positions as the array "AddedControlPoints" (#A tuples of 3, 2D: at
 * the controls' plane z); its number of tuples is #A. Deforming such weights moves the #C
 * controls and leaves the added ones where they are (barylab::Deform, `barylab deform`).
 *
 * The mesh-based cage methods (HARMONIC, BBW with cage handles, LBC: Zhang et al. 2014) compute
 * the weights on a mesh of the cage's interior, made here (the method's TargetNumberOfCells /
 * MaximumCellSize / InsertPointsIntoMesh) or given on input 2 and used as is, then interpolate
 * them at the points. LBC's settings are the method's LBC* properties (defaults: the paper's);
 * a run that does not converge within LBCMaximumIterations fails the request, naming the
 * settings to change.
 *
 * The solver figures of BBW (iterations, KKT residual, bound violation, partition error,
 * times) and of LBC ("mesh_vertices", "mesh_cells", "iterations", "primal_residual",
 * "dual_residual", "primal_threshold", "dual_threshold", "objective", "converged",
 * "partition_error", "reproduction_error", "min_weight", "threads", "geodesic_seconds",
 * "factor_seconds", "admm_seconds", "solve_seconds") are available from GetStatistic() after
 * an update.
 *
 * Output: a shallow copy of input 0 with
 * - a point-data array WeightsArrayName (default "Weights") of #C components: component i is the
 *   weight of cage point i, so ParaView can colour, contour and warp by any component;
 * - if GenerateLocation is on, a point-data array LocationArrayName (default "CageLocation",
 *   unsigned char): 0 inside the cage, 1 outside, 2 on the cage.
 * - for Green coordinates (GREEN, Lipman et al. 2008), whose deformation needs more than the
 *   vertex weights, a second point-data array FaceWeightsArrayName (default "FaceWeights") of
 *   #F components f0, f1, ...: the coefficient psi_j of face j's unit normal (3D: triangle j of
 *   the cage in cell order; 2D: edge j of the polygon, from its j-th to its (j+1)-th point in
 *   the order the polygon lists them), the normal oriented by the face's vertex order, so that
 *   x = sum_i Weights_i c_i + sum_j FaceWeights_j n_j. "Weights" holds phi. Other methods add no
 *   such array (one of that name on the input is removed from the output, so stale
 *   coefficients never sit beside new weights).
 * Mean value coordinates are defined outside the cage too (they may be negative there); points
 * where they are undefined get NaN weights and are counted in NumberOfUndefinedPoints.
 *
 * The cage is validated (closed, manifold, consistently oriented, not self-intersecting; 2D:
 * simple polygon) unless ValidateCage is off; any problem is reported through vtkErrorMacro
 * with a message that names the offending edge/face/vertex, and the request fails.
 *
 * Progress is reported as a real fraction; SetAbortExecute(1) from a progress observer stops
 * the computation (the request then fails with "cancelled").
 *
 * @warning Dense weights: memory is #P x #C doubles.
 * @sa vtkBaryCageDeformation vtkBaryConversion
 */
#ifndef vtkBaryCoordinates_h
#define vtkBaryCoordinates_h

#include "BaryLabFiltersModule.h" // for export macro
#include "vtkPassInputTypeAlgorithm.h"

#include "vtkBaryWeightMethod.h" // for the methods and their settings

#ifndef __VTK_WRAP__
#include "core/common/weights_result.h" // for bary::WeightsResult
#endif

class vtkDataArray;
class vtkDataSet;
class vtkMultiProcessController;
class vtkPolyData;

#include <functional> // for std::function
#include <string>  // for std::string
#include <utility> // for std::pair
#include <vector>  // for std::vector

class BARYLABFILTERS_EXPORT vtkBaryCoordinates : public vtkPassInputTypeAlgorithm
{
public:
  static vtkBaryCoordinates* New();
  vtkTypeMacro(vtkBaryCoordinates, vtkPassInputTypeAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// The weight method and all its settings (method, cage dimension, tolerances, mesh size,
  /// outside policy, each method's own settings: see vtkBaryWeightMethod). A new
  /// vtkBaryWeightMethod (mean value coordinates) by default; never nullptr. The same object
  /// may be shared with a vtkBaryCageDeformation.
  virtual void SetWeightMethod(vtkBaryWeightMethod* method);
  vtkGetObjectMacro(WeightMethod, vtkBaryWeightMethod);
  ///@}

  /// Includes the weight method's modification time (a setting changed on a shared method
  /// re-executes the filter).
  vtkMTimeType GetMTime() override;

  ///@{
  /// The domain (input port 2, optional): of BBW with skeleton handles; of the mesh-based cage
  /// methods (HARMONIC, BBW with cage handles, LBC), a triangulation (2D: triangles in the
  /// cage's plane) or tetrahedralization (3D) of the cage's interior used as is instead of
  /// meshing the cage (each cage vertex must be one of its
  /// boundary vertices, within 1e-6 of the cage diameter, and its boundary must lie on the
  /// cage; the request fails naming the first cage vertex that has no mesh vertex).
  void SetDomainData(vtkDataSet* domain);
  void SetDomainConnection(vtkAlgorithmOutput* output);
  ///@}

  ///@{
  /// Figures of the last computation by name (NaN when the method does not report it), e.g.
  /// "mesh_vertices", "fast_iterations", "max_kkt_residual", "partition_error", "solve_seconds".
  double GetStatistic(const char* name) const;
  int GetNumberOfStatistics() const { return static_cast<int>(this->Statistics.size()); }
  const char* GetStatisticName(int i) const;
  double GetStatisticValue(int i) const;
  ///@}

  ///@{
  /// Name of the output weights array. Default "Weights".
  vtkSetStringMacro(WeightsArrayName);
  vtkGetStringMacro(WeightsArrayName);
  ///@}

  ///@{
  /// Name of the output face-coefficients array of methods that have one (GREEN: psi, one
  /// component per cage face or 2D edge). Default "FaceWeights".
  vtkSetStringMacro(FaceWeightsArrayName);
  vtkGetStringMacro(FaceWeightsArrayName);
  ///@}

  ///@{
  /// Add the per-point location array (inside/outside/on the cage). Default on.
  vtkSetMacro(GenerateLocation, bool);
  vtkGetMacro(GenerateLocation, bool);
  vtkBooleanMacro(GenerateLocation, bool);
  vtkSetStringMacro(LocationArrayName);
  vtkGetStringMacro(LocationArrayName);
  ///@}

  ///@{
  /// The processes of a distributed run (VTK's parallel pipeline: each process holds a piece
  /// of input 0, and the whole cage and domain, which RequestUpdateExtent asks for whole).
  /// Default: the global controller (vtkMultiProcessController::GetGlobalController(): null,
  /// or one process, in a serial program). With several processes every process must execute
  /// the filter, as everywhere in VTK's parallel pipeline: the mesh-based methods (HARMONIC,
  /// BBW, LBC) mesh and solve once, on process 0, and send the mesh weights to the others,
  /// which interpolate their pieces (the serial run's weights, bitwise); an error of that solve
  /// fails the request on every process with its message. Celestial coordinates decide and
  /// place hull points from all the pieces' points (gathered; points flagged as duplicates in
  /// vtkGhostType left out, ordered by the pieces' global point ids when they have them: then
  /// the serial run's hull points). The other methods evaluate each
  /// piece on its own. InsertPointsIntoMesh (a mesh made of all the points) is refused.
  virtual void SetController(vtkMultiProcessController* controller);
  vtkGetObjectMacro(Controller, vtkMultiProcessController);
  ///@}

  ///@{
  /// The cage (input port 1).
  void SetCageData(vtkPolyData* cage);
  void SetCageConnection(vtkAlgorithmOutput* output);
  ///@}

  ///@{
  /// Counts from the last execution.
  vtkGetMacro(NumberOfInsidePoints, vtkIdType);
  vtkGetMacro(NumberOfOutsidePoints, vtkIdType);
  vtkGetMacro(NumberOfBoundaryPoints, vtkIdType);
  vtkGetMacro(NumberOfUndefinedPoints, vtkIdType);
  ///@}

protected:
  vtkBaryCoordinates();
  ~vtkBaryCoordinates() override;
  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  /// Input 0 follows the requested piece; the cage and the domain are requested whole.
  int RequestUpdateExtent(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
#ifndef __VTK_WRAP__
  /// The weights of @p input (a piece) from one solve on process 0 of Controller: @p compute
  /// (points, and the mesh weights to interpolate or null to solve) runs there on no points,
  /// its error or its MeshWeights are broadcast, then every process interpolates its piece.
  bary::WeightsResult ComputeShared(vtkDataSet* input,
    const std::function<bary::WeightsResult(vtkDataSet*, const bary::MeshWeights*)>& compute);
  /// Adds the weights (columns permuted by @p columns) and location arrays, keeps the counts.
  void FinishOutput(vtkDataSet* output, const bary::WeightsResult& result,
    const struct vtkBaryCage& columns);
#endif

  vtkBaryWeightMethod* WeightMethod = nullptr;
  vtkMultiProcessController* Controller = nullptr;
  char* WeightsArrayName = nullptr;
  char* FaceWeightsArrayName = nullptr;
  bool GenerateLocation = true;
  char* LocationArrayName = nullptr;

  vtkIdType NumberOfInsidePoints = 0;
  vtkIdType NumberOfOutsidePoints = 0;
  vtkIdType NumberOfBoundaryPoints = 0;
  vtkIdType NumberOfUndefinedPoints = 0;
  std::vector<std::pair<std::string, double>> Statistics;

private:
  vtkBaryCoordinates(const vtkBaryCoordinates&) = delete;
  void operator=(const vtkBaryCoordinates&) = delete;
};

#endif
