/**
 * @class   vtkBarySurfaceWeights
 * @brief   Weights of points on a surface with respect to anchors on it: the inverse problem of
 *          Panozzo et al., "Weighted averages on surfaces" (ACM TOG 32(4), 2013, §3.4), through
 *          bary::WeightedAverages, with the round trip of §4.4.
 *
 * Input 0: the points (any vtkPointSet: the surface itself for weights at every vertex, or
 * other points, each located on the surface). Input 1: the surface (vtkPolyData of triangles)
 * with its embedding array (EmbeddingArrayName, default `Embedding`). Input 2: the anchors (any
 * vtkPointSet, located on the surface). Points or anchors farther than SurfaceTolerance x the
 * surface's diagonal from it are an error naming the first.
 *
 * Output: a shallow copy of input 0 with point data WeightsArrayName (default `Weights`, one
 * component per anchor, named c0, c1, ...; rows sum to 1; an anchor's own row is e_i),
 * `FaceId`, `Barycentric` (where each point was located) and, with RoundTrip (default on),
 * `RoundTripError` (distance from forward(inverse(x)) to x; NaN where the forward problem
 * failed) and `Defined` (unsigned char: 1 where the round trip returns within RoundTripTolerance
 * x the mean edge length; elsewhere the point is not a weighted average of the anchors and its
 * weights are meaningless, §4.4). GetNumberOfUndefined counts the zeros.
 *
 * Gamma (default 10, the paper's) weighs the anchors' distance off the tangent plane.
 *
 * Local parametrisation and decals (§4.2): with SetAnchorTextureCoordinates(array) (one tuple
 * of 2 components per anchor: where each anchor sits in texture space, e.g. the corners of the
 * unit square for four anchors around a decal), the output also gets `TCoords` = sum_i w_i uv_i,
 * set as the active texture coordinates, with NaN where the point is not `Defined` (needs
 * RoundTrip) so that no texel is placed where the weights are meaningless.
 *
 * @sa vtkBaryWeightedAverage vtkBarySurfaceEmbedding vtkBarySurfaceData
 */
#ifndef vtkBarySurfaceWeights_h
#define vtkBarySurfaceWeights_h

#include "BaryLabSurfaceModule.h" // for export macro
#include "vtkPointSetAlgorithm.h"

class vtkDataArray;

#include <memory> // for the cache

class BARYLABSURFACE_EXPORT vtkBarySurfaceWeights : public vtkPointSetAlgorithm
{
public:
  static vtkBarySurfaceWeights* New();
  vtkTypeMacro(vtkBarySurfaceWeights, vtkPointSetAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// The surface (input 1) and the anchors (input 2).
  void SetSurfaceConnection(vtkAlgorithmOutput* output) { this->SetInputConnection(1, output); }
  void SetSurfaceData(vtkDataObject* data) { this->SetInputData(1, data); }
  void SetAnchorsConnection(vtkAlgorithmOutput* output) { this->SetInputConnection(2, output); }
  void SetAnchorsData(vtkDataObject* data) { this->SetInputData(2, data); }

  vtkSetStringMacro(EmbeddingArrayName);
  vtkGetStringMacro(EmbeddingArrayName);
  vtkSetStringMacro(WeightsArrayName);
  vtkGetStringMacro(WeightsArrayName);
  vtkSetMacro(Gamma, double);
  vtkGetMacro(Gamma, double);
  vtkSetMacro(SurfaceTolerance, double);
  vtkGetMacro(SurfaceTolerance, double);
  vtkSetMacro(RoundTrip, bool);
  vtkGetMacro(RoundTrip, bool);
  vtkBooleanMacro(RoundTrip, bool);
  vtkSetMacro(RoundTripTolerance, double);
  vtkGetMacro(RoundTripTolerance, double);
  vtkSetMacro(NumberOfThreads, int);
  vtkGetMacro(NumberOfThreads, int);
  /// Texture coordinates of the anchors (2 components, one tuple per anchor), or null.
  void SetAnchorTextureCoordinates(vtkDataArray* uv);
  vtkDataArray* GetAnchorTextureCoordinates();
  vtkMTimeType GetMTime() override;

  vtkGetMacro(NumberOfUndefined, vtkIdType);
  vtkGetMacro(NumberOfRoundTripFailures, vtkIdType);
  vtkGetMacro(MedianRoundTripError, double);
  vtkGetMacro(MaximumRoundTripError, double);
  /// Seconds of the inverse problems of the last run (precomputation and round trip excluded).
  vtkGetMacro(QuerySeconds, double);
  /// Seconds of the round trip's forward problems.
  vtkGetMacro(RoundTripSeconds, double);

protected:
  vtkBarySurfaceWeights();
  ~vtkBarySurfaceWeights() override;
  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  char* EmbeddingArrayName = nullptr;
  char* WeightsArrayName = nullptr;
  double Gamma;
  double SurfaceTolerance;
  bool RoundTrip = true;
  double RoundTripTolerance;
  int NumberOfThreads;
  vtkIdType NumberOfUndefined = 0, NumberOfRoundTripFailures = 0;
  double MedianRoundTripError = 0, MaximumRoundTripError = 0;
  double QuerySeconds = 0, RoundTripSeconds = 0;

private:
  vtkBarySurfaceWeights(const vtkBarySurfaceWeights&) = delete;
  void operator=(const vtkBarySurfaceWeights&) = delete;
  struct Internals;
  std::unique_ptr<Internals> Internal;
};

#endif
