/**
 * @class   vtkBarySurfaceEmbedding
 * @brief   The Euclidean embedding of a triangle surface into R^D that weighted averages on
 *          surfaces work in (Panozzo et al., "Weighted averages on surfaces", ACM TOG 32(4), 2013,
 *          §3.5): landmarks, heat-method geodesics between them, SMACOF metric MDS from
 *          classical MDS, least-squares-mesh upsampling (bary::euclidean_embedding).
 *
 * Input: a triangle surface (vtkPolyData; see vtkBarySurfaceData for what is accepted).
 * Output: a shallow copy with the point-data array EmbeddingArrayName (default `Embedding`,
 * D components, double) and the field-data arrays `Landmarks` (vtkIdTypeArray, the landmark
 * point ids) and `EmbeddingQuality` (mean, median and max relative error of embedded against
 * geodesic distances, and the number of pairs measured).
 *
 * Properties default to bary::EmbeddingOptions' defaults (the paper's: D = 8, 1000 landmarks by
 * normal-preserving decimation); core checks their ranges and a value out of range is an error
 * naming it. The results of the last run: GetStress, GetInitialStress, GetSMACOFIterations,
 * GetSMACOFConverged, Get{Mean,Median,Maximum}RelativeError, GetNumberOfQualityPairs and the
 * seconds of each stage (GetNumberOfStages, GetStageName, GetStageSeconds).
 *
 * The pipeline re-executes only when the input or a property changed, so the embedding is
 * computed once per surface; vtkBaryWeightedAverage and vtkBarySurfaceWeights read the array.
 *
 * @sa vtkBaryWeightedAverage vtkBarySurfaceWeights vtkBarySurfaceData
 */
#ifndef vtkBarySurfaceEmbedding_h
#define vtkBarySurfaceEmbedding_h

#include "BaryLabSurfaceModule.h" // for export macro
#include "vtkPolyDataAlgorithm.h"

#include <string> // for the stage names
#include <utility>
#include <vector>

class BARYLABSURFACE_EXPORT vtkBarySurfaceEmbedding : public vtkPolyDataAlgorithm
{
public:
  static vtkBarySurfaceEmbedding* New();
  vtkTypeMacro(vtkBarySurfaceEmbedding, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum LandmarkMethods
  {
    LANDMARKS_DECIMATION = 0,    ///< normal-preserving halfedge collapses (the paper's)
    LANDMARKS_FARTHEST_POINT = 1 ///< farthest-point samples
  };

  vtkSetMacro(Dimension, int);
  vtkGetMacro(Dimension, int);
  vtkSetMacro(NumberOfLandmarks, vtkIdType);
  vtkGetMacro(NumberOfLandmarks, vtkIdType);
  vtkSetMacro(LandmarkMethod, int);
  vtkGetMacro(LandmarkMethod, int);
  vtkSetMacro(StressTolerance, double);
  vtkGetMacro(StressTolerance, double);
  vtkSetMacro(MaximumIterations, int);
  vtkGetMacro(MaximumIterations, int);
  vtkSetMacro(HeatTimeFactor, double);
  vtkGetMacro(HeatTimeFactor, double);
  vtkSetMacro(QualitySources, int);
  vtkGetMacro(QualitySources, int);
  /// OpenMP threads (0: all); the embedding does not depend on it.
  vtkSetMacro(NumberOfThreads, int);
  vtkGetMacro(NumberOfThreads, int);
  vtkSetStringMacro(EmbeddingArrayName);
  vtkGetStringMacro(EmbeddingArrayName);

  vtkGetMacro(Stress, double);
  vtkGetMacro(InitialStress, double);
  vtkGetMacro(SMACOFIterations, int);
  vtkGetMacro(SMACOFConverged, bool);
  vtkGetMacro(MeanRelativeError, double);
  vtkGetMacro(MedianRelativeError, double);
  vtkGetMacro(MaximumRelativeError, double);
  vtkGetMacro(NumberOfQualityPairs, vtkIdType);
  int GetNumberOfStages() const { return static_cast<int>(this->Stages.size()); }
  const char* GetStageName(int i) const;
  double GetStageSeconds(int i) const;

protected:
  vtkBarySurfaceEmbedding();
  ~vtkBarySurfaceEmbedding() override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  int Dimension;
  vtkIdType NumberOfLandmarks;
  int LandmarkMethod;
  double StressTolerance;
  int MaximumIterations;
  double HeatTimeFactor;
  int QualitySources;
  int NumberOfThreads = 0;
  char* EmbeddingArrayName = nullptr;

  double Stress = 0, InitialStress = 0;
  int SMACOFIterations = 0;
  bool SMACOFConverged = false;
  double MeanRelativeError = 0, MedianRelativeError = 0, MaximumRelativeError = 0;
  vtkIdType NumberOfQualityPairs = 0;
  std::vector<std::pair<std::string, double>> Stages;

private:
  vtkBarySurfaceEmbedding(const vtkBarySurfaceEmbedding&) = delete;
  void operator=(const vtkBarySurfaceEmbedding&) = delete;
};

#endif
