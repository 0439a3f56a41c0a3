/**
 * @class   vtkBarySurfaceRemesh
 * @brief   Semiregular remeshing of a surface from a coarse quad layout by weighted averages
 *          (Panozzo et al., "Weighted averages on surfaces", ACM TOG 32(4), 2013, §4.1, Fig. 7):
 *          bary::semiregular_remesh (subdivision by forward problems, then Laplacian smoothing on
 *          the surface).
 *
 * Input 0: the surface (vtkPolyData of triangles) with its embedding array (EmbeddingArrayName,
 * default `Embedding`). Input 1: the coarse quad mesh (vtkPolyData whose polygons are all quads;
 * its points are located on the surface, one farther than SurfaceTolerance x the diagonal is an
 * error naming it).
 *
 * Output: the quad mesh after Levels subdivisions (default 2) and SmoothingSteps (default 5),
 * with point data `FaceId`, `Barycentric` and `Valid` (0 where a forward problem failed: NaN
 * coordinates, never a guess). GetNumberOfFailures counts them.
 *
 * @sa vtkBarySurfaceCurve vtkBaryWeightedAverage
 */
#ifndef vtkBarySurfaceRemesh_h
#define vtkBarySurfaceRemesh_h

#include "BaryLabSurfaceModule.h" // for export macro
#include "vtkPolyDataAlgorithm.h"

#include <memory> // for the cache

class BARYLABSURFACE_EXPORT vtkBarySurfaceRemesh : public vtkPolyDataAlgorithm
{
public:
  static vtkBarySurfaceRemesh* New();
  vtkTypeMacro(vtkBarySurfaceRemesh, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// The coarse quad mesh (input 1).
  void SetCoarseMeshData(vtkDataObject* data) { this->SetInputData(1, data); }
  void SetCoarseMeshConnection(vtkAlgorithmOutput* output) { this->SetInputConnection(1, output); }

  vtkSetStringMacro(EmbeddingArrayName);
  vtkGetStringMacro(EmbeddingArrayName);
  vtkSetMacro(Levels, int);
  vtkGetMacro(Levels, int);
  vtkSetMacro(SmoothingSteps, int);
  vtkGetMacro(SmoothingSteps, int);
  vtkSetMacro(SurfaceTolerance, double);
  vtkGetMacro(SurfaceTolerance, double);
  vtkSetMacro(NumberOfThreads, int);
  vtkGetMacro(NumberOfThreads, int);

  vtkGetMacro(NumberOfFailures, vtkIdType);

protected:
  vtkBarySurfaceRemesh();
  ~vtkBarySurfaceRemesh() override;
  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  char* EmbeddingArrayName = nullptr;
  int Levels;
  int SmoothingSteps;
  double SurfaceTolerance;
  int NumberOfThreads;
  vtkIdType NumberOfFailures = 0;

private:
  vtkBarySurfaceRemesh(const vtkBarySurfaceRemesh&) = delete;
  void operator=(const vtkBarySurfaceRemesh&) = delete;
  struct Internals;
  std::unique_ptr<Internals> Internal;
};

#endif
