/**
 * @class   vtkBaryCageMesher
 * @brief   Triangulates (2D) or tetrahedralizes (3D) the interior of a cage.
 *
 * The volumetric methods (harmonic coordinates, bounded biharmonic weights, local barycentric
 * coordinates) compute weights at the vertices of such a mesh. Input 0: the cage (vtkPolyData,
 * interpreted by vtkBaryConversion::ToCage). Optional input 1: points to insert as mesh vertices
 * (Steiner points: the model's vertices, handle points), so weights exist exactly there; points
 * outside the cage are skipped and counted.
 *
 * 2D: CGAL's constrained Delaunay mesher with a minimum angle (default 20 degrees) and a maximum
 * triangle area. 3D: TetGen with a radius-edge ratio bound (default 1.414) and a maximum
 * tetrahedron volume. The size bound is MaximumCellSize when > 0, otherwise the cage's area or
 * volume divided by TargetNumberOfCells (the result is approximate).
 *
 * Output: a vtkUnstructuredGrid of triangles or tetrahedra with point-data arrays
 * "ControlPointId" (vtkIdTypeArray: the cage point at this vertex, -1 elsewhere) and
 * "OnCage" (unsigned char: 1 for vertices on the cage boundary).
 *
 * The cage is validated first (closed, manifold, oriented, not self-intersecting); failures are
 * reported with vtkErrorMacro naming the culprit.
 *
 * @sa vtkBaryCoordinates
 */
#ifndef vtkBaryCageMesher_h
#define vtkBaryCageMesher_h

#include "BaryLabFiltersModule.h" // for export macro
#include "vtkUnstructuredGridAlgorithm.h"

class vtkPointSet;
class vtkPolyData;

class BARYLABFILTERS_EXPORT vtkBaryCageMesher : public vtkUnstructuredGridAlgorithm
{
public:
  static vtkBaryCageMesher* New();
  vtkTypeMacro(vtkBaryCageMesher, vtkUnstructuredGridAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Approximate number of cells when MaximumCellSize is 0. Default 3000 (the LBC paper's
  /// setting in 2D).
  vtkSetClampMacro(TargetNumberOfCells, int, 1, VTK_INT_MAX);
  vtkGetMacro(TargetNumberOfCells, int);
  ///@}

  ///@{
  /// Maximum triangle area (2D) or tetrahedron volume (3D); 0 (default) = from
  /// TargetNumberOfCells.
  vtkSetClampMacro(MaximumCellSize, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(MaximumCellSize, double);
  ///@}

  ///@{
  /// 2D: minimum triangle angle in degrees, clamped to [0, 20.7] (CGAL's termination bound,
  /// bary::kMaxMinAngleDegrees). Default 20.
  virtual void SetMinimumAngle(double degrees);
  vtkGetMacro(MinimumAngle, double);
  ///@}

  ///@{
  /// 3D: TetGen's radius-edge ratio bound (its 'q' switch); 0 disables quality refinement.
  /// Otherwise in [1.1, 10] (bary::kMinRadiusEdgeRatio, kMaxRadiusEdgeRatio): larger values
  /// are clamped to 10, values in (0, 1.1) make the update fail (TetGen's refinement may not
  /// end). Default 1.414.
  virtual void SetRadiusEdgeRatio(double ratio);
  vtkGetMacro(RadiusEdgeRatio, double);
  ///@}

  ///@{
  /// 3D: add no vertices on the cage's faces (TetGen 'Y'). Default off.
  vtkSetMacro(PreserveBoundary, bool);
  vtkGetMacro(PreserveBoundary, bool);
  vtkBooleanMacro(PreserveBoundary, bool);
  ///@}

  ///@{
  /// Cage interpretation (vtkBaryConversion::CageDimension). Default automatic (0).
  vtkSetClampMacro(CageDimension, int, 0, 3);
  vtkGetMacro(CageDimension, int);
  ///@}

  ///@{
  /// Inputs: the cage (port 0) and the optional points to insert (port 1).
  void SetCageData(vtkPolyData* cage);
  void SetPointsData(vtkPointSet* points);
  void SetPointsConnection(vtkAlgorithmOutput* output);
  ///@}

  /// Inserted points that lay outside the cage in the last execution (not inserted).
  vtkGetMacro(NumberOfSkippedPoints, vtkIdType);

protected:
  vtkBaryCageMesher();
  ~vtkBaryCageMesher() override = default;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  int TargetNumberOfCells = 3000;
  double MaximumCellSize = 0.0;
  double MinimumAngle = 20.0;
  double RadiusEdgeRatio = 1.414;
  bool PreserveBoundary = false;
  int CageDimension = 0;
  vtkIdType NumberOfSkippedPoints = 0;

private:
  vtkBaryCageMesher(const vtkBaryCageMesher&) = delete;
  void operator=(const vtkBaryCageMesher&) = delete;
};

#endif
