/**
 * @class   vtkBaryEnclosingCage
 * @brief   Makes a coarse cage that strictly encloses a model (automatic cage generation).
 *
 * Input: the model (vtkPolyData): a triangle surface (3D; closed or not, every triangle is
 * enclosed), a triangle mesh in a plane z = const (2D), or a polygon / polylines in such a plane
 * (2D, enclosed as segments). Output: the cage (vtkPolyData): 3D, a closed, manifold,
 * outward-oriented triangle surface free of self-intersections; 2D, one counter-clockwise
 * polygon cell in the model's plane. It has NumberOfVertices vertices, or more when no valid
 * collapse was left (ReachedTarget false, with a warning).
 *
 * Method (bary::enclosing_cage, docs/cage-generation.md): the outer offset surface of the
 * model at distance Margin on a grid (marching tetrahedra), then greedy edge collapses by
 * quadric error, each accepted only if the cage stays manifold, unfolded, free of
 * self-intersections and the region it sweeps meets no model triangle (exact predicates, CGAL),
 * then a few rounds moving the vertices toward the model under the same checks.
 *
 * Bad input (empty, NaN, a target below 4 in 3D / 3 in 2D, cells that are neither triangles
 * nor, in 2D, polygons / lines) fails the update with vtkErrorMacro; the error code carries the
 * bary::ErrorCode (vtkBaryConversion::ErrorCodeOf).
 *
 * @sa vtkBaryCageMesher, vtkBaryCoordinates
 */
#ifndef vtkBaryEnclosingCage_h
#define vtkBaryEnclosingCage_h

#include "BaryLabFiltersModule.h" // for export macro
#include "vtkPolyDataAlgorithm.h"

#include <string> // for StopReason

class BARYLABFILTERS_EXPORT vtkBaryEnclosingCage : public vtkPolyDataAlgorithm
{
public:
  static vtkBaryEnclosingCage* New();
  vtkTypeMacro(vtkBaryEnclosingCage, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Target number of cage vertices, >= 3 (a 3D model needs >= 4: the update fails below).
  /// Default 100.
  vtkSetClampMacro(NumberOfVertices, int, 3, VTK_INT_MAX);
  vtkGetMacro(NumberOfVertices, int);
  ///@}

  ///@{
  /// Offset distance of the initial surface, model units; 0 (default) = MarginFraction x the
  /// model's bounding-box diagonal.
  vtkSetClampMacro(Margin, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(Margin, double);
  ///@}

  ///@{
  /// The automatic margin as a fraction of the bounding-box diagonal, in (0, 1]. Default 0.05.
  vtkSetClampMacro(MarginFraction, double, 1e-6, 1.0);
  vtkGetMacro(MarginFraction, double);
  ///@}

  ///@{
  /// Distance-grid cells per margin, in [2, 64]. Default 2.
  vtkSetClampMacro(Resolution, double, 2.0, 64.0);
  vtkGetMacro(Resolution, double);
  ///@}

  ///@{
  /// Tightening after decimation: rounds of moves of each vertex toward its closest model point
  /// (0 = none), in [0, 1000], default 4; the distance they leave, in margins, in [0, 1],
  /// default 0.25.
  vtkSetClampMacro(TightenRounds, int, 0, 1000);
  vtkGetMacro(TightenRounds, int);
  vtkSetClampMacro(Clearance, double, 0.0, 1.0);
  vtkGetMacro(Clearance, double);
  ///@}

  ///@{
  /// Results of the last update (NaN / 0 before one): the margin used, the offset surface's
  /// vertices, whether the target was reached, the cage's volume (3D) or area (2D) over the
  /// model's (NaN for an open 3D model), the largest and mean distance from a cage vertex to
  /// the model, the model's bounding-box diagonal, wall-clock seconds.
  vtkGetMacro(MarginUsed, double);
  vtkGetMacro(OffsetVertices, vtkIdType);
  vtkGetMacro(ReachedTarget, bool);
  vtkGetMacro(VolumeRatio, double);
  vtkGetMacro(ModelMeasure, double);
  vtkGetMacro(CageMeasure, double);
  vtkGetMacro(MaximumDistance, double);
  vtkGetMacro(MeanDistance, double);
  vtkGetMacro(Diagonal, double);
  vtkGetMacro(Seconds, double);
  /// Edge collapses and tightening moves made; why decimation stopped ("target reached", "no
  /// valid collapse left", ...).
  vtkGetMacro(Collapses, vtkIdType);
  vtkGetMacro(TightenMoves, vtkIdType);
  const char* GetStopReason() const { return this->StopReason.c_str(); }
  ///@}

protected:
  vtkBaryEnclosingCage() = default;
  ~vtkBaryEnclosingCage() override = default;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  int NumberOfVertices = 100;
  double Margin = 0.0;
  double MarginFraction = 0.05;
  double Resolution = 2.0;
  int TightenRounds = 4;
  double Clearance = 0.25;
  double MarginUsed = 0.0;
  vtkIdType OffsetVertices = 0;
  bool ReachedTarget = false;
  double VolumeRatio = 0.0;
  double ModelMeasure = 0.0;
  double CageMeasure = 0.0;
  double MaximumDistance = 0.0;
  double MeanDistance = 0.0;
  double Diagonal = 0.0;
  double Seconds = 0.0;
  vtkIdType Collapses = 0;
  vtkIdType TightenMoves = 0;
  std::string StopReason;

private:
  vtkBaryEnclosingCage(const vtkBaryEnclosingCage&) = delete;
  void operator=(const vtkBaryEnclosingCage&) = delete;
};

#endif
