#include "vtkBaryCoordinates.h"

#include "vtkBaryConversion.h"
#include "vtkBaryMixedHandles.h"
#include "vtkBaryFilterErrors.h"

#include "core/common/error.h"

#include "vtkDataArray.h"
#include "vtkDataSet.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkUnsignedCharArray.h"

#include <algorithm>
#include <cmath>
#include <cstring>

vtkStandardNewMacro(vtkBaryCoordinates);

vtkBaryCoordinates::vtkBaryCoordinates()
{
  this->SetNumberOfInputPorts(3);
  this->WeightMethod = vtkBaryWeightMethod::New();
  this->SetWeightsArrayName("Weights");
  this->SetLocationArrayName("CageLocation");
  this->SetFaceWeightsArrayName("FaceWeights");
}

void vtkBaryCoordinates::SetWeightMethod(vtkBaryWeightMethod* method)
{
  if (vtkBaryWeightMethod::Replace(this, this->WeightMethod, method))
    this->Modified();
}

vtkMTimeType vtkBaryCoordinates::GetMTime()
{
  vtkMTimeType t = this->Superclass::GetMTime();
  return std::max(t, this->WeightMethod->GetMTime());
}

vtkBaryCoordinates::~vtkBaryCoordinates()
{
  this->WeightMethod->UnRegister(this);
  this->SetWeightsArrayName(nullptr);
  this->SetLocationArrayName(nullptr);
  this->SetFaceWeightsArrayName(nullptr);
}

void vtkBaryCoordinates::SetCageData(vtkPolyData* cage)
{
  this->SetInputData(1, cage);
}

void vtkBaryCoordinates::SetCageConnection(vtkAlgorithmOutput* output)
{
  this->SetInputConnection(1, output);
}

void vtkBaryCoordinates::SetDomainData(vtkDataSet* domain)
{
  this->SetInputData(2, domain);
}

void vtkBaryCoordinates::SetDomainConnection(vtkAlgorithmOutput* output)
{
  this->SetInputConnection(2, output);
}

double vtkBaryCoordinates::GetStatistic(const char* name) const
{
  for (const auto& entry : this->Statistics)
    if (name && entry.first == name)
      return entry.second;
  return std::nan("");
}

const char* vtkBaryCoordinates::GetStatisticName(int i) const
{
  return i >= 0 && i < this->GetNumberOfStatistics()
    ? this->Statistics[static_cast<std::size_t>(i)].first.c_str()
    : nullptr;
}

double vtkBaryCoordinates::GetStatisticValue(int i) const
{
  return i >= 0 && i < this->GetNumberOfStatistics()
    ? this->Statistics[static_cast<std::size_t>(i)].second
    : std::nan("");
}

int vtkBaryCoordinates::FillInputPortInformation(int port, vtkInformation* info)
{
  if (port == 0)
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataSet");
  else if (port == 1)
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData");
  else
  {
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataSet");
    info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
  }
  return 1;
}

int vtkBaryCoordinates::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkDataSet* input = vtkDataSet::GetData(inputVector[0]);
  vtkPolyData* cagePoly = vtkPolyData::GetData(inputVector[1]);
  vtkDataSet* domain = vtkDataSet::GetData(inputVector[2]);
  vtkDataSet* output = vtkDataSet::GetData(outputVector);
  this->SetErrorCode(0);
  this->Statistics.clear();
  this->NumberOfInsidePoints = this->NumberOfOutsidePoints = 0;
  this->NumberOfBoundaryPoints = this->NumberOfUndefinedPoints = 0;
  if (!input || !output)
  {
    vtkErrorMacro(<< "No input data set.");
    return 0;
  }
  output->ShallowCopy(input);
  if (!cagePoly)
  {
    vtkErrorMacro(<< "No cage: connect a vtkPolyData to input port 1 (SetCageData).");
    return 0;
  }
  if (!this->WeightsArrayName || !*this->WeightsArrayName)
  {
    vtkErrorMacro(<< "WeightsArrayName must not be empty.");
    return 0;
  }
  if (input->GetNumberOfPoints() == 0)
  {
    vtkWarningMacro(<< "The input has no points; nothing to compute.");
    return 1;
  }

  try
  {
    const auto progress = [this](double f) {
      this->UpdateProgress(f);
      return !this->GetAbortExecute();
    };
    vtkBaryCage columns;
    std::vector<std::string> warnings;
    this->UpdateProgress(0.0);
    // BBW with mixed handles (cage faces among other handles, regions, a HandleType array) or
    // with the domain's HandleRegion / ShapePreservation arrays: vtkBaryMixedHandles.
    const bool mixed = this->WeightMethod->GetMethod() == vtkBaryWeightMethod::BBW &&
      vtkBaryMixedHandles::UsesMixedHandles(cagePoly, domain);
    const bary::WeightsResult result = mixed
      ? vtkBaryMixedHandles::Compute(
          this->WeightMethod->GetSettings(), input, cagePoly, domain, progress)
      : this->WeightMethod->Compute(input, cagePoly, domain, progress, &columns, &warnings);
    if (mixed)
    {
      columns = vtkBaryCage(); // identity column order: handle j is component j
      columns.ControlPointIds.resize(static_cast<std::size_t>(result.W.cols()));
      for (std::size_t j = 0; j < columns.ControlPointIds.size(); ++j)
        columns.ControlPointIds[j] = static_cast<vtkIdType>(j);
    }
    for (const std::string& warning : warnings)
      vtkWarningMacro(<< warning);
    this->FinishOutput(output, result, columns);
  }
  VTKBARY_CATCH_ERRORS
  return 1;
}

