/**
 * @class   vtkBarySurfaceCorrespondence
 * @brief   Transfers point data from a source surface to a target surface through corresponding
 *          anchors (Panozzo et al., "Weighted averages on surfaces", ACM TOG 32(4), 2013, §4.3):
 *          each target point's weights on the target (inverse problem), its image on the source
 *          (forward problem), and the source's point data interpolated there
 *          (bary::map_surface_points, bary::map_distortion).
 *
 * Inputs, each a vtkPolyData of triangles with its embedding array (EmbeddingArrayName) where a
 * surface is meant: 0 the target surface, 1 the target's anchors (any vtkPointSet), 2 the source
 * surface, whose point-data arrays are transferred (all of them but the embedding, or only
 * those added with AddArrayName), 3 the source's anchors, in the same order as the target's.
 *
 * Output: a shallow copy of the target with, as point data, each transferred array (same name,
 * double, NaN where undefined), `SourceFaceId` and `SourceBarycentric` (the image on the
 * source), `SourcePosition` (3 components: the image in space, for morphs), `RoundTripError`
 * and `Defined` (unsigned char, 0 where the target point is not a weighted average of the
 * anchors or its image failed: §4.4, never mapped silently); as cell data `Stretch` (the
 * scale-invariant symmetric L2 stretch of each triangle, >= 1, 1 for a similarity, NaN where a
 * corner is undefined) and `Flipped` (unsigned char). Results: GetNumberOfUndefined,
 * GetNumberOfFlipped, GetFlippedAreaFraction, GetStretch, GetStretchBest95.
 *
 * @sa vtkBarySurfaceWeights vtkBaryWeightedAverage
 */
#ifndef vtkBarySurfaceCorrespondence_h
#define vtkBarySurfaceCorrespondence_h

#include "BaryLabSurfaceModule.h" // for export macro
#include "vtkPolyDataAlgorithm.h"

#include <memory> // for the caches
#include <string>
#include <vector>

class BARYLABSURFACE_EXPORT vtkBarySurfaceCorrespondence : public vtkPolyDataAlgorithm
{
public:
  static vtkBarySurfaceCorrespondence* New();
  vtkTypeMacro(vtkBarySurfaceCorrespondence, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  void SetTargetAnchorsData(vtkDataObject* data) { this->SetInputData(1, data); }
  void SetSourceData(vtkDataObject* data) { this->SetInputData(2, data); }
  void SetSourceAnchorsData(vtkDataObject* data) { this->SetInputData(3, data); }

  vtkSetStringMacro(EmbeddingArrayName);
  vtkGetStringMacro(EmbeddingArrayName);
  /// Transfer only these source arrays (default: every point array but the embedding).
  void AddArrayName(const char* name);
  void ClearArrayNames();
  vtkSetMacro(Gamma, double);
  vtkGetMacro(Gamma, double);
  vtkSetMacro(RoundTripTolerance, double);
  vtkGetMacro(RoundTripTolerance, double);
  vtkSetMacro(SurfaceTolerance, double);
  vtkGetMacro(SurfaceTolerance, double);
  vtkSetMacro(NumberOfThreads, int);
  vtkGetMacro(NumberOfThreads, int);

  vtkGetMacro(NumberOfUndefined, vtkIdType);
  vtkGetMacro(NumberOfFlipped, vtkIdType);
  vtkGetMacro(FlippedAreaFraction, double);
  vtkGetMacro(Stretch, double);
  vtkGetMacro(StretchBest95, double);

protected:
  vtkBarySurfaceCorrespondence();
  ~vtkBarySurfaceCorrespondence() override;
  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  char* EmbeddingArrayName = nullptr;
  double Gamma;
  double RoundTripTolerance;
  double SurfaceTolerance;
  int NumberOfThreads = 0;
  vtkIdType NumberOfUndefined = 0, NumberOfFlipped = 0;
  double FlippedAreaFraction = 0, Stretch = 0, StretchBest95 = 0;

private:
  vtkBarySurfaceCorrespondence(const vtkBarySurfaceCorrespondence&) = delete;
  void operator=(const vtkBarySurfaceCorrespondence&) = delete;
  struct Internals;
  std::unique_ptr<Internals> Internal;
};

#endif
