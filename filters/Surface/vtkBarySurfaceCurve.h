/**
 * @class   vtkBarySurfaceCurve
 * @brief   A cubic B-spline curve on a surface whose control points lie on the surface, as
 *          weighted averages (Panozzo et al., "Weighted averages on surfaces", ACM TOG 32(4),
 *          2013, §4.1, Fig. 2): bary::bspline_weights, then forward problems with warm starts.
 *
 * Input 0: the surface (vtkPolyData of triangles) with its embedding array (EmbeddingArrayName,
 * default `Embedding`). Input 1: the control points (any vtkPointSet, in curve order, each
 * located on the surface; farther than SurfaceTolerance x the diagonal is an error naming it).
 *
 * Output: a vtkPolyData with the curve's samples (SamplesPerSegment per segment of the uniform
 * cubic B-spline; an open curve has #controls - 3 segments plus its end point, a closed one
 * #controls segments), polylines joining consecutive valid samples (a failed sample, `Valid` =
 * 0 with NaN coordinates, breaks the line), and point data `FaceId`, `Barycentric`, `Valid`.
 *
 * @sa vtkBaryWeightedAverage vtkBarySurfaceEmbedding
 */
#ifndef vtkBarySurfaceCurve_h
#define vtkBarySurfaceCurve_h

#include "BaryLabSurfaceModule.h" // for export macro
#include "vtkPolyDataAlgorithm.h"

#include <memory> // for the cache

class BARYLABSURFACE_EXPORT vtkBarySurfaceCurve : public vtkPolyDataAlgorithm
{
public:
  static vtkBarySurfaceCurve* New();
  vtkTypeMacro(vtkBarySurfaceCurve, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// The control points (input 1).
  void SetControlPointsConnection(vtkAlgorithmOutput* output) { this->SetInputConnection(1, output); }
  void SetControlPointsData(vtkDataObject* data) { this->SetInputData(1, data); }

  vtkSetStringMacro(EmbeddingArrayName);
  vtkGetStringMacro(EmbeddingArrayName);
  /// Samples per segment, [1, 100000]. Default 16.
  vtkSetMacro(SamplesPerSegment, int);
  vtkGetMacro(SamplesPerSegment, int);
  /// A closed (periodic) curve. Default off.
  vtkSetMacro(Closed, bool);
  vtkGetMacro(Closed, bool);
  vtkBooleanMacro(Closed, bool);
  vtkSetMacro(SurfaceTolerance, double);
  vtkGetMacro(SurfaceTolerance, double);
  vtkSetMacro(NumberOfThreads, int);
  vtkGetMacro(NumberOfThreads, int);

  vtkGetMacro(NumberOfFailures, vtkIdType);

protected:
  vtkBarySurfaceCurve();
  ~vtkBarySurfaceCurve() override;
  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  char* EmbeddingArrayName = nullptr;
  int SamplesPerSegment = 16;
  bool Closed = false;
  double SurfaceTolerance;
  int NumberOfThreads = 0;
  vtkIdType NumberOfFailures = 0;

private:
  vtkBarySurfaceCurve(const vtkBarySurfaceCurve&) = delete;
  void operator=(const vtkBarySurfaceCurve&) = delete;
  struct Internals;
  std::unique_ptr<Internals> Internal;
};

#endif
