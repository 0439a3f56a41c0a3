#include "vtkBarySurfaceWeights.h"

#include "vtkBaryConversion.h"
#include "vtkBaryFilterErrors.h"
#include "vtkBarySurfaceData.h"

#include "vtkDoubleArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPointSet.h"
#include "vtkPolyData.h"
#include "vtkUnsignedCharArray.h"

#include "core/surface/weighted_averages.h"

#include <chrono>

vtkStandardNewMacro(vtkBarySurfaceWeights);

struct vtkBarySurfaceWeights::Internals
{
  vtkBarySurfaceData::Cache Cache;
};

vtkBarySurfaceWeights::vtkBarySurfaceWeights()
  : Internal(new Internals)
{
  this->SetNumberOfInputPorts(3);
  const bary::InverseOptions defaults;
  this->Gamma = defaults.gamma;
  this->NumberOfThreads = defaults.threads;
  this->SurfaceTolerance = bary::kDefaultSurfaceTolerance;
  this->RoundTripTolerance = bary::kDefaultRoundTripTolerance;
  this->SetEmbeddingArrayName(vtkBarySurfaceData::DefaultEmbeddingName());
  this->SetWeightsArrayName("Weights");
}

vtkBarySurfaceWeights::~vtkBarySurfaceWeights()
{
  this->SetEmbeddingArrayName(nullptr);
  this->SetWeightsArrayName(nullptr);
}

int vtkBarySurfaceWeights::FillInputPortInformation(int port, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), port == 1 ? "vtkPolyData" : "vtkPointSet");
  return 1;
}

int vtkBarySurfaceWeights::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPointSet* input = vtkPointSet::GetData(inputVector[0]);
  vtkPolyData* surface = vtkPolyData::GetData(inputVector[1]);
  vtkPointSet* anchorData = vtkPointSet::GetData(inputVector[2]);
  vtkPointSet* output = vtkPointSet::GetData(outputVector);
  this->SetErrorCode(0);
  this->NumberOfUndefined = this->NumberOfRoundTripFailures = 0;
  this->MedianRoundTripError = this->MaximumRoundTripError = 0;
  this->QuerySeconds = this->RoundTripSeconds = 0;
  try
  {
    const std::string name = this->EmbeddingArrayName ? this->EmbeddingArrayName : "";
    const std::string weightsName = this->WeightsArrayName ? this->WeightsArrayName : "";
    if (weightsName.empty())
      throw bary::Error(bary::ErrorCode::InvalidArgument, "WeightsArrayName is empty");
    const auto wa = this->Internal->Cache.Get(surface, name);
    const auto anchors =
      vtkBarySurfaceData::Locate(wa->mesh(), anchorData, this->SurfaceTolerance, "anchor");
    const auto points =
      vtkBarySurfaceData::Locate(wa->mesh(), input, this->SurfaceTolerance, "point");
    bary::InverseOptions options;
    options.gamma = this->Gamma;
    options.threads = this->NumberOfThreads;
    auto progress = [this](double f) {
      this->UpdateProgress(this->RoundTrip ? 0.5 * f : f);
      return !this->GetAbortExecute();
    };
    const auto t0 = std::chrono::steady_clock::now();
    const bary::DenseWeights W = wa->inverse(anchors, points, options, progress);
    this->QuerySeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

    output->ShallowCopy(input);
    vtkNew<vtkDoubleArray> weights;
    weights->SetName(weightsName.c_str());
    weights->SetNumberOfComponents(static_cast<int>(W.cols()));
    for (int c = 0; c < W.cols(); ++c)
      weights->SetComponentName(c, ("c" + std::to_string(c)).c_str());
    weights->SetNumberOfTuples(W.rows());
    std::copy(W.data(), W.data() + W.size(), weights->GetPointer(0));
    output->GetPointData()->AddArray(weights);
    vtkBarySurfaceData::AddSurfacePointArrays(output, points);

    if (this->RoundTrip)
    {
      bary::ForwardOptions forward;
      forward.threads = this->NumberOfThreads;
      const bary::RoundTrip r = wa->round_trip(anchors, points, W, this->RoundTripTolerance,
        forward, [this](double f) {
          this->UpdateProgress(0.5 + 0.5 * f);
          return !this->GetAbortExecute();
        });
      vtkNew<vtkDoubleArray> error;
      error->SetName("RoundTripError");
      error->SetNumberOfTuples(W.rows());
      vtkNew<vtkUnsignedCharArray> defined;
      defined->SetName("Defined");
      defined->SetNumberOfTuples(W.rows());
      for (vtkIdType p = 0; p < W.rows(); ++p)
      {
        error->SetValue(p, r.error[static_cast<std::size_t>(p)]);
        defined->SetValue(p, r.returned[static_cast<std::size_t>(p)]);
      }
      output->GetPointData()->AddArray(error);
      output->GetPointData()->AddArray(defined);
      this->NumberOfUndefined = r.not_returned;
      this->NumberOfRoundTripFailures = r.failures;
      this->MedianRoundTripError = r.median_error;
      this->MaximumRoundTripError = r.max_error;
      this->RoundTripSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() - this->QuerySeconds;
    }
    return 1;
  }
  VTKBARY_CATCH_ERRORS
}

void vtkBarySurfaceWeights::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "EmbeddingArrayName: " << (this->EmbeddingArrayName ? this->EmbeddingArrayName : "(none)")
     << "\n"
     << indent << "WeightsArrayName: " << (this->WeightsArrayName ? this->WeightsArrayName : "(none)") << "\n"
     << indent << "Gamma: " << this->Gamma << "\n"
     << indent << "SurfaceTolerance: " << this->SurfaceTolerance << "\n"
     << indent << "RoundTrip: " << this->RoundTrip << "\n"
     << indent << "RoundTripTolerance: " << this->RoundTripTolerance << "\n"
     << indent << "NumberOfThreads: " << this->NumberOfThreads << "\n";
}
