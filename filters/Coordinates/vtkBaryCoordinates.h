/**
 * @class   vtkBaryCoordinates
 * @brief   Generalized barycentric coordinates of the points of a data set w.r.t. a cage.
 *
 * Input 0: any vtkDataSet whose points are evaluated (a mesh, a point cloud, an image).
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
 * Celestial coordinates (T_CELESTIAL, S_CELESTIAL) take free control points on input 1 (any
 * points; cells ignored; 2D when they lie in a plane z = const): the domain is their convex hull,
 * component i is control point i. When input 0 has cells, Newton's warm starts follow its edges.
 *
 * Local barycentric coordinates (LBC, Zhang et al. 2014) take a cage as HARMONIC does; the
 * weights are computed on a mesh of its interior (made here with TargetNumberOfCells /
 * MaximumCellSize / InsertPointsIntoMesh, or given on input 2 and used as is), then
 * interpolated at the points. Properties LBCLocality ... LBCBarycentricConstraints (defaults:
 * the paper's). A run that does not converge within LBCMaximumIterations fails the request.
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

#ifndef __VTK_WRAP__
#include "core/types.h" // for bary::DenseWeights
#endif

class vtkDataArray;
class vtkDataSet;
class vtkPolyData;

#include <string>  // for std::string
#include <utility> // for std::pair
#include <vector>  // for std::vector

class BARYLABFILTERS_EXPORT vtkBaryCoordinates : public vtkPassInputTypeAlgorithm
{
public:
  static vtkBaryCoordinates* New();
  vtkTypeMacro(vtkBaryCoordinates, vtkPassInputTypeAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// Coordinate methods. More are added by later BaryLab releases; values are stable.
  enum Methods
  {
    MEAN_VALUE = 0, ///< Hormann & Floater 2006 (2D), Ju et al. 2005 (3D); closed form, any point
    HARMONIC = 1,   ///< Joshi et al. 2007: finite elements on a mesh of the cage's interior
    BBW = 2,        ///< Jacobson et al. 2011: bounded biharmonic weights (cage or skeleton handles)
    T_CELESTIAL = 3, ///< Cerveró et al.: T-celestial coordinates of free control points
    S_CELESTIAL = 4, ///< Cerveró et al.: S-celestial coordinates of free control points
    LBC = 5,         ///< Zhang et al. 2014: local barycentric coordinates on a mesh of the cage
    NUMBER_OF_METHODS
  };

  /// Bounded biharmonic weights: how the handles' problems are solved (bary::BBWMode).
  enum BBWModes
  {
    BBW_FAST = 0,   ///< each handle alone, then rows normalized (the paper's §3.4 speed-up)
    BBW_COUPLED = 1 ///< the full problem with partition of unity enforced (default)
  };

  /// What mesh-based methods do with points outside the cage.
  enum OutsidePolicies
  {
    OUTSIDE_ERROR = 0,   ///< fail, naming how many and the first one (default)
    OUTSIDE_NEAREST = 1, ///< use the weights of the nearest point of the domain
    OUTSIDE_NAN = 2      ///< NaN weights, counted in NumberOfUndefinedPoints
  };

  ///@{
  /// The coordinate method. Default MEAN_VALUE.
  vtkSetClampMacro(Method, int, MEAN_VALUE, NUMBER_OF_METHODS - 1);
  vtkGetMacro(Method, int);
  void SetMethodToMeanValue() { this->SetMethod(MEAN_VALUE); }
  void SetMethodToHarmonic() { this->SetMethod(HARMONIC); }
  void SetMethodToBBW() { this->SetMethod(BBW); }
  void SetMethodToTCelestial() { this->SetMethod(T_CELESTIAL); }
  void SetMethodToSCelestial() { this->SetMethod(S_CELESTIAL); }
  void SetMethodToLBC() { this->SetMethod(LBC); }
  ///@}

  /// Local barycentric coordinates: tau of the paper's §3.3 (Eq. 11), the locality weight as a
  /// function of the normalised geodesic distance D to the control point (bary::LocalityFunction).
  enum LBCLocalityFunctions
  {
    LBC_LOCALITY_SQUARED = 0,  ///< tau(D) = D^2, the paper's choice for all its results (default)
    LBC_LOCALITY_CONSTANT = 1, ///< tau = 1: plain total variation (problem (5)), no distances
    LBC_LOCALITY_LINEAR = 2    ///< tau(D) = D
  };

  /// Local barycentric coordinates: how geodesic distances are normalised to [0, 1] (Eq. 12).
  enum LBCDistanceNormalizations
  {
    LBC_NORMALIZE_PER_CONTROL_POINT = 0, ///< by each control point's own maximum (Eq. 12, default)
    LBC_NORMALIZE_GLOBAL = 1 ///< by one maximum over all control points (the authors' code)
  };

  ///@{
  /// LBC: the locality function tau (LBCLocalityFunctions). Default LBC_LOCALITY_SQUARED.
  vtkSetClampMacro(LBCLocality, int, LBC_LOCALITY_SQUARED, LBC_LOCALITY_LINEAR);
  vtkGetMacro(LBCLocality, int);
  void SetLBCLocalityToSquared() { this->SetLBCLocality(LBC_LOCALITY_SQUARED); }
  void SetLBCLocalityToConstant() { this->SetLBCLocality(LBC_LOCALITY_CONSTANT); }
  void SetLBCLocalityToLinear() { this->SetLBCLocality(LBC_LOCALITY_LINEAR); }
  ///@}

  ///@{
  /// LBC: epsilon of the relaxed total variation (Eq. 7-8, §3.2), in units of 1 / (the mesh's
  /// bounding-box diameter), >= 0. 0 (default): plain total variation (exact zeros: local
  /// weights); > 0: globally C^1 weights, less local.
  vtkSetClampMacro(LBCRelaxedEpsilon, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(LBCRelaxedEpsilon, double);
  ///@}

  ///@{
  /// LBC: ADMM stopping thresholds per residual entry (Appendix B, Eq. 26-27, on the mesh
  /// rescaled to diameter 1), range [1e-15, 0.5]. Defaults: the paper's, primal 1e-6, dual 1e-5.
  /// The thresholds grow like the mesh size, the residuals like its square root: tighten them
  /// on large (especially 3D) meshes.
  vtkSetClampMacro(LBCPrimalTolerance, double, 1e-15, 0.5);
  vtkGetMacro(LBCPrimalTolerance, double);
  vtkSetClampMacro(LBCDualTolerance, double, 1e-15, 0.5);
  vtkGetMacro(LBCDualTolerance, double);
  ///@}

  ///@{
  /// LBC: cap on ADMM iterations, >= 1. Default 20000. Reaching it fails the request with a
  /// "did not converge" error (raise it or loosen the tolerances).
  vtkSetClampMacro(LBCMaximumIterations, int, 1, VTK_INT_MAX);
  vtkGetMacro(LBCMaximumIterations, int);
  ///@}

  ///@{
  /// LBC: distance normalisation (LBCDistanceNormalizations). Default
  /// LBC_NORMALIZE_PER_CONTROL_POINT.
  vtkSetClampMacro(LBCDistanceNormalization, int, LBC_NORMALIZE_PER_CONTROL_POINT,
    LBC_NORMALIZE_GLOBAL);
  vtkGetMacro(LBCDistanceNormalization, int);
  ///@}

  ///@{
  /// LBC: enforce partition of unity and reproduction (the barycentric constraints, Eq. 16).
  /// Off gives §3.2's "unconstrained TV" (each weight alone under its boundary values, >= 0):
  /// not barycentric coordinates, for studying one function's shape. Default on.
  vtkSetMacro(LBCBarycentricConstraints, bool);
  vtkGetMacro(LBCBarycentricConstraints, bool);
  vtkBooleanMacro(LBCBarycentricConstraints, bool);
  ///@}

  ///@{
  /// Celestial coordinates: SCC's wrapping-sphere parameter lambda (> 1; the coordinates do not
  /// depend on it). Default 2.
  vtkSetClampMacro(Lambda, double, 1.000001, 1e6);
  vtkGetMacro(Lambda, double);
  ///@}

  ///@{
  /// T-celestial coordinates: the user weights s_i >= 0 of Eq. 8, one tuple per control point
  /// (first component used). nullptr (default): none (Eq. 7).
  virtual void SetUserWeights(vtkDataArray* weights);
  vtkGetObjectMacro(UserWeights, vtkDataArray);
  ///@}

  ///@{
  /// BBW: BBW_FAST or BBW_COUPLED (default).
  vtkSetClampMacro(BBWMode, int, BBW_FAST, BBW_COUPLED);
  vtkGetMacro(BBWMode, int);
  ///@}

  ///@{
  /// The domain (input port 2, optional): of BBW with skeleton handles; of LBC, a
  /// triangulation (2D: triangles in the cage's plane) or tetrahedralization (3D) of the cage's
  /// interior used as is instead of meshing the cage (each cage vertex must be one of its
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
  /// Mesh-based methods: approximate number of cells of the domain mesh; 0 (default) = the
  /// method's default (2D: 3000 triangles, 3D: 20000 tetrahedra).
  vtkSetClampMacro(TargetNumberOfCells, int, 0, VTK_INT_MAX);
  vtkGetMacro(TargetNumberOfCells, int);
  ///@}

  ///@{
  /// Mesh-based methods: maximum triangle area / tetrahedron volume of the domain mesh; 0
  /// (default) = from TargetNumberOfCells.
  vtkSetClampMacro(MaximumCellSize, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(MaximumCellSize, double);
  ///@}

  ///@{
  /// Mesh-based methods: make the input points (those inside the cage) vertices of the domain
  /// mesh, so their weights are the finite-element values themselves rather than interpolated.
  /// Default off.
  vtkSetMacro(InsertPointsIntoMesh, bool);
  vtkGetMacro(InsertPointsIntoMesh, bool);
  vtkBooleanMacro(InsertPointsIntoMesh, bool);
  ///@}

  ///@{
  /// Mesh-based methods: points outside the cage (OutsidePolicies). Default OUTSIDE_ERROR.
  vtkSetClampMacro(OutsidePolicy, int, OUTSIDE_ERROR, OUTSIDE_NAN);
  vtkGetMacro(OutsidePolicy, int);
  ///@}

  /// Short name of a method as used on the command line ("mvc"), nullptr if unknown.
  static const char* GetMethodName(int method);
  /// Inverse of GetMethodName; -1 if unknown.
  static int GetMethodFromName(const char* name);

  ///@{
  /// How the cage is interpreted: vtkBaryConversion::AUTOMATIC (default, 0), CAGE_2D or CAGE_3D.
  vtkSetClampMacro(CageDimension, int, 0, 3);
  vtkGetMacro(CageDimension, int);
  ///@}

  ///@{
  /// Name of the output weights array. Default "Weights".
  vtkSetStringMacro(WeightsArrayName);
  vtkGetStringMacro(WeightsArrayName);
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
  /// Points closer to the cage than this fraction of its bounding-box diagonal are treated as on
  /// the cage (exact linear/barycentric interpolation there). Range [0, 1e-3]. Default 1e-10.
  vtkSetClampMacro(BoundaryTolerance, double, 0.0, 1e-3);
  vtkGetMacro(BoundaryTolerance, double);
  ///@}

  ///@{
  /// Validate the cage before use. Default on.
  vtkSetMacro(ValidateCage, bool);
  vtkGetMacro(ValidateCage, bool);
  vtkBooleanMacro(ValidateCage, bool);
  ///@}

  ///@{
  /// Threads for the evaluation; 0 (default) = all cores (OpenMP's default), except for LBC,
  /// where 0 means one thread: its ADMM iteration is a few short parallel loops, and libgomp's
  /// spin-waiting between them made two threads 3.5-11x slower than one on a 2-core machine
  /// shared with other builds (the authors' gecko: 1.9 s vs 20.8 s; 1.7 s with two threads and
  /// OMP_WAIT_POLICY=passive; docs/local-barycentric-coordinates.md). On an idle machine with
  /// many cores ask for threads explicitly, with OMP_WAIT_POLICY=passive in the environment.
  /// Results do not depend on it.
  vtkSetClampMacro(NumberOfThreads, int, 0, 1024);
  vtkGetMacro(NumberOfThreads, int);
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
  vtkMTimeType GetMTime() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
#ifndef __VTK_WRAP__
  /// Adds the weights (columns permuted by @p columns) and location arrays, keeps the counts.
  void FinishOutput(vtkDataSet* output, const bary::DenseWeights& W, const struct vtkBaryCage& columns,
    const struct vtkBaryMethodReport& report);
#endif

  int Method = MEAN_VALUE;
  int CageDimension = 0;
  char* WeightsArrayName = nullptr;
  bool GenerateLocation = true;
  char* LocationArrayName = nullptr;
  double BoundaryTolerance = 1e-10;
  bool ValidateCage = true;
  int NumberOfThreads = 0;
  int TargetNumberOfCells = 0;
  double MaximumCellSize = 0.0;
  bool InsertPointsIntoMesh = false;
  int OutsidePolicy = OUTSIDE_ERROR;
  int BBWMode = BBW_COUPLED;
  double Lambda = 2.0;
  vtkDataArray* UserWeights = nullptr;
  int LBCLocality = LBC_LOCALITY_SQUARED;
  double LBCRelaxedEpsilon = 0.0;
  double LBCPrimalTolerance = 1e-6;
  double LBCDualTolerance = 1e-5;
  int LBCMaximumIterations = 20000;
  int LBCDistanceNormalization = LBC_NORMALIZE_PER_CONTROL_POINT;
  bool LBCBarycentricConstraints = true;

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
