/**
 * @class   vtkBaryWeightedAverage
 * @brief   Weighted averages of anchor points on a surface: the forward problem of Panozzo et
 *          al., "Weighted averages on surfaces" (ACM TOG 32(4), 2013, §3.3), through
 *          bary::WeightedAverages.
 *
 * Input 0: the surface (vtkPolyData of triangles) with its embedding array
 * (EmbeddingArrayName, default `Embedding`: vtkBarySurfaceEmbedding's output, or read from a
 * file). Input 1: the anchors (any vtkPointSet; each point is located on the surface, and one
 * farther than SurfaceTolerance x the surface's diagonal is an error naming it). The weights:
 * SetWeights(array) with one tuple per query and one component per anchor; each tuple must sum
 * to 1.
 *
 * Output: a vtkPolyData with one point per query, in order, and a vertex cell for each
 * successful one; point data `FaceId` (cell id of the surface triangle, -1 when failed),
 * `Barycentric` (3 components: the weights of the triangle's points in cell order) and `Valid`
 * (unsigned char, 0 where the search found no Phong projection: that point's coordinates are
 * NaN, never a guess). GetNumberOfFailures counts them.
 *
 * The Phong projection is precomputed once per surface and embedding (kept while neither
 * changes), so changing the weights or moving the anchors re-runs only the queries.
 *
 * @sa vtkBarySurfaceEmbedding vtkBarySurfaceWeights vtkBarySurfaceData
 */
#ifndef vtkBaryWeightedAverage_h
#define vtkBaryWeightedAverage_h

#include "BaryLabSurfaceModule.h" // for export macro
#include "vtkPolyDataAlgorithm.h"
#include "vtkSmartPointer.h" // for the weights

#include <memory> // for the cache

class vtkDataArray;

class BARYLABSURFACE_EXPORT vtkBaryWeightedAverage : public vtkPolyDataAlgorithm
{
public:
  static vtkBaryWeightedAverage* New();
  vtkTypeMacro(vtkBaryWeightedAverage, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// The anchors (input 1).
  void SetAnchorsConnection(vtkAlgorithmOutput* output) { this->SetInputConnection(1, output); }
  void SetAnchorsData(vtkDataObject* data) { this->SetInputData(1, data); }

  /// One tuple per query, one component per anchor.
  void SetWeights(vtkDataArray* weights);
  vtkDataArray* GetWeights();

  vtkSetStringMacro(EmbeddingArrayName);
  vtkGetStringMacro(EmbeddingArrayName);
  vtkSetMacro(SurfaceTolerance, double);
  vtkGetMacro(SurfaceTolerance, double);
  /// Project onto every triangle and keep the closest projection (validation; slow).
  vtkSetMacro(BruteForce, bool);
  vtkGetMacro(BruteForce, bool);
  vtkBooleanMacro(BruteForce, bool);
  /// Start each query's search from the previous query's result (curves, animations).
  vtkSetMacro(WarmStart, bool);
  vtkGetMacro(WarmStart, bool);
  vtkBooleanMacro(WarmStart, bool);
  /// Triangles a query's search may try (0: all).
  vtkSetMacro(MaximumTriangles, vtkIdType);
  vtkGetMacro(MaximumTriangles, vtkIdType);
  vtkSetMacro(NumberOfThreads, int);
  vtkGetMacro(NumberOfThreads, int);

  vtkGetMacro(NumberOfFailures, vtkIdType);
  vtkGetMacro(TrianglesTried, vtkIdType);
  /// Seconds of the queries of the last run (precomputation excluded).
  vtkGetMacro(QuerySeconds, double);

  vtkMTimeType GetMTime() override;

protected:
  vtkBaryWeightedAverage();
  ~vtkBaryWeightedAverage() override;
  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  char* EmbeddingArrayName = nullptr;
  double SurfaceTolerance;
  bool BruteForce = false;
  bool WarmStart;
  vtkIdType MaximumTriangles;
  int NumberOfThreads;
  vtkIdType NumberOfFailures = 0, TrianglesTried = 0;
  double QuerySeconds = 0;

private:
  vtkBaryWeightedAverage(const vtkBaryWeightedAverage&) = delete;
  void operator=(const vtkBaryWeightedAverage&) = delete;
  struct Internals;
  std::unique_ptr<Internals> Internal;
};

#endif
