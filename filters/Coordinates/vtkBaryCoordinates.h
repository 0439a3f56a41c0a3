/**
 * @class   vtkBaryCoordinates
 * @brief   Generalized barycentric coordinates of the points of a data set w.r.t. a cage.
 *
 * Input 0: any vtkDataSet whose points are evaluated (a mesh, a point cloud, an image).
 * Input 1 (the cage): a vtkPolyData, interpreted by vtkBaryConversion::ToCage — a closed
 * triangle surface (3D), or one polygon in a plane z = const (2D: a polygon cell, a polyline, or
 * bare points in order as in an .obj with only `v` lines).
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

class vtkPolyData;

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
    NUMBER_OF_METHODS
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

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

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

  vtkIdType NumberOfInsidePoints = 0;
  vtkIdType NumberOfOutsidePoints = 0;
  vtkIdType NumberOfBoundaryPoints = 0;
  vtkIdType NumberOfUndefinedPoints = 0;

private:
  vtkBaryCoordinates(const vtkBaryCoordinates&) = delete;
  void operator=(const vtkBaryCoordinates&) = delete;
};

#endif