void vtkBaryCoordinates::FinishOutput(
  vtkDataSet* output, const bary::WeightsResult& result, const vtkBaryCage& columns)
{
  output->GetPointData()->AddArray(
    vtkBaryConversion::ToArray(result.W, columns, this->WeightsArrayName));
  // Green coordinates: the faces' normal coefficients (psi), faces in core order
  if (result.face_weights.cols() > 0)
  {
    if (!this->FaceWeightsArrayName || !*this->FaceWeightsArrayName)
      throw bary::Error(bary::ErrorCode::InvalidArgument,
        "FaceWeightsArrayName must not be empty: the method computes face coefficients");
    output->GetPointData()->AddArray(
      vtkBaryConversion::FaceArray(result.face_weights, this->FaceWeightsArrayName));
  }
  else if (this->FaceWeightsArrayName && *this->FaceWeightsArrayName)
    output->GetPointData()->RemoveArray(this->FaceWeightsArrayName); // stale: not these weights'
  // control points the method added (celestial hull points): their positions, columns last
  vtkNew<vtkFieldData> field;
  if (output->GetFieldData())
    field->ShallowCopy(output->GetFieldData());
  field->RemoveArray("AddedControlPoints");
  if (result.added_controls.rows() > 0)
  {
    vtkNew<vtkDoubleArray> added;
    added->SetName("AddedControlPoints");
    added->SetNumberOfComponents(3);
    added->SetNumberOfTuples(result.added_controls.rows());
    for (Eigen::Index k = 0; k < result.added_controls.rows(); ++k)
      for (int j = 0; j < 3; ++j)
        added->SetComponent(k, j,
          j < result.added_controls.cols() ? result.added_controls(k, j) : columns.PlaneZ);
    field->AddArray(added);
  }
  output->SetFieldData(field);
  if (this->GenerateLocation && this->LocationArrayName && *this->LocationArrayName)
  {
    vtkNew<vtkUnsignedCharArray> location;
    location->SetName(this->LocationArrayName);
    location->SetNumberOfTuples(static_cast<vtkIdType>(result.location.size()));
    for (std::size_t i = 0; i < result.location.size(); ++i)
      location->SetValue(static_cast<vtkIdType>(i), static_cast<unsigned char>(result.location[i]));
    output->GetPointData()->AddArray(location);
  }
  this->NumberOfInsidePoints = result.count(bary::PointLocation::Inside);
  this->NumberOfOutsidePoints = result.count(bary::PointLocation::Outside);
  this->NumberOfBoundaryPoints = result.count(bary::PointLocation::Boundary);
  this->NumberOfUndefinedPoints = static_cast<vtkIdType>(result.undefined.size());
  this->Statistics = result.statistics;
  if (!result.undefined.empty())
    vtkWarningMacro(<< result.undefined.size()
                    << " point(s) outside the domain have undefined weights (NaN), first id "
                    << result.undefined.front());
}

void vtkBaryCoordinates::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "WeightMethod:\n";
  this->WeightMethod->PrintSelf(os, indent.GetNextIndent());
  os << indent << "WeightsArrayName: " << (this->WeightsArrayName ? this->WeightsArrayName : "(none)")
     << "\n";
  os << indent << "FaceWeightsArrayName: "
     << (this->FaceWeightsArrayName ? this->FaceWeightsArrayName : "(none)") << "\n";
  os << indent << "GenerateLocation: " << this->GenerateLocation << "\n";
  os << indent << "LocationArrayName: "
     << (this->LocationArrayName ? this->LocationArrayName : "(none)") << "\n";
}
