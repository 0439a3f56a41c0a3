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
 * BBW's solver figures (iterations, KKT residual, bound violation, partition error, times) are
 * available from GetStatistic() after an update.
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
  /// The domain of BBW with skeleton handles (input port 2, optional otherwise).
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
  /// Threads for the evaluation; 0 (default) = all cores (OpenMP's default). Results do not
  /// depend on it.
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
