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
#include "vtkSmartPointer.h"
#include "vtkUnsignedCharArray.h"

#include "core/surface/weighted_averages.h"

#include <algorithm>
#include <chrono>
#include <limits>

vtkStandardNewMacro(vtkBarySurfaceWeights);

struct vtkBarySurfaceWeights::Internals
{
  vtkBarySurfaceData::Cache Cache;
  vtkSmartPointer<vtkDataArray> AnchorUV;
};

void vtkBarySurfaceWeights::SetAnchorTextureCoordinates(vtkDataArray* uv)
{
  if (this->Internal->AnchorUV != uv)
  {
    this->Internal->AnchorUV = uv;
    this->Modified();
  }
}

vtkDataArray* vtkBarySurfaceWeights::GetAnchorTextureCoordinates()
{
  return this->Internal->AnchorUV;
}

vtkMTimeType vtkBarySurfaceWeights::GetMTime()
{
  vtkMTimeType t = this->Superclass::GetMTime();
  if (this->Internal->AnchorUV)
    t = std::max(t, this->Internal->AnchorUV->GetMTime());
  return t;
}

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
    if (vtkDataArray* uv = this->Internal->AnchorUV)
    {
      if (uv->GetNumberOfComponents() != 2 || uv->GetNumberOfTuples() != W.cols())
        throw bary::Error(bary::ErrorCode::SizeMismatch, "the anchors' texture coordinates have " +
            std::to_string(uv->GetNumberOfTuples()) + " tuples of " +
            std::to_string(uv->GetNumberOfComponents()) + " components; " +
            std::to_string(W.cols()) + " tuples of 2 (u, v) are needed, one per anchor");
      if (!this->RoundTrip)
        throw bary::Error(bary::ErrorCode::InvalidArgument,
          "texture coordinates need the round trip (RoundTrip on): they are not placed where the "
          "weights are meaningless");
      vtkDataArray* defined = output->GetPointData()->GetArray("Defined");
      vtkNew<vtkDoubleArray> tcoords;
      tcoords->SetName("TCoords");
      tcoords->SetNumberOfComponents(2);
      tcoords->SetNumberOfTuples(W.rows());
      for (vtkIdType p = 0; p < W.rows(); ++p)
        for (int c = 0; c < 2; ++c)
        {
          double value = std::numeric_limits<double>::quiet_NaN();
          if (defined->GetComponent(p, 0) != 0)
          {
            value = 0;
            for (vtkIdType i = 0; i < W.cols(); ++i)
              value += W(p, i) * uv->GetComponent(i, c);
          }
          tcoords->SetComponent(p, c, value);
        }
      output->GetPointData()->SetTCoords(tcoords);
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
