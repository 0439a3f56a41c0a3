#include "vtkBarySurfaceEmbedding.h"

#include "vtkBaryFilterErrors.h"
#include "vtkBarySurfaceData.h"

#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"

#include "core/surface/euclidean_embedding.h"

vtkStandardNewMacro(vtkBarySurfaceEmbedding);

vtkBarySurfaceEmbedding::vtkBarySurfaceEmbedding()
{
  const bary::EmbeddingOptions defaults;
  this->Dimension = defaults.dimension;
  this->NumberOfLandmarks = static_cast<vtkIdType>(defaults.landmarks);
  this->LandmarkMethod = defaults.landmark_method == bary::LandmarkMethod::Decimation
    ? LANDMARKS_DECIMATION
    : LANDMARKS_FARTHEST_POINT;
  this->StressTolerance = defaults.stress_tolerance;
  this->MaximumIterations = defaults.max_iterations;
  this->HeatTimeFactor = defaults.heat_time_factor;
  this->QualitySources = defaults.quality_sources;
  this->SetEmbeddingArrayName(vtkBarySurfaceData::DefaultEmbeddingName());
}

vtkBarySurfaceEmbedding::~vtkBarySurfaceEmbedding()
{
  this->SetEmbeddingArrayName(nullptr);
}

const char* vtkBarySurfaceEmbedding::GetStageName(int i) const
{
  return i >= 0 && i < this->GetNumberOfStages() ? this->Stages[static_cast<std::size_t>(i)].first.c_str()
                                                 : nullptr;
}

double vtkBarySurfaceEmbedding::GetStageSeconds(int i) const
{
  return i >= 0 && i < this->GetNumberOfStages() ? this->Stages[static_cast<std::size_t>(i)].second : 0.0;
}

int vtkBarySurfaceEmbedding::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0]);
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  this->SetErrorCode(0);
  this->Stages.clear();
  try
  {
    const std::string name = this->EmbeddingArrayName ? this->EmbeddingArrayName : "";
    if (name.empty())
      throw bary::Error(bary::ErrorCode::InvalidArgument, "EmbeddingArrayName is empty");
    const bary::SurfaceMesh mesh = vtkBarySurfaceData::ToSurfaceMesh(input);
    bary::EmbeddingOptions options;
    options.dimension = this->Dimension;
    options.landmarks = this->NumberOfLandmarks;
    if (this->LandmarkMethod != LANDMARKS_DECIMATION && this->LandmarkMethod != LANDMARKS_FARTHEST_POINT)
      throw bary::Error(bary::ErrorCode::InvalidArgument,
        "LandmarkMethod must be LANDMARKS_DECIMATION (0) or LANDMARKS_FARTHEST_POINT (1), got " +
          std::to_string(this->LandmarkMethod));
    options.landmark_method = this->LandmarkMethod == LANDMARKS_DECIMATION
      ? bary::LandmarkMethod::Decimation
      : bary::LandmarkMethod::FarthestPoint;
    options.stress_tolerance = this->StressTolerance;
    options.max_iterations = this->MaximumIterations;
    options.heat_time_factor = this->HeatTimeFactor;
    options.quality_sources = this->QualitySources;
    options.threads = this->NumberOfThreads;
    const bary::EmbeddingResult r = bary::euclidean_embedding(mesh, options, [this](double f) {
      this->UpdateProgress(f);
      return !this->GetAbortExecute();
    });

    output->ShallowCopy(input);
    vtkNew<vtkDoubleArray> E;
    E->SetName(name.c_str());
    E->SetNumberOfComponents(static_cast<int>(r.E.cols()));
    E->SetNumberOfTuples(r.E.rows());
    for (vtkIdType i = 0; i < r.E.rows(); ++i)
      for (int d = 0; d < r.E.cols(); ++d)
        E->SetTypedComponent(i, d, r.E(i, d));
    output->GetPointData()->AddArray(E);
    vtkNew<vtkIdTypeArray> landmarks;
    landmarks->SetName("Landmarks");
    for (const int l : r.landmarks)
      landmarks->InsertNextValue(l);
    output->GetFieldData()->AddArray(landmarks);
    vtkNew<vtkDoubleArray> quality;
    quality->SetName("EmbeddingQuality");
    quality->SetNumberOfComponents(4);
    quality->SetComponentName(0, "MeanRelativeError");
    quality->SetComponentName(1, "MedianRelativeError");
    quality->SetComponentName(2, "MaximumRelativeError");
    quality->SetComponentName(3, "Pairs");
    const double q[4] = { r.quality.mean_relative_error, r.quality.median_relative_error,
      r.quality.max_relative_error, static_cast<double>(r.quality.pairs) };
    quality->InsertNextTuple(q);
    output->GetFieldData()->AddArray(quality);

    this->Stress = r.stress;
    this->InitialStress = r.initial_stress;
    this->SMACOFIterations = r.smacof_iterations;
    this->SMACOFConverged = r.smacof_converged;
    this->MeanRelativeError = r.quality.mean_relative_error;
    this->MedianRelativeError = r.quality.median_relative_error;
    this->MaximumRelativeError = r.quality.max_relative_error;
    this->NumberOfQualityPairs = r.quality.pairs;
    this->Stages = r.seconds;
    return 1;
  }
  VTKBARY_CATCH_ERRORS
}

void vtkBarySurfaceEmbedding::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Dimension: " << this->Dimension << "\n"
     << indent << "NumberOfLandmarks: " << this->NumberOfLandmarks << "\n"
     << indent << "LandmarkMethod: "
     << (this->LandmarkMethod == LANDMARKS_DECIMATION ? "decimation" : "farthest-point") << "\n"
     << indent << "StressTolerance: " << this->StressTolerance << "\n"
     << indent << "MaximumIterations: " << this->MaximumIterations << "\n"
     << indent << "HeatTimeFactor: " << this->HeatTimeFactor << "\n"
     << indent << "QualitySources: " << this->QualitySources << "\n"
     << indent << "NumberOfThreads: " << this->NumberOfThreads << "\n"
     << indent << "EmbeddingArrayName: " << (this->EmbeddingArrayName ? this->EmbeddingArrayName : "(none)")
     << "\n";
}
